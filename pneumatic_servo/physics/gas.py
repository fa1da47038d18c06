"""Compressible flow through orifices and laminar clearances (Eqs 8-9, 17-18, 22-25).

Pressures are absolute [Pa], temperatures [K], flows [kg/s]. Every function
returns the *signed* flow from side 1 to side 2, so each path is
bidirectional with the same law and the roles of upstream and downstream
swapped (docs/model.md, settlement 5).
"""
import math

from .._jit import njit

_P_FLOOR = 1.0  # [Pa] keeps ratios finite if a solver probes an empty chamber


@njit(cache=True)
def ideal_critical_ratio(kappa):
    """Critical pressure ratio of an ideal nozzle, (2 / (kappa + 1))^(kappa / (kappa - 1))."""
    return (2.0 / (kappa + 1.0)) ** (kappa / (kappa - 1.0))


@njit(cache=True)
def flow_function(ratio, critical_ratio, kappa, laminar_band):
    """Dimensionless flow function psi(p_d/p_u) of Eq. 8.

    Choked below ``critical_ratio``; the paper's subsonic law above it; and,
    within ``laminar_band`` of ratio 1, a straight line to zero that matches
    the subsonic law at 1 - band. The subsonic law's slope is unbounded at
    ratio 1; the line keeps the equations solvable there without changing the
    flow anywhere else.
    """
    if ratio < critical_ratio:
        return math.sqrt(2.0 * kappa / (kappa + 1.0)
                         * (2.0 / (kappa + 1.0)) ** (2.0 / (kappa - 1.0)))
    edge = 1.0 - laminar_band
    if ratio <= edge:
        return math.sqrt(2.0 * kappa / (kappa - 1.0)
                         * (ratio ** (2.0 / kappa) - ratio ** ((kappa + 1.0) / kappa)))
    psi_edge = math.sqrt(2.0 * kappa / (kappa - 1.0)
                         * (edge ** (2.0 / kappa) - edge ** ((kappa + 1.0) / kappa)))
    return psi_edge * max(1.0 - ratio, 0.0) / laminar_band


@njit(cache=True)
def orifice_flow(area, p1, t1, p2, t2, critical_ratio, gas_constant, kappa, laminar_band):
    """Signed mass flow [kg/s] from side 1 to side 2 through an orifice of ``area`` [m^2]."""
    p1 = max(p1, _P_FLOOR)
    p2 = max(p2, _P_FLOOR)
    if p1 >= p2:
        psi = flow_function(p2 / p1, critical_ratio, kappa, laminar_band)
        return area * p1 / math.sqrt(gas_constant * t1) * psi
    psi = flow_function(p1 / p2, critical_ratio, kappa, laminar_band)
    return -area * p2 / math.sqrt(gas_constant * t2) * psi


@njit(cache=True)
def clearance_flow(spool_diameter, gap_height, length, p1, t1, p2, t2, viscosity, gas_constant):
    """Signed laminar mass flow [kg/s] from side 1 to side 2 through the spool clearance.

    Plane Poiseuille flow in an annular gap of height h0 and ``length`` [m]
    (Eq. 17): m = pi d_s h0^3 p_d (p_u - p_d) / (12 mu L R T_u), density from
    the downstream pressure and the upstream temperature, as the paper writes it.
    """
    k = math.pi * spool_diameter * gap_height * gap_height * gap_height \
        / (12.0 * viscosity * length * gas_constant)
    if p1 >= p2:
        return k * p2 * (p1 - p2) / t1
    return -k * p1 * (p2 - p1) / t2
