"""Speed and accuracy of the model's integrators on the paper's 10 s sine experiment.

Prints figures (this is not a test): simulated seconds per wall-clock second
for one trajectory on one core (offline adaptive integrator, the real-time
Stepper called once per 1 ms period, and ``simulate(method='fixed')``), for a
batch of parameter sets (aggregate, 1 and 2 threads), each one's accuracy
against a tight-tolerance reference, and the gain from numba with its
compile time (a subprocess runs with ``PNEUMATIC_SERVO_JIT=0``).

Targets (issue 2): >= 100x real time for one trajectory, >= 2000x aggregate
for a batch, angle within 0.01 deg and pressures within 100 Pa of the
reference.

Usage::

    python benchmarks/bench_model.py [--quick] [--batch N]
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pneumatic_servo import _jit  # noqa: E402
from pneumatic_servo.model import (  # noqa: E402
    Model,
    ModelConfig,
    Stepper,
    initial_state,
    simulate,
    simulate_batch,
)
from pneumatic_servo.model.circuits import gauge_supply_pa  # noqa: E402
from pneumatic_servo.synth.runs import sine_command  # noqa: E402

TARGET_ONE, TARGET_BATCH = 100.0, 2000.0  # [x real time]
TARGET_ANGLE_DEG, TARGET_PRESSURE_PA = 0.01, 100.0
REFERENCE = {'rtol': 1e-11, 'atol_scale': 1e-4}


def machine() -> str:
    """CPU model, cores and software versions of this machine."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path('/proc/cpuinfo').read_text().splitlines():
            if line.startswith('model name'):
                cpu = line.split(':', 1)[1].strip()
                break
    except OSError:
        pass
    try:
        import numba
        nb = f'numba {numba.__version__}'
    except ImportError:
        nb = 'no numba'
    return (f'{cpu}, {os.cpu_count()} logical cores, Python {platform.python_version()}, '
            f'numpy {np.__version__}, {nb}, {platform.system()} {platform.release()}')


def experiment(duration_s: float):
    """(t [s], command [V], supply [Pa abs]) of the paper's sine test at 1 kHz."""
    t = np.arange(int(round(duration_s * 1000)) + 1) * 1e-3
    return t, sine_command(t), gauge_supply_pa(0.6e6)


def load() -> str:
    """The machine's load averages: the figures are wall-clock times on shared cores."""
    return ' '.join(f'{v:.2f}' for v in os.getloadavg())


def best_of(fn, repeat: int) -> tuple[float, object]:
    """Shortest wall time [s] of ``repeat`` calls, and the last result."""
    best, out = float('inf'), None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def errors(states: np.ndarray, ref: np.ndarray) -> tuple[float, float]:
    """(max angle error [deg], max chamber-pressure error [Pa]) against the reference."""
    ang = float(np.degrees(np.abs(states[:, 0] - ref[:, 0]).max()))
    pres = float(np.abs(states[:, 2:4] - ref[:, 2:4]).max())
    return ang, pres


def run_stepper(model, t, u, ps, x0, method):
    plant = Stepper(model, period_s=1e-3, x0=x0, supply_pa=ps, method=method,
                    command_v=float(u[0]))
    out = np.empty((len(t), model.n_states))
    out[0] = x0
    for k in range(len(t) - 1):
        out[k + 1] = plant.step(u[k])
    return out


