"""PID position control with feed-forward and friction compensation. Pure.

The valve meters flow, so at a given load the actuator's speed follows the
valve opening: the plant is close to an integrator from voltage to angle.
Hence the terms:

* proportional on the angle error, derivative on the *rate* error
  (``ref.velocity - omega``, no derivative kick on steps);
* integral, only within ``integral_zone_rad`` of the target and clamped to
  ``integral_limit_v`` (conditional integration: a large step does not wind
  it up), frozen while the output saturates (anti-windup);
* velocity feed-forward ``kv * ref.velocity`` (the opening that gives that
  speed) and acceleration feed-forward ``ka * ref.acceleration``;
* friction compensation ``friction_v * tanh(e / friction_band_rad)``: the
  extra opening that overcomes the valve overlap (the spool must travel
  a - r = 10 um, 0.05 V, before the metering edge opens) and the piston's
  static friction, so the actuator does not stall a little short of the
  target.

Output: valve voltage [V] around ``null_v`` (the valve centre), clamped to
``[output_min_v, output_max_v]``.
"""
from __future__ import annotations

import math

from .measurement import Measurement
from .params import Spec, SpecSet
from .reference import Reference


def _cross(values: dict):
    lo, hi = values.get('output_min_v'), values.get('output_max_v')
    if lo is not None and hi is not None and not lo < hi:
        return (f'output_min_v = {lo:g} V must be below output_max_v = {hi:g} V; '
                'set a valid 0-10 V range')
    null = values.get('null_v')
    if null is not None and lo is not None and hi is not None and not lo <= null <= hi:
        return f'null_v = {null:g} V must lie within [output_min_v, output_max_v]'
    return None


PID_SPECS = SpecSet([
    Spec('kp', 6.0, 'proportional gain: volts per radian of angle error', 'V/rad', 0.0, 1000.0),
    Spec('ki', 2.0, 'integral gain', 'V/(rad.s)', 0.0, 10000.0),
    Spec('kd', 0.2, 'derivative gain on the rate error', 'V.s/rad', 0.0, 100.0),
    Spec('kdp', 6e-6, 'differential-pressure feedback: volts per pascal of p_a - p_b (damps '
         'the pneumatic spring; 0 = off or no pressures measured)', 'V/Pa', 0.0, 1e-3),
    Spec('kv', 0.25, 'velocity feed-forward: volts per rad/s of reference speed', 'V.s/rad',
         0.0, 100.0),
    Spec('ka', 0.0, 'acceleration feed-forward', 'V.s^2/rad', 0.0, 10.0),
    Spec('friction_v', 0.08, 'friction and valve-overlap compensation amplitude', 'V', 0.0, 2.0),
    Spec('friction_band_rad', 0.002, 'error at which the friction compensation is 76 %',
         'rad', 1e-6, 1.0),
    Spec('integral_zone_rad', 0.05, 'integrate only within this error', 'rad', 0.0, 10.0),
    Spec('integral_limit_v', 0.5, 'largest integral contribution', 'V', 0.0, 5.0),
    Spec('null_v', 5.0, 'valve centre voltage (no flow)', 'V', 0.0, 10.0),
    Spec('output_min_v', 0.0, 'lowest command', 'V', 0.0, 10.0),
    Spec('output_max_v', 10.0, 'highest command', 'V', 0.0, 10.0),
    Spec('velocity_filter_s', 0.0,
         'time constant of the first-order filter on the velocity (measured, or the '
         'derivative of the angle when none is measured)', 's', 0.0, 1.0),
], cross=_cross)


class VelocityEstimator:
    """Filtered angular velocity [rad/s]: first-order low-pass (time constant ``tau_s``) of
    the measured velocity, or of the backward difference of the angle when none is measured.

    The filter matters: the valve moves the shaft within milliseconds, so an
    unfiltered rate term with one period of delay makes the loop chatter at
    the sampling frequency.
    """

    def __init__(self, tau_s: float = 0.005):
        self.tau_s = tau_s
        self.reset()

    def reset(self) -> None:
        self._t = self._x = None
        self.value = 0.0

    def update(self, t: float, angle: float, measured: float = math.nan) -> float:
        if self._t is None:
            self.value = measured if math.isfinite(measured) else 0.0
        elif t > self._t:
            dt = t - self._t
            raw = measured if math.isfinite(measured) else (angle - self._x) / dt
            alpha = dt / (self.tau_s + dt)
            self.value += alpha * (raw - self.value)
        self._t, self._x = t, angle
        return self.value


class ControlLaw:
    """What every control law shares: its parameter values, a velocity estimate, reset.

    Subclasses set ``name`` and ``specs`` (a :class:`~.params.SpecSet`) and
    implement ``update(t, ref, m) -> command [V]``. Unknown parameter names are
    ignored, so one parameter mapping can configure several laws.
    """

    name = ''
    specs = None

    def __init__(self, **params):
        self.p = self.specs.defaults()
        self.configure(params)
        self.velocity = VelocityEstimator(self.p['velocity_filter_s'])
        self.reset()

    def configure(self, values: dict) -> None:
        """Take new parameter values (already validated); keeps the integral."""
        for k, v in values.items():
            if k in self.specs:
                self.p[k] = self.specs[k].coerce(v)
        if hasattr(self, 'velocity'):
            self.velocity.tau_s = self.p['velocity_filter_s']

    def reset(self) -> None:
        self.integral = 0.0
        self._t = None
        self.velocity.reset()
        self.last = {}

    def omega(self, m: Measurement) -> float:
        """Filtered angular velocity [rad/s] (see :class:`VelocityEstimator`)."""
        return self.velocity.update(m.t_s, m.angle_rad, m.velocity_rad_s)


class PidController(ControlLaw):
    """PID + feed-forward + friction compensation; ``update`` once per measurement.

    Parameters are the names of :data:`PID_SPECS`.
    """

    name = 'pid'
    specs = PID_SPECS

    def update(self, t: float, ref: Reference, m: Measurement) -> float:
        """Valve command [V] at ``t`` [s] for reference ``ref`` given measurement ``m``."""
        p = self.p
        dt = 0.0 if self._t is None else max(t - self._t, 0.0)
        self._t = t
        omega = self.omega(m)
        e = ref.position - m.angle_rad
        de = ref.velocity - omega
        ff = p['kv'] * ref.velocity + p['ka'] * ref.acceleration
        fc = p['friction_v'] * math.tanh(e / p['friction_band_rad'])
        dp = m.p_a_pa - m.p_b_pa
        pf = -p['kdp'] * dp if (p['kdp'] and math.isfinite(dp)) else 0.0
        u_free = p['null_v'] + p['kp'] * e + p['kd'] * de + ff + fc + pf
        u = u_free + self.integral
        lo, hi = p['output_min_v'], p['output_max_v']
        saturated = (u >= hi and e > 0) or (u <= lo and e < 0)
        if abs(e) <= p['integral_zone_rad'] and not saturated and dt > 0:
            lim = p['integral_limit_v']
            self.integral = min(max(self.integral + p['ki'] * e * dt, -lim), lim)
        elif abs(e) > p['integral_zone_rad']:
            # far from the target the integral only delays the approach; forget it
            self.integral = 0.0
        u = min(max(u_free + self.integral, lo), hi)
        self.last = {'error_rad': e, 'integral_v': self.integral, 'feedforward_v': ff,
                     'friction_v': fc, 'omega_rad_s': omega}
        return u
