"""The model against physics: the paper's equations re-derived here, balance laws, settlements.

The reference formulas below are written from the paper (Eqs 4, 7, 8, 17, 40)
and its settlements (docs/model.md, section 4), independently of
``pneumatic_servo.physics``, so that a test compares the model with the equations, not
with itself.
"""
import math
import zlib

import numpy as np
import pytest

from pneumatic_servo import _jit
from pneumatic_servo.effects.layout import (
    BLOCKED,
    C_MA,
    C_MB,
    CIRCUITS,
    P_A,
    P_B,
    T_A,
    T_B,
)
from pneumatic_servo.model import Model, ModelConfig, Stepper, initial_state, simulate
from pneumatic_servo.physics.gas import clearance_flow, orifice_flow
from pneumatic_servo.physics.valve import flow_coefficient

# --- the paper's constants (Table 2, Section 5, docs/model.md, settlement 4) ---------------------
KAPPA, R_GAS = 1.4, 287.0
CV, CP = R_GAS / (KAPPA - 1.0), KAPPA * R_GAS / (KAPPA - 1.0)
P_E, T_E = 101325.0, 293.15
A_HALF, R_HOLE = 1.010e-3, 1.000e-3
D_S, D_H = 6.000e-3, 6.023e-3
B_CRIT, C0, MU, L0 = 0.5382, 0.43, 1.83e-5, 2.0e-3
AREA, D_F = 3.4636e-4, 0.014
BAND = 0.005  # laminar band of the settlement (docs/model.md, settlement 8)
SUPPLY = 0.6e6 + P_E
C1_POLY = (-3.5227e11, 1.8641e9, -3.133e6, 1713.94, 0.4517)  # x^4 ... x^0, settled signs


def c1_settled(x):
    """C1 = P(|x_v|), docs/model.md settlement 1."""
    return np.polyval(C1_POLY, abs(x))


def c1_printed(x):
    """Eq. 40 exactly as printed (both branches)."""
    p4, p3, p2, p1, p0 = C1_POLY
    if x < 0:
        return p4 * x ** 4 + p3 * x ** 3 + p2 * x ** 2 + p1 * x + p0
    return p4 * x ** 4 - p3 * x ** 3 + p2 * x ** 2 - p1 * x + p0


def s_v(x):
    """Eq. 4: open area of one sleeve hole at spool travel x >= 0 [m^2]."""
    d = A_HALF - x
    if d >= R_HOLE:
        return 0.0
    return R_HOLE ** 2 * math.acos(d / R_HOLE) - d * math.sqrt(R_HOLE ** 2 - d * d)


def s_e(x):
    """Eqs 3, 5, 7, 21: effective orifice area [m^2] at spool displacement x."""
    s_h = math.pi * (D_H ** 2 - D_S ** 2) / 4.0
    return c1_settled(x) * (2.0 * s_v(abs(x)) + C0 * s_h)


def psi(ratio, b=B_CRIT, band=BAND):
    """Eq. 8 flow function with the laminar band next to ratio 1 (docs/model.md, settlement 8)."""
    if ratio < b:
        return math.sqrt(2 * KAPPA / (KAPPA + 1) * (2 / (KAPPA + 1)) ** (2 / (KAPPA - 1)))

    def sub(r):
        return math.sqrt(2 * KAPPA / (KAPPA - 1) * (r ** (2 / KAPPA) - r ** ((KAPPA + 1) / KAPPA)))
    if ratio <= 1.0 - band:
        return sub(ratio)
    return sub(1.0 - band) * (1.0 - ratio) / band


def eq8(area, p_up, t_up, p_down):
    """Eq. 8/9: orifice mass flow [kg/s] from the upstream to the downstream side."""
    return area * p_up / math.sqrt(R_GAS * t_up) * psi(p_down / p_up)


def eq17(length, p_up, t_up, p_down):
    """Eq. 17/18: clearance mass flow [kg/s], density from p_down and T_up."""
    return (math.pi * D_S * (D_H - D_S) ** 3 * p_down * (p_up - p_down)
            / (96.0 * MU * length * R_GAS * t_up))


