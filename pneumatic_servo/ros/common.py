"""Shared by the nodes: topic names, QoS, message conversion, parameter declaration,
diagnostics. Imports rclpy and the message packages.
"""
from __future__ import annotations

import math

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)

from ..control.measurement import Measurement
from ..control.params import SpecSet
from ..errors import ConfigError
from ..io.topics import CELSIUS_K, SIGNAL_TOPIC, TOPICS
from . import cdr

# ----------------------------------------------------------------------------- topics
#: relative names (the interface contract), so a namespace or remap moves them; declared once, in
#: pneumatic_servo.io.topics
COMMAND = SIGNAL_TOPIC['command_v']
JOINT_STATES = SIGNAL_TOPIC['angle_rad']
PRESSURE_A, PRESSURE_B, PRESSURE_SUPPLY = (SIGNAL_TOPIC[s] for s in ('p_a_pa', 'p_b_pa',
                                                                    'supply_pa'))
TEMPERATURE_A, TEMPERATURE_B = SIGNAL_TOPIC['t_a_k'], SIGNAL_TOPIC['t_b_k']
SETPOINT = SIGNAL_TOPIC['setpoint_rad']
#: extension: trajectory_msgs/JointTrajectory for the controller
TRAJECTORY = 'joint_trajectory'
DIAGNOSTICS = '/diagnostics'
CLOCK = '/clock'

#: measurement topics in publication order (joint_states last: it triggers the controller)
MEASUREMENT_TOPICS = (PRESSURE_A, PRESSURE_B, PRESSURE_SUPPLY, TEMPERATURE_A, TEMPERATURE_B,
                      JOINT_STATES)
#: extension: the voltage the plant's gate gave the valve over the period that ends at the
#: next measurement (std_msgs/Float64 [V], published just before that measurement)
VALVE_APPLIED = 'valve/applied'
#: what the monitor publishes (an extension of the interface; relative names): the model's
#: predictions, stamped like the measurements they predict, and its statistics
MODEL_JOINT_STATES = 'model/joint_states'
MODEL_PRESSURE_A = 'model/chamber_a/pressure'
MODEL_PRESSURE_B = 'model/chamber_b/pressure'
MONITOR_RESIDUALS = 'monitor/residuals'
MONITOR_EFFECTS = 'monitor/effects'
MONITOR_TOPIC_TYPES = {MODEL_JOINT_STATES: 'sensor_msgs/msg/JointState',
                       MODEL_PRESSURE_A: 'sensor_msgs/msg/FluidPressure',
                       MODEL_PRESSURE_B: 'sensor_msgs/msg/FluidPressure',
                       MONITOR_RESIDUALS: 'std_msgs/msg/Float64MultiArray',
                       MONITOR_EFFECTS: 'std_msgs/msg/Float64MultiArray',
                       DIAGNOSTICS: 'diagnostic_msgs/msg/DiagnosticArray'}
#: topic -> message type name, for the recorder and the graph checks
TOPIC_TYPES = {**{name: topic.msgtype for name, topic in TOPICS.items()},
               TRAJECTORY: 'trajectory_msgs/msg/JointTrajectory',
               VALVE_APPLIED: 'std_msgs/msg/Float64', **MONITOR_TOPIC_TYPES}

# -------------------------------------------------------------------------------- QoS
#: measurements: best effort, keep last 5 (a late sample is worthless)
SENSOR_QOS = qos_profile_sensor_data
#: commands and setpoints: reliable, keep last 10
COMMAND_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                         history=HistoryPolicy.KEEP_LAST, durability=DurabilityPolicy.VOLATILE)
DIAGNOSTICS_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


# ----------------------------------------------------------------------------- time
def stamp_to_s(stamp) -> float:
    """``builtin_interfaces/Time`` -> seconds."""
    return stamp.sec + stamp.nanosec * 1e-9


def set_stamp(stamp, ns: int) -> None:
    """Fill a ``builtin_interfaces/Time`` in place from nanoseconds."""
    stamp.sec, stamp.nanosec = divmod(int(ns), 1_000_000_000)


# ------------------------------------------------------------------------- messages
class MeasurementPacker:
    """Serialised (CDR) measurement messages of one plant, ready to publish as bytes: no
    Python message objects per sample, which matters at 1 kHz (see :mod:`.cdr`)."""

    def __init__(self, joint_name: str, frame_id: str = ''):
        self.name = joint_name.encode()
        self.frame = frame_id.encode()

    def pack(self, m: Measurement, stamp_ns: int) -> list[tuple[str, bytes]]:
        """(topic, bytes) for ``m`` stamped ``stamp_ns``; unknown values are left out, and
        joint_states comes last (it is what the controller answers)."""
        sec, nsec = divmod(int(stamp_ns), 1_000_000_000)
        # one header for the six messages of a sample (same stamp, same frame)
        head = cdr.header_block(sec, nsec, self.frame)
        scalar_head = head + b'\x00' * ((-(len(head) - 4)) % 8)
        out = []
        for topic, value in ((PRESSURE_A, m.p_a_pa), (PRESSURE_B, m.p_b_pa),
                             (PRESSURE_SUPPLY, m.supply_pa), (TEMPERATURE_A, m.t_a_k),
                             (TEMPERATURE_B, m.t_b_k)):
            if math.isfinite(value):
                if topic in (TEMPERATURE_A, TEMPERATURE_B):
                    value -= CELSIUS_K
                out.append((topic, scalar_head + cdr.F64x2.pack(float(value), 0.0)))
        out.append((JOINT_STATES, cdr.joint_state_after_header(
            head, self.name, float(m.angle_rad), float(m.velocity_rad_s),
            float(m.effort_n_m))))
        return out


