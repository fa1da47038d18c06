"""One sample of what the plant measures, as the controllers see it. Pure.

Unknown values are NaN: a real rig often has no temperature sensor, and the
velocity may be missing (then the controller differentiates the angle).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

NAN = math.nan


@dataclass
class Measurement:
    """Plant outputs at time ``t_s``.

    Attributes
    ----------
    t_s : float [s]
        Measurement time (sim time in lockstep, wall time otherwise).
    angle_rad : float [rad]
    velocity_rad_s : float [rad/s], NaN if not measured
    p_a_pa, p_b_pa, supply_pa : float [Pa, absolute], NaN if not measured
    t_a_k, t_b_k : float [K], NaN if not measured
    effort_n_m : float [N.m], pneumatic torque A d_f (p_a - p_b), NaN if unknown
    """

    t_s: float
    angle_rad: float
    velocity_rad_s: float = NAN
    p_a_pa: float = NAN
    p_b_pa: float = NAN
    supply_pa: float = NAN
    t_a_k: float = NAN
    t_b_k: float = NAN
    effort_n_m: float = NAN
