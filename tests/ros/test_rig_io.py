"""The rig path without ROS: config loading, scaling, counter unwrapping across the wrap,
output limits, sensor faults, the virtual DAQ's signals, and the NI driver's use of the
nidaqmx API (against a stand-in module: there is no card here)."""
import dataclasses
import math
import sys
import types

import numpy as np
import pytest

from pneumatic_servo.errors import ConfigError
from pneumatic_servo.rig import DaqError, RigConfig, RigIO, SensorFault, make_driver
from pneumatic_servo.rig.driver import DaqDriver, RawSample
from pneumatic_servo.ros.paths import find_config

PE = 101325.0


@pytest.fixture(scope='module')
def cfg():
    return RigConfig.load(find_config('rig_pci6229.yaml'))


class Scripted(DaqDriver):
    """A driver that returns given raw samples and remembers what was written."""

    def __init__(self, samples):
        self.samples = list(samples)
        self.written = []

    def read(self):
        return self.samples.pop(0)

    def write(self, volts):
        self.written.append(volts)


def volts(a=3.0, b=3.0, s=4.5):
    return {'chamber_a': a, 'chamber_b': b, 'supply': s}


# ------------------------------------------------------------------------------ config
def test_shipped_config_is_the_paper_rig(cfg):
    assert cfg.device == 'Dev1'
    assert cfg.chamber_a.to_value(1.0) == 0.0 and cfg.chamber_a.to_value(5.0) == 6e5
    assert cfg.encoder.counts_per_rev == 80000 and cfg.encoder.counter_bits == 32
    assert (cfg.valve.min_v, cfg.valve.safe_v, cfg.valve.max_v) == (0.0, 5.0, 10.0)
    assert set(cfg.inputs()) == {'chamber_a', 'chamber_b', 'supply'}


@pytest.mark.parametrize('data, words', [
    ({'devce': 'Dev2'}, "did you mean 'device'"),
    ({'encoder': {'pulses': 10}}, "did you mean 'pulses_per_rev'"),
    ({'encoder': {'decoding': 3}}, 'decoding 1, 2 or 4'),
    ({'valve': {'max_v': 12.0}}, '0 <= min_v'),
    ({'chamber_a': {'channel': 'ai0', 'volts_lo': 5.0, 'volts_hi': 5.0}}, 'empty'),
    ({'chamber_a': 'ai0'}, 'expected a mapping'),
])
def test_bad_rig_configs_name_the_fix(data, words):
    with pytest.raises(ConfigError, match=words):
        RigConfig.from_dict(data)


def test_missing_rig_config_file(tmp_path):
    with pytest.raises(ConfigError, match='cannot read'):
        RigConfig.load(tmp_path / 'nope.yaml')


# ----------------------------------------------------------------------------- scaling
def test_pressure_scaling_is_gauge_plus_atmosphere(cfg):
    io = RigIO(cfg, Scripted([RawSample(volts(1.0, 5.0, 3.0), 0)]), 1e-3)
    m = io.read(0.0)
    assert m.p_a_pa == pytest.approx(PE) and m.p_b_pa == pytest.approx(PE + 6e5)
    assert m.supply_pa == pytest.approx(PE + 3e5)
    assert math.isnan(m.t_a_k) and math.isnan(m.t_b_k)


@pytest.mark.parametrize('zero', [0, 2**32 - 20000, 2**31, 2**32 - 1, 12345])
def test_counter_unwraps_across_the_wrap(cfg, zero):
    enc = dataclasses.replace(cfg.encoder, zero_count=zero, max_speed_rad_s=1e9)
    c = dataclasses.replace(cfg, encoder=enc)
    counts = [0, 5000, 19999, 20000, 20001, 60000, -3000, 42000]
    raw = [RawSample(volts(), (zero + n) % 2**32) for n in counts]
    io = RigIO(c, Scripted(raw), 1e-3)
    for n in counts:
        assert io.read(0.0).angle_rad == pytest.approx(n * 2 * math.pi / 80000)


def test_direction_and_small_counters(cfg):
    enc = dataclasses.replace(cfg.encoder, direction=-1, counter_bits=16, max_speed_rad_s=1e9)
    c = dataclasses.replace(cfg, encoder=enc)
    seq = [0, 30000, 60000, 90000, 70000]  # steps under half the 16-bit span
    io = RigIO(c, Scripted([RawSample(volts(), n % 2**16) for n in seq]), 1e-3)
    for n in seq:
        assert io.read(0.0).angle_rad == pytest.approx(-n * 2 * math.pi / 80000)


