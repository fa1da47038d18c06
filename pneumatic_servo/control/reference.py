"""Position references for the controllers: a held setpoint or a timed trajectory. Pure.

Times are on the controller's clock [s] (measurement stamps: sim time in
lockstep, wall time otherwise); angles in rad.
"""
from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Optional, Sequence

from ..errors import ConfigError


@dataclass(frozen=True)
class Reference:
    """Desired angle [rad], angular velocity [rad/s] and acceleration [rad/s^2]."""

    position: float
    velocity: float = 0.0
    acceleration: float = 0.0


@dataclass(frozen=True)
class TrajectoryPoint:
    """A trajectory sample at absolute time ``t_s`` [s]; ``velocity``/``acceleration`` optional."""

    t_s: float
    position: float
    velocity: Optional[float] = None
    acceleration: Optional[float] = None


class Trajectory:
    """A time-ordered list of points, sampled at any time.

    Between two points the reference is a cubic Hermite segment when both
    carry velocities, else linear. Before the first point the trajectory is
    not yet active (``sample`` returns None, the caller keeps its previous
    reference); after the last point it holds the last position at rest. A
    single point is therefore a step scheduled at ``t_s``.
    """

    def __init__(self, points: Sequence[TrajectoryPoint]):
        pts = list(points)
        if not pts:
            raise ConfigError('a trajectory needs at least one point')
        for p in pts:
            for name in ('t_s', 'position'):
                if not math.isfinite(getattr(p, name)):
                    raise ConfigError(f'trajectory point {name} must be finite, got {p!r}')
        times = [p.t_s for p in pts]
        if any(b <= a for a, b in zip(times, times[1:])):
            raise ConfigError('trajectory point times must increase strictly')
        self.points = pts
        self._times = times

    @property
    def start_s(self) -> float:
        return self._times[0]

    @property
    def end_s(self) -> float:
        return self._times[-1]

    def sample(self, t: float) -> Optional[Reference]:
        """The reference at ``t`` [s], or None before the first point."""
        if t < self._times[0]:
            return None
        if t >= self._times[-1]:
            return Reference(self.points[-1].position)
        i = bisect.bisect_right(self._times, t) - 1
        a, b = self.points[i], self.points[i + 1]
        h = b.t_s - a.t_s
        s = (t - a.t_s) / h
        if a.velocity is not None and b.velocity is not None \
                and math.isfinite(a.velocity) and math.isfinite(b.velocity):
            # cubic Hermite: position, velocity and acceleration of the segment
            h00, h10, h01, h11 = (2 * s ** 3 - 3 * s ** 2 + 1, s ** 3 - 2 * s ** 2 + s,
                                  -2 * s ** 3 + 3 * s ** 2, s ** 3 - s ** 2)
            d00, d10, d01, d11 = (6 * s ** 2 - 6 * s, 3 * s ** 2 - 4 * s + 1,
                                  -6 * s ** 2 + 6 * s, 3 * s ** 2 - 2 * s)
            e00, e10, e01, e11 = 12 * s - 6, 6 * s - 4, -12 * s + 6, 6 * s - 2
            ma, mb = a.velocity * h, b.velocity * h
            pos = h00 * a.position + h10 * ma + h01 * b.position + h11 * mb
            vel = (d00 * a.position + d10 * ma + d01 * b.position + d11 * mb) / h
            acc = (e00 * a.position + e10 * ma + e01 * b.position + e11 * mb) / h ** 2
            return Reference(pos, vel, acc)
        vel = (b.position - a.position) / h
        return Reference(a.position + s * (b.position - a.position), vel, 0.0)


def sine_points(t0: float, duration_s: float, centre_rad: float, amplitude_rad: float,
                frequency_hz: float, dt_s: float = 0.01) -> list[TrajectoryPoint]:
    """Points of ``centre + amplitude sin(2 pi f (t - t0))`` from ``t0`` [s], every ``dt_s``."""
    n = int(round(duration_s / dt_s))
    w = 2.0 * math.pi * frequency_hz
    out = []
    for k in range(n + 1):
        tau = k * dt_s
        out.append(TrajectoryPoint(t0 + tau, centre_rad + amplitude_rad * math.sin(w * tau),
                                   amplitude_rad * w * math.cos(w * tau),
                                   -amplitude_rad * w * w * math.sin(w * tau)))
    return out
