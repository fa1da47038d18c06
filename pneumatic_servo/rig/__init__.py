"""Rig access: DAQ driver interface, the NI PCI-6229 driver (``nidaqmx``, imported lazily),
the virtual DAQ, and the scaling/checking layer they share. Pure: no ROS.

Layering: ``model -> control -> rig -> ros``.
"""
from .config import AnalogInput, Encoder, RigConfig, ValveOutput, Virtual
from .driver import DaqDriver, DaqError, RawSample
from .rigio import RigIO, SensorFault

DAQS = ('nidaqmx', 'virtual')


def make_driver(config: RigConfig, daq: str, period_s: float, model=None,
                initial_angle_rad: float | None = None) -> DaqDriver:
    """The driver named ``daq`` ('nidaqmx' or 'virtual') for ``config``."""
    from ..errors import ConfigError
    if daq == 'nidaqmx':
        from .nidaq import NiDaqDriver
        return NiDaqDriver(config)
    if daq == 'virtual':
        from .virtual import VirtualDaq
        return VirtualDaq(config, period_s, model=model, initial_angle_rad=initial_angle_rad)
    raise ConfigError(f'unknown daq {daq!r}; use one of {", ".join(DAQS)}')


__all__ = ['AnalogInput', 'DAQS', 'DaqDriver', 'DaqError', 'Encoder', 'RawSample', 'RigConfig',
           'RigIO', 'SensorFault', 'ValveOutput', 'Virtual', 'make_driver']