def test_velocity_from_counts(cfg):
    c = dataclasses.replace(cfg, velocity_filter_s=0.0)
    seq = [RawSample(volts(), 100 * k) for k in range(5)]
    io = RigIO(c, Scripted(seq), 1e-3)
    for k in range(5):
        m = io.read(k * 1e-3)
    assert m.velocity_rad_s == pytest.approx(100 * 2 * math.pi / 80000 / 1e-3)


# ------------------------------------------------------------------------------ faults
@pytest.mark.parametrize('v, words', [(volts(a=0.0), 'open wire'), (volts(b=0.3), 'open wire'),
                                      (volts(s=6.0), 'over range'),
                                      (volts(a=math.nan), 'chamber_a')])
def test_bad_transmitter_signals_are_faults(cfg, v, words):
    io = RigIO(cfg, Scripted([RawSample(v, 0)]), 1e-3)
    with pytest.raises(SensorFault, match=words):
        io.read(0.0)


def test_encoder_jump_is_a_fault(cfg):
    io = RigIO(cfg, Scripted([RawSample(volts(), 0), RawSample(volts(), 30000)]), 1e-3)
    io.read(0.0)
    with pytest.raises(SensorFault, match='encoder jumped'):
        io.read(0.001)


# ------------------------------------------------------------------------------ output
@pytest.mark.parametrize('v, out', [(6.0, 6.0), (11.0, 10.0), (-1.0, 0.0), (math.nan, 5.0),
                                    (math.inf, 5.0)])
def test_output_is_limited_to_the_valve_range(cfg, v, out):
    d = Scripted([])
    RigIO(cfg, d, 1e-3).write(v)
    assert d.written == [out]


def test_safe_swallows_driver_errors(cfg):
    class Broken(Scripted):
        def write(self, volts):
            raise DaqError('cable pulled')
    io = RigIO(cfg, Broken([]), 1e-3)
    io.safe()   # must not raise: we are already failing safe
    with pytest.raises(DaqError):
        io.write(6.0)


# ---------------------------------------------------------------------------- virtual
@pytest.fixture(scope='module')
def virtual_cfg(cfg):
    enc = dataclasses.replace(cfg.encoder, zero_count=2**32 - 20000)
    return dataclasses.replace(cfg, encoder=enc)


def test_virtual_daq_produces_quantised_noisy_signals_that_scale_back(virtual_cfg):
    d = make_driver(virtual_cfg, 'virtual', 1e-3, initial_angle_rad=math.radians(40))
    io = RigIO(virtual_cfg, d, 1e-3)
    raw = d.read()
    lsb = 20.0 / 2**16
    for v in raw.volts.values():
        assert abs(v / lsb - round(v / lsb)) < 1e-9
    assert raw.count == (2**32 - 20000 + round(math.radians(40) / (2 * math.pi / 80000))) % 2**32
    ms = []
    for k in range(300):
        m = io.read(k * 1e-3)
        io.write(7.0)
        ms.append(m)
    truth = d.state
    # scaled back within the noise and quantisation of a 16-bit, +/-10 V input
    assert ms[-1].p_a_pa == pytest.approx(truth[2], abs=1500.0)
    assert ms[-1].angle_rad == pytest.approx(truth[0], abs=2 * math.pi / 80000)
    assert np.std([m.supply_pa for m in ms]) > 0.0
    assert ms[-1].angle_rad > math.radians(90)   # it moved through the counter wrap


def test_virtual_daq_output_quantised_and_clipped(virtual_cfg):
    d = make_driver(virtual_cfg, 'virtual', 1e-3)
    d.write(6.123456)
    assert d.ao_v == pytest.approx(6.123456, abs=20.0 / 2**16)
    d.write(25.0)
    assert d.ao_v < 10.0
    with pytest.raises(DaqError):
        d.write(math.nan)


