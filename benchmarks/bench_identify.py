"""Benchmark: identification from the full bag set, and memory while reading a long bag.

1. Time to read every record in ``bags/`` and run the paper's identification
   (C1, h, friction) on them.
2. Memory while reading a 10-minute, 1 kHz bag (generated in a temporary
   directory, sqlite3 and MCAP): peak Python heap (tracemalloc) and peak
   RSS of a fresh process per read, for all signals and for two signals, and
   for a 1-minute bag. Reading streams messages, so memory follows the
   signals kept (samples x signals x 16 bytes), not the bag's size on disk.

Usage: ``python benchmarks/bench_identify.py [--minutes 10] [--keep DIR]``
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

READ_CHILD = r'''
import json, sys, time, tracemalloc
from pneumatic_servo.io import read_experiment

def status(key):
    # VmHWM: peak resident set of this process (reset by exec, unlike ru_maxrss)
    for line in open('/proc/self/status'):
        if line.startswith(key):
            return int(line.split()[1]) / 1e3
    return float('nan')

path, signals, trace = sys.argv[1], json.loads(sys.argv[2]), sys.argv[3] == 'trace'
before = status('VmRSS')
if trace:
    tracemalloc.start()
t0 = time.perf_counter()
exp = read_experiment(path, signals=signals)
dt = time.perf_counter() - t0
peak = tracemalloc.get_traced_memory()[1] if trace else 0
kept = sum(v.nbytes for v in exp.signals.values()) + exp.t.nbytes
print(json.dumps({'seconds': dt, 'samples': len(exp.t), 'signals': len(exp.signals),
                  'kept_mb': kept / 1e6, 'traced_peak_mb': peak / 1e6,
                  'rss_peak_mb': status('VmHWM'), 'rss_before_read_mb': before}))
'''


def bench_identify() -> dict:
    from pneumatic_servo.identification.identify import identify
    from pneumatic_servo.io import read_experiment
    from pneumatic_servo.model import ModelConfig
    bags = ROOT / 'bags'
    paths = sorted(p for p in bags.iterdir() if p.is_dir() or p.suffix == '.csv')
    t0 = time.perf_counter()
    exps = [read_experiment(p) for p in paths]
    t_read = time.perf_counter() - t0
    t0 = time.perf_counter()
    result = identify(exps, ModelConfig.paper())
    t_ident = time.perf_counter() - t0
    truth = ModelConfig.load(bags / 'truth.yaml')
    errors = {}
    for key in ('wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k',
                'stribeck_friction.static_friction_n', 'stribeck_friction.coulomb_friction_n',
                'stribeck_friction.stribeck_velocity_rad_s',
                'stribeck_friction.viscous_friction_n_s_per_rad'):
        errors[key.split('.')[-1]] = result.config.get(key) / truth.get(key) - 1
    size = sum(f.stat().st_size for f in bags.rglob('*') if f.is_file())
    return {'records': len(paths), 'library_mb': size / 1e6, 'read_s': t_read,
            'identify_s': t_ident, 'errors': errors}


def make_long_bag(path: Path, minutes: float, storage: str) -> dict:
    """A ``minutes`` long 1 kHz servo bag with six signals (analytic, labelled synthetic)."""
    from pneumatic_servo.experiment import Experiment
    from pneumatic_servo.io import write_experiment_bag
    n = int(minutes * 60_000) + 1
    t = np.arange(n) * 1e-3
    rng = np.random.default_rng(0)
    sig = {'command_v': 5.0 + 0.35 * np.sin(2 * np.pi * 2 * t),
           'supply_pa': 701325.0 + rng.normal(0, 600, n),
           'angle_rad': 1.6 + 0.2 * np.sin(2 * np.pi * 2 * t - 1.2),
           'velocity_rad_s': 0.8 * np.pi * np.cos(2 * np.pi * 2 * t - 1.2),
           'p_a_pa': 5.9e5 + 1e4 * np.sin(2 * np.pi * 2 * t) + rng.normal(0, 600, n),
           'p_b_pa': 5.9e5 - 1e4 * np.sin(2 * np.pi * 2 * t) + rng.normal(0, 600, n)}
    exp = Experiment(t, sig, 'servo', path.name)
    t0 = time.perf_counter()
    write_experiment_bag(exp, path, storage, {'synthetic': True,
                                              'generator': 'benchmarks/bench_identify.py'},
                         compress=storage == 'mcap')
    size = sum(f.stat().st_size for f in path.iterdir())
    return {'samples': n, 'messages': n * 5, 'write_s': time.perf_counter() - t0,
            'bag_mb': size / 1e6}


def read_in_child(path: Path, signals) -> dict:
    """Read in fresh processes: once for time and peak RSS, once under tracemalloc."""
    runs = []
    for mode in ('plain', 'trace'):
        out = subprocess.run([sys.executable, '-c', READ_CHILD, str(path), json.dumps(signals),
                              mode], capture_output=True, text=True, check=True, cwd=ROOT)
        runs.append(json.loads(out.stdout))
    plain, traced = runs
    plain['traced_peak_mb'] = traced['traced_peak_mb']
    return plain


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--minutes', type=float, default=10.0)
    parser.add_argument('--keep', help='keep the generated bags in this directory')
    parser.add_argument('--storages', default='sqlite3,mcap')
    args = parser.parse_args(argv)

    ident = bench_identify()
    print('== identification from the bag set')
    print(f'  {ident["records"]} records ({ident["library_mb"]:.1f} MB): read '
          f'{ident["read_s"]:.2f} s, identify {ident["identify_s"]:.2f} s, total '
          f'{ident["read_s"] + ident["identify_s"]:.2f} s')
    print('  errors vs truth: ' + ', '.join(f'{k} {v:+.1%}' for k, v in ident['errors'].items()))

    tmp = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix='bench_bags_'))
    tmp.mkdir(parents=True, exist_ok=True)
    all_signals = None
    two = ['command_v', 'angle_rad']
    print(f'== memory while reading a {args.minutes:g}-minute 1 kHz bag (fresh process per read)')
    print(f'  {"storage":<8} {"length":>7} {"bag MB":>8} {"signals":>8} {"read s":>7} '
          f'{"kept MB":>8} {"heap peak MB":>13} {"RSS peak MB":>12} {"RSS at start":>13}')
    for storage in args.storages.split(','):
        for minutes in (1.0, args.minutes):
            path = tmp / f'long_{storage}_{minutes:g}min'
            if not path.exists():
                info = make_long_bag(path, minutes, storage)
                print(f'  (wrote {path.name}: {info["messages"]} messages, '
                      f'{info["bag_mb"]:.0f} MB in {info["write_s"]:.0f} s)')
            size = sum(f.stat().st_size for f in path.iterdir()) / 1e6
            for signals in (all_signals, two):
                r = read_in_child(path, signals)
                print(f'  {storage:<8} {minutes:>5g} m {size:>8.0f} {r["signals"]:>8} '
                      f'{r["seconds"]:>7.1f} {r["kept_mb"]:>8.1f} {r["traced_peak_mb"]:>13.1f} '
                      f'{r["rss_peak_mb"]:>12.0f} {r["rss_before_read_mb"]:>13.0f}')
    if not args.keep:
        import shutil
        shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
