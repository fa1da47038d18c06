"""Every catalogue effect changes the behaviour in the direction its physics says.

One model holds all twelve catalogue effects (one compilation). Each effect
starts from a neutral value (no leak, no torque, no delay, ...) and is then
switched to an active value, all others staying neutral, so each difference
is that effect's alone. A user-defined effect registers and runs without
editing the package.
"""
import math

import numpy as np
import pytest

from pneumatic_servo import effects
from pneumatic_servo._jit import njit
from pneumatic_servo.effects import CATALOGUE_NAMES, Component, Param
from pneumatic_servo.effects.layout import C_TORQUE, N_CORE_STATES, THETA
from pneumatic_servo.errors import ConfigError
from pneumatic_servo.model import Model, ModelConfig, circuits, initial_state, simulate
from pneumatic_servo.synth import runs

P_E = 101325.0
SUPPLY = 0.6e6 + P_E

#: each effect's 'off' value: the declared one; the spool lag and the supply line have none,
#: so they sit at a near-ideal value (0.1 ms lag, the widest supply line allowed, ~7x the
#: default)
NEUTRAL = {name: effects.get(name).neutral for name in CATALOGUE_NAMES
           if effects.get(name).neutral is not None}
NEUTRAL.update({'valve_spool_dynamics': {'spool_time_constant_s': 1e-4},
                'supply_pressure_drop': {'supply_line_area_m2': 2e-5}})


def _neutral_config():
    cfg = ModelConfig.paper()
    for name in CATALOGUE_NAMES:
        cfg = cfg.with_effect(name, NEUTRAL[name])
    return cfg


@pytest.fixture(scope='module')
def all_effects():
    """(model with every catalogue effect, its neutral config)."""
    cfg = _neutral_config()
    return Model(cfg), cfg


def active(cfg, name, values=None):
    """``cfg`` with effect ``name`` at ``values`` (default: the catalogue defaults)."""
    cls = effects.get(name)
    return cfg.with_effect(name, values if values is not None else cls.defaults())


# --- scenarios: each returns one number; the physics says which way it must move -------------
def _charge(model, cfg, step_at=0.01, u1=6.0, duration=0.06):
    """Pistons held, a from atmosphere, b from supply; valve 5 V then ``u1`` at ``step_at``."""
    t = np.arange(0.0, duration, 1e-4)
    u = np.where(t < step_at, 5.0, u1)
    x0 = initial_state(model, angle_rad=0.0, p_a_pa=P_E, p_b_pa=SUPPLY, command_v=5.0,
                       supply_pa=SUPPLY, config=cfg)
    return simulate(model, t, u, SUPPLY, x0=x0, circuit='blocked', config=cfg)


def _at(res, t):
    return float(np.interp(t, res.t, res.p_a_pa))


def _servo(model, cfg, u, duration, x0=None):
    t = np.arange(0.0, duration, 1e-3)
    x0 = initial_state(model, angle_rad=1.6, p_a_pa=4e5, p_b_pa=4e5, command_v=float(
        np.atleast_1d(u)[0]), supply_pa=SUPPLY, config=cfg) if x0 is None else x0
    return simulate(model, t, u, SUPPLY, x0=x0, config=cfg)


def p_a_shortly_after_step(model, cfg):
    """p_a [Pa] 4 ms after the valve opens: lags and delays make it lower."""
    return _at(_charge(model, cfg), 0.014)


def p_a_while_charging(model, cfg):
    """p_a [Pa] 8 ms into charging: a larger volume or a sagging supply make it lower."""
    return _at(_charge(model, cfg), 0.018)


def closed_port_pressure(model, cfg):
    """Steady valve-chamber p_a [Pa] at 5.2 V (closed ports)."""
    return circuits.steady_closed_port(model, 5.2, SUPPLY, cfg)


def supply_flow_at_centre(model, cfg):
    """Supply mass flow [kg/s] with the valve at its centre and both chambers settled."""
    res = _charge(model, cfg, step_at=10.0, duration=3.0)
    return float(res['supply_mass_flow_kg_s'][-1])


