"""The controller node: measurements and a target in, a valve command out.

Subscribes to ``joint_states`` and the pressure and temperature topics, to
``setpoint`` (std_msgs/Float64, rad) and ``joint_trajectory``
(trajectory_msgs/JointTrajectory); publishes ``valve/command``
(std_msgs/Float64, V) once per measurement. Control laws are pure
(:mod:`pneumatic_servo.control`): ``controller`` = ``pid`` or ``smc``
(sliding mode with the valve inverted through the model core; needs the
chamber pressures).

Time is the measurements' ``header.stamp``: the same law runs in lockstep sim
time, in real time and on a replayed bag. A sample whose stamp is not newer
than the last one handled is ignored, so a measurement sent twice (lockstep
resend) is answered once; if it is still being resent ``REANSWER_S`` after the
answer, that answer was lost (sent before the plant's subscription matched) and
the same command goes out again, or a lockstep plant would wait forever. A stamp
more than ``restart_jump_s`` older, or an older one sent twice (a lockstep plant
restarted its clock less than ``restart_jump_s`` in), starts the law afresh. A
sample whose stamp leaves the stream by more than ``max_stamp_skew_s`` (its offset
from the local monotonic clock jumps) is rejected and reported: one bad stamp never
decides which samples count. The stream is
judged against itself, not against the clock, so a replay of a year-old bag and a
lockstep plant faster than real time are accepted; a stream that really moved (a new
plant, a new clock) is followed after ``REANCHOR_SAMPLES`` samples agree on it. Until a
setpoint or a trajectory arrives the controller holds the first measured angle (or
``initial_setpoint_rad``).
"""
from __future__ import annotations

import math
import time

from rclpy.node import Node
from sensor_msgs.msg import FluidPressure, JointState, Temperature
from std_msgs.msg import Float64
from trajectory_msgs.msg import JointTrajectory

from ..control.measurement import Measurement
from ..control.model_based import SMC_SPECS
from ..control.params import Spec, SpecSet
from ..control.pid import PID_SPECS, PidController
from ..control.reference import Reference, Trajectory, TrajectoryPoint
from ..effects.layout import CORE_INDEX, CORE_PARAMS
from ..errors import ConfigError
from . import cdr, common, private
from .common import COMMAND_QOS, SENSOR_QOS

monotonic = time.monotonic
#: samples in a row that must agree on a new stamp offset before the controller follows it
REANCHOR_SAMPLES = 5
#: [s] a sample still resent this long after its answer did not get it: answer again (a
#: lockstep plant resends every 20 ms; an answer in flight arrives well within this)
REANSWER_S = 0.25
CONTROLLERS = ('pid', 'smc')


def _cross(v: dict):
    return PID_SPECS.cross(v)


NODE_SPECS = [
    Spec('controller', 'pid', 'control law: pid, or smc (model-based sliding mode; needs the '
         'chamber pressures and starts with the model compiled)', choices=CONTROLLERS),
    Spec('joint_name', 'actuator_joint', 'joint to control', read_only=True),
    Spec('model_config', '', "model config YAML for smc ('' = the paper's rig)",
         read_only=True),
    Spec('initial_setpoint_rad', math.nan, 'target before any setpoint (NaN = hold the first '
         'measured angle)', 'rad', 0.0, CORE_PARAMS[CORE_INDEX['stroke_rad']].upper,
         read_only=True, allow_nan=True),
    Spec('input_timeout_s', 0.5, 'measurements older than this are reported stale', 's', 0.001,
         60.0),
    Spec('max_stamp_skew_s', 10.0, 'a sample whose stamp jumps by more than this against the '
         'stream of samples (and the local clock) is rejected and reported (0 = no check)',
         's', 0.0, 1e6),
    Spec('restart_jump_s', 1.0, 'a sample this much older than the last one restarts the '
         'law (the plant restarted its clock)', 's', 0.001, 1e6),
    Spec('diagnostics_period_s', 0.5, 'period of /diagnostics', 's', 0.01, 10.0),
]
_seen = set()
CONTROLLER_SPECS = SpecSet(
    [s for s in NODE_SPECS + list(PID_SPECS) + list(SMC_SPECS)
     if not (s.name in _seen or _seen.add(s.name))], cross=_cross)