@pytest.fixture(scope='module')
def model():
    return Model(ModelConfig.paper())


def sealed_config(friction=True, heat=False):
    """The paper's model with every valve path closed: C0 = 0 (no annulus area), a gap of
    1e-12 m (no clearance flow); at a command within 5 +/- 0.05 V no hole is open."""
    cfg = ModelConfig.paper()
    cfg.set('orifice_flow.area_conversion_coefficient', 0.0)
    cfg.set('core.sleeve_bore_diameter_m', D_S + 2e-12)
    if not heat:
        cfg.set('wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k', 0.0)
    if not friction:
        for key in ('static_friction_n', 'coulomb_friction_n', 'viscous_friction_n_s_per_rad'):
            cfg.set(f'stribeck_friction.{key}', 0.0)
    return cfg


def volumes(cfg, theta):
    """V_a, V_b [m^3] with the settled law dV_a/dtheta = A d_f (docs/model.md, settlement 2)."""
    c = cfg.core
    swept = c['piston_area_m2'] * c['pinion_pitch_diameter_m']
    return (c['dead_volume_a_m3'] + swept * theta,
            c['dead_volume_b_m3'] + swept * (c['stroke_rad'] - theta))


def integral(t, y):
    """Trapezoidal integral of samples ``y`` over ``t``."""
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)))


# --- C1 (docs/model.md, settlement 1) ------------------------------------------------------------
def test_c1_sign_settlement_positive_over_whole_travel(model):
    p = [model.config.get(f'orifice_flow.{k}') for k in (
        'flow_coefficient_p0', 'flow_coefficient_p1_per_m', 'flow_coefficient_p2_per_m2',
        'flow_coefficient_p3_per_m3', 'flow_coefficient_p4_per_m4')]
    xs = np.linspace(0.0, 1e-3, 1001)
    c1 = np.array([flow_coefficient(x, *p) for x in xs])
    assert np.all(c1 > 0.0)
    assert c1[0] == pytest.approx(0.4517, abs=1e-12)
    assert flow_coefficient(0.4e-3, *p) == pytest.approx(0.75, abs=0.01)
    assert flow_coefficient(1e-3, *p) == pytest.approx(0.544, abs=1e-3)
    np.testing.assert_allclose(c1, [c1_settled(x) for x in xs], rtol=1e-12)


def test_c1_as_printed_is_negative_at_6_volts():
    # the error the settlement fixes: Eq. 40's x_v >= 0 branch at 6 V (x_v = 0.2 mm)
    assert c1_printed(2e-4) == pytest.approx(-0.032, abs=1e-3)
    assert c1_printed(1e-3) < 0.0 and c1_printed(-1e-3) < 0.0


# --- flow laws -------------------------------------------------------------------------------
@pytest.mark.parametrize('ratio', [0.2, 0.5, 0.5381, 0.54, 0.7, 0.9, 0.994, 0.997, 0.9999])
def test_orifice_flow_is_eq8_and_bidirectional(ratio):
    area, pu, tu = 2e-7, 7e5, 300.0
    pd = ratio * pu
    expected = eq8(area, pu, tu, pd)
    assert orifice_flow(area, pu, tu, pd, 250.0, B_CRIT, R_GAS, KAPPA, BAND) == \
        pytest.approx(expected, rel=1e-12)
    # same law, roles swapped: the flow from the low to the high side is its negative
    assert orifice_flow(area, pd, 250.0, pu, tu, B_CRIT, R_GAS, KAPPA, BAND) == \
        pytest.approx(-expected, rel=1e-12)


