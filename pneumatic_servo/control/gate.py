"""The safety output gate: the one place every valve command passes before any valve.

Rules, in order of precedence (see docs/ros.md, "Safety"):

1. While the gate is *held* (node inactive, shutting down) the output is the
   safe voltage, 5 V: the spool is centred, both chambers are closed, the
   actuator holds where it is.
2. While a fault is *latched* the output is the safe voltage. Faults latch on a
   non-finite command, on the watchdog (no fresh command for ``watchdog_s``)
   and on :meth:`OutputGate.trip` (exceptions, sensor faults). Only
   :meth:`OutputGate.reset` clears them: the operator re-activates the node.
3. Before the first command after a (re)start the output is the safe voltage;
   the watchdog arms with that first command, so a plant that starts before
   its controller does not trip.
4. Otherwise the output is the last command clamped to ``[min_v, max_v]``. A
   clamp is not a fault (the valve's input range is 0-10 V by design), but it
   is counted and reported as a warning.

The gate is pure and keeps no clock: every call takes ``now`` [s] from a
monotonic clock of the caller, which makes it exactly testable.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ConfigError

#: [V] the valve's centre: spool closed, actuator held (the paper's 5 V null)
SAFE_V = 5.0
#: [V] the valve's input range (paper, Eq. 39: 0 <= U <= 10 V)
MIN_V, MAX_V = 0.0, 10.0
#: [s] default time without a fresh command after which the gate trips
WATCHDOG_S = 0.1

OK, WARN, ERROR = 'ok', 'warn', 'error'


@dataclass
class GateStatus:
    """What the gate is doing, for ``/diagnostics``.

    ``level`` is 'ok', 'warn' or 'error'; ``faults`` are the latched faults in
    the order they happened; the counters run since construction.
    """

    level: str
    message: str
    output_v: float
    armed: bool
    held: str
    faults: tuple[str, ...]
    commands: int
    clamped: int
    non_finite: int
    ignored: int
    last_command_v: float
    command_age_s: float
    values: dict = field(default_factory=dict)


class OutputGate:
    """Maps valve commands to the voltage that reaches the valve.

    Parameters
    ----------
    watchdog_s : float [s]
        Longest time without a fresh command before the output goes safe and
        a ``watchdog`` fault latches; > 0.
    safe_v : float [V]
        Output while held, faulted or not yet armed (the valve centre).
    min_v, max_v : float [V]
        Clamp range of the output; ``min_v <= safe_v <= max_v`` within 0-10 V.
    """

    def __init__(self, watchdog_s: float = WATCHDOG_S, safe_v: float = SAFE_V,
                 min_v: float = MIN_V, max_v: float = MAX_V):
        for name, value in (('watchdog_s', watchdog_s), ('safe_v', safe_v), ('min_v', min_v),
                            ('max_v', max_v)):
            if not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ConfigError(f'output gate: {name} must be a finite number, got {value!r}')
        if watchdog_s <= 0.0:
            raise ConfigError(f'output gate: watchdog_s = {watchdog_s:g} s must be > 0')
        if not (MIN_V <= min_v <= safe_v <= max_v <= MAX_V):
            raise ConfigError(f'output gate: need {MIN_V:g} <= min_v <= safe_v <= max_v <= '
                              f'{MAX_V:g} V, got min_v={min_v:g}, safe_v={safe_v:g}, '
                              f'max_v={max_v:g}')
        self.watchdog_s = float(watchdog_s)
        self.safe_v = float(safe_v)
        self.min_v, self.max_v = float(min_v), float(max_v)
        self._faults: list[str] = []
        self._held = ''
        self._armed = False
        self._last_t = -math.inf
        self._last_raw = math.nan
        self._value = self.safe_v
        self._clamped_now = False
        self.commands = self.clamped = self.non_finite = self.ignored = 0

    # ------------------------------------------------------------------ inputs
    def command(self, value, now: float) -> float:
        """Take a fresh command ``value`` [V] received at ``now`` [s]; returns the output.

        A non-finite or non-numeric value latches a ``non-finite command`` fault.
        """
        self.commands += 1
        try:
            raw = float(value)
        except (TypeError, ValueError):
            raw = math.nan
        self._last_raw = raw
        if self._faults or self._held:
            # a faulted or held gate keeps the valve safe whatever arrives
            self.ignored += 1
            return self.safe_v
        if not math.isfinite(raw):
            self.non_finite += 1
            self._latch(f'non-finite command ({raw!r})')
            return self.safe_v
        clamped = min(max(raw, self.min_v), self.max_v)
        self._clamped_now = clamped != raw
        if self._clamped_now:
            self.clamped += 1
        self._value = clamped
        self._armed = True
        self._last_t = float(now)
        return clamped

    def output(self, now: float) -> float:
        """The voltage [V] to apply at ``now`` [s]; trips the watchdog if the command is stale."""
        if self._held or self._faults or not self._armed:
            return self.safe_v
        age = float(now) - self._last_t
        if not age <= self.watchdog_s:  # also catches a NaN clock
            self._latch(f'watchdog: no command for {age * 1e3:.0f} ms '
                        f'(limit {self.watchdog_s * 1e3:.0f} ms)')
            return self.safe_v
        return self._value

    # ------------------------------------------------------------------ states
    def trip(self, reason: str) -> None:
        """Latch a fault ``reason`` (an exception, a sensor fault): output safe until reset."""
        self._latch(str(reason) or 'tripped')

    def hold(self, reason: str) -> None:
        """Force the safe output without a fault (inactive, shutting down)."""
        self._held = str(reason) or 'held'
        self._armed = False

    def release(self) -> None:
        """End a :meth:`hold`; the output stays safe until the next fresh command."""
        self._held = ''
        self._armed = False

    def reset(self) -> None:
        """Clear latched faults (operator acknowledgement); re-arms on the next command."""
        self._faults.clear()
        self._armed = False
        self._value = self.safe_v

    def _latch(self, reason: str) -> None:
        if reason not in self._faults:
            self._faults.append(reason)
        self._armed = False
        self._value = self.safe_v

    # ------------------------------------------------------------------ report
    @property
    def faulted(self) -> bool:
        return bool(self._faults)

    @property
    def faults(self) -> tuple[str, ...]:
        return tuple(self._faults)

    @property
    def armed(self) -> bool:
        return self._armed

    def status(self, now: float) -> GateStatus:
        """A snapshot for diagnostics at ``now`` [s] (does not trip the watchdog)."""
        age = float(now) - self._last_t if math.isfinite(self._last_t) else math.inf
        if self._faults:
            level, message = ERROR, 'FAULT (valve held at %.2f V): %s' % (
                self.safe_v, '; '.join(self._faults))
        elif self._held:
            level, message = OK, f'held at {self.safe_v:.2f} V: {self._held}'
        elif not self._armed:
            level, message = OK, f'waiting for the first command (valve at {self.safe_v:.2f} V)'
        elif self._clamped_now:
            level, message = WARN, (f'command {self._last_raw:.3g} V clamped to '
                                    f'{self._value:.3g} V (range {self.min_v:g}-'
                                    f'{self.max_v:g} V)')
        else:
            level, message = OK, 'commanding'
        output = self.safe_v if (self._held or self._faults or not self._armed) else self._value
        return GateStatus(level, message, output, self._armed, self._held, self.faults,
                          self.commands, self.clamped, self.non_finite, self.ignored,
                          self._last_raw, age)
