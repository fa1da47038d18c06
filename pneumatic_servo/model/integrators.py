"""Shared pieces of the compiled time integration: tableau, status codes, projection.

The integrators themselves (Dormand-Prince 5(4) with error control for offline work,
fixed-step RK4 for real time) live in :mod:`.stepping`, compiled once for every
composition of components. Discontinuities (choked/subsonic switch,
stick/slip, valve branch at x_v = 0, end stops) are handled by step rejection: the
controller shrinks the step until the local error is met.

After every accepted step the state is projected onto the physical set: the shaft is
clipped to [0, stroke] with an inelastic stop, pressures and temperatures are kept positive.
"""
from .._jit import njit
from ..effects.layout import K_STROKE, OMEGA, P_A, P_B, SERVO, T_A, T_B, THETA

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


@njit(cache=True, allocates=False)
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