def test_laminar_band_is_continuous_and_zero_at_equal_pressure():
    pu = 7e5
    edge = orifice_flow(1e-7, pu, T_E, (1 - BAND) * pu, T_E, B_CRIT, R_GAS, KAPPA, BAND)
    just_in = orifice_flow(1e-7, pu, T_E, (1 - BAND + 1e-12) * pu, T_E, B_CRIT, R_GAS, KAPPA,
                           BAND)
    assert just_in == pytest.approx(edge, rel=1e-6)
    assert orifice_flow(1e-7, pu, T_E, pu, T_E, B_CRIT, R_GAS, KAPPA, BAND) == 0.0
    flows = [orifice_flow(1e-7, pu, T_E, r * pu, T_E, B_CRIT, R_GAS, KAPPA, BAND)
             for r in np.linspace(B_CRIT, 1.0, 500)]
    assert np.all(np.diff(flows) <= 0.0)  # less flow as the pressures approach each other


def test_clearance_flow_is_eq17_and_bidirectional():
    gap = (D_H - D_S) / 2
    for length in (L0, L0 + 3e-4):
        expected = eq17(length, 6e5, 293.15, P_E)
        got = clearance_flow(D_S, gap, length, 6e5, 293.15, P_E, 280.0, MU, R_GAS)
        assert got == pytest.approx(expected, rel=1e-12)
        back = clearance_flow(D_S, gap, length, P_E, 280.0, 6e5, 293.15, MU, R_GAS)
        assert back == pytest.approx(-expected, rel=1e-12)


# --- valve symmetry --------------------------------------------------------------------------
def _rhs(model, x, u, ps, circuit, P=None):
    return model.evaluate(x, u, ps, circuit, params=P)


def test_valve_is_symmetric_with_chambers_swapped(model):
    cfg = model.config.copy()
    cfg.set('core.blocked_angle_rad', 0.5 * cfg.core['stroke_rad'])  # V_a = V_b
    P = model.param_vector(cfg)
    rng = np.random.default_rng(1)
    for _ in range(50):
        dv = rng.uniform(0.01, 5.0)
        pa, pb = rng.uniform(P_E, SUPPLY, 2)
        ta, tb = rng.uniform(260.0, 330.0, 2)
        x = initial_state(model, p_a_pa=pa, p_b_pa=pb, t_a_k=ta, t_b_k=tb)
        xm = initial_state(model, p_a_pa=pb, p_b_pa=pa, t_a_k=tb, t_b_k=ta)
        c, dx = _rhs(model, x, 5.0 + dv, SUPPLY, BLOCKED, P)
        cm, dxm = _rhs(model, xm, 5.0 - dv, SUPPLY, BLOCKED, P)
        assert c[C_MA] == pytest.approx(cm[C_MB], rel=1e-12, abs=1e-18)
        assert c[C_MB] == pytest.approx(cm[C_MA], rel=1e-12, abs=1e-18)
        assert dx[P_A] == pytest.approx(dxm[P_B], rel=1e-10)
        assert dx[T_A] == pytest.approx(dxm[T_B], rel=1e-10, abs=1e-12)


# --- mass and energy balance of closed chambers ----------------------------------------------
def _charge(model, cfg, duration=0.03, u=6.0):
    """Blocked chambers, a from atmosphere and b from supply, valve held at ``u``."""
    t = np.linspace(0.0, duration, 3001)
    x0 = initial_state(model, angle_rad=0.0, p_a_pa=P_E, p_b_pa=SUPPLY, command_v=u,
                       supply_pa=SUPPLY, config=cfg)
    return simulate(model, t, u, SUPPLY, x0=x0, circuit='blocked', rtol=1e-10, config=cfg)


def _known_flows(res, u=6.0):
    """Independent Eqs 8, 9, 17, 18 along the trajectory: (into a, into b) [kg/s] and the
    enthalpy flows (into a, into b) [W], for x_v > 0."""
    xv = 2e-4 * (u - 5.0)
    area, length = s_e(xv), L0 + xv
    m1a = np.array([eq8(area, SUPPLY, T_E, p) for p in res.p_a_pa])
    m5 = np.array([eq17(length, p, t, P_E) for p, t in zip(res.p_a_pa, res.t_a_k)])
    m1b = np.array([eq17(length, SUPPLY, T_E, p) for p in res.p_b_pa])
    m3 = np.array([eq8(area, p, t, P_E) for p, t in zip(res.p_b_pa, res.t_b_k)])
    h_a = CP * T_E * m1a - CP * res.t_a_k * m5
    h_b = CP * T_E * m1b - CP * res.t_b_k * m3
    return m1a - m5, m1b - m3, h_a, h_b


