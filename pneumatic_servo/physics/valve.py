"""Geometry and flow coefficient of the 5/3 proportional valve (paper Eqs 3-7, 21, 39-40).

All lengths in m, areas in m^2, voltages in V.
"""
import math

from .._jit import njit


@njit(cache=True)
def spool_displacement(voltage, null_voltage, gain, max_displacement):
    """Spool displacement x_v [m] for a command ``voltage`` [V] (Eq. 39).

    The command is clipped to the valve's 0-10 V input range and the result to
    +/- ``max_displacement`` [m]; ``gain`` is in m/V.
    """
    u = min(max(voltage, 0.0), 10.0)
    x = gain * (u - null_voltage)
    return min(max(x, -max_displacement), max_displacement)


@njit(cache=True)
def hole_open_area(x_abs, half_shoulder_width, hole_radius):
    """Area S_V [m^2] of one sleeve hole uncovered at spool travel ``x_abs`` >= 0 [m] (Eq. 4).

    The circular-segment formula is used for the whole travel: it is 0 up to
    a - r, half the hole at a and the whole hole at a + r.
    """
    d = half_shoulder_width - x_abs
    r = hole_radius
    if d >= r:
        return 0.0
    if d <= -r:
        return math.pi * r * r
    return r * r * math.acos(d / r) - d * math.sqrt(r * r - d * d)


@njit(cache=True)
def annulus_area(sleeve_bore_diameter, spool_diameter):
    """Horizontal clearance area S_H [m^2] between spool and sleeve (Eq. 5)."""
    return math.pi * (sleeve_bore_diameter ** 2 - spool_diameter ** 2) / 4.0


@njit(cache=True)
def flow_coefficient(x_abs, p0, p1, p2, p3, p4):
    """Orifice flow coefficient C1 at spool travel ``x_abs`` [m] (Eq. 40, sign settled).

    C1 = P(|x_v|) with P(x) = p4 x^4 + p3 x^3 + p2 x^2 + p1 x + p0; the paper's
    printed odd terms have the wrong sign (docs/model.md, settlement 1). Coefficients are in
    1, 1/m, 1/m^2, 1/m^3, 1/m^4.
    """
    x = x_abs
    return (((p4 * x + p3) * x + p2) * x + p1) * x + p0


@njit(cache=True)
def effective_area(x_abs, c1, c0, half_shoulder_width, hole_radius, s_h):
    """Effective orifice area S_e [m^2] of the open metering edge (Eqs 3, 7, 21).

    S_e = C1 (2 S_V + C0 S_H): two holes plus the annular clearance area
    converted by C0.
    """
    return c1 * (2.0 * hole_open_area(x_abs, half_shoulder_width, hole_radius) + c0 * s_h)
