"""Pure control code: parameter declarations, references, PID, the model-based law, metrics."""
import math

import numpy as np
import pytest

from pneumatic_servo.control.measurement import Measurement
from pneumatic_servo.control.metrics import step_metrics, tracking_rms
from pneumatic_servo.control.params import Spec
from pneumatic_servo.control.pid import PID_SPECS, PidController, VelocityEstimator
from pneumatic_servo.control.reference import Reference, Trajectory, TrajectoryPoint, sine_points
from pneumatic_servo.errors import ConfigError

DEG = math.pi / 180


# ------------------------------------------------------------------------ parameters
def test_spec_checks_type_range_choice_and_nan():
    s = Spec('k', 1.0, 'gain', 'V/rad', 0.0, 10.0)
    assert s.coerce(2) == 2.0 and s.coerce('2.5') == 2.5
    assert s.check(5.0) is None
    assert '[0, 10]' in s.check(11.0) and 'V/rad' in s.check(11.0)
    assert 'finite' in s.check(math.inf)
    assert 'finite' in s.check(math.nan)
    with pytest.raises(ConfigError, match='expected float'):
        s.coerce(True)
    n = Spec('a', math.nan, 'angle', 'rad', 0.0, 6.5, allow_nan=True)
    assert n.check(math.nan) is None and n.check(7.0)
    c = Spec('mode', 'pid', 'law', choices=('pid', 'smc'))
    assert c.check('smc') is None and 'one of' in c.check('lqr')
    b = Spec('flag', False, 'flag')
    assert b.coerce('true') is True and b.coerce('False') is False
    i = Spec('n', 1, 'count', '', 0, 5)
    assert i.coerce('3') == 3 and i.check(6)


def test_spec_set_cross_check_and_assignments():
    assert PID_SPECS.validate({'output_min_v': 6.0, 'output_max_v': 4.0})
    assert PID_SPECS.validate({'output_min_v': 2.0, 'output_max_v': 8.0, 'null_v': 9.0})
    assert PID_SPECS.validate(PID_SPECS.defaults()) is None
    assert PID_SPECS.parse_assignments(['kp=3', 'ki = 0.5']) == {'kp': 3.0, 'ki': 0.5}
    with pytest.raises(ConfigError, match="did you mean 'kp'"):
        PID_SPECS.parse_assignments(['kpp=3'])
    with pytest.raises(ConfigError, match='NAME=VALUE'):
        PID_SPECS.parse_assignments(['kp'])


def test_every_spec_default_is_within_its_own_range():
    from pneumatic_servo.control.model_based import SMC_SPECS
    for specs in (PID_SPECS, SMC_SPECS):
        for s in specs:
            assert s.check(s.default) is None, s.name
            assert s.description and s.describe()


# ------------------------------------------------------------------------ references
def test_single_point_is_a_scheduled_step():
    tr = Trajectory([TrajectoryPoint(0.5, 2.0)])
    assert tr.sample(0.49) is None
    assert tr.sample(0.5) == Reference(2.0) and tr.sample(9.0) == Reference(2.0)


def test_linear_and_hermite_segments():
    tr = Trajectory([TrajectoryPoint(0.0, 0.0), TrajectoryPoint(1.0, 2.0)])
    r = tr.sample(0.25)
    assert r.position == pytest.approx(0.5) and r.velocity == pytest.approx(2.0)
    pts = sine_points(1.0, 4.0, 1.5, 0.5, 0.5, dt_s=0.01)
    tr = Trajectory(pts)
    w = math.pi
    for t in np.linspace(1.0, 4.99, 57):
        r = tr.sample(t)
        assert r.position == pytest.approx(1.5 + 0.5 * math.sin(w * (t - 1.0)), abs=1e-7)
        assert r.velocity == pytest.approx(0.5 * w * math.cos(w * (t - 1.0)), abs=1e-4)
        assert r.acceleration == pytest.approx(-0.5 * w * w * math.sin(w * (t - 1.0)), abs=2e-2)
    assert tr.sample(99.0) == Reference(pts[-1].position)


