"""NI PCI-6229 (or any NI-DAQmx card) through the ``nidaqmx`` Python API.

Three software-timed, on-demand tasks, as the paper's rig wires them:

* analog inputs: the pressure transmitters (1-5 V for 0-0.6 MPa gauge) and,
  when wired, temperature transmitters; one read returns one sample each;
* counter input: the 20,000-line quadrature encoder, X4 decoding, in raw
  ticks (:class:`~.rigio.RigIO` unwraps the 32-bit counter and scales);
* analog output: the valve command, 0-10 V.

``nidaqmx`` is imported when the driver is created, so the package works
without it; a missing module or driver is a one-line error that names the
fix. On-demand reads are paced by the plant node's loop; the jitter of that
loop (see benchmarks/bench_ros.py) is the jitter of the sampling.
"""
from __future__ import annotations

from ..errors import ConfigError
from .config import RigConfig
from .driver import DaqDriver, DaqError, RawSample

INSTALL_HINT = ('the rig backend with daq nidaqmx needs NI-DAQmx and its Python API: install '
                'the NI-DAQmx driver, then `pip install nidaqmx`; or use daq:=virtual for a '
                'simulated rig')


def import_nidaqmx():
    """The ``nidaqmx`` module and its constants; ConfigError with the fix if absent."""
    try:
        import nidaqmx
        from nidaqmx import constants
    except ImportError:
        raise ConfigError(INSTALL_HINT) from None
    return nidaqmx, constants


class NiDaqDriver(DaqDriver):
    """The rig's DAQ card through NI-DAQmx. Channels and ranges come from ``config``."""

    def __init__(self, config: RigConfig):
        nidaqmx, c = import_nidaqmx()
        self.config = config
        self._nidaqmx = nidaqmx
        dev = config.device
        self.description = f'NI-DAQmx {dev}'
        self._names = list(config.inputs())
        terminals = {'rse': c.TerminalConfiguration.RSE, 'nrse': c.TerminalConfiguration.NRSE,
                     'diff': c.TerminalConfiguration.DIFF}
        self.ai = self.ci = self.ao = None
        try:
            self.ai = nidaqmx.Task('pneumatic_servo_ai')
            for name, ai in config.inputs().items():
                if ai.terminal not in terminals:
                    raise ConfigError(f'{name}.terminal {ai.terminal!r}: use rse, nrse or diff')
                self.ai.ai_channels.add_ai_voltage_chan(
                    f'{dev}/{ai.channel}', name_to_assign_to_channel=name,
                    terminal_config=terminals[ai.terminal], min_val=-config.ai_range_v,
                    max_val=config.ai_range_v)
            enc = config.encoder
            decoding = {1: c.EncoderType.X_1, 2: c.EncoderType.X_2, 4: c.EncoderType.X_4}
            self.ci = nidaqmx.Task('pneumatic_servo_encoder')
            self.ci.ci_channels.add_ci_ang_encoder_chan(
                f'{dev}/{enc.counter}', name_to_assign_to_channel='angle',
                decoding_type=decoding[enc.decoding], zidx_enable=False,
                units=c.AngleUnits.TICKS, pulses_per_rev=enc.pulses_per_rev, initial_angle=0.0)
            valve = config.valve
            self.ao = nidaqmx.Task('pneumatic_servo_ao')
            self.ao.ao_channels.add_ao_voltage_chan(
                f'{dev}/{valve.channel}', name_to_assign_to_channel='valve',
                min_val=valve.min_v, max_val=valve.max_v)
            for task in (self.ai, self.ci, self.ao):
                task.start()
            self.ao.write(valve.safe_v)
        except ConfigError:
            self.close()
            raise
        except Exception as exc:  # nidaqmx.DaqError and OS errors: one line with the device
            self.close()
            raise DaqError(f'cannot open {dev} through NI-DAQmx: {exc}'.splitlines()[0]) from None

    def read(self) -> RawSample:
        try:
            volts = self.ai.read()
            ticks = self.ci.read()
        except Exception as exc:
            raise DaqError(f'{self.config.device} read failed: {exc}'.splitlines()[0]) from None
        if not isinstance(volts, (list, tuple)):
            volts = [volts]
        return RawSample(dict(zip(self._names, (float(v) for v in volts))),
                         int(round(float(ticks))))

    def write(self, volts: float) -> None:
        try:
            self.ao.write(float(volts))
        except Exception as exc:
            raise DaqError(f'{self.config.device} write failed: {exc}'.splitlines()[0]) from None

    def close(self) -> None:
        for task in (self.ao, self.ci, self.ai):
            if task is None:
                continue
            try:
                if task is self.ao:
                    task.write(self.config.valve.safe_v)
                task.close()
            except Exception:  # closing after a failure: nothing more to do
                pass
        self.ai = self.ci = self.ao = None
