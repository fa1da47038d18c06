"""The integrators, compiled once for every composition: the right-hand side is an argument.

Each composition of components has its own right-hand side ``rhs(t, x, u, ps, P, circuit, c,
dx)`` (:mod:`.kernel_cache`). The integrators take it as their first argument, typed by its
signature alone (numba's first-class function type), so numba compiles them once per
machine and every composition calls its own right-hand side through them. Compiled with the
right-hand side inside, as they were until 2026-11-27, each new composition compiled them
again: about 5 s of the 7 s a composition took on a fresh machine (a 2-core AMD EPYC). The
call through the function's address gives the same trajectories and about the same speed
(``benchmarks/bench_model.py``: one trajectory 368x real time against 386x, a batch of 32
on two threads 703-787x against 688x; with its rows in Python threads, 1,043x, idle).

* ``adaptive_interval``: Dormand-Prince 5(4) with error control, the accurate offline
  integrator. Discontinuities are handled by step rejection.
* ``fixed_interval``: classical RK4 with a fixed number of substeps, the real-time
  stepper (constant cost per control period).
* ``run`` / ``run_batch``: a whole simulation over sample times with zero-order-hold
  inputs, one parameter vector or many (each row over its own number of samples).

Every array is C-contiguous (the signatures say so): the callers make them so.
"""
import math
from concurrent.futures import ThreadPoolExecutor, wait

import numpy as np

from pneumatic_servo import _jit
from pneumatic_servo._jit import njit
from pneumatic_servo.effects.layout import K_STROKE, N_CONTEXT, OUTPUTS, SERVO, THETA
from pneumatic_servo.model.integrators import (
    _A21,
    _A31,
    _A32,
    _A41,
    _A42,
    _A43,
    _A51,
    _A52,
    _A53,
    _A54,
    _A61,
    _A62,
    _A63,
    _A64,
    _A65,
    _B1,
    _B3,
    _B4,
    _B5,
    _B6,
    _E1,
    _E3,
    _E4,
    _E5,
    _E6,
    _E7,
    MAX_STEPS_OFFLINE,
    NON_FINITE,
    OK,
    STEP_CAP,
    STEP_UNDERFLOW,
    STOP_TOL,
    project,
)


def _signatures() -> dict:
    """The numba signature of each integrator, or nothing when compilation is off: the first
    argument is any right-hand side, typed by its signature alone."""
    if not _jit.ENABLED:
        return {}
    from numba import types as nt
    f8, i8, b1, none = nt.float64, nt.int64, nt.boolean, nt.none
    vec, mat, cube = f8[::1], f8[:, ::1], f8[:, :, ::1]
    rhs = none(f8, vec, f8, f8, vec, i8, vec, vec)
    fn = nt.FunctionType(rhs)
    run = (fn, vec, vec, vec, vec, vec, i8, b1, f8, vec, i8, mat, mat)
    return {
        'fixed_interval': i8(fn, f8, vec, f8, f8, vec, i8, f8, i8, vec, mat),
        'adaptive_interval': nt.Tuple((i8, f8))(fn, f8, vec, f8, f8, vec, i8, f8, f8, f8, vec,
                                                vec, mat, i8),
        'record': none(fn, f8, vec, f8, f8, vec, i8, vec, vec, mat, mat, i8),
        'run_to': nt.Tuple((i8, i8))(*run, i8),
        'run_batch': none(fn, mat, vec, mat, mat, mat, i8, b1, f8, vec, i8, cube, cube,
                          i8[::1], i8[::1]),
    }


SIGNATURES = _signatures()


@njit(cache=True, allocates=False, signature=SIGNATURES.get('fixed_interval'))
def fixed_interval(rhs, t, x, u, ps, P, circuit, h, n_sub, c, w):
    """Advance ``x`` in place over [t, t+h] with ``n_sub`` RK4 substeps."""
    dt = h / n_sub
    k1, k2, k3, k4, xt = w[0], w[1], w[2], w[3], w[4]
    for _ in range(n_sub):
        rhs(t, x, u, ps, P, circuit, c, k1)
        for i in range(len(x)):
            xt[i] = x[i] + 0.5 * dt * k1[i]
        rhs(t + 0.5 * dt, xt, u, ps, P, circuit, c, k2)
        for i in range(len(x)):
            xt[i] = x[i] + 0.5 * dt * k2[i]
        rhs(t + 0.5 * dt, xt, u, ps, P, circuit, c, k3)
        for i in range(len(x)):
            xt[i] = x[i] + dt * k3[i]
        rhs(t + dt, xt, u, ps, P, circuit, c, k4)
        for i in range(len(x)):
            x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        project(x, P, circuit)
        t += dt
    for i in range(len(x)):
        if not math.isfinite(x[i]):
            return NON_FINITE
    return OK


