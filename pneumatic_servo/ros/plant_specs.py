"""The plant node's parameters, declared once: read by the node, ``pneumatic-servo plant``,
the parameter file and the launch file (without importing the node)."""
from __future__ import annotations

import math

from ..control.gate import MAX_V, MIN_V, SAFE_V, WATCHDOG_S
from ..control.params import Spec, SpecSet
from ..effects.layout import CORE_INDEX, CORE_PARAMS

BACKENDS = ('sim', 'rig', 'replay')
CLOCK_MODES = ('free', 'lockstep')
#: [s] lockstep: wall time without a new command before the controller is given up on. A
#: healthy controller's answer was seen 0.34 s late on a loaded 2-core machine, and a stall
#: of over 0.1 s (the gate's watchdog) ended a lockstep run 2.3 s in on another; a dead
#: controller is still given up on within seconds
LOCKSTEP_PATIENCE_S = 2.0


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
    Spec('lockstep_patience_s', LOCKSTEP_PATIENCE_S, 'lockstep: give the controller up '
         '(latched watchdog fault, valve safe, the plant on in real time) after this long '
         'without a new command (wall time; in lockstep it stands for watchdog_s: the '
         'simulation waits for each answer and no valve is at stake, so a loaded machine '
         'stalling a healthy controller must not end the run); fixed while active', 's',
         0.01, 60.0, safety=True),
    Spec('wait_subscribers', 0, 'lockstep and replay: start when joint_states has this many '
         'subscribers (say, the controller and a recorder that must see every sample); '
         'lockstep waits for at least 1', '', 0, 100, read_only=True),
    Spec('diagnostics_period_s', 0.1, 'period of /diagnostics', 's', 0.01, 10.0),
    Spec('realtime_priority', 0, 'SCHED_FIFO priority of the loop (1-99; 0 = normal '
         'scheduling); needs CAP_SYS_NICE or an rtprio limit', '', 0, 99, read_only=True),
    Spec('autostart', True, 'configure and activate at start (no lifecycle manager needed)',
         read_only=True),
], cross=_cross)