def chamber_pressure_difference(model, cfg):
    """p_a - p_b [Pa] of the blocked chambers settled at 5.5 V."""
    res = _charge(model, cfg, step_at=0.0, u1=5.5, duration=4.0)
    return float(res.p_a_pa[-1] - res.p_b_pa[-1])


def lowest_valve_supply(model, cfg):
    """Lowest supply pressure at the valve [Pa] while charging."""
    return float(_charge(model, cfg)['valve_supply_pressure_pa'].min())


def mean_angle_under_sine(model, cfg):
    """Mean angle [rad] over the last second of the 2 Hz sine response."""
    res = runs.sine_response(model, duration_s=3.0, config=cfg)
    return float(res.angle_rad[res.t >= 2.0].mean())


def angle_after_opening(model, cfg):
    """Angle travelled [rad] 40 ms after the valve opens to 6 V from rest."""
    res = _servo(model, cfg, 6.0, 0.041)
    return float(res.angle_rad[-1] - res.angle_rad[0])


def travel_towards_zero(model, cfg):
    """Angle travelled towards 0 [rad] in 80 ms at 4 V from rest."""
    res = _servo(model, cfg, 4.0, 0.081)
    return float(res.angle_rad[0] - res.angle_rad[-1])


#: effect -> (scenario, direction of the change (+1 up, -1 down), smallest change that counts,
#: active values or None for the catalogue defaults, what the physics says)
DIRECTIONS = {
    'valve_spool_dynamics': (p_a_shortly_after_step, -1, 1e3, {'spool_time_constant_s': 0.01},
                             'the spool lags the step, so a charges later'),
    'transport_delay': (p_a_shortly_after_step, -1, 1e3, {'command_delay_s': 0.01},
                        'the valve sees the step later'),
    'valve_null_offset': (closed_port_pressure, -1, 1e3, {'null_offset_v': 0.1},
                          'a centre above 5 V opens supply -> a less at the same command'),
    'valve_null_leakage': (supply_flow_at_centre, +1, 1e-6, None,
                           'extra leak paths at the centre draw more supply air'),
    'supply_pressure_drop': (lowest_valve_supply, -1, 1e3, None,
                             'a narrower supply line sags more under flow'),
    'piston_seal_leakage': (chamber_pressure_difference, -1, 1e3, None,
                            'a -> b leakage evens the chamber pressures'),
    'external_leakage': (closed_port_pressure, -1, 1e3, {'leak_area_a_m2': 2e-8,
                                                         'leak_area_b_m2': 2e-8},
                         'a leak to atmosphere lowers a charged chamber'),
    'external_load_torque': (mean_angle_under_sine, +1, 1e-3, {'load_torque_n_m': 0.2},
                             'a positive torque turns the shaft towards larger angles'),
    'payload_inertia': (angle_after_opening, -1, 1e-3, {'payload_inertia_kg_m2': 2e-3},
                        'more inertia accelerates more slowly'),
    'asymmetric_friction': (travel_towards_zero, -1, 1e-3, {'extra_negative_friction_n': 10.0},
                            'extra friction when turning towards 0 slows that motion'),
    'dead_volume': (p_a_while_charging, -1, 1e3, {'extra_dead_volume_a_m3': 5e-6,
                                                  'extra_dead_volume_b_m3': 5e-6},
                    'more volume fills more slowly'),
    'sensor_delay': (p_a_shortly_after_step, -1, 1e3, {'measurement_delay_s': 0.005},
                     'the measured pressure shows the rise later'),
}


def test_every_catalogue_effect_has_a_direction_test():
    assert set(DIRECTIONS) == set(CATALOGUE_NAMES) == set(NEUTRAL)
    assert len(CATALOGUE_NAMES) == 12


