"""The four test circuits: steady states solved by hand from the paper's equations, time
simulations that settle on them, and the paper's charge/discharge and sine experiments."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq
from test_physics import (
    B_CRIT,
    C0,
    D_H,
    D_S,
    KAPPA,
    L0,
    P_E,
    R_GAS,
    T_E,
    c1_settled,
    eq8,
    eq17,
    psi,
    s_e,
    s_v,
)

from pneumatic_servo.analysis.paper_figures import check_charge_discharge, sine_summary
from pneumatic_servo.errors import SimulationError
from pneumatic_servo.experiment import Experiment
from pneumatic_servo.model import Model, ModelConfig, circuits
from pneumatic_servo.synth import runs

GAUGES = (0.5e6, 0.7e6, 0.83e6)


@pytest.fixture(scope='module')
def model():
    return Model(ModelConfig.paper())


def hand_closed_port(u, ps):
    """Closed-port p_a [Pa] from Eq. 8 = Eq. 17 (x_v >= 0) or Eq. 24 = Eq. 22 (x_v < 0).

    At zero net flow the gas in the valve chamber is at T_s = T_e (inflow at
    T_s replaces outflow), so both laws are evaluated at 293.15 K.
    """
    xv = 2e-4 * (min(max(u, 0.0), 10.0) - 5.0)
    area, length = s_e(xv), L0 + abs(xv)
    if xv >= 0.0:
        def net(p):
            return eq8(area, ps, T_E, p) - eq17(length, p, T_E, P_E)
    else:
        def net(p):
            return eq17(length, ps, T_E, p) - eq8(area, p, T_E, P_E)
    return brentq(net, P_E, ps, xtol=1e-9, rtol=1e-15)


@pytest.mark.parametrize('gauge', GAUGES)
def test_closed_port_steady_state_by_hand(model, gauge):
    ps = gauge + P_E
    for u in circuits.PAPER_TABLE5_VOLTAGES_V + (4.0, 4.6, 4.97):
        got = circuits.steady_closed_port(model, u, ps)
        assert got == pytest.approx(hand_closed_port(u, ps), abs=1e-3), u
        assert P_E < got < ps


def test_closed_port_pressure_rises_with_voltage(model):
    ps = 0.7e6 + P_E
    p = [circuits.steady_closed_port(model, u, ps) for u in circuits.PAPER_TABLE5_VOLTAGES_V]
    assert np.all(np.diff(p) > 0.0)


def test_flow_test_conserves_mass_and_recovers_c1_by_eq38(model):
    """M4 + M5 is the supply inflow; where it is choked, Eq. 38 returns C1 = P(|x_v|)."""
    ps = 0.6e6 + P_E
    outlet = model.config.core['flow_outlet_area_m2']
    choked = math.sqrt(2 * KAPPA / (R_GAS * T_E * (KAPPA + 1))
                       * (2 / (KAPPA + 1)) ** (2 / (KAPPA - 1)))
    crit_ideal = (2 / (KAPPA + 1)) ** (KAPPA / (KAPPA - 1))
    s_h = math.pi * (D_H ** 2 - D_S ** 2) / 4
    n_choked = 0
    for u in np.arange(5.0, 10.01, 0.5):
        p_a, m4, m5 = circuits.steady_flow(model, u, ps)
        xv = 2e-4 * (u - 5.0)
        inflow = eq8(s_e(xv), ps, T_E, p_a)
        assert m4 + m5 == pytest.approx(inflow, rel=1e-9)
        assert m5 == pytest.approx(eq17(L0 + xv, p_a, T_E, P_E), rel=1e-9)
        assert m4 == pytest.approx(outlet * p_a / math.sqrt(R_GAS * T_E)
                                   * psi(P_E / p_a, crit_ideal), rel=1e-9)
        if p_a / ps < B_CRIT:
            n_choked += 1
            c1 = (m4 + m5) / (ps * (2 * s_v(xv) + C0 * s_h) * choked)
            assert c1 == pytest.approx(c1_settled(xv), rel=1e-9)
            assert c1 > 0.0
    assert n_choked >= 5


@pytest.mark.parametrize('circuit, u', [('closed_port', 5.5), ('closed_port', 4.7),
                                        ('flow', 6.0), ('flow', 9.0)])
def test_time_simulation_settles_on_the_steady_state(model, circuit, u):
    ps = 0.6e6 + P_E
    res = runs.static_response(model, circuit, u, ps, duration_s=3.0)
    steady = circuits.steady_outputs(model, circuit, u, ps)
    assert res.p_a_pa[-1] == pytest.approx(steady['p_a_pa'], abs=1.0)
    assert res.t_a_k[-1] == pytest.approx(steady['t_a_k'], abs=1e-3)
    assert res['m4_kg_s'][-1] == pytest.approx(steady['m4_kg_s'], rel=1e-5, abs=1e-12)
    assert res['m5_kg_s'][-1] == pytest.approx(steady['m5_kg_s'], rel=1e-5, abs=1e-12)


def test_steady_temperature_between_supply_and_room_when_they_differ(model):
    cfg = model.config.copy()
    cfg.core['supply_temperature_k'] = 303.15
    x = circuits.steady_state(model, 'closed_port', 6.0, 0.6e6 + P_E, cfg)
    assert 293.15 < x[4] < 303.15
    res = runs.static_response(model, 'closed_port', 6.0, 0.6e6 + P_E, duration_s=4.0,
                                   config=cfg)
    assert res.p_a_pa[-1] == pytest.approx(x[2], abs=1.0)
    assert res.t_a_k[-1] == pytest.approx(x[4], abs=1e-3)


def test_predict_static_on_a_table(model):
    volts = np.array([5.0, 6.0, 8.0])
    supplies = np.full(3, 0.7e6 + P_E)
    exp = Experiment(np.arange(3.0), {'command_v': volts, 'supply_pa': supplies},
                     circuit='closed_port', name='table5', static=True)
    pred = circuits.predict_static(model, exp)
    for i, u in enumerate(volts):
        assert pred['p_a_pa'][i] == pytest.approx(hand_closed_port(u, supplies[i]), abs=1e-3)
    with pytest.raises(SimulationError):
        circuits.steady_state(model, 'servo', 5.0)


# --- the paper's experiments -----------------------------------------------------------------
def test_charge_discharge_reproduces_the_papers_claims(model):
    cfg = model.config
    res = runs.charge_discharge(model, duration_s=6.0)
    ps = circuits.gauge_supply_pa(0.6e6, cfg)
    assert res.circuit == 'blocked'
    assert res.p_a_pa[0] == P_E and res.p_b_pa[0] == ps  # the documented start
    checks = check_charge_discharge(res, cfg, step_time_s=0.1)
    claims = ('p_a_rises', 'p_a_stays_below_supply', 'p_b_falls', 'p_b_stays_above_atmosphere',
              't_a_jumps', 't_a_recovers', 't_b_dips', 't_b_recovers')
    assert {c: checks[c] for c in claims} == {c: True for c in claims}
    # where a settles: Eq. 8 inflow = Eq. 17 outflow, the same balance as the closed port
    assert res.p_a_pa[-1] == pytest.approx(hand_closed_port(5.5, ps), rel=1e-6)


def test_charge_discharge_claims_fail_without_clearance_by_parameters(model):
    """The claims rest on the clearance: a (near) zero gap lets p_a reach supply."""
    cfg = model.config.copy()
    cfg.set('core.sleeve_bore_diameter_m', D_S + 2e-9)
    res = runs.charge_discharge(model, duration_s=6.0, config=cfg)
    checks = check_charge_discharge(res, cfg, step_time_s=0.1)
    assert not checks['p_a_stays_below_supply']
    assert not checks['p_b_stays_above_atmosphere']


@pytest.mark.parametrize('method', ['adaptive', 'fixed'])
def test_sine_response_is_periodic_after_settling(model, method):
    res = runs.sine_response(model, duration_s=6.0, method=method)
    period = 500  # samples: 0.5 s at 1 kHz for 2 Hz
    last, previous = res.angle_rad[-period:], res.angle_rad[-2 * period:-period]
    assert np.abs(last - previous).max() < math.radians(0.05)
    assert np.ptp(last) > math.radians(5.0)  # the shaft really oscillates
    summary = sine_summary(res)
    assert summary['finite'] and P_E < summary['p_b_pa_min'] < summary['p_a_pa_max'] < 0.7e6 + P_E