def test_mass_balance_of_blocked_chambers(model):
    cfg = model.config
    res = _charge(model, cfg)
    # stay where the paper's laws hold unmodified (outside the laminar band)
    assert res.p_a_pa.max() < (1 - BAND) * SUPPLY and P_E / res.p_b_pa.min() < 1 - BAND
    v_a, v_b = volumes(cfg, 0.0)
    m_a = res.p_a_pa * v_a / (R_GAS * res.t_a_k)
    m_b = res.p_b_pa * v_b / (R_GAS * res.t_b_k)
    md_a, md_b, _, _ = _known_flows(res)
    assert m_a[-1] - m_a[0] == pytest.approx(integral(res.t, md_a), rel=1e-5)
    assert m_b[-1] - m_b[0] == pytest.approx(integral(res.t, md_b), rel=1e-5)
    assert m_a[-1] - m_a[0] > 0.5 * m_a[0]  # a real change, not a trivial pass


@pytest.mark.parametrize('heat', [False, True])
def test_energy_balance_of_blocked_chambers(model, heat):
    """U = c_v m T = p V / (kappa - 1) changes by the enthalpy flows plus the wall heat."""
    cfg = model.config.copy()
    h = cfg.get('wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k') if heat else 0.0
    cfg.set('wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k', h)
    res = _charge(model, cfg)
    v_a, v_b = volumes(cfg, 0.0)
    s_a = cfg.get('wall_heat_transfer.wall_area_a_m2')
    s_b = cfg.get('wall_heat_transfer.wall_area_b_m2')
    _, _, h_a, h_b = _known_flows(res)
    q_a, q_b = h * s_a * (T_E - res.t_a_k), h * s_b * (T_E - res.t_b_k)
    du_a = (res.p_a_pa[-1] - res.p_a_pa[0]) * v_a / (KAPPA - 1)
    du_b = (res.p_b_pa[-1] - res.p_b_pa[0]) * v_b / (KAPPA - 1)
    assert du_a == pytest.approx(integral(res.t, h_a + q_a), rel=1e-5)
    assert du_b == pytest.approx(integral(res.t, h_b + q_b), rel=1e-5)
    if not heat:  # adiabatic charging from atmosphere heats the gas well above T_s
        assert res.t_a_k.max() > T_E + 20.0


# --- factor-of-two volume settlement (docs/model.md, settlement 2) -------------------------------
def test_sealed_actuator_conserves_energy_and_follows_isentropes(model):
    """No flow, no friction, no heat: the pistons swing on two gas springs.

    The gas's p dV work must equal the shaft's torque x angle. With
    dV_a/dtheta = A d_f (the settlement) the internal energy given up,
    -Delta(p_a V_a + p_b V_b)/(kappa-1), equals the kinetic energy gained,
    and p V^kappa stays constant in each chamber; Eq. 33 as printed (half the
    volume change) would break both by a factor of two.
    """
    cfg = sealed_config(friction=False)
    theta0 = 0.5 * cfg.core['stroke_rad']
    x0 = initial_state(model, angle_rad=theta0, p_a_pa=4.0e5, p_b_pa=2.5e5, config=cfg)
    t = np.linspace(0.0, 0.3, 3001)
    res = simulate(model, t, 5.0, SUPPLY, x0=x0, rtol=1e-10, config=cfg)
    th = res.angle_rad
    assert th.max() - th.min() > 0.5  # a real swing ...
    assert 0.0 < th.min() and th.max() < cfg.core['stroke_rad']  # ... clear of the stops
    v_a, v_b = volumes(cfg, th)
    core = cfg.core
    inertia = 0.5 * core['piston_mass_kg'] * D_F ** 2 + core['gear_inertia_kg_m2']
    u_gas = (res.p_a_pa * v_a + res.p_b_pa * v_b) / (KAPPA - 1)
    kinetic = 0.5 * inertia * res.velocity_rad_s ** 2
    work = AREA * D_F * integral(th, res.p_a_pa - res.p_b_pa)  # torque x angle, to the end
    assert kinetic.max() > 0.1  # [J]
    np.testing.assert_allclose(u_gas - u_gas[0], -kinetic, atol=1e-5 * kinetic.max())
    assert kinetic[-1] == pytest.approx(work, abs=1e-4 * kinetic.max())
    for p, v in ((res.p_a_pa, v_a), (res.p_b_pa, v_b)):
        np.testing.assert_allclose(p * v ** KAPPA, p[0] * v[0] ** KAPPA, rtol=1e-6)
    half_a = core['dead_volume_a_m3'] + 0.5 * AREA * D_F * th  # Eq. 33 as printed
    drift = np.ptp(res.p_a_pa * half_a ** KAPPA) / (res.p_a_pa[0] * half_a[0] ** KAPPA)
    assert drift > 0.05  # the test can tell the two volume laws apart


