"""Fleet throughput on Dask, the compile cache, and where a simulate's time goes.

1. Recordings per minute of ``fleet`` for compare (verify) and for ``--track`` with 1 and
   2 local workers, on a generated fleet (warm kernel cache, as a second run has), and the
   speed-up of 2 workers over 1 (target >= 1.7x on this 2-core machine); peak memory per
   worker.
2. The compile share: ``pneumatic-servo simulate`` of a 10 s, 1 kHz bag in a fresh process
   with an empty kernel cache, then again with it warm (target >= 5x real time end to end).
3. Where a simulate's time goes: start-up (imports), bag read, simulation, bag write.

Usage: ``python benchmarks/bench_fleet.py [--rigs 4] [--days 10]``
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
BIN = Path(sys.executable).parent


def throughput(fleet: Path, work: Path, workers: int, track: bool) -> tuple[float, float]:
    """(recordings per minute, peak RSS per worker [MB]) of one run with an empty store, on
    a local cluster started (and warmed up) before the clock starts, as a standing one is."""
    from distributed import Client, LocalCluster

    from pneumatic_servo.fleet import FleetOptions, TaskOptions, find_recordings
    from pneumatic_servo.fleet.run import WORKER_ENV, run_fleet
    from pneumatic_servo.model.config import ModelConfig
    from pneumatic_servo.synth.fleet import FRICTION_KEY
    recs = find_recordings([fleet])
    task = TaskOptions(track=('piston_seal_leakage',) if track else (),
                       free=(FRICTION_KEY,) if track else ())
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None, env=WORKER_ENV) as cluster:
        address = cluster.scheduler_address

        def options(name):
            return FleetOptions(work / f'{name}_{workers}_{track}.jsonl', address, None,
                                False, task)
        # every worker loads its kernels once, as the workers of a standing cluster have
        run_fleet(recs[:2 * workers], ModelConfig.paper(), options('warm'))
        t0 = time.perf_counter()
        run_fleet(recs, ModelConfig.paper(), options('rows'))
        minutes = (time.perf_counter() - t0) / 60
        with Client(address) as client:
            rss = client.run(lambda: __import__('resource').getrusage(
                __import__('resource').RUSAGE_SELF).ru_maxrss / 1024)
    return len(recs) / minutes, max(rss.values())


def timed(cmd: list[str], env: dict) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, capture_output=True)
    return time.perf_counter() - t0


def simulate_figures(work: Path) -> None:
    """Cold and warm end-to-end simulate of a 10 s, 1 kHz bag, and the phases of a warm one."""
    bag = ROOT / 'bags' / 'unlisted_effect_demo'
    env = {**os.environ, 'PNEUMATIC_SERVO_CACHE': str(work / 'kernel_cache')}
    cmd = [str(BIN / 'pneumatic-servo'), 'simulate', str(bag), '--out']
    cold = timed(cmd + [str(work / 'sim_cold')], env)
    warm = min(timed(cmd + [str(work / f'sim_warm{i}')], env) for i in range(3))
    print(f'simulate, 10 s at 1 kHz, end to end: first run {cold:.2f} s (compiling), '
          f'then {warm:.2f} s = {10.0 / warm:.1f}x real time (target >= 5x); '
          f'compile share of the first run {100 * (cold - warm) / cold:.0f} %')
    probe = ('import time; t0 = time.perf_counter()\n'
             'from pneumatic_servo.io import read_experiment, write_experiment\n'
             'from pneumatic_servo.analysis.compare import model_for, resolve_config\n'
             'from pneumatic_servo.prediction import config_for, predict_checked\n'
             't1 = time.perf_counter()\n'
             f'exp = read_experiment({str(bag)!r}); t2 = time.perf_counter()\n'
             'cfg = config_for(exp, resolve_config())\n'
             'pred = predict_checked(model_for(cfg), exp, cfg); t3 = time.perf_counter()\n'
             f'write_experiment(exp, {str(work / "sim_io")!r}, "mcap")\n'
             't4 = time.perf_counter()\n'
             'print(f"{t1 - t0:.2f} {t2 - t1:.2f} {t3 - t2:.2f} {t4 - t3:.2f}")')
    out = subprocess.run([sys.executable, '-c', probe], env=env, capture_output=True,
                         text=True, check=True).stdout.split()
    print(f'  phases of a warm run: imports {out[0]} s, bag read {out[1]} s (rosbags CDR '
          f'deserialisation of every message), simulation {out[2]} s (kernels loaded from '
          f'the cache), bag write {out[3]} s')


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--rigs', type=int, default=4)
    parser.add_argument('--days', type=int, default=10)
    args = parser.parse_args(argv)
    from pneumatic_servo.synth.fleet import FleetDesign, write_fleet
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        simulate_figures(work)
        fleet = write_fleet(work / 'fleet', FleetDesign(rigs=args.rigs, days=args.days,
                                                        broken=('none', -1)))
        n = args.rigs * args.days
        for track in (False, True):
            rates = {}
            for workers in (1, 2):
                rates[workers], rss = throughput(fleet, work, workers, track)
                print(f'fleet {"--track" if track else "compare"}, {n} recordings of 3 s, '
                      f'{workers} worker(s): {rates[workers]:.1f} recordings/min; peak '
                      f'worker RSS {rss:.0f} MB')
            print(f'  2 workers / 1 worker: {rates[2] / rates[1]:.2f}x (target >= 1.7x)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