class ControllerNode(Node):
    """Position controller node (see module doc)."""

    def __init__(self, node_name: str = 'pneumatic_servo_controller',
                 overrides: dict | None = None, **kwargs):
        super().__init__(node_name, **kwargs)
        self.p = common.declare(self, CONTROLLER_SPECS, overrides)
        self.pid = PidController(**self.p)
        self.smc = None
        if self.p['controller'] == 'smc':
            self._build_smc()
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.joint = self.p['joint_name']
        self.m = Measurement(math.nan, math.nan)
        self._stamps = {}
        self._last_done = -1
        self._stale = -1  # [ns] the last out-of-order stamp dropped (see _on_joint)
        self._answered_at = -math.inf
        self._pending = None
        self.ref = None
        self.trajectory = None
        self.commands = 0
        self.fallbacks = 0
        self.rejected = 0
        self.restarts = 0
        self.reanswers = 0
        self._offset = self._new_offset = None  # [ns] stamp - monotonic clock
        self._agreeing = 0
        self.last_u = math.nan
        self._last_input = -math.inf
        self.pub = self.create_publisher(Float64, common.COMMAND, COMMAND_QOS)
        self.diag_pub = self.create_publisher(common.DiagnosticArray, common.DIAGNOSTICS,
                                              common.DIAGNOSTICS_QOS)
        # measurements arrive serialised and are read straight from the bytes (see .cdr);
        # temperatures and supply only matter to the model-based law
        subs = [self.create_subscription(JointState, common.JOINT_STATES, self._on_joint,
                                         SENSOR_QOS, raw=True)]
        fields = [(common.PRESSURE_A, 'p_a_pa', 0.0), (common.PRESSURE_B, 'p_b_pa', 0.0)]
        if self.smc is not None:
            fields += [(common.PRESSURE_SUPPLY, 'supply_pa', 0.0),
                       (common.TEMPERATURE_A, 't_a_k', common.CELSIUS_K),
                       (common.TEMPERATURE_B, 't_b_k', common.CELSIUS_K)]
        for topic, field, offset in fields:
            kind = Temperature if topic.endswith('temperature') else FluidPressure
            subs.append(self.create_subscription(kind, topic, self._scalar_cb(field, offset),
                                                 SENSOR_QOS, raw=True))
        # with use_sim_time the clock subscription is hot too: it changes every period
        clock_sub = private.clock_subscription(self)
        self.hot_subscriptions = subs + ([clock_sub] if clock_sub is not None else [])
        self.create_subscription(Float64, common.SETPOINT, self._on_setpoint, COMMAND_QOS)
        self.create_subscription(JointTrajectory, common.TRAJECTORY, self._on_trajectory,
                                 COMMAND_QOS)
        self._next_diag = 0.0
        self.state = 'waiting for measurements'
        self.get_logger().info(f'{self.p["controller"]} controller for {self.joint}')

    # -------------------------------------------------------------- parameters
    def _build_smc(self) -> None:
        from ..control.model_based import SlidingModeController
        from ..model import Model, ModelConfig
        from .paths import resolve
        path = resolve(self.p['model_config'])
        cfg = ModelConfig.load(path) if path else ModelConfig.paper()
        self.smc = SlidingModeController(Model(cfg), **self.p)
        # compile the kernels now, not on the first measurement
        self.smc.update(0.0, Reference(1.0), Measurement(0.0, 1.0, 0.0, 4e5, 4e5))
        self.smc.reset()

    def _on_set_parameters(self, params):
        result = common.validate_update(CONTROLLER_SPECS, self.p, params)
        if not result.successful:
            return result
        new = {p.name: CONTROLLER_SPECS[p.name].coerce(p.value) for p in params
               if p.name in CONTROLLER_SPECS}
        if new.get('controller') == 'smc' and self.smc is None:
            result.successful = False
            result.reason = ('controller smc needs the model compiled at start-up (seconds); '
                             'restart the node with controller:=smc')
            return result
        if 'controller' in new and new['controller'] != self.p['controller']:
            self.pid.reset()
            if self.smc is not None:
                self.smc.reset()
        self.p.update(new)
        self.pid.configure(new)
        if self.smc is not None:
            self.smc.configure(new)
        return result

    # ---------------------------------------------------------------- targets
    def _on_setpoint(self, msg: Float64) -> None:
        if not math.isfinite(msg.data):
            self.get_logger().warn(f'ignoring non-finite setpoint {msg.data!r}')
            return
        self.trajectory = None
        self.ref = Reference(float(msg.data))

    def _on_trajectory(self, msg: JointTrajectory) -> None:
        names = list(msg.joint_names)
        if self.joint not in names:
            self.get_logger().warn(f'trajectory without joint {self.joint!r} ignored')
            return
        i = names.index(self.joint)
        t0 = common.stamp_to_s(msg.header.stamp)
        if t0 == 0.0:  # JointTrajectory convention: a zero stamp means "start now"
            t0 = self.m.t_s if math.isfinite(self.m.t_s) else 0.0
        pts = []
        for pt in msg.points:
            vel = pt.velocities[i] if len(pt.velocities) > i else None
            acc = pt.accelerations[i] if len(pt.accelerations) > i else None
            pts.append(TrajectoryPoint(t0 + pt.time_from_start.sec
                                       + pt.time_from_start.nanosec * 1e-9,
                                       pt.positions[i], vel, acc))
        try:
            self.trajectory = Trajectory(pts)
        except ConfigError as exc:
            self.get_logger().warn(f'trajectory rejected: {exc}')

    def reference(self, t: float) -> Reference:
        if self.trajectory is not None:
            r = self.trajectory.sample(t)
            if r is not None:
                self.ref = Reference(r.position)  # hold its end afterwards
                return r
        if self.ref is None:
            init = self.p['initial_setpoint_rad']
            self.ref = Reference(init if math.isfinite(init) else self.m.angle_rad)
        return self.ref

    # ----------------------------------------------------------- measurements
    def _scalar_cb(self, field: str, offset: float):
        def cb(data: bytes):
            stamp, value = cdr.unpack_scalar(data)
            setattr(self.m, field, value + offset)
            self._stamps[field] = stamp
            if field in ('p_a_pa', 'p_b_pa'):
                self._try_compute()
        return cb

    def _on_joint(self, data: bytes) -> None:
        got = cdr.unpack_joint_state(data, self.joint)
        if got is None:
            return
        stamp, position, velocity, effort = got
        if not self._stamp_ok(stamp):
            return
        if stamp <= self._last_done:
            jump_ok = self._last_done - stamp <= self.p['restart_jump_s'] * 1e9
            if stamp == self._last_done:
                self._reanswer()
                return
            if jump_ok and stamp != self._stale:
                self._stale = stamp
                return  # an out-of-order sample: a later one was answered already
            # far older, or an older sample sent again: only a restarted plant resends a
            # sample from before the last one (a lockstep restart within restart_jump_s)
            self._restart()
        if self._pending is not None and self._pending[0] < stamp:
            self._compute()  # the pressures of the older sample never came: use the latest
        m = self.m
        m.t_s = stamp * 1e-9
        m.angle_rad = position
        m.velocity_rad_s = velocity
        m.effort_n_m = effort
        self._pending = (stamp,)
        self._last_input = monotonic()
        self._try_compute()

    def _stamp_ok(self, stamp: int) -> bool:
        """False (and counted, and reported) for a stamp that jumps away from the stream.

        The offset of a stamp from the local monotonic clock stays nearly the same from one
        sample to the next whatever the time base (wall, sim, a replayed recording); the
        reference follows every accepted sample, so a slow drift (a lockstep plant faster
        than real time) is accepted, and moves to a new offset only when
        ``REANCHOR_SAMPLES`` samples in a row agree on it."""
        skew = self.p['max_stamp_skew_s'] * 1e9
        offset = stamp - time.monotonic_ns()
        if skew <= 0.0 or self._offset is None or abs(offset - self._offset) <= skew:
            self._offset, self._new_offset, self._agreeing = offset, None, 0
            return True
        if self._new_offset is not None and abs(offset - self._new_offset) <= skew:
            self._agreeing += 1
        else:
            self._new_offset, self._agreeing = offset, 1
        if self._agreeing >= REANCHOR_SAMPLES:  # the stream itself moved: follow it
            self.get_logger().info(f'measurement stamps moved by '
                                   f'{(offset - self._offset) * 1e-9:+.3g} s: following them')
            self._offset, self._new_offset, self._agreeing = offset, None, 0
            return True
        self.rejected += 1
        if self.rejected == 1 or self.rejected % 1000 == 0:
            jump = (offset - self._offset) * 1e-9
            self.get_logger().warn(f'rejected a sample stamped {jump:+.3g} s off the stream '
                                   f'({self.rejected} so far); check the sender\'s clock')
        return False

    def _reanswer(self) -> None:
        """The last sample again: if its answer went out ``REANSWER_S`` ago, it was lost;
        send the same command again (the law is not run twice)."""
        if monotonic() - self._answered_at < REANSWER_S:
            return
        self.reanswers += 1
        if self.reanswers == 1:
            self.get_logger().info('a measurement was resent after its answer: the answer '
                                   'was lost, sent again')
        self._send(self.last_u)

    def _send(self, u: float) -> None:
        """Publish command ``u`` [V] and note when (see :meth:`_reanswer`)."""
        self.pub.publish(cdr.pack_float64(float(u)))
        self._answered_at = monotonic()

    def _restart(self) -> None:
        """The plant's clock went back (a restart, a replay loop): start the law afresh."""
        self.restarts += 1
        self._last_done = -1
        self._pending = None
        self.pid.reset()
        if self.smc is not None:
            self.smc.reset()
        self.trajectory = None
        self.get_logger().info('measurement time went back: control law restarted')

    def _try_compute(self) -> None:
        """Compute once the sample is complete: the laws that use the chamber pressures
        (smc, and pid with kdp > 0) wait for the pressures stamped like the joint state, so
        the result does not depend on which topic arrived first (lockstep is deterministic).
        Without pressure topics, or if they never match, the next joint state releases it."""
        if self._pending is None:
            return
        uses_p = self.p['controller'] == 'smc' or self.p['kdp'] > 0
        if uses_p and 'p_a_pa' in self._stamps:
            stamp = self._pending[0]
            if self._stamps.get('p_a_pa') != stamp or self._stamps.get('p_b_pa') != stamp:
                return
        self._compute()

    def _compute(self) -> None:
        stamp = self._pending[0]
        self._pending = None
        self._last_done = stamp
        t = stamp * 1e-9
        ref = self.reference(t)
        law = self.smc if (self.p['controller'] == 'smc' and self.smc is not None) else self.pid
        try:
            u = law.update(t, ref, self.m)
        except ValueError:
            # no pressures (a rig without transmitters on a bag): PID keeps control
            self.fallbacks += 1
            u = self.pid.update(t, ref, self.m)
        self.last_u = u
        self._send(u)
        self.commands += 1
        self.state = 'tracking'

    # ----------------------------------------------------------- loop protocol
    def next_deadline(self) -> float:
        return self._next_diag

    def tick(self, now: float) -> None:
        if now >= self._next_diag:
            self._next_diag = now + self.p['diagnostics_period_s']
            self.publish_diagnostics(now)

    def publish_diagnostics(self, now: float, extra: str = '') -> None:
        age = now - self._last_input
        level, message = 'ok', self.state
        if self.commands == 0:
            level = 'ok' if age == math.inf else 'warn'
        elif age > self.p['input_timeout_s']:
            level, message = 'warn', f'no measurement for {age:.1f} s'
        if self.fallbacks:
            level = 'warn' if level == 'ok' else level
            message += f'; smc fell back to pid {self.fallbacks} times (no pressures)'
        if self.rejected:
            level = 'warn' if level == 'ok' else level
            message += (f'; rejected {self.rejected} samples stamped more than '
                        f'{self.p["max_stamp_skew_s"]:g} s off the stream')
        if extra:
            message = f'{extra}; {message}'
        ref = self.ref.position if self.ref is not None else math.nan
        values = {'controller': self.p['controller'], 'commands': self.commands,
                  'last_command_v': self.last_u, 'setpoint_rad': ref,
                  'angle_rad': self.m.angle_rad,
                  'error_rad': ref - self.m.angle_rad,
                  'trajectory': 'active' if self.trajectory is not None else 'none',
                  'input_age_ms': age * 1e3, 'rejected_stamps': self.rejected,
                  'restarts': self.restarts, 'reanswers': self.reanswers}
        self.diag_pub.publish(common.diagnostic_array(
            self.get_clock().now().nanoseconds, f'{self.get_name()}: controller', self.joint,
            level, message, values))

    def shutdown(self, reason: str) -> None:
        """Centre the valve (the plant's watchdog would do it too, with a fault) and report."""
        try:
            self.pub.publish(Float64(data=self.pid.p['null_v']))
            self.publish_diagnostics(monotonic(), extra=f'shut down ({reason})')
        except Exception:  # the context may already be gone
            pass