# --- stiction (Eqs 34-37) --------------------------------------------------------------------
@pytest.mark.parametrize('fraction, moves', [(0.95, False), (-0.95, False), (1.05, True),
                                             (-1.05, True)])
def test_stiction_holds_below_breakaway_and_slips_above(model, fraction, moves):
    """Breakaway when A d_f (p_a - p_b) exceeds (d_f/2) F_s, i.e. p_a - p_b > F_s / (2 A)."""
    cfg = sealed_config(friction=True)
    f_s = cfg.get('stribeck_friction.static_friction_n')
    dp = fraction * f_s / (2.0 * AREA)
    p0 = 4.0e5
    x0 = initial_state(model, angle_rad=1.5, p_a_pa=p0 + dp, p_b_pa=p0, config=cfg)
    t = np.linspace(0.0, 0.5, 501)
    res = simulate(model, t, 5.0, SUPPLY, x0=x0, config=cfg)
    travel = res.angle_rad - 1.5
    if moves:
        assert np.sign(fraction) * travel[-1] > 1e-4
        assert np.abs(res.velocity_rad_s).max() > cfg.core['stiction_velocity_band_rad_s']
    else:
        assert np.abs(travel).max() < 1e-9
        assert np.abs(res.velocity_rad_s).max() < 1e-9


# --- bounds and robustness -------------------------------------------------------------------
def test_blocked_chambers_stay_between_atmosphere_and_supply(model):
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 1.0, 201)
    for _ in range(12):
        u = rng.uniform(0.0, 10.0)
        ps = rng.uniform(2e5, 9e5)
        pa, pb = rng.uniform(P_E, ps, 2)
        x0 = initial_state(model, angle_rad=0.0, p_a_pa=pa, p_b_pa=pb, command_v=u,
                           supply_pa=ps)
        res = simulate(model, t, u, ps, x0=x0, circuit='blocked')
        for p in (res.p_a_pa, res.p_b_pa):
            assert p.min() >= P_E - 1e-6 and p.max() <= ps + 1e-6, (u, ps, pa, pb)


