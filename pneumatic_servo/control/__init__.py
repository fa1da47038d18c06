"""Control laws and the safety output gate. Pure: no ROS.

* :mod:`.gate`: the one output gate between any command and any valve;
* :mod:`.pid`: PID with feed-forward, pressure feedback and friction compensation;
* :mod:`.model_based`: sliding mode with the valve inverted through the model core;
* :mod:`.reference`: setpoints and timed trajectories;
* :mod:`.metrics`: step and tracking figures;
* :mod:`.params`: parameter declarations shared by the nodes and the command line.
"""
from .gate import MAX_V, MIN_V, SAFE_V, WATCHDOG_S, GateStatus, OutputGate
from .measurement import Measurement
from .pid import PID_SPECS, PidController
from .reference import Reference, Trajectory, TrajectoryPoint

CONTROLLERS = ('pid', 'smc')

__all__ = ['CONTROLLERS', 'GateStatus', 'MAX_V', 'MIN_V', 'Measurement', 'OutputGate',
           'PID_SPECS', 'PidController', 'Reference', 'SAFE_V', 'Trajectory', 'TrajectoryPoint',
           'WATCHDOG_S']
