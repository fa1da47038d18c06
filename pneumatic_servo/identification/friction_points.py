"""Friction points from servo runs at held valve voltages (paper Section 5.3, Eq. 43).

* **steady segments**: where the shaft turns at constant speed, the moment
  balance (Eq. 37) reduces to Eq. 43, F_f = 2 A (p_a - p_b); each segment
  gives one (speed, force) point;
* **breakaway**: the force at which a stuck shaft starts to move is the
  static friction F_s;
* **slip points**: below the speed where the motion becomes steady, a
  pneumatic actuator stick-slips and has no constant-speed segment. There
  the moment balance is used with its inertia term,
  F_f = 2 A (p_a - p_b) - (2 J_tot / d_f) theta'' (Eq. 37; Eq. 43 is its
  theta'' = 0 case), with theta' and theta'' from a short Savitzky-Golay
  fit of the encoder angle, and the points are binned by speed.

Forces in N (total on the pistons), speeds in rad/s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..effects.layout import C_INERTIA
from ..errors import ExperimentError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import context, initial_state
from ..smoothing import savgol_filter


def total_inertia(config: ModelConfig) -> float:
    """Moment of inertia [kg.m^2] on the shaft with every component's share (a payload
    effect, a user's own), as the model itself sums it."""
    model = Model(config)
    x = initial_state(model, config=config)
    return float(context(model, x, config.core['valve_null_voltage_v'],
                         config.core['supply_pressure_pa'], config)[C_INERTIA])


@dataclass
class FrictionPoint:
    """One measured point of the friction curve."""

    speed_rad_s: float    # [rad/s], >= 0 (direction folded)
    force_n: float        # [N], >= 0 for motion (total friction on the pistons)
    sigma_n: float        # [N] standard error of force_n
    kind: str             # 'steady', 'slip' or 'breakaway'
    source: str = ''      # experiment name
    t_span: tuple = ()    # [s] where in the experiment
    n: int = 1            # samples behind the point


@dataclass
class _Rig:
    area: float      # [m^2] one piston
    arm: float       # [m] d_f / 2
    inertia: float   # [kg.m^2] total on the shaft
    stroke: float    # [rad]
    step: float      # [rad] encoder resolution (from the data)

    @classmethod
    def of(cls, config: ModelConfig, exp: Experiment) -> '_Rig':
        core = config.core
        df = core['pinion_pitch_diameter_m']
        steps = np.abs(np.diff(exp['angle_rad']))
        steps = steps[steps > 1e-12]
        step = float(np.min(steps)) if len(steps) else 0.0
        sensors = exp.metadata.get('sensors') or {}
        step = float(sensors.get('encoder_step_rad', step))
        return cls(core['piston_area_m2'], 0.5 * df, total_inertia(config), core['stroke_rad'],
                   step)


def _require(exp: Experiment):
    for sig in ('angle_rad', 'p_a_pa', 'p_b_pa'):
        if sig not in exp.signals:
            raise ExperimentError(f'{exp.name}: friction identification needs {sig}')
    if exp.circuit != 'servo' or exp.static:
        raise ExperimentError(f'{exp.name}: friction runs are servo time series, not '
                              f'{exp.circuit}')


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, stop) index ranges where ``mask`` is True."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)))


def _savgol(x: np.ndarray, window: int, deriv: int, dt: float) -> np.ndarray:
    window = min(window, len(x) - (1 - len(x) % 2))
    return savgol_filter(x, window, 3, deriv=deriv, delta=dt)


