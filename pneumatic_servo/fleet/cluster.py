"""Run a fleet check on Dask: an embedded ``LocalCluster`` by default, or an existing cluster.

The client computes each recording's key, skips those already in the row store, maps
:func:`~.task.check_recording` over the rest and writes each row to the store the moment
it arrives, so a killed run or a lost worker loses nothing that had finished.
"""
from __future__ import annotations

import logging
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

from ..analysis.compare import resolve_config
from ..model.config import ModelConfig
from .alerts import Alert, detect_alerts
from .discover import Recording, rig_of
from .row import Row
from .store import RowStore
from .task import TaskOptions, check_recording, content_key

#: one thread per local worker process, numba's parallel batches and BLAS included: the
#: workers already fill the cores, and more threads would only contend for them
WORKER_ENV = {'NUMBA_NUM_THREADS': '1', 'OMP_NUM_THREADS': '1', 'OPENBLAS_NUM_THREADS': '1'}


@dataclass
class FleetOptions:
    """How to run: the row store [path], a scheduler address (None: a local cluster of
    ``workers`` processes, default one per core) and whether to show a progress bar."""

    store: Path
    scheduler: str | None = None
    workers: int | None = None
    progress: bool = True
    task: TaskOptions = field(default_factory=TaskOptions)


@dataclass
class FleetResult:
    rows: list[Row]
    alerts: list[Alert]
    computed: int  # recordings checked in this run (the rest came from the store)

    @property
    def failed(self) -> bool:
        return any(r.failed for r in self.rows)

    def to_json(self) -> dict:
        return {'recordings': [r.to_json() for r in self.rows],
                'alerts': [a.to_json() for a in self.alerts]}


def parameter_names(config: ModelConfig, track) -> callable:
    """``key -> (label, unit)`` for alert texts and plots, from the parameters' declarations."""
    cfg = resolve_config(config, list(track))

    def name(key: str) -> tuple[str, str]:
        try:
            p = cfg.param(key)
        except Exception:  # a key the config does not know: show it as it is
            return key, ''
        return p.description or key, p.unit
    return name


def _client(options: FleetOptions):
    from distributed import Client, LocalCluster
    if options.scheduler:
        return Client(options.scheduler, timeout='30s'), None
    cluster = LocalCluster(n_workers=options.workers or os.cpu_count() or 1,
                           threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=logging.ERROR, env=WORKER_ENV)
    return Client(cluster), cluster


def _lost(recording: Recording, key: str, exc: BaseException) -> Row:
    """The row of a recording whose task died with its worker or with a bug (not stored: a
    rerun retries it)."""
    from distributed import KilledWorker
    if isinstance(exc, KilledWorker):
        why = 'the worker running it was lost; run again to retry'
    else:
        why = (f'internal error {type(exc).__name__}: {" ".join(str(exc).split())}; please '
               'report it')
    return Row(recording.path, rig_of(recording, {}), key=key, status='error', error=why)


def run_fleet(recordings: list[Recording], config: ModelConfig,
              options: FleetOptions) -> FleetResult:
    """Check every recording (skipping those already in the store) and find the alerts."""
    from distributed import as_completed
    config_dict = config.to_dict()
    keys = [content_key(r, config_dict, options.task) for r in recordings]
    store = RowStore(options.store)
    todo = [(r, k) for r, k in zip(recordings, keys) if k not in store]
    lost = {}
    if todo:
        client, cluster = _client(options)
        try:
            futures = client.map(check_recording, [r for r, _ in todo],
                                 [config_dict] * len(todo), [options.task] * len(todo),
                                 [k for _, k in todo], key=[f'recording-{k}' for _, k in todo],
                                 pure=False)
            which = {f.key: item for f, item in zip(futures, todo)}
            done = as_completed(futures, with_results=False)
            if options.progress:
                from tqdm import tqdm
                done = tqdm(done, total=len(futures), unit='recording', file=sys.stderr,
                            desc='fleet', disable=None)
            for fut in done:
                rec, key = which[fut.key]
                if fut.status == 'finished':
                    store.add(fut.result())
                else:
                    lost[key] = _lost(rec, key, fut.exception())
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    rows = [store.rows[k] if k in store else lost[k] for k in keys]
    alerts = detect_alerts(rows,
                           parameter_names(config, options.task.track))
    return FleetResult(rows, alerts, len(todo))
