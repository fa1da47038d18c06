"""Samples from the interface topics: each measurement with the valve command that acted after
it. Pure: the ROS node feeds it what it takes from its subscriptions.

The plant publishes a sample's pressures and temperatures and then its ``joint_states``,
all with the sample's stamp; the controller answers with ``valve/command``, which has no
stamp; the plant applies the latest command it has when it steps to the next sample. So
the command that acted from sample ``k`` to ``k + 1`` is the last one *published* before
sample ``k + 1``'s ``joint_states`` was. Messages reach a monitor in any order across
topics (best effort, separate writers, a busy process), so the order is taken from the
publishers' source timestamps, which the middleware carries with every message, not from
arrival: in lockstep and in a replay this recovers the pairing exactly. Publishers must then
share a clock to within a control period (one host, or PTP); ``clock='received'`` orders
by arrival instead.

A free-running plant applies the last command it has *received* when it steps, so a
command published only just before the next measurement may have come too late for that
step: where the gap is under :data:`AMBIGUOUS_FRACTION` of a period (in a free-running
loop, nearly always), the command before it is kept as ``command_alt_v`` (NaN elsewhere),
and the monitor's floor counts that uncertainty (:mod:`.judge`). A lockstep plant steps
only after the command arrived, and a replay publishes commands in recorded order; their
samples are on an exact grid, and the monitor drops the ambiguity there.

While the plant says its output gate holds the valve at the safe voltage (a latched
fault, such as its watchdog tripping when the controller was starved; inactive), the
commands do not reach the valve: without ``valve/applied`` (below), those samples get no
command (:meth:`Assembler.valve_held`), from :data:`HELD_MARGIN_NS` before the plant said
so; the monitor judges the model, not the gate.

A plant of this package also publishes what its gate gave the valve (``valve/applied``,
just before each measurement, the value for the period that ends there): where it came, it
is the sample's command, exactly, whatever the timing (:meth:`Assembler.applied`).

A sample is finished :data:`HOLD_NS` after the next one was published (by then every
command published before it has arrived), or :data:`IDLE_NS` after it if no next one
comes (the plant stopped). A sample without its pressures is finished with NaN there (the
windows over it are skipped).
"""
from __future__ import annotations

import bisect
import collections
import math

import numpy as np

#: [ns] a sample is finished this long after the next sample was published: messages of
#: one sample reach a busy monitor (low priority, loaded cores) over separate writers, up to
#: tens of ms apart; what comes later than this is not used
HOLD_NS = 300_000_000
#: [ns] the last sample is finished this long after it was published, if no other comes
IDLE_NS = 1_000_000_000
#: the signals of a sample (``command_alt_v``: see module doc)
FIELDS = ('angle_rad', 'p_a_pa', 'p_b_pa', 'supply_pa', 't_a_k', 't_b_k', 'command_v',
          'command_alt_v')
#: a command published less than this share of a period before the next measurement may
#: have reached the plant after its step: DDS latency between processes is 0.1-0.5 ms on
#: an idle machine and a period or more under load, where a free-running plant's ticks are
#: late and catch up (benchmarks/bench_monitor.py measured a false WARN at 0.5 under load
#: 7); so in a free-running loop the command that acted is known to within one sample
AMBIGUOUS_FRACTION = 1.0
#: commands kept at most (about a second at 1 kHz, many more than are ever waiting)
MAX_COMMANDS = 4096
#: a step in the stamps longer than this many typical steps is a gap (see :meth:`take`)
GAP_PERIODS = 3
#: [ns] samples this long before the plant said its valve is held are not judged either (it
#: reports at once, on the next tick; this covers a late report)
HELD_MARGIN_NS = 50_000_000


