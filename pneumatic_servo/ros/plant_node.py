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

Every valve command passes the output gate (:mod:`pneumatic_servo.control.gate`).
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

from ..control.gate import MAX_V, MIN_V, SAFE_V, WATCHDOG_S, OutputGate
from ..control.params import Spec, SpecSet
from ..effects.layout import CORE_INDEX, CORE_PARAMS
from ..errors import ConfigError, PneumaticServoError
from . import cdr, common
from .common import COMMAND_QOS, SENSOR_QOS, MeasurementPacker

monotonic = time.monotonic
BACKENDS = ('sim', 'rig', 'replay')
CLOCK_MODES = ('free', 'lockstep')


def _cross(v: dict):
    if not (v.get('min_v', MIN_V) <= v.get('safe_v', SAFE_V) <= v.get('max_v', MAX_V)):
        return 'need min_v <= safe_v <= max_v (the safe voltage inside the clamp range)'
    if v.get('clock_mode') == 'lockstep' and v.get('backend', 'sim') != 'sim':
        return ('clock_mode lockstep needs backend sim (a rig runs in real time, a replay in '
                "the bag's time); use clock_mode:=free")
    if v.get('backend') == 'replay' and not v.get('bag'):
        return 'backend replay needs bag:=PATH (a rosbag2 directory)'
    if v.get('sim_values') and v.get('backend', 'sim') != 'sim':
        return 'sim_values needs backend sim (it sets parameters of the simulated plant)'
    return None


PLANT_SPECS = SpecSet([
    Spec('backend', 'sim', 'what is behind the node', choices=BACKENDS, read_only=True),
    Spec('clock_mode', 'free', 'sim: free-running real time, or lockstep with the controller '
         '(the node publishes /clock)', choices=CLOCK_MODES, read_only=True),
    Spec('rate_hz', 1000.0, 'sample and control rate', 'Hz', 1.0, 10000.0, read_only=True),
    Spec('joint_name', 'actuator_joint', 'joint name in joint_states', read_only=True),
    Spec('frame_id', '', 'header.frame_id of the measurements', read_only=True),
    Spec('model_config', '', "model config YAML ('' = the paper's rig); sim plant, virtual "
         'DAQ and the effort (A d_f (p_a - p_b))', read_only=True),
    Spec('integrator', 'adaptive', 'sim: adaptive (error-controlled, work-capped: default) or '
         'fixed-step RK4 (constant cost)',
         choices=('fixed', 'adaptive'), read_only=True),
    Spec('initial_angle_rad', math.nan, 'sim and virtual DAQ: start angle', 'rad', 0.0,
         CORE_PARAMS[CORE_INDEX['stroke_rad']].upper,
         read_only=True, allow_nan=True),
    Spec('supply_pa', math.nan, "sim: supply pressure (NaN = the config's)", 'Pa',
         CORE_PARAMS[CORE_INDEX['supply_pressure_pa']].lower,
         CORE_PARAMS[CORE_INDEX['supply_pressure_pa']].upper, allow_nan=True),
    Spec('rig_config', '', "rig wiring and scaling YAML ('' = config/rig_pci6229.yaml)",
         read_only=True),
    Spec('daq', 'nidaqmx', 'rig: DAQ driver', choices=('nidaqmx', 'virtual'), read_only=True),
    Spec('bag', '', 'replay: rosbag2 directory (sqlite3 or MCAP)', read_only=True),
    Spec('replay_rate', 1.0, 'replay: speed relative to the recording', '1', 0.01, 100.0),
    Spec('replay_loop', False, 'replay: start again at the end', read_only=True),
    Spec('replay_command', False, 'replay: also publish the recorded valve commands on '
         'valve/command, as ros2 bag play would (for a monitor beside a replay; run no '
         'controller then)', read_only=True),
    Spec('sim_values', '', "sim: model parameter values of the running plant, 'owner.name="
         "value, ...' [SI], settable at run time (e.g. piston_seal_leakage.seal_leak_area_m2="
         '3e-8 switches on a seal leak that model_config holds at its neutral value)'),
    Spec('replay_clock', False, "replay: also publish the bag's time on /clock (for a stack "
         'with use_sim_time; adds /clock to the graph)', read_only=True),
    Spec('watchdog_s', WATCHDOG_S, 'valve goes safe (latched fault) after this long without '
         'a new command; fixed while active', 's', 0.001, 10.0, safety=True),
    Spec('safe_v', SAFE_V, 'valve voltage while inactive, faulted or shutting down (the '
         'centre); fixed while active', 'V', MIN_V, MAX_V, safety=True),
    Spec('min_v', MIN_V, 'lowest valve voltage commanded (clamp); fixed while active', 'V',
         MIN_V, MAX_V, safety=True),
    Spec('max_v', MAX_V, 'highest valve voltage commanded (clamp); fixed while active', 'V',
         MIN_V, MAX_V, safety=True),
    Spec('lockstep_resend_s', 0.02, 'lockstep: resend the last measurement if unanswered '
         'this long (wall time)', 's', 0.001, 1.0),
    Spec('wait_subscribers', 0, 'lockstep and replay: start when joint_states has this many '
         'subscribers (say, the controller and a recorder that must see every sample); '
         'lockstep waits for at least 1', '', 0, 100, read_only=True),
    Spec('diagnostics_period_s', 0.1, 'period of /diagnostics', 's', 0.01, 10.0),
    Spec('realtime_priority', 0, 'SCHED_FIFO priority of the loop (1-99; 0 = normal '
         'scheduling); needs CAP_SYS_NICE or an rtprio limit', '', 0, 99, read_only=True),
    Spec('autostart', True, 'configure and activate at start (no lifecycle manager needed)',
         read_only=True),
], cross=_cross)


