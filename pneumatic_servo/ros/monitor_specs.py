"""The monitor node's parameters, declared once: read by the node, ``pneumatic-servo
monitor``, the parameter file and the launch file."""
from __future__ import annotations

from ..control.params import Spec, SpecSet
from ..errors import PneumaticServoError
from ..text import comma_list


def _cross(v: dict):
    from .. import effects as registry
    for name in comma_list(v.get('track', '')):
        try:
            registry.get(name)
        except PneumaticServoError as exc:
            return f'track: {exc}'
    return None


MONITOR_SPECS = SpecSet([
    Spec('model_config', '', "the identified model: config YAML ('' = the paper's rig)",
         read_only=True),
    Spec('joint_name', 'actuator_joint', 'joint in joint_states', read_only=True),
    Spec('floor_file', '', 'floor file: loaded if it exists (judging starts at once), else '
         'measured on the baseline and saved there (\'\' = '
         '$ROS_HOME/pneumatic_servo/<node>_floor.yaml, measured each start)', read_only=True),
    Spec('baseline_s', 20.0, 'data on which the floor is measured before judging starts '
         '(without a floor file)', 's', 1.0, 86400.0, read_only=True),
    Spec('horizon_s', 0.2, 'k-step horizon of the judged windows', 's', 0.01, 5.0,
         read_only=True),
    Spec('lead_s', 0.05, 'lead-in before each prediction for the unmeasured states', 's', 0.0,
         1.0, read_only=True),
    Spec('replicas', 8, 'copies of each window that measure its floor', '', 3, 64,
         read_only=True),
    Spec('false_alarm_per_hour', 0.01, 'stated rate of false WARNs per hour of data, all '
         'channels together, when the model describes the rig', '1/h', 1e-6, 1000.0,
         read_only=True),
    Spec('error_ratio', 10.0, 'a departing channel this many times its floor is an ERROR',
         '', 1.0, 1e6, read_only=True),
    Spec('recent_s', 10.0, 'data over which departures and regimes are reported', 's', 1.0,
         3600.0, read_only=True),
    Spec('max_backlog_s', 2.0, 'data waiting beyond this are skipped (decimation, reported)',
         's', 0.2, 600.0, read_only=True),
    Spec('track', '', "effects fitted when a channel departs, comma-separated (e.g. "
         "piston_seal_leakage; '' = none)", read_only=True),
    Spec('fit_window_s', 10.0, 'data per tracked fit', 's', 1.0, 600.0, read_only=True),
    Spec('fit_period_s', 10.0, 'data time between tracked fits while a channel departs', 's',
         0.5, 86400.0, read_only=True),
    Spec('command_order', 'source', 'pair commands with measurements by their publishers\' '
         'source timestamps (one host, or synchronised clocks) or by arrival',
         choices=('source', 'received'), read_only=True),
    Spec('plant_status', 'pneumatic_servo_plant: plant', "the plant's status on /diagnostics "
         "('' = none): while it says its gate holds the valve safe, the commands do not reach "
         'the valve and those samples are not judged', read_only=True),
    Spec('publish_model', True, 'publish the model/ predictions'),
    Spec('diagnostics_period_s', 1.0, 'period of /diagnostics', 's', 0.05, 60.0),
    Spec('seed', 0, "seed of the copies' jitter and noise", '', 0, 2 ** 31 - 1,
         read_only=True),
    Spec('nice', 10, 'scheduling niceness of the monitor and its workers (0-19): on shared '
         'cores the plant and the controller win the CPU', '', 0, 19, read_only=True),
    Spec('autostart', True, 'configure and activate at start (no lifecycle manager needed)',
         read_only=True),
], cross=_cross)