@njit(cache=True, allocates=False, signature=SIGNATURES.get('adaptive_interval'))
def adaptive_interval(rhs, t, x, u, ps, P, circuit, h, dt, rtol, atol, c, w, max_steps):
    """Advance ``x`` in place over [t, t+h]; returns (status, next step guess).

    ``w[0]`` must hold rhs(t, x) on entry (the caller has it: it records
    the outputs at every sample with that same evaluation). A step
    that would carry the shaft through an end stop is shortened (secant
    on the step size) until it lands within ``STOP_TOL`` of the stop, so
    the impact happens at the right time.
    """
    k1, k2, k3, k4, k5, k6, k7, xt, xn = w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7], w[8]
    t_end = t + h
    n_steps = 0
    while t < t_end - 1e-15 * max(1.0, abs(t_end)):
        last = dt >= t_end - t
        hs = t_end - t if last else dt
        for i in range(len(x)):
            xt[i] = x[i] + hs * _A21 * k1[i]
        rhs(t + hs / 5, xt, u, ps, P, circuit, c, k2)
        for i in range(len(x)):
            xt[i] = x[i] + hs * (_A31 * k1[i] + _A32 * k2[i])
        rhs(t + 3 * hs / 10, xt, u, ps, P, circuit, c, k3)
        for i in range(len(x)):
            xt[i] = x[i] + hs * (_A41 * k1[i] + _A42 * k2[i] + _A43 * k3[i])
        rhs(t + 4 * hs / 5, xt, u, ps, P, circuit, c, k4)
        for i in range(len(x)):
            xt[i] = x[i] + hs * (_A51 * k1[i] + _A52 * k2[i] + _A53 * k3[i] + _A54 * k4[i])
        rhs(t + 8 * hs / 9, xt, u, ps, P, circuit, c, k5)
        for i in range(len(x)):
            xt[i] = x[i] + hs * (_A61 * k1[i] + _A62 * k2[i] + _A63 * k3[i] + _A64 * k4[i]
                                 + _A65 * k5[i])
        rhs(t + hs, xt, u, ps, P, circuit, c, k6)
        for i in range(len(x)):
            xn[i] = x[i] + hs * (_B1 * k1[i] + _B3 * k3[i] + _B4 * k4[i] + _B5 * k5[i]
                                 + _B6 * k6[i])
        rhs(t + hs, xn, u, ps, P, circuit, c, k7)
        err = 0.0
        for i in range(len(x)):
            e = hs * (_E1 * k1[i] + _E3 * k3[i] + _E4 * k4[i] + _E5 * k5[i] + _E6 * k6[i]
                      + _E7 * k7[i])
            sc = atol[i] + rtol * max(abs(x[i]), abs(xn[i]))
            err += (e / sc) ** 2
        err = math.sqrt(err / len(x))
        if not math.isfinite(err):
            err = 1e10
        if err <= 1.0 and circuit == SERVO and hs > 1e-9:
            bound = -1.0
            if x[THETA] > 0.0 and xn[THETA] < -STOP_TOL:
                bound = 0.0
            elif x[THETA] < P[K_STROKE] and xn[THETA] > P[K_STROKE] + STOP_TOL:
                bound = P[K_STROKE]
            if bound >= 0.0:
                frac = (x[THETA] - bound) / (x[THETA] - xn[THETA])
                dt = hs * min(max(frac, 0.05), 0.95)
                n_steps += 1
                continue
        if err <= 1.0:
            t = t_end if last else t + hs
            for i in range(len(x)):
                x[i] = xn[i]
            if last:
                project(x, P, circuit)
            elif project(x, P, circuit):
                rhs(t, x, u, ps, P, circuit, c, k1)
            else:  # first same as last: k7 is the derivative at the new point
                for i in range(len(x)):
                    k1[i] = k7[i]
            grown = hs * (5.0 if err == 0.0 else min(5.0, 0.9 * err ** -0.2))
            dt = max(dt, grown) if last else grown
        else:
            dt = hs * max(0.2, 0.9 * err ** -0.25)
        n_steps += 1
        if dt < 1e-12:
            return STEP_UNDERFLOW, dt
        if n_steps > max_steps:
            return STEP_CAP, dt
    for i in range(len(x)):
        if not math.isfinite(x[i]):
            return NON_FINITE, dt
    return OK, dt