@pytest.mark.parametrize('name', CATALOGUE_NAMES)
def test_effect_changes_behaviour_in_its_physical_direction(all_effects, name):
    model, neutral = all_effects
    scenario, sign, least, values, why = DIRECTIONS[name]
    base = scenario(model, neutral)
    changed = scenario(model, active(neutral, name, values))
    assert math.isfinite(base) and math.isfinite(changed)
    assert sign * (changed - base) > least, f'{name}: expected {why} ({base:g} -> {changed:g})'


def test_neutral_effects_reproduce_the_paper_model(all_effects):
    model, neutral = all_effects
    res = runs.sine_response(model, duration_s=2.0, config=neutral)
    ref = runs.sine_response(Model(ModelConfig.paper()), duration_s=2.0)
    assert np.abs(res.angle_rad - ref.angle_rad).max() < math.radians(0.5)
    assert np.abs(res.p_a_pa - ref.p_a_pa).max() < 1e3


# --- specific physics of single effects ------------------------------------------------------
def test_transport_delay_shifts_the_response_by_the_delay(all_effects):
    """From a steady state, a delayed step gives the same response, later by the delay."""
    model, neutral = all_effects
    t = np.arange(0.0, 0.06, 1e-4)
    u = np.where(t < 0.01, 5.0, 6.0)

    def run(cfg):
        x0 = circuits.steady_state(model, 'closed_port', 5.0, SUPPLY, cfg)
        return simulate(model, t, u, SUPPLY, x0=x0, circuit='closed_port', config=cfg)
    base = run(neutral)
    late = run(active(neutral, 'transport_delay', {'command_delay_s': 0.005}))
    assert np.ptp(base.p_a_pa) > 1e4
    keep = (t > 0.005) & (t < 0.05)
    np.testing.assert_allclose(np.interp(t[keep] + 0.005, late.t, late.p_a_pa),
                               base.p_a_pa[keep], rtol=1e-6)


def test_sensor_delay_lags_measurements_by_the_delay(all_effects):
    model, neutral = all_effects
    base = _charge(model, neutral)
    lag = _charge(model, active(neutral, 'sensor_delay', {'measurement_delay_s': 0.004}))
    t = base.t[(base.t > 0.01) & (base.t < 0.05)]
    for name in ('p_a_pa', 'p_b_pa', 't_a_k'):
        np.testing.assert_allclose(np.interp(t + 0.004, lag.t, lag[name]),
                                   np.interp(t, base.t, base[name]), rtol=1e-6)


def test_null_offset_is_a_shifted_command(all_effects):
    """A valve whose centre is at 5 + d V behaves at U as a centred valve at U - d."""
    model, neutral = all_effects
    shifted = active(neutral, 'valve_null_offset', {'null_offset_v': 0.3})
    for u in (5.5, 6.0, 7.5):
        assert circuits.steady_closed_port(model, u, SUPPLY, shifted) == pytest.approx(
            circuits.steady_closed_port(model, u - 0.3, SUPPLY, neutral), rel=1e-6)


def test_load_torque_shifts_the_angle_towards_its_direction(all_effects):
    model, neutral = all_effects
    base = mean_angle_under_sine(model, neutral)
    for torque in (0.2, -0.2):
        moved = mean_angle_under_sine(model, active(neutral, 'external_load_torque',
                                                    {'load_torque_n_m': torque}))
        assert np.sign(moved - base) == np.sign(torque)


def test_asymmetric_friction_leaves_motion_away_from_zero_alone(all_effects):
    model, neutral = all_effects
    base = angle_after_opening(model, neutral)
    asym = angle_after_opening(model, active(neutral, 'asymmetric_friction',
                                             {'extra_negative_friction_n': 10.0}))
    assert base > 0.01 and asym == pytest.approx(base, rel=1e-6)


