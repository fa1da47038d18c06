"""The monitor's core, without ROS: the false-alarm rate of its decisions checked by
simulation, the pairing of commands with measurements, and the verdicts on a healthy closed
loop, a seal leak switched on in the middle of it, and the bundled hidden-effect bag.
(The nodes over DDS: tests/ros/test_ros_monitor.py.)"""
import math

import numpy as np
import pytest
from scipy.stats import t as student

from pneumatic_servo.analysis.diagnosis.floor import Floor
from pneumatic_servo.errors import ConfigError
from pneumatic_servo.monitor import cusum
from pneumatic_servo.monitor.assemble import Assembler
from pneumatic_servo.monitor.core import Monitor
from pneumatic_servo.monitor.floorfile import load_floor, save_floor
from pneumatic_servo.monitor.judge import CHANNELS, Sensors
from pneumatic_servo.monitor.options import MonitorOptions
from pneumatic_servo.monitor.tracking import Tracker, look_level

WINDOWS_PER_HOUR = 18000.0  # 0.2 s windows
T0 = 1_700_000_000_000_000_000
LEAK_AT_S, LEAK_M2 = 16.0, 3e-8


# ------------------------------------------------------------ the stated rate, simulated
def _alarms(draw, rows: int, windows: int, h: float) -> int:
    """Alarm episodes of ``rows`` CUSUMs over ``windows`` windows, each window's statistics
    from ``draw(w)``, with the monitor's rule: WARN from S >= h until S returns to 0."""
    s = np.zeros(rows)
    alarm = np.zeros(rows, bool)
    count = 0
    for w in range(windows):
        s = np.maximum(0.0, s + draw(w) - cusum.REFERENCE_K)
        alarm &= s > 0.0
        new = ~alarm & (s >= h)
        count += int(new.sum())
        alarm |= new
    return count


@pytest.mark.parametrize('rate', [30.0, 3.0])
def test_the_threshold_gives_the_stated_false_alarm_rate(rate):
    """i.i.d. N(0, 1) window statistics (a model that describes the rig, copies that
    represent it exactly: the case the bound is exact for): 400 hours per channel."""
    h = cusum.threshold(rate, WINDOWS_PER_HOUR, len(CHANNELS))
    rng = np.random.default_rng(1)
    hours = 400
    rows = len(CHANNELS) * hours
    observed = _alarms(lambda w: rng.standard_normal(rows), rows, int(WINDOWS_PER_HOUR),
                       h) / hours  # all channels together, per hour
    assert 0.85 * rate < observed < 1.1 * rate, (rate, observed)
    # the default: 1 false WARN per 100 hours over the three channels
    assert cusum.threshold(0.01, WINDOWS_PER_HOUR, 3) == pytest.approx(13.64, abs=0.01)
    assert cusum.p_value(h, WINDOWS_PER_HOUR) == pytest.approx(
        -math.expm1(-rate / len(CHANNELS)), rel=1e-6)


def _window_p(ms: np.ndarray, reps: np.ndarray) -> np.ndarray:
    """:meth:`Floor.test`'s p-value for one unit, vectorised over windows (rows)."""
    logs = np.log(reps)
    r = reps.shape[1]
    spread = np.sqrt(np.var(logs, axis=1, ddof=1) + 2.0)
    z = (np.log(ms) - logs.mean(axis=1)) / (spread * np.sqrt(1 + 1 / r))
    return student.sf(z, r - 1)