class PlantNode(LifecycleNode):
    """Plant node (see module doc). ``overrides`` preset parameter values (command line)."""

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
        self.backend = None
        self.replay = None
        self.state = 'unconfigured'
        self.halt_reason = ''
        self.packer = MeasurementPacker(self.p['joint_name'], self.p['frame_id'])
        self.pubs = {}
        for topic in common.MEASUREMENT_TOPICS:
            kind = (JointState if topic == common.JOINT_STATES else
                    FluidPressure if topic.endswith('pressure') else Temperature)
            self.pubs[topic] = self.create_publisher(kind, topic, SENSOR_QOS)
        self.diag_pub = self.create_publisher(common.DiagnosticArray, common.DIAGNOSTICS,
                                              common.DIAGNOSTICS_QOS)
        lockstep = self.p['clock_mode'] == 'lockstep'
        replay_clock = self.p['backend'] == 'replay' and self.p['replay_clock']
        self.clock_pub = (self.create_publisher(Clock, common.CLOCK, QoSProfile(depth=10))
                          if lockstep or replay_clock else None)
        self.command_sub = self.create_subscription(Float64, common.COMMAND, self._on_command,
                                                    COMMAND_QOS, raw=True)
        self.replay_command_pub = (
            self.create_publisher(Float64, common.COMMAND, COMMAND_QOS)
            if self.p['backend'] == 'replay' and self.p['replay_command'] else None)
        # the voltage the gate gave the valve over the period that ends at a sample, just
        # before that sample (an extension of the interface: a monitor then knows the input)
        self.applied_pub = self.create_publisher(Float64, common.VALVE_APPLIED, SENSOR_QOS)
        self._applied = None
        self.hot_subscriptions = [self.command_sub]
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
        self.state = 'inactive'
        self.get_logger().info(f'configured: {self.description}')
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
        self.description = (self.backend or self.replay).description

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
        if self.halt_reason and self.backend is None and self.replay is None:
            return TransitionCallbackReturn.FAILURE
        self._set_priority()
        # activation is the operator's acknowledgement: latched faults clear
        self.gate.reset()
        self.gate.release()
        self.halt_reason = ''
        self.state = 'active'
        now = monotonic()
        self._reset_counters()
        self._t_start = now
        if self.replay is not None:
            self._replay_start = now
            self._started = False
        else:
            try:
                self._m = self.backend.start()
            except PneumaticServoError as exc:
                self._halt(f'start failed: {exc}', now)
                return TransitionCallbackReturn.SUCCESS
            if self.lockstep:
                self._started = False  # the first sample waits for the subscribers
            else:
                self._publish(self._m, now)
            self._next_step = now + self.period_s
        self.get_logger().info(f'active: {self.p["backend"]}, {self.p["clock_mode"]} clock, '
                               f'{self.p["rate_hz"]:g} Hz')
        self._publish_diagnostics(now, force=True)
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._go_safe('inactive')
        self.state = 'inactive'
        self._publish_diagnostics(monotonic(), force=True)
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._go_safe('unconfigured')
        if self.backend is not None:
            self.backend.close()
        self.backend = self.replay = None
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
        self._publish_diagnostics(now, force=True)

    def shutdown(self, reason: str) -> None:
        """Safe output, last diagnostics (the event loop calls this on signals and errors)."""
        if self.state == 'shut down':
            return
        self._go_safe(f'shutdown ({reason})')
        self.state = 'shut down'
        try:
            self._publish_diagnostics(monotonic(), force=True,
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
        self.gate.command(value, now)
        if self._sent_at:
            # plant publish -> command received, on this process's monotonic clock
            self._latency.append(now - self._sent_at)
        if self.state == 'active' and self.backend is not None:
            try:
                self.backend.apply(self.gate.output(now))
            except PneumaticServoError as exc:
                self._halt(f'valve write failed: {exc}', now)
        if self._awaiting:
            self._answered = True
        if self.gate.faulted:
            self._publish_diagnostics(now)

    # ---------------------------------------------------------------- the loop
    def _reset_counters(self) -> None:
        self._k = 0
        self._awaiting = False
        self._answered = False
        self._sent_at = 0.0
        self._next_step = math.inf
        self._paced = False
        self._started = True
        self._ready_since = None
        self._periods = collections.deque(maxlen=5000)  # the last ~5 s at 1 kHz
        self._latency = collections.deque(maxlen=5000)
        self._last_tick = None
        self.overruns = 0
        self.resends = 0

    @property
    def lockstep(self) -> bool:
        return self.p['clock_mode'] == 'lockstep'

    @property
    def started(self) -> bool:
        """Whether the first sample has gone out (lockstep and replay wait for subscribers)."""
        return self._started

    @property
    def samples(self) -> int:
        """Sample periods run so far (sim time = ``samples * period_s``)."""
        return self._k

    def next_deadline(self) -> float:
        if self.state != 'active':
            return self._next_diag
        if self.replay is not None:
            nxt = (self._replay_start + self.replay.next_offset_s() if self._started
                   else monotonic() + 0.005)
        elif self.lockstep and not self._started:
            nxt = monotonic() + 0.005
        elif self.lockstep and not self._paced:
            nxt = (monotonic() if self._answered else
                   self._sent_at + min(self.p['lockstep_resend_s'], self.gate.watchdog_s))
        else:
            nxt = self._next_step
        return min(nxt, self._next_diag)

    def tick(self, now: float) -> None:
        if self.state == 'active':
            try:
                if self.replay is not None:
                    self._tick_replay(now)
                elif self.lockstep and not self._paced:
                    self._tick_lockstep(now)
                elif now >= self._next_step:
                    self._tick_free(now)
            except Exception as exc:  # noqa: BLE001 - any failure must leave the valve safe
                self._halt(f'{type(exc).__name__}: {exc}', now)
        if now >= self._next_diag:
            self._publish_diagnostics(now)

    def _step(self, now: float) -> None:
        """One sample period: the gate's output to the backend, the measurement out."""
        if self._last_tick is not None:
            self._periods.append(now - self._last_tick)
        self._last_tick = now
        u = self.gate.output(now)
        self._m = self.backend.step(u)
        self._applied = u
        self._k += 1
        self._publish(self._m, now)

    def _tick_free(self, now: float) -> None:
        self._step(now)
        self._next_step += self.period_s
        if now - self._next_step > self.period_s:
            # more than a period late: count it and resynchronise instead of bursting
            self.overruns += 1
            self._next_step = now + self.period_s

    def _tick_lockstep(self, now: float) -> None:
        if not self._started:
            # start once the controller (and whoever else must see sample 0, such as a
            # recorder) is subscribed, plus a moment for the other topics to match too
            if self._ready(now, max(1, self.p['wait_subscribers'])):
                self._started = True
                self._publish(self._m, now)
            return
        if self._answered:
            self._step(now)
            return
        waited = now - self._sent_at
        # the watchdog counts from the last *new* command: resending the measurement below
        # does not feed it, so a dead controller trips it in lockstep as in real time
        armed = self.gate.armed
        self.gate.output(now)
        if armed and self.gate.faulted:
            self.get_logger().error('lockstep: no new command within the watchdog period; '
                                    'valve safe, continuing in real time')
            self._paced = True
            self._next_step = now
            self._publish_diagnostics(now, force=True)
        elif waited > self.p['lockstep_resend_s']:
            # a lost measurement, or a controller that is not there yet: say it again
            self.resends += 1
            self._publish(self._m, now)

    def _ready(self, now: float, subscribers: int) -> bool:
        """True once joint_states has ``subscribers`` subscribers, plus 0.1 s for the other
        topics of the same subscribers to match too."""
        if self.pubs[common.JOINT_STATES].get_subscription_count() < subscribers:
            self._ready_since = None
            return False
        if self._ready_since is None:
            self._ready_since = now
        return now - self._ready_since >= 0.1

    def _tick_replay(self, now: float) -> None:
        r = self.replay
        if not self._started:
            if self._ready(now, self.p['wait_subscribers']):
                self._started = True
                self._replay_start = now
            return
        if r.index >= len(r.events):
            if not r.loop:
                self.state = 'finished'
                self._go_safe('replay finished')
                self.get_logger().info('replay finished')
                self._publish_diagnostics(now, force=True)
                return
            r.index, r.laps = 0, r.laps + 1
            self._replay_start = now
        shift = r.lap_offset_ns()
        for e in r.due(now - self._replay_start):
            self._publish_replay(e, e.t_ns + shift)
        self.gate.output(now)

    # ------------------------------------------------------------- publishing
    def _publish(self, m, now: float) -> None:
        stamp = self._k * self.period_ns if self.lockstep else self.get_clock().now().nanoseconds
        self._stamp_ns = stamp
        if self.clock_pub is not None:
            self.clock_pub.publish(cdr.pack_clock(*divmod(stamp, 1_000_000_000)))
        if self._applied is not None:
            self.applied_pub.publish(cdr.pack_float64(self._applied))
            self._applied = None
        for topic, data in self.packer.pack(m, stamp):
            self.pubs[topic].publish(data)
        self._sent_at = now
        self._awaiting = self.lockstep and not self._paced
        self._answered = False

    def _publish_replay(self, e, stamp_ns: int) -> None:
        self._stamp_ns = stamp_ns
        sec, nsec = divmod(stamp_ns, 1_000_000_000)
        if self.clock_pub is not None:
            self.clock_pub.publish(cdr.pack_clock(sec, nsec))
        if e.topic == common.COMMAND:
            self.replay_command_pub.publish(cdr.pack_float64(e.value))
            return
        if e.topic == common.JOINT_STATES:
            data = cdr.pack_joint_state(sec, nsec, self.packer.frame, self.packer.name, e.value,
                                        e.velocity, e.effort)
        else:
            data = cdr.pack_scalar(sec, nsec, self.packer.frame, e.value)
        self.pubs[e.topic].publish(data)
        self._k += 1

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

    def _publish_diagnostics(self, now: float, force: bool = False, extra: str = '') -> None:
        gs = self.gate.status(now)
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
                  'watchdog_ms': self.gate.watchdog_s * 1e3, 'samples': self._k,
                  'overruns': self.overruns, 'resends': self.resends,
                  'scheduling': getattr(self, 'priority', 'normal'),
                  'sim_time_s': self._k * self.period_s if self.lockstep else math.nan}
        values.update(self.timing())
        stamp = getattr(self, '_stamp_ns', None) if self.lockstep else None
        if stamp is None:
            stamp = self.get_clock().now().nanoseconds
        source = self.backend or self.replay
        values['description'] = getattr(source, 'description', self.p['backend'])
        hardware = getattr(source, 'hardware_id', '') or self.p['backend']
        self.diag_pub.publish(common.diagnostic_array(
            stamp, f'{self.get_name()}: plant', hardware, level, message, values))


def common_path(path: str):
    from .paths import resolve
    return resolve(path) if path else None
