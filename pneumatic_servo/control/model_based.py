"""Model-based position control: a sliding mode on the angle with the valve inverted through
the model core. Pure (no ROS); uses the model's right-hand side
(:meth:`pneumatic_servo.model.Model.evaluate`).

The actuator is third order from the valve to the angle: the valve sets the
chamber pressure *rates*, the pressure difference sets the acceleration. With
the tracking error ``e = theta - theta_d`` the controller drives the surface

    s = e'' + 2 lam e' + lam^2 e

to zero with ``s' = -eta sat(s / phi)``, so on the surface the error decays as
``(p + lam)^2 e = 0``. The acceleration comes from the model (pressures,
friction and all effects of the config), not from a differentiator. The
wanted jerk gives the wanted rate of the pressure difference,

    d(p_a - p_b)/dt = (J theta''' + d_f/2 dF_f/dt) / (A d_f),

and the valve voltage that produces it is found by bisection on the core's
pressure equations at the measured state (they are monotonic in the spool
position). This is feedback linearisation of the pressure dynamics with the
exact flow laws of the model (orifice and clearance flows, heat transfer),
plus a sliding-mode robustness term.

Measured temperatures are used when present, else the wall temperature.
"""
from __future__ import annotations

import math

import numpy as np

from ..effects.layout import (
    C_INERTIA,
    K_AREA,
    K_DF,
    K_STROKE,
    N_CONTEXT,
    OMEGA,
    P_A,
    P_B,
    SERVO,
    T_A,
    T_B,
    THETA,
)
from .measurement import Measurement
from .params import Spec, SpecSet
from .pid import PID_SPECS, ControlLaw
from .reference import Reference


def _cross(values: dict):
    return PID_SPECS.cross(values)


SMC_SPECS = SpecSet([
    Spec('smc_lambda', 120.0, 'bandwidth of the sliding surface (double pole)', '1/s', 0.1,
         2000.0),
    Spec('smc_eta', 1.0e6, 'reaching gain of the switching term', 'rad/s^3', 0.0, 1e10),
    Spec('smc_boundary', 3300.0, 'boundary layer of the switching term; inside it the surface '
         'decays at smc_eta / smc_boundary [1/s], which must stay well below the sampling '
         'rate', 'rad/s^2', 1e-6, 1e10),
    Spec('smc_ki', 0.0, 'integral of the angle error added to the surface', '1/s', 0.0, 1000.0),
    Spec('smc_integral_zone_rad', 0.02, 'integrate only within this error', 'rad', 0.0, 10.0),
    PID_SPECS['null_v'], PID_SPECS['output_min_v'], PID_SPECS['output_max_v'],
    PID_SPECS['velocity_filter_s'],
], cross=_cross)


class SlidingModeController(ControlLaw):
    """Sliding-mode position control with valve inversion through ``model``.

    Parameters
    ----------
    model : pneumatic_servo.model.Model
        The plant model (its config's effects and parameter values are used).
    supply_pa : float [Pa, absolute], optional
        Supply pressure when none is measured (default: the config's).
    **params
        Values for :data:`SMC_SPECS`.
    """

    name = 'smc'
    specs = SMC_SPECS

    def __init__(self, model, supply_pa: float | None = None, **params):
        from ..model.simulate import initial_state  # the model layer, imported when used
        super().__init__(**params)
        self.model = model
        core = model.config.core
        self.supply_pa = core['supply_pressure_pa'] if supply_pa is None else supply_pa
        self.room_k = core['room_temperature_k']
        self._x = initial_state(model)
        self._out = np.zeros(N_CONTEXT), np.zeros(model.n_states)  # filled by each evaluation
        P = model.params
        self.area_df = P[K_AREA] * P[K_DF]
        self.stroke = P[K_STROKE]
        # total inertia as the core computes it (pistons, gear and any payload effect)
        c, _ = model.evaluate(self._x, 5.0, self.supply_pa, SERVO, out=self._out)
        self.inertia = float(c[C_INERTIA])

    def reset(self) -> None:
        super().reset()
        self._acc_prev = None

    def _state(self, m: Measurement, omega: float) -> np.ndarray:
        x = self._x
        x[THETA] = min(max(m.angle_rad, 0.0), self.stroke)
        x[OMEGA] = omega
        x[P_A] = m.p_a_pa
        x[P_B] = m.p_b_pa
        x[T_A] = m.t_a_k if math.isfinite(m.t_a_k) else self.room_k
        x[T_B] = m.t_b_k if math.isfinite(m.t_b_k) else self.room_k
        return x

    def _rates(self, t, x, u, ps):
        """(d(p_a - p_b)/dt [Pa/s], angular acceleration [rad/s^2]) at command ``u``."""
        _, dx = self.model.evaluate(x, u, ps, SERVO, t=t, out=self._out)
        return dx[P_A] - dx[P_B], dx[OMEGA]

    def update(self, t: float, ref: Reference, m: Measurement) -> float:
        """Valve command [V] at ``t`` [s] for ``ref`` given ``m`` (needs both pressures)."""
        p = self.p
        lo, hi = p['output_min_v'], p['output_max_v']
        if not (math.isfinite(m.p_a_pa) and math.isfinite(m.p_b_pa)):
            raise ValueError('the model-based controller needs both chamber pressures')
        dt = 0.0 if self._t is None else max(t - self._t, 0.0)
        self._t = t
        omega = self.omega(m)
        ps = m.supply_pa if math.isfinite(m.supply_pa) else self.supply_pa
        x = self._state(m, omega)
        lam = p['smc_lambda']
        _, acc = self._rates(t, x, p['null_v'], ps)
        e = m.angle_rad - ref.position
        if abs(e) <= p['smc_integral_zone_rad'] and dt > 0:
            self.integral += e * dt
        elif abs(e) > p['smc_integral_zone_rad']:
            self.integral = 0.0
        de = omega - ref.velocity
        dde = acc - ref.acceleration
        s = dde + 2.0 * lam * de + lam * lam * e + p['smc_ki'] * lam * lam * self.integral
        sat = max(-1.0, min(1.0, s / p['smc_boundary']))
        # the reference jerk is not part of Reference; a smooth trajectory's is small
        jerk = -2.0 * lam * dde - lam * lam * de - p['smc_ki'] * lam * lam * e - p['smc_eta'] * sat
        dp_rate = jerk * self.inertia / self.area_df
        # the inversion sees the valve overlap and the friction: no extra compensation
        u = self._invert(t, x, ps, dp_rate, lo, hi)
        self.last = {'surface': s, 'acc_rad_s2': acc, 'dp_rate_pa_s': dp_rate,
                     'omega_rad_s': omega}
        return u

    def _invert(self, t, x, ps, target, lo, hi, iterations: int = 24) -> float:
        """Command in [lo, hi] whose d(p_a - p_b)/dt is closest to ``target`` (bisection)."""
        f_lo, _ = self._rates(t, x, lo, ps)
        if target <= f_lo:
            return lo
        f_hi, _ = self._rates(t, x, hi, ps)
        if target >= f_hi:
            return hi
        a, b = lo, hi
        for _ in range(iterations):
            mid = 0.5 * (a + b)
            f, _ = self._rates(t, x, mid, ps)
            if f < target:
                a = mid
            else:
                b = mid
        return 0.5 * (a + b)