def test_external_leakage_lowers_a_charged_blocked_chamber(all_effects):
    model, neutral = all_effects
    leaky = active(neutral, 'external_leakage', {'leak_area_a_m2': 2e-8, 'leak_area_b_m2': 0.0})
    base = _charge(model, neutral, step_at=0.0, u1=5.5, duration=3.0)
    leak = _charge(model, leaky, step_at=0.0, u1=5.5, duration=3.0)
    assert leak.p_a_pa[-1] < base.p_a_pa[-1] - 1e3
    assert P_E < leak.p_a_pa[-1]


def test_steady_state_settles_effect_states(all_effects):
    """Spool position and valve supply pressure are states: the static solver settles them."""
    model, neutral = all_effects
    cfg = active(active(neutral, 'supply_pressure_drop'), 'valve_null_offset')
    for circuit in circuits.STATIC_CIRCUITS:
        x = circuits.steady_state(model, circuit, 7.0, SUPPLY, cfg)
        _, dx = model.evaluate(x, 7.0, SUPPLY, circuit, params=model.param_vector(cfg))
        assert np.all(np.abs(dx[2]) < 1e-3) and np.all(np.abs(dx[N_CORE_STATES:]) <
                                                       1e-6 * np.abs(x[N_CORE_STATES:]) + 1e-9)
        res = runs.static_response(model, circuit, 7.0, SUPPLY, duration_s=2.0, config=cfg)
        assert res.p_a_pa[-1] == pytest.approx(x[2], abs=5.0)


# The supply-line bounds are chosen so that the line's own eigenvalue (R T_s / V_line * dm/dp)
# stays within what fixed RK4 at 0.1 ms follows; this checks the stepper at those bounds.
@pytest.mark.parametrize('values', [{'supply_line_area_m2': 2e-5},
                                    {'supply_line_volume_m3': 1e-5}])
def test_fixed_step_integrator_stays_physical_at_supply_line_bounds(all_effects, values):
    model, neutral = all_effects
    cfg = active(neutral, 'supply_pressure_drop', values)
    fixed = runs.sine_response(model, duration_s=0.3, method='fixed', config=cfg)
    exact = runs.sine_response(model, duration_s=0.3, config=cfg)
    assert fixed.p_a_pa.max() <= SUPPLY + 1.0 and fixed['valve_supply_pressure_pa'].max() \
        <= SUPPLY + 1.0
    assert np.abs(fixed.angle_rad - exact.angle_rad).max() < math.radians(0.1)


# --- catalogue metadata ----------------------------------------------------------------------
@pytest.mark.parametrize('name', CATALOGUE_NAMES)
def test_effect_declares_bounded_si_parameters_and_its_physics(name):
    cls = effects.get(name)
    assert cls.slot is None and cls.summary and cls.reference and cls.__doc__
    assert cls.acts_on in ('angle', 'pressure', 'both')
    for p in cls.params:
        assert p.unit and p.description
        assert p.lower <= p.default <= p.upper
        lo, hi = p.plausible_range()
        assert p.lower <= lo <= hi <= p.upper


# --- a user's own effect ---------------------------------------------------------------------
@njit(cache=False)
def _spring_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] -= p[0] * (x[THETA] - p[1])


class TorsionSpring(Component):
    """A return spring on the shaft: torque -k (theta - theta_0)."""

    name = 'test_torsion_spring'
    summary = 'return spring on the shaft'
    reference = 'Hooke'
    acts_on = 'angle'
    params = (Param('stiffness_n_m_per_rad', 'N.m/rad', 0.5, 0.0, 10.0, 'spring rate k'),
              Param('rest_angle_rad', 'rad', 0.5, 0.0, 3.3, 'angle where the spring is slack'))
    mechanics = _spring_hook


