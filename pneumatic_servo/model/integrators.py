"""Compiled time integration of an assembled right-hand side.

``make_integrators(rhs)`` returns kernels that advance the state over one
zero-order-hold input interval:

* ``adaptive_interval``: Dormand-Prince 5(4) with error control, the
  accurate offline integrator. Discontinuities (choked/subsonic switch,
  stick/slip, valve branch at x_v = 0, end stops) are handled by step
  rejection: the controller shrinks the step until the local error is met.
* ``fixed_interval``: classical RK4 with a fixed number of substeps, the
  real-time stepper (constant cost per control period).

After every accepted step the state is projected onto the physical set:
the shaft is clipped to [0, stroke] with an inelastic stop, pressures and
temperatures are kept positive.
"""
import math

import numpy as np

from .._jit import njit, prange
from ..effects.layout import K_STROKE, N_CONTEXT, OMEGA, OUTPUTS, P_A, P_B, SERVO, T_A, T_B, THETA

# Dormand-Prince 5(4) tableau
_A21 = 1 / 5
_A31, _A32 = 3 / 40, 9 / 40
_A41, _A42, _A43 = 44 / 45, -56 / 15, 32 / 9
_A51, _A52, _A53, _A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
_A61, _A62, _A63, _A64, _A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
_B1, _B3, _B4, _B5, _B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
_E1, _E3, _E4, _E5, _E6, _E7 = (71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200,
                                22 / 525, -1 / 40)

OK, NON_FINITE, STEP_UNDERFLOW, STEP_CAP = 0, 1, 2, 3
STOP_TOL = 1e-7  # [rad] how far a step may carry the shaft past an end stop
MAX_STEPS_OFFLINE = 1_000_000  # per sample interval


@njit(cache=True)
def project(x, P, circuit):
    """Keep the state physical after a step: end stops, positive p and T.

    Returns True if the state was changed.
    """
    before = x[THETA] + x[OMEGA] + x[P_A] + x[P_B] + x[T_A] + x[T_B]
    if circuit == SERVO:
        if x[THETA] <= 0.0:
            x[THETA] = 0.0
            x[OMEGA] = max(x[OMEGA], 0.0)
        elif x[THETA] >= P[K_STROKE]:
            x[THETA] = P[K_STROKE]
            x[OMEGA] = min(x[OMEGA], 0.0)
    else:
        x[OMEGA] = 0.0
    x[P_A] = max(x[P_A], 10.0)
    x[P_B] = max(x[P_B], 10.0)
    x[T_A] = max(x[T_A], 10.0)
    x[T_B] = max(x[T_B], 10.0)
    return x[THETA] + x[OMEGA] + x[P_A] + x[P_B] + x[T_A] + x[T_B] != before


