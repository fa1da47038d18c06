"""A single-threaded event loop for real-time nodes: fast message waits, deadlines, signals.

Why not ``rclpy.spin``: the stock executor rebuilds its wait set from every
entity of every node on each turn (parameter and lifecycle services
included), about 0.1 ms of Python per turn on this machine. At 1 kHz, with
six measurement topics and a round trip per control period, that overhead
alone would cap lockstep near real time. Here the *hot* subscriptions (the
measurements, the valve command, ``/clock``) wait in a small wait set of
their own and are dispatched directly to their callbacks; the executor runs
once per ``service_period_s`` for everything else (parameters, lifecycle,
setpoints, trajectories). Nodes publish from the same thread: no locks, no
GIL hand-offs.

A node taking part implements::

    hot_subscriptions: list          # rclpy Subscriptions to wait on directly
    next_deadline() -> float         # monotonic time of its next due work, or inf
    tick(now) -> None                # do whatever is due at ``now`` [s, monotonic]
    shutdown(reason) -> None         # drive outputs safe; last diagnostics

Every catchable signal that would end the process (:data:`STOP_SIGNALS`: SIGINT,
SIGTERM, SIGHUP, SIGQUIT, SIGUSR1/2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGXFSZ)
ends the loop instead; then every node's ``shutdown`` runs (the plant writes the
safe valve voltage and says so on /diagnostics). SIGKILL cannot be caught: the
plant's watchdog covers a killed controller, and a child process is killed with
its parent (``PR_SET_PDEATHSIG``, see :mod:`.run`).
"""
from __future__ import annotations

import math
import signal
import threading
import time

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions

from . import private

monotonic = time.monotonic


class _Stop:
    """Why the process was asked to stop (a signal name), and whom to tell."""

    def __init__(self):
        self.reason = ''
        self.listener = None

    def __call__(self, signum, frame):
        self.reason = self.reason or signal.Signals(signum).name
        if self.listener is not None:
            self.listener(self.reason)


STOP = _Stop()
#: the catchable signals whose default action ends the process (SIGPIPE stays ignored, as
#: Python sets it: a closed pipe is an error on the write, not a stop)
STOP_SIGNALS = tuple(getattr(signal, name) for name in (
    'SIGINT', 'SIGTERM', 'SIGHUP', 'SIGQUIT', 'SIGUSR1', 'SIGUSR2', 'SIGALRM', 'SIGVTALRM',
    'SIGPROF', 'SIGXCPU', 'SIGXFSZ') if hasattr(signal, name))


def init_ros(args=None, domain_id: int | None = None) -> None:
    """``rclpy.init`` without rclpy's signal handlers (the event loop handles signals)."""
    rclpy.init(args=args, domain_id=domain_id,
               signal_handler_options=SignalHandlerOptions.NO)


def shutdown_ros() -> None:
    rclpy.try_shutdown()


def install_stop_handlers(listener=None) -> None:
    """Every signal of :data:`STOP_SIGNALS` records a stop request instead of killing the
    process, from the very start (a signal while a model compiles must still end with the
    valve safe)."""
    if threading.current_thread() is not threading.main_thread():
        return
    STOP.listener = listener
    for sig in STOP_SIGNALS:
        signal.signal(sig, STOP)


class FastWaiter:
    """Waits on a fixed set of subscriptions and dispatches each message to its callback."""

    def __init__(self, context, subscriptions):
        self.subs = [s for s in subscriptions if s is not None]
        self._ws = private.wait_set(context, len(self.subs))

    def wait(self, timeout_s: float) -> int:
        """Wait up to ``timeout_s`` [s]; dispatch everything ready; returns the count."""
        if not self.subs:
            if timeout_s > 0:
                time.sleep(timeout_s)
            return 0
        ready = private.wait(self._ws, self.subs, timeout_s * 1e9)
        n = 0
        if ready:
            for s in self.subs:
                # one message per subscription and turn: a queue left over makes the next
                # wait return at once, and saves the empty take that ends a drain loop
                if private.is_ready(s, ready):
                    msg = private.take(s)
                    if msg is not None:
                        s.callback(msg)
                        n += 1
        return n