def test_virtual_faults_on_schedule_and_on_demand(virtual_cfg):
    c = dataclasses.replace(virtual_cfg, virtual=dataclasses.replace(
        virtual_cfg.virtual, faults=({'at_s': 0.005, 'kind': 'open_wire',
                                      'channel': 'supply'},)))
    d = make_driver(c, 'virtual', 1e-3)
    io = RigIO(c, d, 1e-3)
    for k in range(5):
        io.read(k * 1e-3)
    with pytest.raises(SensorFault, match='supply'):
        io.read(0.005)
    d2 = make_driver(virtual_cfg, 'virtual', 1e-3)
    io2 = RigIO(virtual_cfg, d2, 1e-3)
    io2.read(0.0)
    d2.inject('encoder_jump', counts=50000)
    with pytest.raises(SensorFault, match='encoder'):
        io2.read(0.001)
    d2.inject('daq_error')
    with pytest.raises(DaqError):
        d2.read()
    with pytest.raises(ConfigError):
        d2.inject('gremlins')


# ----------------------------------------------------------------------------- nidaqmx
def test_nidaqmx_missing_is_one_line_with_the_fix(cfg, monkeypatch):
    monkeypatch.setitem(sys.modules, 'nidaqmx', None)   # import nidaqmx -> ImportError
    with pytest.raises(ConfigError, match='pip install nidaqmx') as exc:
        make_driver(cfg, 'nidaqmx', 1e-3)
    assert '\n' not in str(exc.value) and 'virtual' in str(exc.value)


def test_unknown_daq(cfg):
    with pytest.raises(ConfigError, match='unknown daq'):
        make_driver(cfg, 'labjack', 1e-3)


def fake_nidaqmx():
    """A stand-in for the nidaqmx package with the calls the driver makes (no card here):
    it records the channel set-up and answers reads."""
    calls = []

    class Chans:
        def __init__(self, kind):
            self.kind = kind

        def __getattr__(self, name):
            def add(physical, **kw):
                calls.append((self.kind, name, physical, kw))
            return add

    class Task:
        def __init__(self, name=''):
            self.name = name
            self.ai_channels, self.ci_channels = Chans('ai'), Chans('ci')
            self.ao_channels = Chans('ao')
            self.written = []

        def start(self):
            calls.append((self.name, 'start'))

        def read(self):
            return [3.0, 3.0, 4.0] if 'ai' in self.name else 12345.0

        def write(self, v):
            calls.append((self.name, 'write', v))

        def close(self):
            calls.append((self.name, 'close'))

    const = types.SimpleNamespace(
        TerminalConfiguration=types.SimpleNamespace(RSE='RSE', NRSE='NRSE', DIFF='DIFF'),
        EncoderType=types.SimpleNamespace(X_1='X1', X_2='X2', X_4='X4'),
        AngleUnits=types.SimpleNamespace(TICKS='TICKS'))
    mod = types.ModuleType('nidaqmx')
    mod.Task = Task
    mod.constants = const
    return mod, const, calls


def test_ni_driver_sets_up_the_paper_rig(cfg, monkeypatch):
    mod, const, calls = fake_nidaqmx()
    monkeypatch.setitem(sys.modules, 'nidaqmx', mod)
    monkeypatch.setitem(sys.modules, 'nidaqmx.constants', const)
    d = make_driver(cfg, 'nidaqmx', 1e-3)
    ai = [c for c in calls if c[0] == 'ai']
    assert [c[2] for c in ai] == ['Dev1/ai0', 'Dev1/ai1', 'Dev1/ai2']
    assert ai[0][3]['terminal_config'] == 'RSE' and ai[0][3]['max_val'] == 10.0
    ci = [c for c in calls if c[0] == 'ci'][0]
    assert ci[1] == 'add_ci_ang_encoder_chan' and ci[2] == 'Dev1/ctr0'
    assert ci[3]['decoding_type'] == 'X4' and ci[3]['units'] == 'TICKS'
    assert ci[3]['pulses_per_rev'] == 20000
    ao = [c for c in calls if c[0] == 'ao'][0]
    assert ao[2] == 'Dev1/ao0' and (ao[3]['min_val'], ao[3]['max_val']) == (0.0, 10.0)
    assert ('pneumatic_servo_ao', 'write', 5.0) in calls   # safe output first
    raw = d.read()
    assert raw.volts == {'chamber_a': 3.0, 'chamber_b': 3.0, 'supply': 4.0}
    assert raw.count == 12345
    d.write(6.0)
    n = len(calls)
    d.close()
    assert calls[n - 1] == ('pneumatic_servo_ao', 'write', 6.0)
    assert calls[n:] == [('pneumatic_servo_ao', 'write', 5.0), ('pneumatic_servo_ao', 'close'),
                         ('pneumatic_servo_encoder', 'close'), ('pneumatic_servo_ai', 'close')]
