"""How the plant node paces its samples: one strategy per clock mode.

A strategy decides *when* the next sample is due and what a due tick does;
the plant node (:mod:`.plant_node`) owns the gate, the backend and the
publishers, and its ``step`` and ``publish`` do the work. Strategies:

* :class:`FreeRunning`: real time at the node's rate; a tick more than a
  period late is counted as an overrun and the schedule restarts from now.
* :class:`Lockstep`: the node owns ``/clock``; the next period runs only
  once the controller has answered the last measurement. An unanswered
  measurement is resent; a controller that stays silent past
  ``lockstep_patience_s`` trips the gate, and the plant goes on in real time
  (:class:`FreeRunning`).
* :class:`Replay`: a bag's measurement events in their own time
  (:class:`.backends.ReplaySource`).

Lockstep and replay wait for subscribers before the first sample (say, the
controller and a recorder that must see every sample).
"""
from __future__ import annotations

import time

from . import cdr, common

monotonic = time.monotonic
#: how often a strategy that waits for subscribers looks again [s]
POLL_S = 0.005
#: after the subscriber count is reached, time for the same subscribers' other topics to
#: match too [s]
MATCH_S = 0.1


class SubscriberWait:
    """True once ``joint_states`` has enough subscribers, plus :data:`MATCH_S`."""

    def __init__(self, subscribers: int):
        self.subscribers = subscribers
        self._since = None

    def ready(self, node, now: float) -> bool:
        if node.pubs[common.JOINT_STATES].get_subscription_count() < self.subscribers:
            self._since = None
            return False
        if self._since is None:
            self._since = now
        return now - self._since >= MATCH_S


class FreeRunning:
    """Real time at the node's rate, from the backend's first measurement."""

    started = True

    def __init__(self, node, now: float, measurement_out: bool = False):
        self.period_s = node.period_s
        if measurement_out:  # taking over: the last measurement is out, the next period is due
            self.next_s = now
        else:
            node.publish(node.measurement, now)
            self.next_s = now + self.period_s

    def deadline(self, node, now: float) -> float:
        return self.next_s

    def tick(self, node, now: float) -> None:
        if now < self.next_s:
            return
        node.step(now)
        self.next_s += self.period_s
        if now - self.next_s > self.period_s:
            # more than a period late: count it and resynchronise instead of bursting
            node.overruns += 1
            self.next_s = now + self.period_s


class Lockstep:
    """One period per answered measurement (see module doc)."""

    #: the gate counts sim time (:meth:`.plant_node.PlantNode.gate_time`)
    sim_clock = True

    def __init__(self, node, now: float):
        self.started = False  # the first sample waits for the subscribers
        self.wait = SubscriberWait(max(1, node.p['wait_subscribers']))

    def deadline(self, node, now: float) -> float:
        if not self.started:
            return monotonic() + POLL_S
        if node.answered:
            return monotonic()
        return node.sent_at + min(node.p['lockstep_resend_s'], node.p['lockstep_patience_s'])

    def tick(self, node, now: float) -> None:
        if not self.started:
            if self.wait.ready(node, now):
                self.started = True
                node.publish(node.measurement, now)
            return
        if node.answered:
            node.step(now)
            return
        # while it waits, the simulation stands still and no valve is at stake (lockstep
        # runs the sim backend only): the gate counts sim time, and the controller is given
        # up on after lockstep_patience_s of wall time without a new command, which a loaded
        # machine's stall of a healthy controller does not outlast. Resending the
        # measurement below does not feed it, so a dead controller is given up on
        age = now - node.commanded_at
        patience = node.p['lockstep_patience_s']
        if node.gate.armed and not age <= patience:
            node.gate.trip(f'watchdog: no command for {age * 1e3:.0f} ms in lockstep '
                           f'(limit lockstep_patience_s = {patience * 1e3:.0f} ms)')
            node.get_logger().error('lockstep: no new command within lockstep_patience_s; '
                                    'valve safe, continuing in real time')
            node.pacing = FreeRunning(node, now, measurement_out=True)
            node.publish_diagnostics(now, force=True)
        elif now - node.sent_at > node.p['lockstep_resend_s']:
            # a lost measurement, or a controller that is not there yet: say it again
            node.resends += 1
            node.publish(node.measurement, now)


class Replay:
    """A bag's measurements in their own time, ``replay_rate`` times real time."""

    def __init__(self, node, now: float):
        self.source = node.replay
        self.started = False
        self.wait = SubscriberWait(node.p['wait_subscribers'])
        self.lap_start = now

    def deadline(self, node, now: float) -> float:
        if not self.started:
            return monotonic() + POLL_S
        return self.lap_start + self.source.next_offset_s()

    def tick(self, node, now: float) -> None:
        r = self.source
        if not self.started:
            if self.wait.ready(node, now):
                self.started = True
                self.lap_start = now
            return
        if r.index >= len(r.events):
            if not r.loop:
                node.finish('replay finished', now)
                return
            r.index, r.laps = 0, r.laps + 1
            self.lap_start = now
        shift = r.lap_offset_ns()
        for e in r.due(now - self.lap_start):
            self._publish(node, e, e.t_ns + shift)
        node.gate.output(now)

    @staticmethod
    def _publish(node, e, stamp_ns: int) -> None:
        node.stamp_ns = stamp_ns
        sec, nsec = divmod(stamp_ns, 1_000_000_000)
        if node.clock_pub is not None:
            node.clock_pub.publish(cdr.pack_clock(sec, nsec))
        if e.topic == common.COMMAND:
            node.replay_command_pub.publish(cdr.pack_float64(e.value))
            return
        if e.topic == common.JOINT_STATES:
            data = cdr.pack_joint_state(sec, nsec, node.packer.frame, node.packer.name,
                                        e.value, e.velocity, e.effort)
        else:
            data = cdr.pack_scalar(sec, nsec, node.packer.frame, e.value)
        node.pubs[e.topic].publish(data)
        node.samples += 1