def test_on_synthetic_residual_streams_the_rate_holds_and_a_departure_is_found():
    """Window mean squares of a correct model, whose size changes with what the rig does
    (a log-normal scale per window) and whose copies come from the same law (a scaled
    chi-square of 10 effective samples): judged by the monitor's window test, then its
    CUSUM. The false-alarm rate stays under the stated one; an RMS residual twice the
    floor is found."""
    rate, replicas, dof = 30.0, 8, 10
    h = cusum.threshold(rate, WINDOWS_PER_HOUR, len(CHANNELS))
    rng = np.random.default_rng(2)
    n, hours = int(WINDOWS_PER_HOUR), 30
    rows = len(CHANNELS) * hours
    fl = Floor({'p_a': np.array([1.0, 2.0, 3.0])}, np.array([1.0, 2.0, 3.0]), 1)
    assert _window_p(np.array([2.5]), np.array([[1.0, 2.0, 3.0]]))[0] == pytest.approx(
        fl.test(2.5, 'p_a').p_value)
    z = np.empty((rows, n))
    for i in range(rows):
        scale = np.exp(rng.normal(0.0, 1.0, n))[:, None]
        draws = scale * rng.chisquare(dof, (n, replicas + 1)) / dof
        p = _window_p(draws[:, 0], draws[:, 1:])
        z[i] = np.clip(student.isf(np.clip(p, 1e-300, 1.0), np.inf), -8, 8)
    observed = _alarms(lambda w: z[:, w], rows, n, h) / hours
    assert observed <= 1.1 * rate, observed
    # a departure: the residual's RMS twice the floor's, found within a few seconds
    scale = np.exp(rng.normal(0.0, 1.0, (200, 1)))
    draws = scale * rng.chisquare(dof, (200, replicas + 1)) / dof
    draws[:, 0] *= 4.0
    c = cusum.Cusum(cusum.threshold(0.01, WINDOWS_PER_HOUR, 3))
    first = next(w for w, p in enumerate(_window_p(draws[:, 0], draws[:, 1:]))
                 if c.update(cusum.probit(p)))
    assert first < 60, first  # 12 s of data


# ------------------------------------------------------------------------- pairing
def test_commands_are_paired_by_when_they_were_published_not_when_they_came():
    """Lockstep order (measurement k, its command, measurement k + 1, ...), delivered to the
    monitor late and out of order across topics: every sample gets the command that
    answered it."""
    rng = np.random.default_rng(3)
    events = []
    for k in range(200):
        source = 1_000_000 * k
        stamp = T0 + 1_000_000 * k
        events.append((source + 10, 'p_a', stamp, 4e5 + k))
        events.append((source + 20, 'joint', stamp, 0.01 * k))
        events.append((source + 300_000, 'command', None, 5.0 + 0.001 * k))
    # each topic late by up to 3 ms, in its own order (DDS keeps a writer's order)
    arrival = np.empty(len(events))
    for kind in ('p_a', 'joint', 'command'):
        idx = [i for i, e in enumerate(events) if e[1] == kind]
        late = np.maximum.accumulate(np.array([events[i][0] for i in idx])
                                     + rng.uniform(0, 3e6, len(idx)))
        arrival[idx] = late
    order = np.argsort(arrival, kind='stable')
    a = Assembler()
    for i in order:
        source, kind, stamp, value = events[i]
        if kind == 'joint':
            a.joint(stamp, value, source)
        elif kind == 'command':
            a.command(value, source)
        else:
            a.scalar('p_a_pa', stamp, value)
    stamps, cols = a.take(10 ** 12)
    assert len(stamps) == 200 and np.all(np.diff(stamps) == 1_000_000)
    assert np.allclose(cols['command_v'], 5.0 + 0.001 * np.arange(200))
    assert np.allclose(cols['p_a_pa'], 4e5 + np.arange(200))
    # each came less than a period before the next measurement: in a free-running loop it
    # may have been late, so the one before it is the other candidate (the monitor drops
    # the doubt where the stamps are on an exact grid: lockstep, replay)
    assert np.allclose(cols['command_alt_v'][1:-1], cols['command_v'][:-2])
    from pneumatic_servo.model import ModelConfig
    for jitter, kept in ((0, False), (1234, True)):
        mon = Monitor(ModelConfig.paper(), period_s=1e-3)
        wall = stamps + jitter * (np.arange(len(stamps)) % 2)  # wall-clock stamps jitter
        mon.add(wall, {k: v for k, v in cols.items() if k != 'angle_rad'})
        assert np.isfinite(mon.grid.cols['command_alt_v'][1:]).any() == kept


def test_a_resent_sample_a_lost_joint_state_and_a_late_command():
    a = Assembler()
    a.scalar('p_a_pa', T0, 1.0)
    a.joint(T0, 0.5, 0)
    a.joint(T0, 0.5, 20_000_000)  # a lockstep resend: the same sample
    a.command(5.1, 20_500_000)
    a.scalar('p_a_pa', T0 + 1_000_000, 2.0)  # its joint_states never comes
    a.scalar('p_a_pa', T0 + 2_000_000, 3.0)
    a.command(5.2, 20_900_000)  # 0.1 ms before the next measurement: it may be late
    a.joint(T0 + 2_000_000, 0.7, 21_000_000)
    a.joint(T0 + 3_000_000, 0.8, 22_000_000)
    assert a.take(21_000_000) is None  # the next sample is not yet HOLD_NS old
    stamps, cols = a.take(10 ** 12)
    assert list(stamps - T0) == [0, 1_000_000, 2_000_000, 3_000_000]
    assert np.isnan(cols['angle_rad'][1]) and cols['p_a_pa'][1] == 2.0
    assert cols['command_v'][0] == 5.2 and cols['command_alt_v'][0] == 5.1