def steady_segments(exp: Experiment, config: ModelConfig, min_duration_s: float = 0.15,
                    margin_rad: float = 0.1, min_speed_rad_s: float = 0.05,
                    max_variation: float = 0.04) -> list[FrictionPoint]:
    """Constant-speed segments of a servo run, each one point of Eq. 43.

    A segment is at least ``min_duration_s`` [s] long, ``margin_rad`` [rad]
    away from the end stops, faster than ``min_speed_rad_s`` [rad/s], and its
    short-window speed varies by less than ``max_variation`` of its mean.
    Its speed is the slope of a straight line through the angle; its force
    the mean of 2 A (p_a - p_b).
    """
    _require(exp)
    rig = _Rig.of(config, exp)
    dt = exp.dt
    th = exp['angle_rad']
    force = 2.0 * rig.area * (exp['p_a_pa'] - exp['p_b_pa'])
    v = _savgol(th, max(5, int(round(0.015 / dt)) | 1), 1, dt)
    inside = (th > margin_rad) & (th < rig.stroke - margin_rad) & (np.abs(v) > min_speed_rad_s)
    need = int(round(min_duration_s / dt))
    csum = np.concatenate([[0.0], np.cumsum(v)])
    out = []
    for a, b in _runs(inside):
        k = a
        while b - k >= need:
            # grow a window while the speed stays within the tolerance of its running mean
            j = k + need
            seg = v[k:j]
            if np.std(seg) > max_variation * abs(np.mean(seg)):
                k += max(1, need // 10)
                continue
            while j < b:
                mean = (csum[j] - csum[k]) / (j - k)
                if abs(v[j] - mean) >= 2.5 * max_variation * abs(mean):
                    break
                j += 1
            tt = exp.t[k:j]
            slope = np.polyfit(tt - tt[0], th[k:j], 1)[0]
            f = force[k:j]
            # neighbouring samples of the pressures are correlated over a few ms
            sigma = float(np.std(f)) / math.sqrt(max(1.0, (j - k) * dt / 0.005))
            out.append(FrictionPoint(abs(float(slope)), float(np.sign(slope) * np.mean(f)),
                                     sigma, 'steady', exp.name, (float(tt[0]), float(tt[-1])),
                                     j - k))
            k = j
    return out


def breakaway_forces(exp: Experiment, config: ModelConfig, min_stuck_s: float = 0.008,
                     fit_s: float = 0.015) -> list[FrictionPoint]:
    """Static friction from each stick -> slip transition (speed 0).

    The encoder first changes a little after the shaft breaks away, while
    the pressure force keeps rising; the force at breakaway is the force at
    the first count, extrapolated back by the onset delay of a shaft that
    starts under a force ramp F' [N/s]: theta = r F' t^3 / (6 J) reaches half
    an encoder step q after delta = (3 J q / (r F'))^(1/3) [s].
    """
    _require(exp)
    rig = _Rig.of(config, exp)
    dt = exp.dt
    th = exp['angle_rad']
    force = 2.0 * rig.area * (exp['p_a_pa'] - exp['p_b_pa'])
    changed = np.flatnonzero(np.abs(np.diff(th)) > 0.5 * rig.step) + 1
    need, nfit = int(round(min_stuck_s / dt)), max(3, int(round(fit_s / dt)))
    out = []
    prev = 0
    for i in changed:
        stuck = i - prev
        prev = i
        if stuck < need or i < nfit:
            continue
        direction = np.sign(th[i] - th[i - 1])
        tt = exp.t[i - nfit:i]
        slope, icpt = np.polyfit(tt - exp.t[i], direction * force[i - nfit:i], 1)
        if slope <= 0:
            continue  # the force was not rising: not a breakaway under a ramp
        delay = (3.0 * rig.inertia * rig.step / (rig.arm * slope)) ** (1.0 / 3.0)
        delay = min(delay, stuck * dt)
        resid = direction * force[i - nfit:i] - (icpt + slope * (tt - exp.t[i]))
        # a fast ramp moves the force a lot within one sample: weigh by the timing uncertainty
        sigma = math.hypot(float(np.std(resid)) / math.sqrt(nfit), slope * dt)
        out.append(FrictionPoint(0.0, float(icpt - slope * delay), sigma, 'breakaway',
                                 exp.name, (float(exp.t[i]),), nfit))
    return out


def slip_points(exp: Experiment, config: ModelConfig, exclude=(), window_s: float = 0.009,
                bin_width_rad_s: float = 0.05, max_speed_rad_s: float = 1.5,
                min_speed_rad_s: float = 0.03, min_count: int = 20,
                margin_rad: float = 0.05) -> list[FrictionPoint]:
    """Friction from the moment balance with its inertia term, binned by speed.

    Samples inside ``exclude`` (time spans [s] of steady segments) are left
    out; each bin of ``bin_width_rad_s`` gives the median force with a
    robust standard error.
    """
    _require(exp)
    rig = _Rig.of(config, exp)
    dt = exp.dt
    w = max(5, int(round(window_s / dt)) | 1)
    th = exp['angle_rad']
    v = _savgol(th, w, 1, dt)
    acc = _savgol(th, w, 2, dt)
    dp = _savgol(exp['p_a_pa'] - exp['p_b_pa'], w, 0, dt)
    force = 2.0 * rig.area * dp - rig.inertia / rig.arm * acc
    sel = (th > margin_rad) & (th < rig.stroke - margin_rad) & (np.abs(v) > min_speed_rad_s)
    for t0, t1 in exclude:
        sel &= ~((exp.t >= t0) & (exp.t <= t1))
    speed, f = np.abs(v[sel]), (np.sign(v) * force)[sel]
    edges = np.arange(0.0, max_speed_rad_s + bin_width_rad_s, bin_width_rad_s)
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (speed >= lo) & (speed < hi)
        if m.sum() < min_count:
            continue
        med = float(np.median(f[m]))
        mad = 1.4826 * float(np.median(np.abs(f[m] - med)))
        # samples within one smoothing window are not independent
        eff = max(1.0, m.sum() / w)
        out.append(FrictionPoint(float(np.median(speed[m])), med, 1.25 * mad / math.sqrt(eff),
                                 'slip', exp.name, (), int(m.sum())))
    return out


def friction_points(experiments, config: ModelConfig, slip: bool = True
                    ) -> list[FrictionPoint]:
    """All friction points (steady, breakaway and, if ``slip``, slip) of servo runs."""
    points = []
    for exp in experiments:
        steady = steady_segments(exp, config)
        points += steady + breakaway_forces(exp, config)
        if slip:
            points += slip_points(exp, config, exclude=[p.t_span for p in steady])
    if not any(p.kind == 'steady' for p in points):
        raise ExperimentError('no constant-speed segment in the friction runs; hold the valve '
                              'at voltages that give steady motion (record longer, or higher '
                              'voltages)')
    return points


# ---------------------------------------------------------------------------- fits