def test_user_defined_effect_registers_and_acts_without_editing_the_package():
    """Registered for this test only: a later diagnosis (test_open_world) must not meet it
    as a named candidate."""
    with effects.registered(TorsionSpring):
        assert 'test_torsion_spring' in effects.names()
        cfg = ModelConfig.from_dict({'effects': {'test_torsion_spring': {
            'stiffness_n_m_per_rad': 0.5, 'rest_angle_rad': '30 deg'}}})
        assert cfg.get('test_torsion_spring.rest_angle_rad') == pytest.approx(math.radians(30))
        model = Model(cfg)
        t = np.arange(0.0, 2.0, 1e-3)
        # equal pressures, valve at centre: only the spring (and the valve's own bias) acts
        free = simulate(Model(ModelConfig.paper()), t, 5.0, SUPPLY,
                        x0=initial_state(Model(ModelConfig.paper()), angle_rad=2.5))
        sprung = simulate(model, t, 5.0, SUPPLY, x0=initial_state(model, angle_rad=2.5))
        assert sprung.angle_rad[-1] < free.angle_rad[-1] - 0.1  # pulled back towards 30 deg
        with pytest.raises(ConfigError, match='outside'):
            ModelConfig.from_dict({'effects': {'test_torsion_spring': {
                'stiffness_n_m_per_rad': -1}}})


@pytest.mark.study
@pytest.mark.parametrize('name', [n for n in CATALOGUE_NAMES if effects.get(n).neutral])
def test_declared_neutral_values_add_exactly_nothing(name):
    """An effect at its declared ``neutral`` values reproduces the model without it."""
    t = np.arange(0.0, 0.3, 1e-3)
    u = 5.0 + 0.8 * np.sin(2 * np.pi * 3 * t)
    base = simulate(Model(ModelConfig.paper()), t, u)
    with_it = simulate(Model(ModelConfig.paper().with_effect(name, effects.get(name).neutral)),
                       t, u)
    np.testing.assert_array_equal(with_it.states[:, :N_CORE_STATES], base.states)


def _failing_hook(t, x, s, p, P, c, dx):
    if t > p[0]:
        if p[1] > 0.5:
            raise ValueError('the user table ends here')
        c[C_TORQUE] += np.nan


class FailingTable(Component):
    """A user's torque table that ends: its hook raises, or gives NaN, after a time."""

    name = 'test_failing_table'
    summary = 'a torque table that ends'
    acts_on = 'angle'
    params = (Param('fail_after_s', 's', 0.15, 0.0, 10.0, 'when it fails'),
              Param('raises', '1', 1.0, 0.0, 1.0, '1: raises, 0: gives NaN'))
    mechanics = _failing_hook


def test_a_failing_user_hook_is_named_with_its_own_error():
    """Compiled, a hook that raises shows as the kernel's error (from the batch, run in
    threads, as 'SystemError: CPUDispatcher(...) returned a result with an exception set') and one that
    gives NaN as a non-finite state: both are named, with the hook's own error, wherever the
    model runs."""
    from pneumatic_servo.errors import EffectError, SimulationError
    from pneumatic_servo.model import Stepper, simulate_batch
    with effects.registered(FailingTable):
        raises = ModelConfig.paper().with_effect('test_failing_table')
        nans = raises.with_effect('test_failing_table', {'raises': 0.0})
        model = Model(raises)
        t = np.arange(0.0, 0.3, 1e-3)
        named = r"effect 'test_failing_table' \(.*FailingTable\) "
        said = named + r'raised ValueError in its mechanics hook at t = 0\.15.*: the user table'
        with pytest.raises(EffectError, match=said):
            simulate(model, t, 5.3)
        x0 = initial_state(model)
        with pytest.raises(EffectError, match=said):  # the batch, in two threads
            simulate_batch(model, t, 5.3, SUPPLY, np.array([x0, x0]),
                           np.array([model.params, model.params]))
        stepper = Stepper(model)
        with pytest.raises(EffectError, match=said):  # the real-time plant
            for _ in range(300):
                stepper.step(5.3)
        nan = named + r'gave NaN or inf in its mechanics hook at t = 0\.15'
        with pytest.raises(SimulationError, match='simulation failed at t = 0.15 s: .*: ' + nan):
            simulate(model, t, 5.3, config=nans)
        stepper = Stepper(Model(nans))
        with pytest.raises(SimulationError, match=nan):
            for _ in range(300):
                stepper.step(5.3)