def test_after_a_gap_a_command_from_before_it_is_not_taken():
    """The monitor stalled: samples 10-59 never came, and of their commands only the last
    five, kept in its queue; the answer to sample 60 was lost too. The samples at the gap
    get no command rather than a wrong one."""
    a = Assembler()
    for k in list(range(10)) + list(range(60, 70)):
        src = 1_000_000 * k
        a.scalar('p_a_pa', T0 + src, 4e5)
        a.joint(T0 + src, 1.0, src + 10)
        if k != 60:
            a.command(5.0 + 0.01 * k, src + 300_000)
    for k in range(55, 60):
        a.command(5.0 + 0.01 * k, 1_000_000 * k + 300_000)
    stamps, cols = a.take(10 ** 12)
    u = dict(zip((stamps - T0) // 1_000_000, cols['command_v']))
    assert u[8] == pytest.approx(5.08) and math.isnan(u[9])
    assert math.isnan(u[60]) and u[61] == pytest.approx(5.61)
    # a plant's tick 5 periods late, its one answer in between: nothing lost
    a = Assembler()
    for k in list(range(10)) + list(range(14, 20)):
        src = 1_000_000 * k
        a.joint(T0 + src, 1.0, src)
        a.command(5.0 + 0.01 * k, src + 300_000)
    stamps, cols = a.take(10 ** 12)
    assert np.isfinite(cols['command_v']).all()


def test_while_the_plant_holds_its_valve_safe_no_command_is_taken():
    """The plant's watchdog tripped (its controller starved) and it said so at sample 100:
    the valve stays at the safe voltage whatever the controller sends, until re-activated
    (said at sample 200). Those samples, from 50 ms before, get no command."""
    a = Assembler()
    for k in range(300):
        src = 1_000_000 * k
        a.joint(T0 + src, 1.0, src)
        a.command(5.2, src + 300_000)
        if k == 100:
            a.valve_held(T0 + src, True)
        if k == 150:
            a.valve_held(T0 + src, True)  # said again: one interval
        if k == 200:
            a.valve_held(T0 + src, False)
    stamps, cols = a.take(10 ** 12)
    unknown = np.flatnonzero(np.isnan(cols['command_v']))
    assert list(unknown) == list(range(50, 201)) and len(a.held) == 1


def test_what_the_gate_gave_the_valve_is_the_command_when_the_plant_says_it():
    """A free-running plant late by more than a period, its controller's answer late too:
    the command pairing can only guess; the plant's valve/applied, published just before
    each measurement, says it, also while the gate holds the valve safe."""
    a = Assembler()
    for k in range(20):
        src = 1_000_000 * k
        if k:
            a.applied(5.0 if k > 10 else 5.0 + 0.01 * (k - 2), src - 5)  # u(k-2): late
        a.joint(T0 + src, 1.0, src)
        a.command(5.0 + 0.01 * k, src + 900_000)
        if k == 11:
            a.valve_held(T0 + src, True)
    stamps, cols = a.take(10 ** 12)
    assert np.allclose(cols['command_v'][:10], 5.0 + 0.01 * (np.arange(10) - 1))
    assert np.allclose(cols['command_v'][10:19], 5.0)  # held at 5 V, and it says so
    assert np.isnan(cols['command_alt_v'][:19]).all()
    assert a.received['applied_used'] == 19


# --------------------------------------------------------------- a simulated rig
def _moves(duration_s: float, seed: int):
    from pneumatic_servo.control.reference import TrajectoryPoint
    rng = np.random.default_rng(seed)
    return [TrajectoryPoint(0.5 + k, float(rng.uniform(0.6, 2.6)), 0.0, 0.0)
            for k in range(int(duration_s))]


def closed_loop(duration_s: float, leak_at_s: float = math.inf, seed: int = 0):
    """What the lockstep sim plant publishes under the PID, moving between random angles
    every second; a seal leak of LEAK_M2 switched on at ``leak_at_s``: (stamps, columns)."""
    from pneumatic_servo.control.measurement import Measurement
    from pneumatic_servo.control.pid import PidController
    from pneumatic_servo.control.reference import Reference, Trajectory
    from pneumatic_servo.model import Model, ModelConfig, Stepper, initial_state
    cfg = ModelConfig.paper().with_effect('piston_seal_leakage', {'seal_leak_area_m2': 0.0})
    model = Model(cfg)
    plant = Stepper(model, 1e-3, x0=initial_state(model, angle_rad=1.0))
    pid, traj = PidController(), Trajectory(_moves(duration_s, seed))
    n = int(round(duration_s * 1000))
    names = ('angle_rad', 'velocity_rad_s', 'p_a_pa', 'p_b_pa', 't_a_k', 't_b_k')
    cols = {k: np.empty(n) for k in names + ('command_v', 'supply_pa')}
    x = plant.x.copy()
    for k in range(n):
        t = k * 1e-3
        if abs(t - leak_at_s) < 5e-4:
            leaky = cfg.copy()
            leaky.set('piston_seal_leakage.seal_leak_area_m2', LEAK_M2)
            plant.params = model.param_vector(leaky)
        u = pid.update(t, traj.sample(t) or Reference(1.0),
                       Measurement(t, x[0], x[1], x[2], x[3], plant.supply_pa, x[4], x[5]))
        for i, name in enumerate(names):
            cols[name][k] = x[i]
        cols['supply_pa'][k] = plant.supply_pa
        cols['command_v'][k] = u
        x = plant.step(u).copy()
    del cols['velocity_rad_s']
    return T0 + 1_000_000 * np.arange(n, dtype=np.int64), cols


def feed(mon: Monitor, stamps, cols, chunk: int = 50, on_window=None):
    """Hand the samples over as the node does, judging everything as it comes."""
    alarms = {}
    for i in range(0, len(stamps), chunk):
        mon.add(stamps[i:i + chunk], {k: v[i:i + chunk] for k, v in cols.items()})
        while True:
            out = mon.process()
            for ch in out['alarms']:
                alarms.setdefault(ch, (mon.channels[ch].since_ns - T0) * 1e-9)
            if on_window is not None:
                on_window(mon, out)
            if not out['windows']:
                break
    return alarms


@pytest.fixture(scope='module')
def leak_run():
    return closed_loop(26.0, LEAK_AT_S)


@pytest.fixture(scope='module')
def paper():
    from pneumatic_servo.model import ModelConfig
    return ModelConfig.paper()


def test_a_healthy_loop_stays_ok_a_seal_leak_warns_and_its_estimate_rises(leak_run, paper):
    """One pass over the leak run: no departure while the rig is the model; after the leak,
    WARN on both pressures within 2 s of data; the tracked fits the monitor asks for (the
    baseline, then once a whole window lies after the departure, then every period), each
    made as the fit process makes it, go from about 0 to the leak, with an alert."""
    stamps, cols = leak_run
    opts = MonitorOptions(baseline_s=4.0, track=('piston_seal_leakage',), fit_window_s=3.0,
                          fit_period_s=2.0)
    mon = Monitor(paper, opts)
    tracker = Tracker(paper, opts.track, opts.horizon_s)
    reports = []

    def watch(m, out):
        if m.report_due():
            reports.append(m.report())
        req = m.fit_request()
        if req is not None:
            tracker.fit((req['t_ns'] - T0) * 1e-9, req['signals'], req['dt'])
    alarms = feed(mon, stamps, cols, on_window=watch)
    assert mon.counts['skipped'] == 0 and mon.counts['lost'] == 0
    before = [r for r in reports if r['t_ns'] < T0 + LEAK_AT_S * 1e9]
    assert before and all(c['level'] == 'ok' for r in before for c in r['channels'].values())
    assert all(c['cusum'] < 0.5 * mon.h for r in before for c in r['channels'].values())
    # the leak: WARN on both pressures (and the angle), within 2 s of data
    assert {'p_a', 'p_b'} <= set(alarms)
    for ch, when in alarms.items():
        assert LEAK_AT_S <= when < LEAK_AT_S + 2.0, (ch, when)
    final = mon.report()
    for ch in ('p_a', 'p_b'):
        c = final['channels'][ch]
        assert c['level'] in ('warn', 'error') and c['ratio'] > 3 and c['p_value'] < 1e-6
        assert 'departs' in c['message']
    assert final['floor_source'] == 'baseline' and final['sensors'] is not None
    # the tracked parameter
    series = tracker.series['piston_seal_leakage.seal_leak_area_m2']
    assert series.t_s[0] < LEAK_AT_S and abs(series.values[0]) < 0.1 * LEAK_M2
    # no fit of the healthy rig but the reference; the next lie wholly after the onset
    assert all(t - opts.fit_window_s > LEAK_AT_S for t in series.t_s[1:])
    assert abs(series.values[-1] - LEAK_M2) < 0.05 * LEAK_M2
    assert series.alert is not None and series.alert['to'] > 0.9 * LEAK_M2
    assert 'seal leak rose' in series.alert['text']


def test_the_hidden_effect_bag_departs(paper):
    """The bundled demo (a load torque and two leaks the paper's model does not have,
    realistic sensors): the floor measured on its own first 3 s, then WARN."""
    from pneumatic_servo.io import read_series
    series, _ = read_series('bags/hidden_effect_demo')
    stamps = series['angle_rad'][0]
    cols = {}
    for sig in ('angle_rad', 'p_a_pa', 'p_b_pa', 'supply_pa', 'command_v'):
        t, v = series[sig]
        assert np.array_equal(t, stamps)
        cols[sig] = v
    mon = Monitor(paper, MonitorOptions(baseline_s=3.0))
    alarms = feed(mon, stamps, cols)
    assert alarms, mon.report()
    assert mon.sensors.quantum['angle'] == pytest.approx(2 * math.pi / 20000, rel=1e-6)


@pytest.mark.study
def test_with_its_own_truth_the_hidden_effect_bag_does_not_depart():
    from pneumatic_servo.io import read_series
    from pneumatic_servo.synth.hidden import hidden_config
    series, meta = read_series('bags/hidden_effect_demo')
    import json
    truth = hidden_config(json.loads(meta['hidden_effects']) if isinstance(
        meta['hidden_effects'], str) else meta['hidden_effects'])
    cols = {sig: series[sig][1] for sig in ('angle_rad', 'p_a_pa', 'p_b_pa', 'supply_pa',
                                            'command_v')}
    mon = Monitor(truth, MonitorOptions(baseline_s=3.0))
    assert feed(mon, series['angle_rad'][0], cols) == {}
    assert all(c['ratio'] < 2 for c in mon.report()['channels'].values())


# ---------------------------------------------------------------- the bookkeeping
def test_a_floor_file_is_saved_loaded_and_refused_at_another_rate(tmp_path, paper):
    stamps, cols = closed_loop(3.0)
    mon = Monitor(paper, MonitorOptions(baseline_s=1.0))
    saved = []
    feed(mon, stamps, cols,
         on_window=lambda m, out: out['floor'] and saved.append(
             save_floor(tmp_path / 'floor.yaml', m.floor_data())))
    assert saved
    floor = load_floor(saved[0])
    assert floor['period_s'] == pytest.approx(1e-3) and floor['horizon_s'] == pytest.approx(0.2)
    assert set(floor['floor_rms']) == set(CHANNELS)
    # a monitor with the file judges from the first window: no baseline
    again = Monitor(paper, MonitorOptions(baseline_s=100.0), floor['sensors'],
                    floor_period_s=floor['period_s'])
    feed(again, stamps[:1000], {k: v[:1000] for k, v in cols.items()})
    assert again.counts['judged'] > 0 and again.report()['floor_source'] == 'file'
    # data at another rate: a new baseline, and the report says why
    other = Monitor(paper, MonitorOptions(baseline_s=100.0), floor['sensors'],
                    floor_period_s=2e-3)
    feed(other, stamps[:1000], {k: v[:1000] for k, v in cols.items()})
    assert other.counts['judged'] == 0 and '500 Hz' in other.report()['floor_source']
    (tmp_path / 'bad.yaml').write_text('format: something else\n')
    with pytest.raises(ConfigError, match='not a floor'):
        load_floor(tmp_path / 'bad.yaml')


def test_a_monitor_that_falls_behind_skips_and_says_so(paper):
    stamps, cols = closed_loop(6.0)
    sensors = Sensors({ch: 0.0 for ch in CHANNELS}, {ch: 0.0 for ch in CHANNELS})
    mon = Monitor(paper, MonitorOptions(max_backlog_s=0.5), sensors)
    mon.add(stamps, cols)  # six seconds at once, then one batch
    mon.process()
    rep = mon.report()
    assert rep['decimating'] and rep['counts']['skipped'] >= 20
    assert 0 < rep['counts']['judged'] <= 3  # the windows of the last 0.5 s


def test_lost_samples_and_a_restart(paper):
    stamps, cols = closed_loop(3.0)
    keep = np.ones(len(stamps), bool)
    keep[1500:1520] = False  # 20 ms lost
    mon = Monitor(paper, MonitorOptions(baseline_s=1.0))
    feed(mon, stamps[keep], {k: v[keep] for k, v in cols.items()})
    assert mon.counts['lost'] == 20 and mon.counts['incomplete'] >= 1
    feed(mon, stamps[:500], {k: v[:500] for k, v in cols.items()})  # the clock went back
    assert mon.counts['restarts'] == 1


def test_options_and_look_levels_are_checked():
    with pytest.raises(ConfigError, match='replicas'):
        MonitorOptions(replicas=1)
    with pytest.raises(ConfigError, match='horizon_s'):
        MonitorOptions(horizon_s=0.0)
    # the levels of the looks at a growing series spend at most the fleet's 1 %
    assert sum(look_level(j) for j in range(1, 10000)) < 0.01


def test_compare_and_fleet_read_a_bag_that_holds_the_monitors_topics(tmp_path, paper):
    """The bundled demo again, with what a monitor publishes recorded beside it (its
    predictions under model/, stamped like the measurements, its statistics, /diagnostics):
    read, compared and checked by fleet exactly as the demo itself."""
    from rosbags.highlevel import AnyReader

    from pneumatic_servo.analysis.compare import compare
    from pneumatic_servo.fleet.discover import Recording
    from pneumatic_servo.fleet.task import TaskOptions, check_recording
    from pneumatic_servo.io import read_experiment
    from pneumatic_servo.io.bag.writer import write_raw_bag
    from pneumatic_servo.io.codecs import typestore
    store = typestore()
    JS = store.types['sensor_msgs/msg/JointState']
    FP = store.types['sensor_msgs/msg/FluidPressure']
    MA = store.types['std_msgs/msg/Float64MultiArray']
    Layout = store.types['std_msgs/msg/MultiArrayLayout']
    Dim = store.types['std_msgs/msg/MultiArrayDimension']
    DA = store.types['diagnostic_msgs/msg/DiagnosticArray']
    DS = store.types['diagnostic_msgs/msg/DiagnosticStatus']
    src = 'bags/hidden_effect_demo'
    messages = []
    from pneumatic_servo.io.bag.metadata import custom_data
    custom = custom_data(__import__('pathlib').Path(src))
    with AnyReader([__import__('pathlib').Path(src)], default_typestore=store) as reader:
        for conn, rec, raw in reader.messages():
            msg = reader.deserialize(raw, conn.msgtype)
            messages.append((conn.topic, conn.msgtype, rec, msg))
            if conn.topic == '/joint_states':  # the model's prediction, a little off
                messages.append(('/model/joint_states', conn.msgtype, rec + 1, JS(
                    header=msg.header, name=list(msg.name), position=msg.position + 0.01,
                    velocity=np.array([]), effort=np.array([]))))
            elif conn.topic == '/chamber_a/pressure':
                messages.append(('/model/chamber_a/pressure', conn.msgtype, rec + 1, FP(
                    header=msg.header, fluid_pressure=msg.fluid_pressure + 1e3, variance=0.0)))
            if conn.topic == '/joint_states' and msg.header.stamp.nanosec % 10 ** 9 == 0:
                layout = Layout(dim=[Dim(label='channel:angle,p_a,p_b', size=3, stride=33),
                                     Dim(label='field:...', size=11, stride=11)],
                                data_offset=0)
                messages.append(('/monitor/residuals', 'std_msgs/msg/Float64MultiArray', rec + 2,
                                 MA(layout=layout, data=np.zeros(33))))
                messages.append(('/diagnostics', 'diagnostic_msgs/msg/DiagnosticArray', rec + 2,
                                 DA(header=msg.header, status=[DS(
                                     level=1, name='m: monitor p_a', message='departs',
                                     hardware_id='monitor', values=[])])))
    messages.sort(key=lambda m: m[2])
    bag = write_raw_bag(tmp_path / 'with_monitor', messages, 'mcap', custom)
    plain, mixed = read_experiment(src), read_experiment(bag)
    assert set(plain.signals) == set(mixed.signals)
    for sig in plain.signals:
        assert np.array_equal(plain[sig], mixed[sig]), sig
    a = compare(plain, paper, mode='k_step')['channels']
    b = compare(mixed, paper, mode='k_step')['channels']
    assert a == b
    row = check_recording(Recording(str(bag), 'cell'), paper.to_dict(), TaskOptions(), 'k')
    assert row.status == 'ok', row.error
