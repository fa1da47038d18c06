"""pneumatic_servo: a nonlinear model of a valve-controlled pneumatic rotary actuator
(Zhang et al., Energies 2019), its identification, and model-discrepancy diagnosis.

The core (this package except ``ros``) has no ROS imports.
"""
__version__ = '0.1.0'