class EventLoop:
    """Runs ``nodes`` (see module doc) until a signal, :meth:`stop` or ``until`` [monotonic s].

    Parameters
    ----------
    nodes : list
        rclpy nodes implementing the loop protocol (others are only spun).
    service_period_s : float [s]
        How often the executor serves parameters, services and cold topics.
    """

    def __init__(self, nodes, service_period_s: float = 0.005):
        self.nodes = list(nodes)
        self.service_period_s = service_period_s
        self.context = self.nodes[0].context
        self.executor = SingleThreadedExecutor(context=self.context)
        for n in self.nodes:
            self.executor.add_node(n)
        self.stop_reason = ''
        self._rebuild = True
        self._waiter = None

    def refresh(self) -> None:
        """Re-read the nodes' hot subscriptions (after a node created or destroyed some)."""
        self._rebuild = True

    def stop(self, reason: str = 'stopped') -> None:
        if not self.stop_reason:
            self.stop_reason = reason

    def install_signal_handlers(self) -> None:
        """The stop signals end the loop (then the nodes shut down safely)."""
        install_stop_handlers(self.stop)
        if STOP.reason:  # a signal arrived while the nodes were being built
            self.stop(STOP.reason)

    def _hot(self):
        subs = []
        for n in self.nodes:
            subs += list(getattr(n, 'hot_subscriptions', ()))
        return subs

    def spin_once(self, timeout_s: float = 0.0) -> None:
        """One turn: due ticks, a wait on the hot subscriptions, maybe the executor."""
        if self._rebuild:
            self._waiter = FastWaiter(self.context, self._hot())
            self._rebuild = False
            self._next_service = 0.0
        now = monotonic()
        for n in self.nodes:
            tick = getattr(n, 'tick', None)
            if tick is not None:
                tick(now)
        now = monotonic()
        deadline = min((n.next_deadline() for n in self.nodes if hasattr(n, 'next_deadline')),
                       default=math.inf)
        wake = min(deadline, self._next_service, now + timeout_s)
        self._waiter.wait(max(wake - now, 0.0))
        now = monotonic()
        if now >= self._next_service:
            self.executor.spin_once(timeout_sec=0.0)
            self._next_service = now + self.service_period_s

    def run(self, until: float = math.inf, stop_when=None) -> str:
        """Loop until stopped, a signal, the context shuts down, ``until`` [monotonic s], or
        ``stop_when()`` returns a reason (checked every turn; '' or None: go on); returns
        why it stopped."""
        while not self.stop_reason:
            if not self.context.ok():
                self.stop('context shut down')
                break
            if monotonic() >= until:
                self.stop('time up')
                break
            reason = stop_when() if stop_when is not None else None
            if reason:
                self.stop(reason)
                break
            self.spin_once(min(self.service_period_s, max(until - monotonic(), 0.0)))
        return self.stop_reason

    def shutdown(self, reason: str | None = None, drain_s: float = 0.1) -> None:
        """Every node's safe shutdown (reverse order: controller before plant), then
        ``drain_s`` [s] of spinning so the last messages leave (and reach a recorder in the
        same process)."""
        reason = reason or self.stop_reason or 'shutdown'
        for n in reversed(self.nodes):
            fn = getattr(n, 'shutdown', None)
            if fn is not None:
                try:
                    fn(reason)
                except Exception as exc:  # keep going: the other nodes must go safe too
                    n.get_logger().error(f'shutdown failed: {exc}')
        end = monotonic() + drain_s
        while monotonic() < end and self.context.ok():
            try:
                self.executor.spin_once(timeout_sec=0.02)
            except Exception:
                break


def run_nodes(factories, duration_s: float = math.inf, ros_args=None, stop_when=None,
              domain_id: int | None = None, drain_s: float = 0.1) -> str:
    """The one way the package runs nodes: initialise rclpy, create the nodes from
    ``factories`` (callables, in order), run them in one :class:`EventLoop` until a signal,
    ``duration_s`` [wall s] or ``stop_when()`` returns a reason; then every node's safe
    shutdown, ``drain_s`` [s] for the last messages, ``destroy_node`` and rclpy's shutdown,
    on every exit path. Returns why it stopped (:func:`.run.exit_code` maps it to an exit
    status). A node that needs to finish something after the drain (a recorder closing its
    bag) does it in ``destroy_node``."""
    install_stop_handlers()
    init_ros(ros_args, domain_id)
    nodes, loop = [], None
    try:
        for make in factories:
            nodes.append(make())
            if STOP.reason:
                break
        loop = EventLoop(nodes)
        loop.install_signal_handlers()
        try:
            reason = loop.run(monotonic() + duration_s, stop_when)
        except Exception as exc:  # noqa: BLE001 - every failure ends with the valve safe
            reason = f'exception: {type(exc).__name__}: {exc}'
            for n in nodes:
                n.get_logger().error(reason)
        loop.shutdown(reason, drain_s)
        return reason
    except BaseException:
        if loop is None:  # failed while building: whatever exists goes safe
            for n in reversed(nodes):
                try:
                    getattr(n, 'shutdown', lambda reason: None)('start-up failed')
                except Exception:
                    pass
        raise
    finally:
        for n in reversed(nodes):
            try:
                n.destroy_node()
            except Exception:
                pass
        shutdown_ros()