@njit(cache=True, allocates=False, signature=SIGNATURES.get('record'))
def record(rhs, t, x, u, ps, P, circuit, c, dx, X, Y, k):
    """Store state and outputs at sample k; leaves rhs(t, x) in ``dx``."""
    rhs(t, x, u, ps, P, circuit, c, dx)
    for i in range(len(x)):
        X[k, i] = x[i]
    for j in range(len(OUTPUTS)):
        Y[k, j] = c[OUTPUTS[j]]


@njit(cache=True, signature=SIGNATURES.get('run_to'))
def run_to(rhs, x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub, X, Y, n):
    """``run`` over the first ``n`` samples of ``t`` only (the rest of X, Y untouched)."""
    c = np.zeros(N_CONTEXT)
    w = np.zeros((9, len(x0)))
    x = x0.copy()
    project(x, P, circuit)
    record(rhs, t[0], x, u[0], ps[0], P, circuit, c, w[0], X, Y, 0)
    dt = 1e-5
    for k in range(n - 1):
        h = t[k + 1] - t[k]
        if adaptive:
            status, dt = adaptive_interval(rhs, t[k], x, u[k], ps[k], P, circuit, h, dt, rtol,
                                           atol, c, w, MAX_STEPS_OFFLINE)
            dt = min(dt, 1.0)
        else:
            status = fixed_interval(rhs, t[k], x, u[k], ps[k], P, circuit, h, n_sub, c, w)
        if status != OK:
            return status, k
        record(rhs, t[k + 1], x, u[k + 1], ps[k + 1], P, circuit, c, w[0], X, Y, k + 1)
    return OK, n - 1


def run(rhs, x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub, X, Y):
    """Simulate over the sample times ``t`` with ZOH inputs; fills X, Y; returns status.
    Not compiled itself: ``run_to`` over every sample (a compiled copy cost 0.8 s on a fresh
    machine, for nothing)."""
    return run_to(rhs, x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub, X, Y, len(t))


@njit(cache=True, nogil=True, signature=SIGNATURES.get('run_batch'))
def run_batch(rhs, X0, t, U, PS, PM, circuit, adaptive, rtol, atol, n_sub, XB, YB, status, N):
    """``run`` for each row of the parameter matrix ``PM`` (and of X0, U, PS), over the
    first ``N[m]`` samples of row m (windows of unequal length share one array). It releases
    the GIL: :func:`run_batch_threaded` runs blocks of rows in threads."""
    for m in range(PM.shape[0]):
        s, _ = run_to(rhs, X0[m], t, U[m], PS[m], PM[m], circuit, adaptive, rtol, atol, n_sub,
                      XB[m], YB[m], N[m])
        status[m] = s


_POOL: ThreadPoolExecutor | None = None


def _threads() -> int:
    """How many threads a batch may use: numba's thread count (one per core, or what
    ``NUMBA_NUM_THREADS`` or ``numba.set_num_threads`` say: one in a fleet worker)."""
    if not _jit.ENABLED:
        return 1  # plain Python holds the GIL: threads would only take turns
    import numba
    return numba.get_num_threads()


def run_batch_threaded(rhs, X0, t, U, PS, PM, circuit, adaptive, rtol, atol, n_sub, XB, YB,
                       status, N):
    """``run_batch`` over equal blocks of rows, one per thread (:func:`_threads`), the first
    in this thread; each block writes only its own rows. numba's own parallel loop
    (``prange``) did the same, but cost 3.4 s to compile on a fresh machine against 0.9 s
    for the plain loop, and its idle threads spin: a fresh diagnosis took 60 s of CPU in
    its main process with it and 45 s without (a 2-core AMD EPYC), time the compile helper
    of :mod:`.compile_ahead` needs."""
    global _POOL
    rows = PM.shape[0]
    n = max(1, min(_threads(), rows))
    edges = [rows * i // n for i in range(n + 1)]

    def block(a, b):
        run_batch(rhs, X0[a:b], t, U[a:b], PS[a:b], PM[a:b], circuit, adaptive, rtol, atol,
                  n_sub, XB[a:b], YB[a:b], status[a:b], N[a:b])

    if n == 1:
        return block(0, rows)
    if _POOL is None:
        _POOL = ThreadPoolExecutor(thread_name_prefix='pneumatic_servo_batch')
    others = [_POOL.submit(block, a, b) for a, b in zip(edges[1:-1], edges[2:])]
    try:
        block(edges[0], edges[1])
    finally:
        wait(others)  # no thread still writes when this returns or raises
    for future in others:
        future.result()  # a block that raised raises here
