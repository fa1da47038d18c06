"""``pneumatic-servo simulate`` of a 10 s, 1 kHz bag, the whole process, and where its time goes.

1. The first run in a fresh process with an empty kernel cache (compiling), then warm runs
   (the kernels loaded from the cache, as every run after the first on a machine): wall
   time of the whole ``pneumatic-servo simulate`` process and its real-time factor
   (target >= 10x: <= 1.0 s for 10 s of recording).
2. The phases of a warm run in one process: start-up (the imports the verb makes), bag read,
   simulation (kernels loaded from the cache, numba's start included), bag write.

The machine is shared: the load average is printed with the figures, the best of several
warm runs is the figure (the median beside it), and the process's CPU time (user + system)
says what it takes where it has a core to itself.

Usage: ``python benchmarks/bench_simulate.py [--bag DIR] [--runs 5]``
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
BAG = ROOT / 'bags' / 'unlisted_effect_demo'  # 10 s at 1 kHz, MCAP, five topics
TARGET = 10.0

PHASES = '''
import sys, time
t0 = time.perf_counter()
from pneumatic_servo.cli import build_parser
build_parser('simulate')
from pneumatic_servo.analysis.compare import resolve_config
from pneumatic_servo.experiment import Experiment
from pneumatic_servo.io import read_experiment, write_experiment
from pneumatic_servo.model.assembly import Model
from pneumatic_servo.prediction import config_for, predict_checked
t1 = time.perf_counter()
exp = read_experiment(sys.argv[1])
t2 = time.perf_counter()
cfg = config_for(exp, resolve_config(None, None))
pred = predict_checked(Model(cfg), exp, cfg)
t3 = time.perf_counter()
signals = {k: pred.get(k, v) for k, v in exp.signals.items()}
write_experiment(Experiment(exp.t, signals, exp.circuit, 'sim'), sys.argv[2],
                 exp.metadata['storage'], {'synthetic': True})
t4 = time.perf_counter()
print(f'{t1 - t0:.3f} {t2 - t1:.3f} {t3 - t2:.3f} {t4 - t3:.3f}')
'''


def load() -> str:
    return ' '.join(f'{x:.2f}' for x in os.getloadavg())


def timed(cmd: list[str], env: dict) -> tuple[float, float]:
    """(wall time, CPU time: user + system) [s] of one run of ``cmd``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, capture_output=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def simulate_figures(work: Path, bag: Path = BAG, runs: int = 5) -> float:
    """Print the cold and warm figures and the phases; return the best warm real-time
    factor."""
    env = {**os.environ, 'PNEUMATIC_SERVO_CACHE': str(work / 'kernel_cache')}
    cmd = [str(BIN / 'pneumatic-servo'), 'simulate', str(bag), '--out']
    print(f'load average before: {load()}')
    cold = timed(cmd + [str(work / 'sim_cold')], env)[0]
    runs_ = [timed(cmd + [str(work / f'sim_warm{i}')], env) for i in range(runs)]
    warm = [w for w, _ in runs_]
    best, median, cpu = min(warm), statistics.median(warm), min(c for _, c in runs_)
    print(f'simulate, 10 s at 1 kHz, whole process: first run {cold:.2f} s (compiling), then '
          f'{best:.2f} s best, {median:.2f} s median of {runs} (load average now {load()}); '
          f'CPU time {cpu:.2f} s (what an idle core takes: {10.0 / cpu:.1f}x)')
    print(f'warm simulate 10 s 1 kHz bag: {10.0 / best:.1f}x real time (target >= '
          f'{TARGET:.0f}x); median {10.0 / median:.1f}x')
    phases = []
    for i in range(3):
        out = subprocess.run([sys.executable, '-c', PHASES, str(bag), str(work / f'ph{i}')],
                             env=env, capture_output=True, text=True, check=True)
        phases.append([float(x) for x in out.stdout.split()])
    imports, read, sim, write = (min(p[i] for p in phases) for i in range(4))
    print(f'  phases of a warm run (best of 3): imports {imports:.2f} s, bag read {read:.2f} s, '
          f'simulation {sim:.2f} s (kernels from the cache, numba starting), bag write '
          f'{write:.2f} s')
    return 10.0 / best


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--bag', type=Path, default=BAG)
    parser.add_argument('--runs', type=int, default=5)
    args, _ = parser.parse_known_args(argv)  # ./run.sh bench passes every bench the same
    with tempfile.TemporaryDirectory() as tmp:
        simulate_figures(Path(tmp), args.bag, args.runs)
    return 0


if __name__ == '__main__':
    sys.exit(main())