@pytest.mark.parametrize('pts', [[], [TrajectoryPoint(1.0, 0.0), TrajectoryPoint(1.0, 1.0)],
                                 [TrajectoryPoint(2.0, 0.0), TrajectoryPoint(1.0, 1.0)],
                                 [TrajectoryPoint(math.nan, 0.0)],
                                 [TrajectoryPoint(0.0, math.inf)]])
def test_bad_trajectories_are_rejected(pts):
    with pytest.raises(ConfigError):
        Trajectory(pts)


# ----------------------------------------------------------------------------- PID
def pid(**kw):
    base = dict(ki=0.0, kd=0.0, kdp=0.0, kv=0.0, friction_v=0.0)
    base.update(kw)
    return PidController(**base)


def test_pid_sign_null_and_limits():
    c = pid(kp=5.0)
    m = Measurement(0.0, 1.0, 0.0)
    assert c.update(0.0, Reference(1.0), m) == pytest.approx(5.0)
    assert c.update(0.001, Reference(1.1), m) == pytest.approx(5.5)   # fill chamber a
    assert c.update(0.002, Reference(0.9), m) == pytest.approx(4.5)
    assert c.update(0.003, Reference(10.0), m) == 10.0
    assert c.update(0.004, Reference(-10.0), m) == 0.0
    c = pid(kp=5.0, output_min_v=3.0, output_max_v=7.0, null_v=5.2)
    assert c.update(0.0, Reference(1.0), m) == pytest.approx(5.2)
    assert c.update(0.001, Reference(9.0), m) == 7.0


def test_pid_feedforward_pressure_feedback_and_friction_terms():
    m = Measurement(0.0, 1.0, 0.0, 3e5, 2e5)
    assert pid(kp=0.0, kv=0.2).update(0.0, Reference(1.0, 2.0), m) == pytest.approx(5.4)
    assert pid(kp=0.0, kdp=1e-6).update(0.0, Reference(1.0), m) == pytest.approx(4.9)
    c = pid(kp=0.0, friction_v=0.1, friction_band_rad=0.001)
    assert c.update(0.0, Reference(1.01), m) == pytest.approx(5.1, abs=1e-6)
    assert c.update(0.001, Reference(0.99), m) == pytest.approx(4.9, abs=1e-6)
    # no pressures measured: the pressure term is off, not NaN
    assert pid(kdp=1e-6).update(0.0, Reference(1.0), Measurement(0.0, 1.0)) == 5.0


def test_pid_integral_zone_limit_and_anti_windup():
    c = pid(kp=0.0, ki=10.0, integral_zone_rad=0.1, integral_limit_v=0.2)
    m = Measurement(0.0, 1.0, 0.0)
    for k in range(1, 200):
        c.update(k * 0.01, Reference(1.05), m)
    assert c.integral == pytest.approx(0.2)     # clamped
    c.update(3.0, Reference(2.0), m)            # far away: forgotten
    assert c.integral == 0.0
    c = pid(kp=100.0, ki=10.0, integral_zone_rad=1.0)
    for k in range(1, 50):
        u = c.update(k * 0.01, Reference(1.5), m)  # saturated at 10 V
    assert u == 10.0 and c.integral == 0.0


def test_velocity_estimator_differentiates_and_filters():
    v = VelocityEstimator(0.0)
    for k in range(5):
        out = v.update(k * 0.001, 2.0 * k * 0.001)
    assert out == pytest.approx(2.0)
    v = VelocityEstimator(0.01)
    assert v.update(0.0, 0.0, 3.0) == 3.0       # measured velocity used when present
    v.update(0.001, 0.0, 0.0)
    assert 0.0 < v.value < 3.0