@pytest.mark.parametrize('method', ['adaptive', 'fixed'])
@pytest.mark.parametrize('circuit', list(CIRCUITS))
def test_no_nan_across_random_valid_inputs(model, circuit, method):
    rng = np.random.default_rng(zlib.crc32(f'{circuit}-{method}'.encode()))
    stroke = model.config.core['stroke_rad']
    t = np.arange(0.0, 0.3, 1e-3)
    for _ in range(4):
        ps = rng.uniform(1.5e5, 1.0e6)
        u = np.repeat(rng.uniform(0.0, 10.0, 6), len(t) // 6 + 1)[:len(t)] \
            + rng.uniform(0.0, 1.0) * np.sin(2 * np.pi * rng.uniform(0.5, 20.0) * t)
        x0 = initial_state(model, angle_rad=rng.uniform(0.0, stroke),
                           velocity_rad_s=rng.uniform(-5.0, 5.0),
                           p_a_pa=rng.uniform(P_E, ps), p_b_pa=rng.uniform(P_E, ps),
                           t_a_k=rng.uniform(250.0, 350.0), t_b_k=rng.uniform(250.0, 350.0),
                           supply_pa=ps)
        res = simulate(model, t, u, ps, x0=x0, circuit=circuit, method=method)
        assert np.all(np.isfinite(res.states)) and np.all(np.isfinite(res.outputs))
        assert res.p_a_pa.min() > 0.0 and res.p_b_pa.min() > 0.0
        assert res.t_a_k.min() > 0.0 and res.t_b_k.min() > 0.0
        assert res.angle_rad.min() >= 0.0 and res.angle_rad.max() <= stroke


@pytest.mark.parametrize('method', ['adaptive', 'fixed'])
def test_stepper_stays_finite_and_physical(model, method):
    rng = np.random.default_rng(3)
    plant = Stepper(model, period_s=1e-3, method=method)
    stroke = model.config.core['stroke_rad']
    u = 5.0
    for k in range(600):
        u = rng.uniform(0.0, 10.0) if k % 50 == 0 else u
        x = plant.step(u)
        assert np.all(np.isfinite(x))
        assert x[P_A] > 0.0 and x[P_B] > 0.0 and 0.0 <= x[0] <= stroke


def _delayed_plant(command_delay_s, measurement_delay_s):
    cfg = ModelConfig.paper().with_effect('transport_delay', {'command_delay_s': command_delay_s})
    return Model(cfg.with_effect('sensor_delay', {'measurement_delay_s': measurement_delay_s}))


def _stepped(model, u, **kw):
    plant = Stepper(model, period_s=1e-3, command_v=float(u[0]), **kw)
    return np.array([plant.x.copy()] + [plant.step(uk) for uk in u[:-1]])


def test_stepper_delays_of_whole_periods_are_samples():
    """Delays of whole periods (what the Stepper's ring buffers gave before it took fractions)
    shift the undelayed run by exactly those samples: the command 3 periods late, the
    measurement 2 periods late, bit for bit."""
    u = 5.0 + 0.4 * np.sin(2 * np.pi * 3.0 * np.arange(400) * 1e-3)
    plain = _stepped(_delayed_plant(0.0, 0.0), u)
    command_late = _stepped(_delayed_plant(3e-3, 0.0), u)
    # the valve sees u[0] for three periods, then u shifted by three: the same as commanding
    # the undelayed plant with that sequence
    assert np.array_equal(command_late, _stepped(_delayed_plant(0.0, 0.0),
                                                 np.concatenate([np.full(3, u[0]), u[:-3]])))
    measured_late = _stepped(_delayed_plant(0.0, 2e-3), u)
    assert np.array_equal(measured_late[2:], plain[:-2])
    assert np.array_equal(measured_late[:2], np.repeat(plain[:1], 2, axis=0))


@pytest.mark.parametrize('method', ['adaptive', 'fixed'])
def test_stepper_takes_fractional_delays_as_simulate_does(method):
    """A delay that is no whole number of periods (2.4 ms command, 1.7 ms measurement at
    1 kHz) acts in the Stepper as it does offline: the valve sees the command interpolated
    between the samples around t - d_in, the sensors the state interpolated around t - d_out.
    Before, the Stepper rounded both to whole periods (2 ms and 2 ms)."""
    model = _delayed_plant(2.4e-3, 1.7e-3)
    t = np.arange(600) * 1e-3
    u = 5.0 + 0.4 * np.sin(2 * np.pi * 3.0 * t)
    x0 = initial_state(model, command_v=u[0])
    stepped = _stepped(model, u, x0=x0, method=method, substeps=40)
    offline = simulate(model, t, u, x0=x0, method=method, substeps=40)
    # the same steps, the same interpolation: equal to rounding [rad, rad/s, Pa, Pa]
    assert np.allclose(stepped[:, :4], offline.states[:, :4], rtol=0,
                       atol=[1e-8, 1e-6, 1e-3, 1e-3])
    rounded = simulate(_delayed_plant(2e-3, 2e-3), t, u, x0=x0, method=method, substeps=40)
    assert np.abs(rounded.p_a_pa - offline.p_a_pa).max() > 10.0  # [Pa]: rounding shows


def test_end_stops_hold_the_shaft(model):
    t = np.linspace(0.0, 1.0, 1001)
    for u, stop in ((8.0, model.config.core['stroke_rad']), (2.0, 0.0)):
        res = simulate(model, t, u, SUPPLY)
        assert res.angle_rad[-1] == pytest.approx(stop, abs=1e-6)
        assert abs(res.velocity_rad_s[-1]) < 1e-3


@pytest.mark.parametrize('window,order,deriv', [(5, 2, 0), (31, 3, 2), (31, 2, 1), (101, 2, 0),
                                                (7, 3, 1)])
def test_savitzky_golay_equals_scipys(window, order, deriv):
    """The package's filter (kept to spare every process the import of scipy.signal) gives
    scipy's result, edges included."""
    from scipy.signal import savgol_filter as scipys

    from pneumatic_servo.smoothing import savgol_filter
    x = np.cumsum(np.random.default_rng(1).normal(size=500))
    want = scipys(x, window, order, deriv=deriv, delta=1e-3)
    got = savgol_filter(x, window, order, deriv=deriv, delta=1e-3)
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))
    with pytest.raises(ValueError, match='odd'):
        savgol_filter(x, 4, 2)