class Assembler:
    """Builds samples (see module doc)."""

    def __init__(self):
        self.rows: dict[int, dict] = {}
        self.joints: collections.deque = collections.deque()  # (source ns, stamp ns)
        self.commands: list = []                               # (source ns, value), sorted
        self.last_command = math.nan
        self._last_source = -1           # source ns of the command last used
        self._gap_source = None          # source ns of the first sample after a gap
        self._period_ns = None           # typical stamp step of the samples
        self.held: list = []             # [from, to] stamps with the valve held safe
        self.applied_values: list = []   # (source ns, value) of valve/applied, sorted
        self.received = {'joint_states': 0, 'scalars': 0, 'commands': 0, 'late': 0,
                         'lost_joint_states': 0, 'applied': 0, 'applied_used': 0}
        self._done_stamp = None

    def joint(self, stamp_ns: int, angle: float, source_ns: int) -> None:
        self.received['joint_states'] += 1
        if self.joints and self.joints[-1][1] == stamp_ns:
            return  # the same sample again (a lockstep plant resends an unanswered one)
        if self._done_stamp is not None and stamp_ns <= self._done_stamp:
            if stamp_ns == self._done_stamp:
                return  # resent after it was finished
            self._done_stamp = None  # the plant's clock went back: a new run
        self.rows.setdefault(stamp_ns, {})['angle_rad'] = angle
        self.joints.append((source_ns, stamp_ns))

    def scalar(self, signal: str, stamp_ns: int, value: float) -> None:
        self.received['scalars'] += 1
        if self._done_stamp is not None and stamp_ns <= self._done_stamp \
                and stamp_ns not in self.rows:
            self.received['late'] += 1
            return
        self.rows.setdefault(stamp_ns, {})[signal] = value

    def valve_held(self, stamp_ns: int, held: bool) -> None:
        """The plant says, in its status stamped ``stamp_ns`` (its measurements' clock),
        whether its gate holds the valve at the safe voltage."""
        if held and (not self.held or self.held[-1][1] is not None):
            self.held.append([stamp_ns - HELD_MARGIN_NS, None])
        elif not held and self.held and self.held[-1][1] is None:
            self.held[-1][1] = stamp_ns
        del self.held[:-16]

    def _is_held(self, stamp_ns: int) -> bool:
        return any(a <= stamp_ns and (b is None or stamp_ns <= b) for a, b in self.held)

    def applied(self, value: float, source_ns: int) -> None:
        """What the plant's gate gave the valve over the period that ends at the next
        measurement, published just before it."""
        self.received['applied'] += 1
        bisect.insort(self.applied_values, (source_ns, value))
        del self.applied_values[:-MAX_COMMANDS]

    def _applied_between(self, after_ns: int, until_ns: int) -> float:
        """The applied value published in (after, until], or NaN; older ones forgotten."""
        i = bisect.bisect_right(self.applied_values, (until_ns, math.inf))
        j = bisect.bisect_right(self.applied_values, (after_ns, math.inf))
        value = self.applied_values[i - 1][1] if i > j else math.nan
        del self.applied_values[:j]
        return value

    def command(self, value: float, source_ns: int) -> None:
        self.received['commands'] += 1
        bisect.insort(self.commands, (source_ns, value))
        if len(self.commands) > MAX_COMMANDS:
            self.last_command = self.commands[0][1]
            del self.commands[0]

    def _command_before(self, source_ns: int, period_ns: float) -> tuple[float, float]:
        """The last command published before ``source_ns``, and the one before it if the
        last came within :data:`AMBIGUOUS_FRACTION` of ``period_ns`` of it (else NaN);
        older ones are forgotten."""
        i = bisect.bisect_left(self.commands, (source_ns, -math.inf))
        alt = math.nan
        if i > 0:
            previous = self.last_command
            source, self.last_command = self.commands[i - 1]
            self._last_source = source
            if i > 1:
                previous = self.commands[i - 2][1]
            if source_ns - source < AMBIGUOUS_FRACTION * period_ns:
                alt = previous
            del self.commands[:i - 1]
        return self.last_command, alt

    def take(self, now_ns: int) -> tuple[np.ndarray, dict] | None:
        """The samples finished by ``now_ns`` (same clock as the source timestamps):
        (stamps [ns], {signal: values [SI]}), or None.

        After a gap in the samples, unless exactly one command came in it (a plant's late
        tick, answered), the monitor lost messages (it was stalled, its queues overflowed)
        and the commands of that time may be lost too: the sample before the gap, and any
        later one whose command would be one published before the first sample after it,
        get none (NaN: the windows over them are not judged)."""
        stamps, out = [], {f: [] for f in FIELDS}
        while self.joints:
            source, stamp = self.joints[0]
            if len(self.joints) > 1:
                nxt, next_stamp = self.joints[1]
                if now_ns < nxt + HOLD_NS:
                    break
                step = next_stamp - stamp
                answers = (bisect.bisect_left(self.commands, (nxt, -math.inf))
                           - bisect.bisect_right(self.commands, (source, math.inf)))
                command, alt = self._command_before(nxt, step)
                if self._period_ns is not None and step > GAP_PERIODS * self._period_ns:
                    # a plant's late tick, with its one answer in between; or samples lost,
                    # and their commands (none, or a backlog's worth, in between)
                    if answers != 1:
                        self._gap_source = nxt  # commands published before it may be lost
                        command = alt = math.nan
                elif step > 0:
                    self._period_ns = step if self._period_ns is None else min(
                        max(0.9 * self._period_ns + 0.1 * step, 0.5 * self._period_ns),
                        2.0 * self._period_ns)
                if self._gap_source is not None and self._last_source <= self._gap_source:
                    command = alt = math.nan
                exact = self._applied_between(source, nxt) if self.applied_values else math.nan
                if math.isfinite(exact):  # what the gate gave the valve: no doubt left, even
                    command, alt = exact, math.nan  # while it holds it safe
                    self.received['applied_used'] += 1
                elif self.held and self._is_held(stamp):
                    command = alt = math.nan
            elif now_ns >= source + IDLE_NS:
                command, alt = self._command_before(now_ns, 0.0)
            else:
                break
            self.joints.popleft()
            # a sample whose joint_states was lost but whose pressures came: a sample all the
            # same (without its angle), so that the grid shows the gap
            for lost in sorted(s for s in self.rows if s < stamp
                               and (self._done_stamp is None or s > self._done_stamp)):
                row = self.rows.pop(lost)
                stamps.append(lost)
                row.update(command_v=command, command_alt_v=alt)
                for f in FIELDS:
                    out[f].append(row.get(f, math.nan))
                self.received['lost_joint_states'] += 1
            row = self.rows.pop(stamp, {})
            row.update(command_v=command, command_alt_v=alt)
            stamps.append(stamp)
            for f in FIELDS:
                out[f].append(row.get(f, math.nan))
            self._done_stamp = stamp
        if not stamps:
            return None
        # scalars of samples whose joint_states never came are forgotten
        done = self._done_stamp
        for s in [s for s in self.rows if s <= done]:
            del self.rows[s]
        return np.array(stamps, np.int64), {f: np.array(v, float) for f, v in out.items()}