def make_integrators(rhs, n_state):
    """Compile integrators around ``rhs(t, x, u, ps, P, circuit, c, dx)``."""

    @njit
    def fixed_interval(t, x, u, ps, P, circuit, h, n_sub, c, w):
        """Advance ``x`` in place over [t, t+h] with ``n_sub`` RK4 substeps."""
        dt = h / n_sub
        k1, k2, k3, k4, xt = w[0], w[1], w[2], w[3], w[4]
        for _ in range(n_sub):
            rhs(t, x, u, ps, P, circuit, c, k1)
            for i in range(n_state):
                xt[i] = x[i] + 0.5 * dt * k1[i]
            rhs(t + 0.5 * dt, xt, u, ps, P, circuit, c, k2)
            for i in range(n_state):
                xt[i] = x[i] + 0.5 * dt * k2[i]
            rhs(t + 0.5 * dt, xt, u, ps, P, circuit, c, k3)
            for i in range(n_state):
                xt[i] = x[i] + dt * k3[i]
            rhs(t + dt, xt, u, ps, P, circuit, c, k4)
            for i in range(n_state):
                x[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            project(x, P, circuit)
            t += dt
        for i in range(n_state):
            if not math.isfinite(x[i]):
                return NON_FINITE
        return OK

    @njit
    def adaptive_interval(t, x, u, ps, P, circuit, h, dt, rtol, atol, c, w, max_steps):
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
            for i in range(n_state):
                xt[i] = x[i] + hs * _A21 * k1[i]
            rhs(t + hs / 5, xt, u, ps, P, circuit, c, k2)
            for i in range(n_state):
                xt[i] = x[i] + hs * (_A31 * k1[i] + _A32 * k2[i])
            rhs(t + 3 * hs / 10, xt, u, ps, P, circuit, c, k3)
            for i in range(n_state):
                xt[i] = x[i] + hs * (_A41 * k1[i] + _A42 * k2[i] + _A43 * k3[i])
            rhs(t + 4 * hs / 5, xt, u, ps, P, circuit, c, k4)
            for i in range(n_state):
                xt[i] = x[i] + hs * (_A51 * k1[i] + _A52 * k2[i] + _A53 * k3[i] + _A54 * k4[i])
            rhs(t + 8 * hs / 9, xt, u, ps, P, circuit, c, k5)
            for i in range(n_state):
                xt[i] = x[i] + hs * (_A61 * k1[i] + _A62 * k2[i] + _A63 * k3[i] + _A64 * k4[i]
                                     + _A65 * k5[i])
            rhs(t + hs, xt, u, ps, P, circuit, c, k6)
            for i in range(n_state):
                xn[i] = x[i] + hs * (_B1 * k1[i] + _B3 * k3[i] + _B4 * k4[i] + _B5 * k5[i]
                                     + _B6 * k6[i])
            rhs(t + hs, xn, u, ps, P, circuit, c, k7)
            err = 0.0
            for i in range(n_state):
                e = hs * (_E1 * k1[i] + _E3 * k3[i] + _E4 * k4[i] + _E5 * k5[i] + _E6 * k6[i]
                          + _E7 * k7[i])
                sc = atol[i] + rtol * max(abs(x[i]), abs(xn[i]))
                err += (e / sc) ** 2
            err = math.sqrt(err / n_state)
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
                for i in range(n_state):
                    x[i] = xn[i]
                if last:
                    project(x, P, circuit)
                elif project(x, P, circuit):
                    rhs(t, x, u, ps, P, circuit, c, k1)
                else:  # first same as last: k7 is the derivative at the new point
                    for i in range(n_state):
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
        for i in range(n_state):
            if not math.isfinite(x[i]):
                return NON_FINITE, dt
        return OK, dt

    @njit
    def record(t, x, u, ps, P, circuit, c, dx, X, Y, k):
        """Store state and outputs at sample k; leaves rhs(t, x) in ``dx``."""
        rhs(t, x, u, ps, P, circuit, c, dx)
        for i in range(n_state):
            X[k, i] = x[i]
        for j in range(len(OUTPUTS)):
            Y[k, j] = c[OUTPUTS[j]]

    @njit
    def run(x0, t, u, ps, P, circuit, adaptive, rtol, atol, n_sub, X, Y):
        """Simulate over the sample times ``t`` with ZOH inputs; fills X, Y; returns status."""
        c = np.zeros(N_CONTEXT)
        w = np.zeros((9, n_state))
        x = x0.copy()
        project(x, P, circuit)
        record(t[0], x, u[0], ps[0], P, circuit, c, w[0], X, Y, 0)
        dt = 1e-5
        for k in range(len(t) - 1):
            h = t[k + 1] - t[k]
            if adaptive:
                status, dt = adaptive_interval(t[k], x, u[k], ps[k], P, circuit, h, dt, rtol,
                                               atol, c, w, MAX_STEPS_OFFLINE)
                dt = min(dt, 1.0)
            else:
                status = fixed_interval(t[k], x, u[k], ps[k], P, circuit, h, n_sub, c, w)
            if status != OK:
                return status, k
            record(t[k + 1], x, u[k + 1], ps[k + 1], P, circuit, c, w[0], X, Y, k + 1)
        return OK, len(t) - 1

    @njit(parallel=True)
    def run_batch(X0, t, U, PS, PM, circuit, adaptive, rtol, atol, n_sub, XB, YB, status):
        """``run`` for each row of the parameter matrix ``PM`` (and of X0, U, PS), in parallel."""
        for m in prange(PM.shape[0]):
            s, _ = run(X0[m], t, U[m], PS[m], PM[m], circuit, adaptive, rtol, atol, n_sub,
                       XB[m], YB[m])
            status[m] = s

    return {'fixed_interval': fixed_interval, 'adaptive_interval': adaptive_interval,
            'run': run, 'run_batch': run_batch}
