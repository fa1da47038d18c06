"""A one-sided CUSUM of the windows' departures, with a stated false-alarm rate per hour.

Each judged window gives, per channel, a one-sided p-value ``p`` of a departure upwards
(:mod:`.judge`). Its probit ``z = Phi^-1(1 - p)`` is standard normal when the model
describes the rig and the window's copies represent it (smaller than that where the test is
conservative, as :meth:`Floor.test` is by design). The CUSUM

    S_w = max(0, S_(w-1) + z_w - k),     WARN when S_w >= h,

accumulates evidence over windows: one window is weak evidence (one independent unit), a
persistent departure is not. The reference ``k`` = 0.5 is the optimal one for a shift of
one standard deviation in ``z``.

**The threshold from the stated rate.** With ``z`` i.i.d. N(0, 1), Siegmund's approximation
of the in-control average run length (windows between false alarms) of a threshold ``h``:

    ARL0(h) = (exp(2 k b) - 2 k b - 1) / (2 k^2),     b = h + 1.166

(D. Siegmund, *Sequential Analysis*, 1985, p. 27; exact to a few per cent for normal
steps). False alarms then arrive as a Poisson stream of ``W / ARL0`` per hour, ``W`` the
windows per hour of data (3600 / horizon). A stated rate ``lambda`` per hour for the whole
rig is split equally over the ``C`` judged channels (Bonferroni), so each channel's
threshold solves ``ARL0(h) = W C / lambda``: at the defaults (0.01 per hour, 0.2 s
windows, 3 channels) ARL0 = 5.4e6 windows and h = 13.6. ``tests/test_monitor.py`` checks
the rate by simulation.

**Its p-value.** A current value ``S`` is reported as the chance that a channel the model
describes reaches it within an hour of data: ``1 - exp(-W / ARL0(S))``; WARN is exactly
``p <= lambda / C``.

**After an alarm** the channel stays WARN until ``S`` returns to 0 (the departure has
ended and the evidence is spent); then the statistic renews, so each false alarm counts
once.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq
from scipy.stats import norm

#: reference value of the CUSUM [standard deviations of z]
REFERENCE_K = 0.5
#: Siegmund's correction of the threshold for the overshoot of normal steps
OVERSHOOT = 1.166
#: probit of p-values is clipped here (p = 1e-15): one window never weighs more than this
Z_MAX = 8.0


def arl0(h: float, k: float = REFERENCE_K) -> float:
    """In-control average run length [windows] of threshold ``h`` (Siegmund)."""
    b = h + OVERSHOOT
    x = 2.0 * k * b
    return (math.expm1(x) - x) / (2.0 * k * k)


def threshold(rate_per_hour: float, windows_per_hour: float, channels: int = 1,
              k: float = REFERENCE_K) -> float:
    """The threshold ``h`` whose false alarms on ``channels`` channels together arrive at
    ``rate_per_hour`` per hour of data, at ``windows_per_hour`` windows per hour."""
    if not (rate_per_hour > 0 and windows_per_hour > 0 and channels >= 1):
        raise ValueError('rate, windows per hour and channels must be positive')
    target = windows_per_hour * channels / rate_per_hour
    if target <= arl0(0.0, k):
        return 0.0
    return float(brentq(lambda h: arl0(h, k) - target, 0.0, 300.0, xtol=1e-9))


def p_value(s: float, windows_per_hour: float, k: float = REFERENCE_K) -> float:
    """Chance that a channel the model describes reaches CUSUM value ``s`` within an hour
    of data."""
    return float(-math.expm1(-windows_per_hour / arl0(max(s, 0.0), k)))


def probit(p: float) -> float:
    """``Phi^-1(1 - p)``, clipped to +/- :data:`Z_MAX`."""
    return float(min(max(norm.isf(min(max(p, 0.0), 1.0)), -Z_MAX), Z_MAX))


@dataclass
class Cusum:
    """The CUSUM of one channel (see module doc)."""

    h: float
    k: float = REFERENCE_K
    s: float = 0.0
    alarm: bool = False
    #: number of alarms raised (episodes)
    alarms: int = 0

    def update(self, z: float) -> bool:
        """Add one window's ``z``; returns True when this window raises a new alarm."""
        self.s = max(0.0, self.s + z - self.k)
        if self.alarm and self.s == 0.0:
            self.alarm = False
        if not self.alarm and self.s >= self.h:
            self.alarm = True
            self.alarms += 1
            return True
        return False
