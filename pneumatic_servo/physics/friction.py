"""Friction laws on the pistons (Eqs 34-36). Forces in N, speeds in rad/s."""
import math

from .._jit import njit


@njit(cache=True)
def sign(v):
    """Sign of ``v`` as -1.0, 0.0 or 1.0."""
    return 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)


@njit(cache=True)
def stribeck_force(speed, static, coulomb, stribeck_speed, viscous):
    """Sliding friction force [N] of Eq. 36 at angular ``speed`` [rad/s].

    ``static`` F_s and ``coulomb`` F_c in N, ``stribeck_speed`` in rad/s and
    ``viscous`` B in N.s/rad.
    """
    s = sign(speed)
    return s * (coulomb + (static - coulomb) * math.exp(-(speed / stribeck_speed) ** 2)) \
        + viscous * speed


@njit(cache=True)
def coulomb_viscous_force(speed, coulomb, viscous):
    """Sliding friction force [N] of the Coulomb + viscous law (no Stribeck dip)."""
    return sign(speed) * coulomb + viscous * speed
