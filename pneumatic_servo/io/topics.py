"""The recorded-experiment vocabulary of docs/interfaces.md: topics, message types, signals.

Topic names are relative (a namespace or remap moves them); ``/diagnostics``
and the usual ROS infrastructure topics may be present and are ignored.
"""
from __future__ import annotations

from dataclasses import dataclass

FLOAT64 = 'std_msgs/msg/Float64'
JOINT_STATE = 'sensor_msgs/msg/JointState'
FLUID_PRESSURE = 'sensor_msgs/msg/FluidPressure'
TEMPERATURE = 'sensor_msgs/msg/Temperature'

#: custom_data keys of a bag's metadata.yaml written and read by this package
KEY_PREFIX = 'pneumatic_servo.'
CIRCUIT_KEY = KEY_PREFIX + 'circuit'
SYNTHETIC_KEY = KEY_PREFIX + 'synthetic'

#: default name of the actuator joint in ``joint_states``
DEFAULT_JOINT = 'actuator_joint'
#: [K] offset of the Celsius scale (``sensor_msgs/Temperature`` is in degC)
CELSIUS_K = 273.15


@dataclass(frozen=True)
class Topic:
    """One docs/interfaces.md topic: its type and the Experiment signals it carries.

    ``stamped`` topics carry the measurement time in ``header.stamp``; the
    others (``std_msgs/Float64``) are timed by their record time.
    ``hold`` signals are commands, held between samples (zero-order hold);
    the others are measurements, interpolated linearly. ``fields`` are the
    message fields that carry ``signals`` (one each), in the message's unit:
    the signal [SI] is the field plus ``offset``.
    """

    name: str
    msgtype: str
    signals: tuple[str, ...]
    stamped: bool
    hold: bool = False
    fields: tuple[str, ...] = ('data',)
    offset: float = 0.0

TOPICS = {t.name: t for t in (
    Topic('valve/command', FLOAT64, ('command_v',), stamped=False, hold=True),
    Topic('joint_states', JOINT_STATE, ('angle_rad', 'velocity_rad_s', 'effort_n_m'),
          stamped=True, fields=('position', 'velocity', 'effort')),
    Topic('chamber_a/pressure', FLUID_PRESSURE, ('p_a_pa',), stamped=True,
          fields=('fluid_pressure',)),
    Topic('chamber_b/pressure', FLUID_PRESSURE, ('p_b_pa',), stamped=True,
          fields=('fluid_pressure',)),
    Topic('supply/pressure', FLUID_PRESSURE, ('supply_pa',), stamped=True,
          fields=('fluid_pressure',)),
    Topic('chamber_a/temperature', TEMPERATURE, ('t_a_k',), stamped=True,
          fields=('temperature',), offset=CELSIUS_K),
    Topic('chamber_b/temperature', TEMPERATURE, ('t_b_k',), stamped=True,
          fields=('temperature',), offset=CELSIUS_K),
    # the controller's target (closed-loop records)
    Topic('setpoint', FLOAT64, ('setpoint_rad',), stamped=False, hold=True),
)}
#: Experiment signal -> topic that carries it
SIGNAL_TOPIC = {sig: t.name for t in TOPICS.values() for sig in t.signals}

#: topics a ROS system records alongside anything; never an error, never read
INFRASTRUCTURE = frozenset({
    'diagnostics', 'rosout', 'parameter_events', 'tf', 'tf_static', 'clock',
    'robot_description', 'events/write_split', 'diagnostics_agg', 'joint_commands',
    'joint_trajectory', 'valve/applied',
})

#: namespaces of what a monitor publishes beside the measurements (``model/joint_states``,
#: ``model/chamber_a/pressure``: the model's predictions; ``monitor/residuals``): never
#: measurements, so a bag that recorded them reads as if they were not there
DERIVED_NAMESPACES = frozenset({'model', 'monitor'})

#: topics that must be present for a time series of each circuit: any one of each tuple
REQUIRED = {
    'servo': (('valve/command',), ('joint_states',)),
    'blocked': (('valve/command',), ('chamber_a/pressure', 'chamber_b/pressure')),
    'closed_port': (('valve/command',), ('chamber_a/pressure',)),
    'flow': (('valve/command',), ('chamber_a/pressure',)),
}
