"""The plant node: the actuator as ROS sees it, whatever is behind it.

Publishes ``joint_states``, ``chamber_a/pressure``, ``chamber_b/pressure``,
``supply/pressure`` and, when known, ``chamber_a/temperature`` and
``chamber_b/temperature``; subscribes to ``valve/command``; reports on
``/diagnostics``. The parameter ``backend`` picks what is behind it:

* ``sim``: the nonlinear model (``model_config``: components, effects,
  values), ``clock_mode`` ``free`` (real time at ``rate_hz``) or
  ``lockstep`` (the node owns ``/clock`` and advances one period only after
  the controller answered the last measurement: deterministic, faster than
  real time; a controller with ``use_sim_time`` cannot tell);
* ``rig``: a DAQ through :mod:`pneumatic_servo.rig` (``daq`` ``nidaqmx`` or
  ``virtual``; scaling and channels from ``rig_config``);
* ``replay``: a recorded bag's measurements in their own time (and its
  time on ``/clock``).

Parameters: :mod:`.plant_specs`; when samples are due: one pacing strategy per clock
mode (:mod:`.pacing`). Every valve command passes the output gate
(:mod:`pneumatic_servo.control.gate`).
A lifecycle node: inactive, shutting down, faulted or on any exception the
valve is at 5 V. With ``autostart`` (default) it configures and activates
itself, so it runs without a lifecycle manager.
"""
from __future__ import annotations

import collections
import math
import time

from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.qos import QoSProfile
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import FluidPressure, JointState, Temperature
from std_msgs.msg import Float64

from ..control.gate import OutputGate
from ..errors import ConfigError, PneumaticServoError
from . import cdr, common
from .common import COMMAND_QOS, SENSOR_QOS, MeasurementPacker
from .plant_specs import PLANT_SPECS

monotonic = time.monotonic