def test_a_batch_row_stops_at_its_own_length_with_the_same_states():
    """k-step windows of unequal length share one batch: a row simulated over its first n
    samples has exactly the states of the full-length row there, and NaN after them."""
    from pneumatic_servo.model.simulate import simulate_batch
    model = Model(ModelConfig.paper())
    t = np.arange(0.0, 0.2, 1e-3)
    command = 5.0 + 0.3 * np.sin(30 * t)
    x0 = initial_state(model)
    XB, _, status = simulate_batch(model, t, command, 7e5, np.array([x0, x0]),
                                   np.array([model.params, model.params]), lengths=[200, 73])
    assert list(status) == [0, 0]
    np.testing.assert_array_equal(XB[1, :73], XB[0, :73])
    assert np.isnan(XB[1, 73:]).all() and np.isfinite(XB[0]).all()


@pytest.mark.skipif(not _jit.ENABLED, reason='threads take turns in plain Python')
def test_a_batch_gives_each_row_the_same_states_in_one_thread_or_several():
    """A batch runs blocks of rows in threads (``stepping.run_batch_threaded``): each row is
    the same whether its block ran in this thread or another, and whatever the number of
    threads (five rows over two threads: blocks of two and three)."""
    import numba

    from pneumatic_servo.model.simulate import simulate_batch
    model = Model(ModelConfig.paper())
    t = np.arange(0.0, 0.1, 1e-3)
    params = np.array([model.params] * 5)
    params[:, model.param_index('core.gear_inertia_kg_m2')] *= np.linspace(0.5, 1.5, 5)
    x0s = np.array([initial_state(model)] * 5)
    runs = []
    for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
        numba.set_num_threads(threads)
        try:
            runs.append(simulate_batch(model, t, 5.2, 7e5, x0s, params, lengths=[100, 60, 100,
                                                                                  80, 100]))
        finally:
            numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    (one, _, status_one), (several, _, status_several) = runs
    np.testing.assert_array_equal(status_one, [0] * 5)
    np.testing.assert_array_equal(status_several, status_one)
    np.testing.assert_array_equal(several, one)
    assert len({float(np.nanmax(np.abs(row[:, 1]))) for row in one}) == 5  # rows differ
