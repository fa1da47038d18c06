"""Check one recording of a fleet: a pure function of its files, the model and the options.

This is what a Dask worker runs. It never raises for a bad recording: a truncated bag, a
missing topic, NaN or a bad number in a CSV becomes a :class:`~.row.Row` with ``status:
error`` and the one-line reason, so the rest of the fleet completes.
"""
from __future__ import annotations

import hashlib
import json
import time
from dataclasses import asdict, dataclass, field
from datetime import datetime, timezone
from pathlib import Path

from ..errors import PneumaticServoError
from .discover import Recording, rig_of
from .row import Row


@dataclass(frozen=True)
class TaskOptions:
    """What to run per recording.

    ``track``: effects added to the model and fitted per recording (with ``free`` base
    parameters, ``'owner.name'`` keys); ``diagnose``: the full diagnosis; ``limits``: the
    verify limits by channel [SI] (None: the paper's).
    """

    track: tuple[str, ...] = ()
    free: tuple[str, ...] = ()
    diagnose: bool = False
    mode: str = 'open_loop'
    limits: dict | None = field(default=None, hash=False)

    def digest(self) -> str:
        return json.dumps(asdict(self), sort_keys=True)


def content_key(recording: Recording, config: dict, options: TaskOptions) -> str:
    """Hash of the recording's bytes (every file of a bag, a CSV and its .meta.yaml), the
    model config and the options: a rerun skips exactly the rows this still matches."""
    h = hashlib.sha256()
    path = Path(recording.path)
    files = sorted(p for p in path.rglob('*') if p.is_file()) if path.is_dir() else \
        [p for p in (path, path.with_suffix('.meta.yaml')) if p.is_file()]
    for f in files:
        h.update(f.name.encode())
        with f.open('rb') as stream:
            h.update(hashlib.file_digest(stream, 'sha256').digest())
    h.update(json.dumps(config, sort_keys=True, default=str).encode())
    h.update(options.digest().encode())
    h.update(str(recording.rig).encode())
    return h.hexdigest()[:32]


def _start_time(meta: dict) -> str | None:
    ns = meta.get('start_time_ns')
    if ns is None:
        return None
    return datetime.fromtimestamp(int(ns) / 1e9, tz=timezone.utc).isoformat()


#: start points of a tracked parameter, as multiples of its default: a recording of a worn
#: rig can sit an order of magnitude from it, beyond a local minimum near the default
SPREAD = (0.25, 4.0, 16.0)


def _spread(cfg, keys: list[str]) -> list[dict]:
    """One start point per tracked parameter and multiple (the others at their values)."""
    return [{key: cfg.get(key) * f} for key in keys for f in SPREAD if cfg.get(key) != 0]


def _tracked(exp, config, options: TaskOptions) -> dict:
    """Fit the tracked effects (and free base parameters) to this recording alone."""
    from .. import effects as registry
    from ..analysis.compare import resolve_config
    from ..identification.output_error import fit_output_error
    cfg = resolve_config(config, list(options.track))
    free = [f'{name}.{k}' for name in options.track
            for k in registry.get(name).refit_keys(cfg.effects[name])]
    result = fit_output_error(cfg, [exp], free + list(options.free), mode='k_step',
                              starts=_spread(cfg, free), bracket=True)
    return {key: {'value': float(value), 'stderr': result.stderr.get(key)}
            for key, value in result.values.items()}


def diagnosis_text(found: dict) -> str:
    """A row's diagnosis in a few words: its status, and the verdict if one is named."""
    return found['status'] + ('' if found['verdict'] == 'none' else f': {found["verdict"]}')


def check_recording(recording: Recording, config: dict, options: TaskOptions,
                    key: str) -> Row:
    """One row of the fleet table (never raises for a bad recording)."""
    from ..analysis.compare import limits_for, verify
    from ..io import read_experiment
    from ..model.config import ModelConfig
    t0 = time.perf_counter()
    found = {'rig': recording.rig}
    try:
        cfg = ModelConfig.from_dict(config)
        exp = read_experiment(recording.path)
        found.update(rig=rig_of(recording, exp.metadata), start_time=_start_time(exp.metadata),
                     synthetic=bool(exp.metadata.get('synthetic', False)))
        limits = options.limits if options.limits is not None else limits_for()
        passed, rows, result = verify(exp, cfg, limits=limits, mode=options.mode)
        found.update(channels=result['channels'],
                     units={ch: result['units'][ch] for ch in result['channels']},
                     verify={'passed': passed, 'mode': options.mode, 'checks': rows})
        if options.track:
            found['params'] = _tracked(exp, cfg, options)
        if options.diagnose:
            from ..analysis.diagnosis import diagnose
            diagnosis = diagnose([exp], cfg).to_json()
            # the status too: verdict 'none' is both "the model fits" and "no name fits"
            found['diagnosis'] = {k: diagnosis[k] for k in ('status', 'verdict', 'reason')}
            found['verdict'] = diagnosis['verdict']
    except PneumaticServoError as exc:
        found.update(status='error', error=' '.join(str(exc).split()))
    except (OSError, UnicodeError, ValueError, RuntimeError) as exc:
        found.update(status='error',
                     error=f'{type(exc).__name__}: {" ".join(str(exc).split())}')
    if found['rig'] is None:  # the recording could not be read: no custom data to ask
        found['rig'] = rig_of(recording, {})
    return Row(recording.path, key=key, seconds=round(time.perf_counter() - t0, 3), **found)