class PlantNode(LifecycleNode):
    """Plant node (see module doc). ``overrides`` preset parameter values (command line).

    ``state`` refines the lifecycle state for /diagnostics: 'unconfigured', 'inactive',
    'active', 'halted' (a latched fault: valve safe until reactivated), 'finished' (a replay
    at its end) or 'shut down'.
    """

    def __init__(self, node_name: str = 'pneumatic_servo_plant', overrides: dict | None = None,
                 **kwargs):
        super().__init__(node_name, **kwargs)
        self.p = common.declare(self, PLANT_SPECS, overrides)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.period_s = 1.0 / self.p['rate_hz']
        self.period_ns = int(round(self.period_s * 1e9))
        self.gate = OutputGate(self.p['watchdog_s'], self.p['safe_v'], self.p['min_v'],
                               self.p['max_v'])
        self.gate.hold('not active')
        self.backend = self.replay = self.pacing = None
        self.state = 'unconfigured'
        self.halt_reason = ''
        self.packer = MeasurementPacker(self.p['joint_name'], self.p['frame_id'])
        self.pubs = {}
        self.clock_pub = self.replay_command_pub = self.applied_pub = None
        self.diag_pub = self.create_publisher(common.DiagnosticArray, common.DIAGNOSTICS,
                                              common.DIAGNOSTICS_QOS)
        self.command_sub = self.create_subscription(Float64, common.COMMAND, self._on_command,
                                                    COMMAND_QOS, raw=True)
        self.hot_subscriptions = [self.command_sub]
        self._applied = None
        self._reset_counters()
        self._next_diag = 0.0
        self._last_diag_key = None
        if self.p['autostart']:
            ret = self.trigger_configure()
            if ret != TransitionCallbackReturn.SUCCESS:
                raise ConfigError(self.halt_reason or 'plant: configure failed')
            if self.trigger_activate() != TransitionCallbackReturn.SUCCESS:
                reason = self.halt_reason or 'activation failed'
                self.get_logger().error(f'activate failed: {reason}; valve held safe')
                raise ConfigError(f'plant: {reason}')

    # -------------------------------------------------------------- parameters
    def _on_set_parameters(self, params):
        result = common.validate_update(PLANT_SPECS, self.p, params,
                                        active=self.state == 'active')
        values = [prm.value for prm in params if prm.name == 'sim_values']
        if result.successful and values and self.backend is not None \
                and self.backend.kind == 'sim':
            try:
                self.backend.set_values(values[-1])
            except ConfigError as exc:
                result.successful, result.reason = False, str(exc)
            else:
                self.get_logger().info(f'sim_values set: {values[-1]!r}')
        if result.successful:
            for prm in params:
                if prm.name in self.p:
                    self.p[prm.name] = PLANT_SPECS[prm.name].coerce(prm.value)
            # safety values change only while inactive (validate_update refuses them else)
            self.gate = OutputGate(self.p['watchdog_s'], self.p['safe_v'], self.p['min_v'],
                                   self.p['max_v']) if self.state != 'active' else self.gate
            if self.state != 'active':
                self.gate.hold(self.state)
            if self.backend is not None and self.backend.kind == 'sim' \
                    and math.isfinite(self.p['supply_pa']):
                self.backend.stepper.supply_pa = self.p['supply_pa']
            if self.replay is not None:
                self.replay.rate = self.p['replay_rate']
        return result

    # --------------------------------------------------------------- lifecycle
    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        try:
            self._build_backend()
        except Exception as exc:  # noqa: BLE001 - whatever it is, the reason is logged
            reason = str(exc) if isinstance(exc, PneumaticServoError) else \
                f'{type(exc).__name__}: {exc}'
            self.halt_reason = ' '.join(reason.split())
            self.get_logger().error(f'configure failed: {self.halt_reason}')
            return TransitionCallbackReturn.FAILURE
        self._create_publishers()
        self.state = 'inactive'
        self.get_logger().info(f'configured: {self.source.description}')
        return TransitionCallbackReturn.SUCCESS

    def _build_backend(self) -> None:
        from ..model import ModelConfig
        from .backends import ReplaySource, RigBackend, SimBackend
        p = self.p
        path = common_path(p['model_config'])
        model_config = ModelConfig.load(path) if path else ModelConfig.paper()
        if p['backend'] == 'sim':
            self.backend = SimBackend(model_config, self.period_s, p['initial_angle_rad'],
                                      p['supply_pa'], p['integrator'])
            if p['sim_values']:
                self.backend.set_values(p['sim_values'])
        elif p['backend'] == 'rig':
            from ..rig import RigConfig
            from .paths import resolve
            rig = RigConfig.load(resolve(p['rig_config'], 'rig_pci6229.yaml'))
            self.backend = RigBackend(rig, p['daq'], self.period_s, model_config,
                                      p['initial_angle_rad'])
        else:
            self.replay = ReplaySource(p['bag'], p['joint_name'], p['replay_rate'],
                                       p['replay_loop'], p['replay_command'])

    def _create_publishers(self) -> None:
        """The measurement publishers, and /clock and valve/command where the mode needs
        them (as ros2/demos lifecycle_py: publishers belong to the configured node)."""
        for topic in common.MEASUREMENT_TOPICS:
            kind = (JointState if topic == common.JOINT_STATES else
                    FluidPressure if topic.endswith('pressure') else Temperature)
            self.pubs[topic] = self.create_publisher(kind, topic, SENSOR_QOS)
        replay = self.replay is not None
        if self.lockstep or (replay and self.p['replay_clock']):
            self.clock_pub = self.create_publisher(Clock, common.CLOCK, QoSProfile(depth=10))
        if replay and self.p['replay_command']:
            self.replay_command_pub = self.create_publisher(Float64, common.COMMAND,
                                                            COMMAND_QOS)
        # the voltage the gate gave the valve over the period that ends at a sample, just
        # before that sample (an extension of the interface: a monitor then knows the input)
        self.applied_pub = self.create_publisher(Float64, common.VALVE_APPLIED, SENSOR_QOS)

    def _destroy_publishers(self) -> None:
        for pub in [*self.pubs.values(), self.clock_pub, self.replay_command_pub,
                    self.applied_pub]:
            if pub is not None:
                self.destroy_publisher(pub)
        self.pubs = {}
        self.clock_pub = self.replay_command_pub = self.applied_pub = None

    @property
    def source(self):
        """What is behind the node: the backend, or the replayed bag (None unconfigured)."""
        return self.backend or self.replay

    def _set_priority(self) -> None:
        """Real-time scheduling for the loop thread, if asked for and allowed."""
        prio = self.p['realtime_priority']
        self.priority = 'normal'
        if prio <= 0:
            return
        import os
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(prio))
            self.priority = f'SCHED_FIFO {prio}'
        except (OSError, AttributeError) as exc:
            self.get_logger().warn(f'realtime_priority {prio} not set ({exc}); running with '
                                   'normal scheduling')

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        from . import pacing
        if self.halt_reason and self.source is None:
            return TransitionCallbackReturn.FAILURE
        self._set_priority()
        # activation is the operator's acknowledgement: latched faults clear
        self.gate.reset()
        self.gate.release()
        self.halt_reason = ''
        self.state = 'active'
        now = monotonic()
        self._reset_counters()
        if self.replay is None:
            try:
                self.measurement = self.backend.start()
            except PneumaticServoError as exc:
                self._halt(f'start failed: {exc}', now)
                return TransitionCallbackReturn.SUCCESS
        strategy = (pacing.Replay if self.replay is not None else
                    pacing.Lockstep if self.lockstep else pacing.FreeRunning)
        self.pacing = strategy(self, now)
        self.get_logger().info(f'active: {self.p["backend"]}, {self.p["clock_mode"]} clock, '
                               f'{self.p["rate_hz"]:g} Hz')
        self.publish_diagnostics(now, force=True)
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._go_safe('inactive')
        self.state = 'inactive'
        self.publish_diagnostics(monotonic(), force=True)
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._go_safe('unconfigured')
        if self.backend is not None:
            self.backend.close()
        self.backend = self.replay = self.pacing = None
        self._destroy_publishers()
        self.state = 'unconfigured'
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.shutdown('lifecycle shutdown')
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._go_safe('error')
        return TransitionCallbackReturn.SUCCESS

    # ----------------------------------------------------------------- safety
    def _go_safe(self, reason: str) -> None:
        """Hold the gate and write the safe voltage to whatever valve there is."""
        self.gate.hold(reason)
        if self.backend is not None:
            try:
                self.backend.safe()
            except Exception as exc:  # already failing safe; say so, keep going
                self.get_logger().error(f'writing the safe output failed: {exc}')

    def _halt(self, reason: str, now: float) -> None:
        """A fault the loop cannot continue from: latch it, go safe, stop stepping."""
        self.gate.trip(reason)
        if self.backend is not None:
            try:
                self.backend.safe()
            except Exception as exc:
                self.get_logger().error(f'writing the safe output failed: {exc}')
        self.halt_reason = reason
        self.state = 'halted'
        self.get_logger().error(f'halted, valve at {self.gate.safe_v:.2f} V: {reason}')
        self.publish_diagnostics(now, force=True)

    def finish(self, reason: str, now: float) -> None:
        """The source has ended (a replay without loop): valve safe, say so."""
        self.state = 'finished'
        self._go_safe(reason)
        self.get_logger().info(reason)
        self.publish_diagnostics(now, force=True)

    def shutdown(self, reason: str) -> None:
        """Safe output, last diagnostics (the event loop calls this on signals and errors)."""
        if self.state == 'shut down':
            return
        self._go_safe(f'shutdown ({reason})')
        self.state = 'shut down'
        try:
            self.publish_diagnostics(monotonic(), force=True,
                                     extra=f'shut down ({reason}): valve at '
                                           f'{self.gate.safe_v:.2f} V')
        except Exception:  # the context may already be gone
            pass
        if self.backend is not None:
            try:
                self.backend.close()
            except Exception as exc:
                self.get_logger().error(f'closing the backend failed: {exc}')

    # --------------------------------------------------------------- commands
    def _on_command(self, data: bytes) -> None:
        now = monotonic()
        try:
            value = cdr.unpack_float64(data)
        except (ValueError, IndexError):
            value = math.nan  # a malformed command is a non-finite one: the gate latches
        self.gate.command(value, self.gate_time(now))
        self.commanded_at = now
        if self.sent_at:
            # plant publish -> command received, on this process's monotonic clock
            self._latency.append(now - self.sent_at)
        if self.state == 'active' and self.backend is not None:
            try:
                self.backend.apply(self.gate.output(self.gate_time(now)))
            except PneumaticServoError as exc:
                self._halt(f'valve write failed: {exc}', now)
        self.answered = True  # the last measurement has its answer (lockstep waits for it)
        if self.gate.faulted:
            self.publish_diagnostics(now)

    # ---------------------------------------------------------------- the loop
    def _reset_counters(self) -> None:
        self.samples = 0  # sample periods run (sim time = samples * period_s)
        self.answered = False
        self.sent_at = 0.0
        self.commanded_at = 0.0  # [s] wall time of the last command
        self._periods = collections.deque(maxlen=5000)  # the last ~5 s at 1 kHz
        self._latency = collections.deque(maxlen=5000)
        self._last_tick = None
        self.overruns = 0
        self.resends = 0

    def gate_time(self, now: float) -> float:
        """[s] The clock the gate's watchdog counts: sim time while in lockstep, where the
        simulation waits for each answer and a controller stalled by a loaded machine must
        not trip it (:class:`.pacing.Lockstep` gives a silent one up after
        ``lockstep_patience_s`` of wall time instead); else ``now``."""
        return self.samples * self.period_s if getattr(self.pacing, 'sim_clock', False) \
            else now

    @property
    def lockstep(self) -> bool:
        return self.p['clock_mode'] == 'lockstep'

    @property
    def started(self) -> bool:
        """Whether the first sample has gone out (lockstep and replay wait for subscribers)."""
        return self.pacing is not None and self.pacing.started

    def next_deadline(self) -> float:
        if self.state != 'active' or self.pacing is None:
            return self._next_diag
        return min(self.pacing.deadline(self, monotonic()), self._next_diag)

    def tick(self, now: float) -> None:
        if self.state == 'active' and self.pacing is not None:
            try:
                self.pacing.tick(self, now)
            except Exception as exc:  # noqa: BLE001 - any failure must leave the valve safe
                self._halt(f'{type(exc).__name__}: {exc}', now)
        if now >= self._next_diag:
            self.publish_diagnostics(now)

    def step(self, now: float) -> None:
        """One sample period: the gate's output to the backend, the measurement out."""
        if self._last_tick is not None:
            self._periods.append(now - self._last_tick)
        self._last_tick = now
        u = self.gate.output(self.gate_time(now))
        self.measurement = self.backend.step(u)
        self._applied = u
        self.samples += 1
        self.publish(self.measurement, now)

    def publish(self, m, now: float) -> None:
        """A measurement out, stamped with sim time (lockstep) or the node's clock."""
        stamp = self.samples * self.period_ns if self.lockstep else \
            self.get_clock().now().nanoseconds
        self.stamp_ns = stamp
        if self.clock_pub is not None:
            self.clock_pub.publish(cdr.pack_clock(*divmod(stamp, 1_000_000_000)))
        if self._applied is not None:
            self.applied_pub.publish(cdr.pack_float64(self._applied))
            self._applied = None
        for topic, data in self.packer.pack(m, stamp):
            self.pubs[topic].publish(data)
        self.sent_at = now
        self.answered = False

    # ------------------------------------------------------------- diagnostics
    def timing(self) -> dict:
        """Achieved rate and period jitter over the recent ticks."""
        import numpy as np
        if len(self._periods) < 2:
            return {}
        per = np.fromiter(self._periods, float)
        jitter = np.abs(per - self.period_s)
        out = {'achieved_rate_hz': 1.0 / float(np.mean(per)),
               'period_p50_ms': float(np.percentile(per, 50)) * 1e3,
               'jitter_p50_ms': float(np.percentile(jitter, 50)) * 1e3,
               'jitter_p99_ms': float(np.percentile(jitter, 99)) * 1e3,
               'timed_periods': len(per)}
        if len(self._latency) > 1:
            lat = np.fromiter(self._latency, float)
            out.update({'latency_p50_ms': float(np.percentile(lat, 50)) * 1e3,
                        'latency_p99_ms': float(np.percentile(lat, 99)) * 1e3})
        return out

    def publish_diagnostics(self, now: float, force: bool = False, extra: str = '') -> None:
        gs = self.gate.status(self.gate_time(now))
        level, message = gs.level, gs.message
        if self.state == 'halted' and level != 'error':
            level, message = 'error', f'halted: {self.halt_reason}'
        if extra:
            message = f'{extra}; {message}'
        key = (level, message.split(':')[0])
        if not force and now < self._next_diag and key == self._last_diag_key:
            return
        self._last_diag_key = key
        self._next_diag = now + self.p['diagnostics_period_s']
        values = {'backend': self.p['backend'], 'clock_mode': self.p['clock_mode'],
                  'state': self.state, 'output_v': gs.output_v,
                  'last_command_v': gs.last_command_v,
                  'command_age_ms': gs.command_age_s * 1e3, 'faults': list(gs.faults),
                  'commands': gs.commands, 'clamped': gs.clamped,
                  'non_finite': gs.non_finite, 'ignored': gs.ignored,
                  'watchdog_ms': self.gate.watchdog_s * 1e3, 'samples': self.samples,
                  'overruns': self.overruns, 'resends': self.resends,
                  'scheduling': getattr(self, 'priority', 'normal'),
                  'sim_time_s': self.samples * self.period_s if self.lockstep else math.nan}
        values.update(self.timing())
        stamp = getattr(self, 'stamp_ns', None) if self.lockstep else None
        if stamp is None:
            stamp = self.get_clock().now().nanoseconds
        source = self.source
        values['description'] = getattr(source, 'description', self.p['backend'])
        hardware = getattr(source, 'hardware_id', '') or self.p['backend']
        self.diag_pub.publish(common.diagnostic_array(
            stamp, f'{self.get_name()}: plant', hardware, level, message, values))


def common_path(path: str):
    from .paths import resolve
    return resolve(path) if path else None