def test_pid_closes_the_loop_on_the_model():
    from pneumatic_servo.model import Model, ModelConfig, Stepper, initial_state
    model = Model(ModelConfig.paper())
    s = Stepper(model, 1e-3, x0=initial_state(model, angle_rad=40 * DEG), method='fixed')
    c = PidController()
    x = s.x.copy()
    ys = []
    for k in range(800):
        u = c.update(k * 1e-3, Reference(60 * DEG), Measurement(k * 1e-3, x[0], x[1], x[2],
                                                                 x[3]))
        assert 0.0 <= u <= 10.0
        x = s.step(u).copy()
        ys.append(x[0])
    assert abs(ys[-1] - 60 * DEG) < 0.5 * DEG


# ---------------------------------------------------------------------- model-based
@pytest.fixture(scope='module')
def smc():
    from pneumatic_servo.control.model_based import SlidingModeController
    from pneumatic_servo.model import Model, ModelConfig
    return SlidingModeController(Model(ModelConfig.paper()))


def test_smc_needs_pressures(smc):
    with pytest.raises(ValueError, match='pressures'):
        smc.update(0.0, Reference(1.0), Measurement(0.0, 1.0, 0.0))


def test_smc_direction_and_range(smc):
    smc.reset()
    m = Measurement(0.0, 1.0, 0.0, 5e5, 5e5, 7e5)
    up = smc.update(0.0, Reference(1.2), m)
    smc.reset()
    down = smc.update(0.0, Reference(0.8), m)
    assert 5.0 < up <= 10.0 and 0.0 <= down < 5.0


def test_smc_inversion_hits_the_wanted_pressure_rate(smc):
    from pneumatic_servo.control.measurement import Measurement as M
    x = smc._state(M(0.0, 1.0, 0.0, 4.5e5, 5.5e5), 0.0)
    lo_rate, _ = smc._rates(0.0, x, 0.0, 7e5)
    hi_rate, _ = smc._rates(0.0, x, 10.0, 7e5)
    assert lo_rate < 0.0 < hi_rate
    for target in np.linspace(0.9 * lo_rate, 0.9 * hi_rate, 7):
        u = smc._invert(0.0, x, 7e5, target, 0.0, 10.0)
        got, _ = smc._rates(0.0, x, u, 7e5)
        assert got == pytest.approx(target, rel=1e-3, abs=1e3)
    assert smc._invert(0.0, x, 7e5, 10 * hi_rate, 0.0, 10.0) == 10.0
    assert smc._invert(0.0, x, 7e5, 10 * lo_rate, 0.0, 10.0) == 0.0


# ---------------------------------------------------------------------------- metrics
def test_step_metrics_of_a_known_response():
    t = np.arange(0.0, 3.0, 0.001)
    tau = 0.1
    y = np.where(t < 0.5, 0.0, 1.0 - np.exp(-(t - 0.5) / tau))
    m = step_metrics(t, y, 0.5, 0.0, 1.0, band_rad=0.01)
    assert m['settling_time_s'] == pytest.approx(tau * math.log(100), abs=2e-3)
    assert m['overshoot_rad'] == 0.0
    assert m['rise_time_s'] == pytest.approx(tau * math.log(9), abs=2e-3)
    y2 = y + np.where(t > 1.0, 0.2 * np.exp(-(t - 1.0) / 0.05), 0.0)
    m2 = step_metrics(t, y2, 0.5, 0.0, 1.0, band_rad=0.01)
    assert m2['overshoot_rad'] > 0.1 and m2['overshoot_percent'] > 10.0
    never = step_metrics(t, 0.5 * y, 0.5, 0.0, 1.0, band_rad=0.01)
    assert math.isnan(never['settling_time_s'])


def test_tracking_rms():
    t = np.linspace(0.0, 1.0, 101)
    r = tracking_rms(t, np.zeros(101), np.full(101, 0.5), 0.2, 0.8)
    assert r['rms_error_rad'] == pytest.approx(0.5) and r['max_error_rad'] == 0.5
    with pytest.raises(ValueError):
        tracking_rms(t, t, t, 5.0, 6.0)