def single(model, duration_s: float, repeat: int) -> tuple[list, dict]:
    """Rows for one trajectory: offline, simulate fixed, Stepper fixed and adaptive."""
    t, u, ps = experiment(duration_s)
    x0 = initial_state(model, command_v=u[0], supply_pa=ps)
    t_ref, ref = best_of(lambda: simulate(model, t, u, ps, x0=x0, **REFERENCE).states, 1)
    cases = [
        ('offline adaptive DP5(4), rtol 1e-7', lambda: simulate(model, t, u, ps, x0=x0).states),
        ("simulate(method='fixed'), RK4 10 substeps/ms",
         lambda: simulate(model, t, u, ps, x0=x0, method='fixed').states),
        ("Stepper(method='fixed'), 1 call per 1 ms",
         lambda: run_stepper(model, t, u, ps, x0, 'fixed')),
        ("Stepper(method='adaptive'), 1 call per 1 ms",
         lambda: run_stepper(model, t, u, ps, x0, 'adaptive')),
    ]
    rows = []
    for name, fn in cases:
        fn()  # compile outside the timing
        wall, states = best_of(fn, repeat)
        rows.append((name, duration_s / wall) + errors(states, ref))
    rows.append(('reference (rtol 1e-11, atol x 1e-4)', duration_s / t_ref, 0.0, 0.0))
    # the reference's own error: against one 10x tighter still
    t_tight, tight = best_of(lambda: simulate(model, t, u, ps, x0=x0, rtol=1e-12,
                                              atol_scale=1e-5).states, 1)
    rows.append(('check: rtol 1e-12, atol x 1e-5, vs reference', duration_s / t_tight)
                + errors(tight, ref))
    return rows


def batch(model, n: int, duration_s: float, repeat: int, n_check: int) -> list:
    """Aggregate speed and accuracy of ``simulate_batch`` over ``n`` parameter sets."""
    import numba  # the batch kernel is parallel only when numba is present
    rng = np.random.default_rng(0)
    keys = ['stribeck_friction.static_friction_n', 'stribeck_friction.coulomb_friction_n',
            'wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k',
            'orifice_flow.area_conversion_coefficient', 'core.dead_volume_a_m3',
            'core.dead_volume_b_m3']
    configs = []
    for _ in range(n):
        cfg = model.config.copy()
        for key in keys:
            cfg.set(key, cfg.get(key) * rng.uniform(0.9, 1.1))
        if cfg.get(keys[0]) < cfg.get(keys[1]):
            cfg.set(keys[0], cfg.get(keys[1]))
        configs.append(cfg)
    pm = np.array([model.param_vector(c) for c in configs])
    t, u, ps = experiment(duration_s)
    x0 = initial_state(model, command_v=u[0], supply_pa=ps)
    refs = [simulate(model, t, u, ps, x0=x0, config=c, **REFERENCE).states
            for c in configs[:n_check]]
    rows = []
    for method in ('adaptive', 'fixed'):
        for threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
            numba.set_num_threads(threads)
            simulate_batch(model, t[:50], u[:50], ps, x0, pm[:2], method=method)  # compile
            wall, (xb, _, status) = best_of(
                lambda: simulate_batch(model, t, u, ps, x0, pm, method=method), repeat)
            errs = [errors(xb[i], refs[i]) for i in range(n_check)]
            rows.append((f'simulate_batch {method}, {n} sets, {threads} thread(s)',
                         n * duration_s / wall, max(e[0] for e in errs),
                         max(e[1] for e in errs), int(np.count_nonzero(status))))
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return rows


_CHILD = r'''
import json, time, numpy as np
from pneumatic_servo.model import Model, initial_state, simulate
from pneumatic_servo.model.circuits import gauge_supply_pa
from pneumatic_servo.synth.runs import sine_command
m = Model()
t = np.arange(int(round({dur} * 1000)) + 1) * 1e-3
u, ps = sine_command(t), gauge_supply_pa(0.6e6)
x0 = initial_state(m, command_v=u[0], supply_pa=ps)
first = time.perf_counter()
simulate(m, t, u, ps, x0=x0, method='{method}')
first = time.perf_counter() - first
again = time.perf_counter()
simulate(m, t, u, ps, x0=x0, method='{method}')
again = time.perf_counter() - again
print(json.dumps({{'first_s': first, 'again_s': again}}))
'''


def jit_gain(duration_s: float) -> list:
    """Rows comparing a fresh process with and without numba on a short run."""
    rows = []
    for method in ('adaptive', 'fixed'):
        res = {}
        for jit in ('1', '0'):
            env = dict(os.environ, PNEUMATIC_SERVO_JIT=jit, NUMBA_NUM_THREADS='1')
            proc = subprocess.run([sys.executable, '-c', _CHILD.format(dur=duration_s,
                                                                      method=method)],
                                  cwd=ROOT, env=env, capture_output=True, text=True,
                                  timeout=3600)
            if proc.returncode != 0:
                raise RuntimeError(proc.stderr.strip().splitlines()[-1])
            res[jit] = json.loads(proc.stdout.strip().splitlines()[-1])
        on, off = res['1'], res['0']
        rows.append((method, duration_s / on['again_s'], duration_s / off['again_s'],
                     off['again_s'] / on['again_s'], on['first_s'] - on['again_s']))
    return rows


