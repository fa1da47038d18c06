"""Fleet throughput on Dask and the compile cache.

Recordings per minute of ``fleet`` for compare (verify) and for ``--track`` with 1 and 2
local workers, on a generated fleet (warm kernel cache, as a second run has), and the
speed-up of 2 workers over 1 (target >= 1.7x on this 2-core machine); peak memory per
worker. With ``--diagnose N``: ``fleet --diagnose`` on N recordings of 20 s at 1 kHz with one
worker, in recordings per hour per worker (target >= 100), on a first pass over them and on
a second (every composition they need already loaded in the worker). (A single ``simulate``, cold and
warm, and where its time goes: ``bench_simulate.py``.)

Usage: ``python benchmarks/bench_fleet.py [--rigs 4] [--days 10] [--diagnose N]``
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def throughput(fleet: Path, work: Path, workers: int, track: bool, diagnose: bool = False
               ) -> tuple:
    """(recordings per minute, peak RSS per worker [MB]) of one run with an empty store, on
    a local cluster started (and warmed up) before the clock starts, as a standing one is;
    with ``diagnose`` the rate of a first and of a second pass over the same recordings."""
    from distributed import Client, LocalCluster

    from pneumatic_servo.fleet import FleetOptions, TaskOptions, find_recordings
    from pneumatic_servo.fleet.cluster import WORKER_ENV, run_fleet
    from pneumatic_servo.model.config import ModelConfig
    from pneumatic_servo.synth.fleet import FRICTION_KEY
    recs = find_recordings([fleet])
    task = TaskOptions(track=('piston_seal_leakage',) if track else (),
                       free=(FRICTION_KEY,) if track else (), diagnose=diagnose)
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None, env=WORKER_ENV) as cluster:
        address = cluster.scheduler_address

        def options(name):
            return FleetOptions(work / f'{name}_{workers}_{track}.jsonl', address, None,
                                False, task)
        # every worker loads its kernels once, as the workers of a standing cluster have
        warm = recs[:workers if diagnose else 2 * workers]
        run_fleet(warm, ModelConfig.paper(), options('warm'))
        timed = recs[len(warm):] if diagnose else recs
        rates = []
        # diagnose: a second pass over the same recordings is the steady state, where every
        # composition a recording needs is already loaded in the worker
        for name in ('rows', 'steady') if diagnose else ('rows',):
            t0 = time.perf_counter()
            run_fleet(timed, ModelConfig.paper(), options(name))
            rates.append(len(timed) / ((time.perf_counter() - t0) / 60))
        with Client(address) as client:
            rss = client.run(lambda: __import__('resource').getrusage(
                __import__('resource').RUSAGE_SELF).ru_maxrss / 1024)
    return (rates if diagnose else rates[0]), max(rss.values())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--rigs', type=int, default=4)
    parser.add_argument('--days', type=int, default=10)
    parser.add_argument('--diagnose', type=int, default=0, metavar='N',
                        help='only fleet --diagnose on N recordings of 20 s at 1 kHz')
    args = parser.parse_args(argv)
    from pneumatic_servo.synth.fleet import FleetDesign, write_fleet
    print(f'load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores')
    if args.diagnose:
        return diagnose_throughput(args.diagnose)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
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


def diagnose_throughput(count: int) -> int:
    """``fleet --diagnose`` with one worker on ``count`` recordings of 20 s at 1 kHz (one more
    warms the worker up first)."""
    from pneumatic_servo.synth.fleet import FleetDesign, write_fleet
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        design = FleetDesign(rigs=count + 1, days=1, duration_s=20.0, rate_hz=1000.0,
                             broken=('none', -1))
        fleet = write_fleet(work / 'fleet', design)
        (first, steady), rss = throughput(fleet, work, 1, False, diagnose=True)
    print(f'fleet --diagnose, {count} recordings of 20 s at 1 kHz, 1 worker: '
          f'{60 * first:.0f} recordings/hour/worker on their first pass (compiling or loading '
          f'each composition a recording needs for the first time in the worker), '
          f'{60 * steady:.0f} on a second pass (steady state) (target >= 100); peak worker RSS '
          f'{rss:.0f} MB; load average {os.getloadavg()[0]:.1f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