# ------------------------------------------------------------------------ parameters
def descriptor(spec) -> ParameterDescriptor:
    """ROS parameter descriptor (description with unit, range, read-only) of a Spec."""
    d = ParameterDescriptor(description=spec.describe(), read_only=spec.read_only)
    if spec.kind is float and spec.lo is not None and spec.hi is not None \
            and not spec.allow_nan:
        d.floating_point_range = [FloatingPointRange(from_value=float(spec.lo),
                                                     to_value=float(spec.hi), step=0.0)]
    elif spec.kind is int and spec.lo is not None and spec.hi is not None:
        d.integer_range = [IntegerRange(from_value=int(spec.lo), to_value=int(spec.hi), step=1)]
    if spec.choices:
        d.additional_constraints = 'one of: ' + ', '.join(spec.choices)
    return d


def sim_time(on: bool = True) -> list:
    """The parameter overrides of a node that runs on ``/clock`` (none if not ``on``)."""
    from rclpy.parameter import Parameter
    return [Parameter('use_sim_time', value=True)] if on else []


def declare(node, specs: SpecSet, overrides: dict | None = None) -> dict:
    """Declare every parameter of ``specs`` on ``node``; returns the values.

    ``overrides`` (from the command line) take precedence over defaults; values
    from ``--ros-args -p``/``--params-file`` take precedence over both, as in
    ROS. A bad value raises ConfigError with the reason.
    """
    overrides = overrides or {}
    values = {}
    for spec in specs:
        default = overrides.get(spec.name, spec.default)
        try:
            param = node.declare_parameter(spec.name, default, descriptor(spec))
        except (InvalidParameterValueException, InvalidParameterTypeException) as exc:
            raise ConfigError(f'parameter {spec.name}: {str(exc).splitlines()[0]}; '
                              f'{spec.describe()}') from None
        value = param.value
        try:
            value = spec.coerce(value)
        except ConfigError:
            raise ConfigError(f'parameter {spec.name} = {value!r}: expected a '
                              f'{spec.kind.__name__}') from None
        values[spec.name] = value
    reason = specs.validate(values)
    if reason:
        raise ConfigError(f'bad parameter: {reason}')
    return values


def validate_update(specs: SpecSet, current: dict, params, active: bool = False
                    ) -> SetParametersResult:
    """Run-time check of a set-parameters request against ``specs`` and the cross checks;
    while ``active``, safety parameters are refused too."""
    proposed = dict(current)
    for p in params:
        spec = specs.specs.get(p.name)
        if spec is None:
            continue
        if spec.read_only:
            return SetParametersResult(successful=False,
                                       reason=f'{p.name} is read-only; restart the node to '
                                              'change it')
        if spec.safety and active:
            return SetParametersResult(successful=False,
                                       reason=f'{p.name} is a safety parameter and cannot '
                                              'change while the node is active; deactivate '
                                              'it first')
        try:
            proposed[p.name] = spec.coerce(p.value)
        except ConfigError as exc:
            return SetParametersResult(successful=False, reason=str(exc))
    reason = specs.validate({k: proposed[k] for k in proposed if k in specs})
    if reason:
        return SetParametersResult(successful=False, reason=reason)
    return SetParametersResult(successful=True)


# ------------------------------------------------------------------------ diagnostics
LEVELS = {'ok': DiagnosticStatus.OK, 'warn': DiagnosticStatus.WARN,
          'error': DiagnosticStatus.ERROR, 'stale': DiagnosticStatus.STALE}


def diagnostic_array(stamp_ns: int, name: str, hardware_id: str, level: str, message: str,
                     values: dict) -> DiagnosticArray:
    """A DiagnosticArray with one status; ``values`` become key/value strings."""
    arr = DiagnosticArray()
    set_stamp(arr.header.stamp, stamp_ns)
    st = DiagnosticStatus(level=LEVELS[level], name=name, message=message,
                          hardware_id=hardware_id)
    st.values = [KeyValue(key=str(k), value=_fmt(v)) for k, v in values.items()]
    arr.status = [st]
    return arr


def _fmt(v) -> str:
    if isinstance(v, float):
        return f'{v:.6g}'
    if isinstance(v, (list, tuple)):
        return '; '.join(str(x) for x in v)
    return str(v)


# ------------------------------------------------------------------------ trajectories
def joint_trajectory(points, joint_name: str, stamp_ns: int = 0):
    """A trajectory_msgs/JointTrajectory for one joint from TrajectoryPoints.

    Point times ``t_s`` are absolute on the controller's clock when ``stamp_ns`` is 0:
    the header then carries 1 ns (a zero stamp would mean "start on receipt") and each
    ``time_from_start`` is ``t_s``. With ``stamp_ns`` > 0 the times are relative to it.
    """
    from builtin_interfaces.msg import Duration
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
    msg = JointTrajectory()
    msg.joint_names = [joint_name]
    set_stamp(msg.header.stamp, stamp_ns or 1)
    base = (stamp_ns or 1) * 1e-9
    for p in points:
        pt = JointTrajectoryPoint()
        pt.positions = [float(p.position)]
        if p.velocity is not None:
            pt.velocities = [float(p.velocity)]
        if p.acceleration is not None:
            pt.accelerations = [float(p.acceleration)]
        sec, nsec = divmod(int(round((p.t_s - base) * 1e9)), 1_000_000_000)
        pt.time_from_start = Duration(sec=sec, nanosec=nsec)
        msg.points.append(pt)
    return msg