def table(header, rows, fmt) -> str:
    lines = ['| ' + ' | '.join(header) + ' |', '|' + '|'.join('---' for _ in header) + '|']
    for r in rows:
        lines.append('| ' + ' | '.join(f(v) for f, v in zip(fmt, r)) + ' |')
    return '\n'.join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--quick', action='store_true', help='2 s records instead of 10 s')
    ap.add_argument('--batch', type=int, default=32, help='parameter sets in the batch')
    ap.add_argument('--repeat', type=int, default=3, help='timing repeats (best is kept)')
    args = ap.parse_args(argv)
    duration = 2.0 if args.quick else 10.0
    if not _jit.ENABLED:
        print('numba is not active (absent or PNEUMATIC_SERVO_JIT=0): figures are for the '
              'plain-Python model')
    print(f'Machine: {machine()}')
    print(f'load average {load()} (1, 5, 15 min) on {os.cpu_count()} cores\n')
    start = time.perf_counter()
    model = Model(ModelConfig.paper())
    t, u, ps = experiment(0.05)
    simulate(model, t, u, ps)
    print(f'Compile time of the paper model (first simulate, numba): '
          f'{time.perf_counter() - start:.1f} s\n')

    print(f'### One trajectory: the {duration:g} s sine experiment (5 ± 0.35 V, 2 Hz, 1 kHz), '
          'one core\n')
    rows = single(model, duration, args.repeat)
    ok = (lambda x_rt, a, p: 'yes' if (x_rt >= TARGET_ONE and a <= TARGET_ANGLE_DEG
                                       and p <= TARGET_PRESSURE_PA) else 'no')
    judged = len(rows) - 2  # the reference and its check are not candidates
    print(table(('integrator', 'x real time', 'max angle error [deg]',
                 'max pressure error [Pa]', 'meets targets'),
                [r + (ok(*r[1:]) if i < judged else '-',) for i, r in enumerate(rows)],
                (str, '{:.0f}'.format, '{:.2e}'.format, '{:.2e}'.format, str)))
    print(f'\nTargets: >= {TARGET_ONE:g}x real time, angle <= {TARGET_ANGLE_DEG} deg, '
          f'pressures <= {TARGET_PRESSURE_PA:g} Pa of the reference.\n')

    if _jit.ENABLED:
        print(f'### Batch of {args.batch} parameter sets (friction, h, C0, dead volumes '
              '+/- 10 %), aggregate\n')
        brow = batch(model, args.batch, duration, max(1, args.repeat - 1), n_check=4)
        okb = (lambda x_rt, a, p: 'yes' if (x_rt >= TARGET_BATCH and a <= TARGET_ANGLE_DEG
                                            and p <= TARGET_PRESSURE_PA) else 'no')
        print(table(('run', 'x real time (aggregate)', 'max angle error [deg]',
                     'max pressure error [Pa]', 'failed rows', 'meets targets'),
                    [r + (okb(*r[1:4]),) for r in brow],
                    (str, '{:.0f}'.format, '{:.2e}'.format, '{:.2e}'.format, str, str)))
        print(f'\nTarget: >= {TARGET_BATCH:g}x real time aggregate; errors of 4 rows against '
              f'their own references. Load average after the batch: {load()}\n')

        short = 0.2 if args.quick else 0.5
        print(f'### numba gain ({short:g} s of the sine experiment, fresh process each)\n')
        print(table(('integrator', 'x real time, numba', 'x real time, plain Python',
                     'speed-up', 'compile time [s]'), jit_gain(short),
                    (str, '{:.0f}'.format, '{:.2f}'.format, '{:.0f}'.format,
                     '{:.1f}'.format)))
    return 0


if __name__ == '__main__':
    sys.exit(main())
