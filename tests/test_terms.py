"""The discovery's vocabulary is declared once (pneumatic_servo.effects.terms): the compiled
hooks, the arrays of the sensor errors and the report, and the emitted effect files all
evaluate the same expression, including the command's memory."""
import importlib.util
import math

import numpy as np
import pytest

from pneumatic_servo import effects as registry
from pneumatic_servo.analysis.diagnosis.discovery import Discovered
from pneumatic_servo.analysis.diagnosis.emit import effect_source
from pneumatic_servo.effects.corrections import BY_EQUATION, EQUATIONS, coefficient_name
from pneumatic_servo.effects.layout import C_MA, C_PS, C_TORQUE, C_U, C_XV, K_GAIN
from pneumatic_servo.effects.terms import TERMS, direction, lag, term_values
from pneumatic_servo.fitting.problem import with_values
from pneumatic_servo.model import Model, ModelConfig, simulate
from pneumatic_servo.model.simulate import initial_state

#: equation -> the context slot its correction changes, and the factor from term to change
SLOTS = {'moment_balance': (C_TORQUE, 1.0), 'mass_balance_a': (C_MA, 1.0),
         'valve_input': (C_XV, 'gain'), 'measurement_supply': (C_PS, -1.0)}
STATE = {'angle_rad': 1.3, 'velocity_rad_s': 0.4, 'p_a_pa': 4.2e5, 'p_b_pa': 2.9e5}
COMMAND_V, SUPPLY_PA = 5.21, 7.0e5


@pytest.fixture(scope='module')
def hosts():
    cfg = ModelConfig.paper()
    for eq in SLOTS:
        cfg = cfg.with_effect(BY_EQUATION[eq].name, BY_EQUATION[eq].neutral)
    return cfg, Model(cfg)


@pytest.mark.parametrize('equation', list(SLOTS))
def test_compiled_hooks_evaluate_the_terms_expressions(hosts, equation):
    """Each term's compiled form, with its coefficient at 1, adds what its expression gives
    over arrays at the same state (the memory's state at the command: direction 0)."""
    cfg, model = hosts
    eq = BY_EQUATION[equation].equation
    x = initial_state(model, command_v=COMMAND_V, supply_pa=SUPPLY_PA, config=cfg, **STATE)
    signals = {k: np.array([v]) for k, v in STATE.items()}
    signals.update(command_v=np.array([COMMAND_V]), supply_pa=np.array([SUPPLY_PA]))
    expected = term_values(eq.terms, signals, cfg.core)[0]
    slot, factor = SLOTS[equation]
    zero = model.evaluate(x, COMMAND_V, SUPPLY_PA, params=model.param_vector(cfg))[0][slot]
    for term, want in zip(eq.terms, expected):
        key = f'{BY_EQUATION[equation].name}.{coefficient_name(term.name)}'
        c = 0.5 * eq.size / term.typical  # half a plausible size: inside every clamp
        one = with_values(cfg, [key], [c])
        got = model.evaluate(x, COMMAND_V, SUPPLY_PA, params=model.param_vector(one))[0][slot]
        scale = cfg.core['spool_gain_m_per_v'] if factor == 'gain' else factor
        assert (got - zero) == pytest.approx(scale * c * want, rel=1e-9, abs=1e-15), term.name


@pytest.mark.parametrize('equation', ['moment_balance', 'mass_balance_a'])
def test_a_corrections_switch_is_on_while_a_coefficient_is_set_and_off_it_adds_nothing(
        hosts, equation):
    """The parameter vector ends each correction's slice with its switch (1 while a
    coefficient is not zero), and the compiled model reads the switch: with it forced off,
    a set coefficient adds nothing, in a stateless correction (not called) and in one with
    a memory (called, its terms skipped)."""
    cfg, model = hosts
    cls = BY_EQUATION[equation]
    _, end = model.layout.param_slices[model.layout.classes.index(cls)]
    one = with_values(cfg, [f'{cls.name}.{coefficient_name("constant")}'],
                      [0.5 * cls.equation.size])
    assert model.param_vector(cfg)[end - 1] == 0.0 and model.param_vector(one)[end - 1] == 1.0
    x = initial_state(model, command_v=COMMAND_V, supply_pa=SUPPLY_PA, config=cfg, **STATE)
    slot = SLOTS[equation][0]

    def context(params):
        return model.evaluate(x, COMMAND_V, SUPPLY_PA, params=params)[0][slot]
    forced_off = model.param_vector(one)
    forced_off[end - 1] = 0.0
    assert context(model.param_vector(one)) != context(model.param_vector(cfg))
    assert context(forced_off) == context(model.param_vector(cfg))


def test_a_free_function_of_each_variable_is_offered_to_probe_a_dependence_never_screened():
    """The knots of a free function of each probed variable are offered in every equation
    the modulations are, never screened and never part of the shape over the stroke; they
    sum to one within their span and the end knots hold beyond it."""
    from pneumatic_servo.analysis.diagnosis.dependence import probe_keys
    from pneumatic_servo.analysis.diagnosis.shape import shape_terms
    from pneumatic_servo.effects.terms import N_PROBE_KNOTS, PROBED, knot
    for equation in ('moment_balance', 'mass_balance_b', 'valve_input', 'measurement_p_a'):
        blind = BY_EQUATION[equation].equation.blind_to
        for variable, *_ in PROBED:
            # none of a variable the equation is blind to (the command in a torque)
            knots = 0 if variable in blind else N_PROBE_KNOTS
            assert len(probe_keys(equation, variable)) == knots, (equation, variable)
        assert not any(t.probes and t.screened for t in BY_EQUATION[equation].equation.terms)
        assert not any('probe' in k for k in shape_terms(equation))
    assert not probe_keys('energy_balance_a', 'p_a')
    x = np.linspace(-1.0, 3.0, 41)
    basis = np.array([knot(x, 0.0, 2.0, k) for k in range(N_PROBE_KNOTS)])
    inside = (x >= 0.0) & (x <= 2.0)
    assert np.allclose(basis[:, inside].sum(axis=0), 1.0)
    assert np.all(basis[0, x < 0.0] == 1.0) and np.all(basis[-1, x > 2.0] == 1.0)
    assert knot(1.0, 0.0, 2.0, N_PROBE_KNOTS // 2) == 1.0  # the middle knot at mid-span


def test_a_free_functions_span_is_a_fixed_parameter_of_its_correction(hosts):
    """The knots of a free function span what the correction's span parameters say (the
    dependence test sets them to what the record holds), in the compiled hook and over a
    sensor's arrays alike; a span alone switches nothing on."""
    from pneumatic_servo.effects.terms import PROBE_SPANS, probe_spans
    cfg, model = hosts
    cls = BY_EQUATION['mass_balance_a']
    low, high = (f'{cls.name}.{p.name}' for p in PROBE_SPANS['p_a'])
    spanned = with_values(cfg, [low, high], [4.0e5, 4.4e5])  # p_a = 4.2e5 at its middle
    _, end = model.layout.param_slices[model.layout.classes.index(cls)]
    assert model.param_vector(spanned)[end - 1] == 0.0  # the switch
    x = initial_state(model, command_v=COMMAND_V, supply_pa=SUPPLY_PA, config=cfg, **STATE)
    key = f'{cls.name}.{coefficient_name("p_a_probe_2")}'
    added = []
    for config in (cfg, spanned):
        zero, one = (model.evaluate(x, COMMAND_V, SUPPLY_PA, params=model.param_vector(
            with_values(config, [key], [c])))[0][C_MA] for c in (0.0, 1e-5))
        added.append((one - zero) / 1e-5)
    # over atmosphere to the supply the middle knot is 0.88 at 4.2e5 Pa; over the span, 1
    assert added[0] == pytest.approx(1.0 - abs(4 * (4.2e5 - 101325.0) / 6e5 - 2))
    assert added[1] == pytest.approx(1.0)
    sensor = BY_EQUATION['measurement_p_a']
    values = {**sensor.defaults(), 'p_a_probe_low_pa': 4.0e5, 'p_a_probe_high_pa': 4.4e5,
              coefficient_name('p_a_probe_2'): 1.0}
    p_a = np.array([4.0e5, 4.1e5, 4.2e5, 4.4e5, 5.0e5])
    got = sensor.sensor_error(values, {'p_a_pa': p_a}, cfg.core)['p_a_pa']
    assert np.allclose(got, [0.0, 0.0, 1.0, 0.0, 0.0])
    # the spans of a record: from its least to its largest value of each variable
    spans = probe_spans([{'p_a_pa': p_a, 'command_v': np.array([4.5, 5.5, 6.0])}], cfg.core)
    null = cfg.core['valve_null_voltage_v']
    assert (spans['p_a_probe_low_pa'], spans['p_a_probe_high_pa']) == (4.0e5, 5.0e5)
    assert spans['command_probe_low_v'] == pytest.approx(4.5 - null)
    assert spans['command_probe_high_v'] == pytest.approx(6.0 - null)
    assert 'angle_probe_low_rad' not in spans  # the record holds no angle


def test_every_equation_offers_the_plain_terms_and_sensors_the_shafts_memory():
    plain = [t.name for t in TERMS if t.equations is None]
    for eq in EQUATIONS:
        names = [t.name for t in eq.terms]
        if eq.generic:  # every plain term it is not blind to, in the vocabulary's order
            seen = [t.name for t in TERMS if t.equations is None
                    and not set(t.depends_on) & set(eq.blind_to)]
            assert [n for n in names if n in plain] == seen, eq.name
            assert not any(set(t.depends_on) & set(eq.blind_to) for t in eq.terms), eq.name
        else:  # a temperature reading: the constant and its own terms only
            assert names[0] == 'constant' and not set(plain[1:]) & set(names), eq.name
            assert names[1:] == [t.name for t in TERMS if eq.name in (t.equations or ())]
    assert [eq.name for eq in EQUATIONS if not eq.generic] == ['measurement_t_a',
                                                               'measurement_t_b']
    # a reading's gain over a gauge span comes before one of the absolute pressure: where
    # both fit alike, the first leads
    for v in ('p_a', 'p_b', 'supply'):
        names = [t.name for t in BY_EQUATION[f'measurement_{v}'].equation.terms]
        assert names.index(f'gauge_{v}') < names.index(v)
        assert f'gauge_{v}' not in [t.name for t in BY_EQUATION['moment_balance'].equation.terms]
    assert 'motion_direction' in [t.name for t in BY_EQUATION['measurement_angle'].equation.terms]
    assert 'motion_direction' not in [t.name for t in
                                      BY_EQUATION['moment_balance'].equation.terms]
    assert BY_EQUATION['valve_input'].states and not BY_EQUATION['moment_balance'].states
    # a torque, and the angle and chamber pressure sensors, see no valve command; flows do
    for name in ('moment_balance', 'measurement_angle', 'measurement_p_a', 'measurement_p_b'):
        assert not {'command', 'sign_command', 'command_times_velocity'} & {
            t.name for t in BY_EQUATION[name].equation.terms}, name
    for name in ('mass_balance_a', 'valve_input', 'measurement_supply'):
        assert 'command' in [t.name for t in BY_EQUATION[name].equation.terms], name


def test_a_correction_is_said_in_the_words_its_leading_term_carries():
    """Every term, in every equation it is offered in, is said in its own words (``says``)
    where it has some, else in the equation's general words; the interpretation dispatches
    on no term's name (a term's words live on the term)."""
    import inspect
    import re

    from pneumatic_servo.analysis.diagnosis import interpret as module
    from pneumatic_servo.effects.term_words import KINDS
    assert not re.findall(r"\breg\b\s*(?:==|in\b|\.startswith)", inspect.getsource(module))
    cfg = ModelConfig.paper()
    spoken = 0
    for eq in EQUATIONS:
        for term in eq.terms:
            assert set(term.says) <= set(KINDS), term.name
            text = module.interpret(eq.name, {term.name: -0.3}, cfg)
            signal = eq.name.removeprefix('measurement_') if 'measurement' in eq.name else ''
            own = term.explain(module._kind(eq.name), module.Context(
                -0.3, {term.name: -0.3}, cfg.core, term.words, eq.name[-1], signal))
            if own:
                spoken += 1
                assert own in text, (eq.name, term.name, text)
            else:
                assert term.words in text, (eq.name, term.name, text)
    assert spoken >= 60  # most pairs have words of their own
    friction = module.interpret('moment_balance', {'sign_velocity_times_mean_pressure': -4e-7},
                                cfg)
    assert 'grows with the chambers\' pressure, 0.04 N.m per bar' in friction, friction


def test_a_modulation_says_what_the_leading_terms_size_varies_with():
    """A correction led by a term, with a modulation of it (the command's valve gain growing
    with the pressure drop: a flow force on the spool), depends on the variables of both,
    and its words say the size varies, by how much; a term added beside them (a constant
    level, the angle) adds nothing to what the correction's main part depends on."""
    from pneumatic_servo.analysis.diagnosis.interpret import depends_on, interpret
    from pneumatic_servo.effects.terms import BY_NAME
    product = BY_NAME['command_times_pressure_difference']
    assert (product.modulates, product.modulator, product.cost, product.unit) == (
        'command', 'pressure_difference', 2, 'V*Pa')
    coefficient = next(p for p in BY_EQUATION['valve_input'].params
                       if p.name == 'command_times_pressure_difference_coefficient')
    assert coefficient.unit == 'V/(V*Pa)'  # SI per unit of the product
    terms = {'command': -0.1, 'command_times_pressure_difference': 2e-7, 'angle': 0.01}
    assert depends_on(terms, 'command') == ['p_a', 'p_b', 'command']
    assert depends_on({'command': -0.1, 'angle': 0.01}, 'command') == ['command']
    # a friction over part of the stroke: a product declared with words of its own
    assert depends_on({'sign_velocity': -0.04, 'sign_velocity_in_window_2': -0.01},
                      'sign_velocity') == ['angle', 'velocity']
    # damping over another part of the stroke is beside a window's torque, not its size
    assert depends_on({'window_1': 0.05, 'velocity_in_window_2': 0.01}, 'window_1') == ['angle']
    text = interpret('valve_input', terms, ModelConfig.paper())
    assert 'its size varies with p_a - p_b [Pa] (-2e-06 of it per unit)' in text, text
    # no term modulates itself or its own variable; windows only where none is declared
    assert 'command_times_command' not in BY_NAME and 'angle_in_window_1' not in BY_NAME
    assert BY_NAME['sign_velocity_in_window_1'].modulates == ''


def test_a_window_the_record_never_enters_is_not_said_to_confine_the_correction():
    """Damping over the second quarter of the stroke (48-95 deg) fitted to a record that
    stays within 100-124 deg (an open-loop chirp of held-out set 4) meets only the window's
    tail there: the words say so, and do not say it acts only in that part; a record that
    enters the window keeps the plain words."""
    from pneumatic_servo.analysis.diagnosis.interpret import interpret
    terms = {'velocity_in_window_1': -0.03}
    cfg = ModelConfig.paper()
    outside = interpret('moment_balance', terms, cfg, angles_deg=(100.0, 124.0))
    assert 'the record stays within 100-124 deg and meets only its tail' in outside, outside
    inside = interpret('moment_balance', terms, cfg, angles_deg=(40.0, 124.0))
    assert 'between about 48 and 95 deg: a damper' in inside and 'tail' not in inside, inside


def test_direction_is_a_play_that_remembers_across_missing_samples():
    v = np.array([0.0, 0.3, 0.6, 0.5, np.nan, 0.4, 0.9])
    d = direction(v, 0.2)
    assert d[0] == 0.0 and d[2] == pytest.approx(1.0) and d[3] == pytest.approx(0.0)
    assert math.isnan(d[4]), 'a missing sample says nothing'
    assert d[5] == pytest.approx(-1.0), 'the memory holds across it: still moving down'
    assert d[6] == pytest.approx(1.0)


def test_lag_is_a_first_order_lag_that_holds_across_missing_samples():
    """The transmitter lag's operator: a step read through tau = 20 ms is at 1 - 1/e after
    tau; a missing sample says nothing and the lag holds; without sample times, no lag."""
    t = np.arange(0.0, 0.1, 1e-3)
    v = np.where(t >= 0.01, 1.0, 0.0)
    y = lag(v, t, 0.02)
    assert y[0] == 0.0 and y[30] == pytest.approx(1.0 - math.exp(-1.0), abs=0.03)
    gap = v.copy()
    gap[20] = np.nan
    z = lag(gap, t, 0.02)
    assert math.isnan(z[20]) and z[21] == pytest.approx(y[21], abs=0.05)
    assert np.array_equal(lag(v, None, 0.02), v)


def _emitted(term, tmp_path, stem):
    """The effect class ``--emit-effect`` writes for ``term``, loaded from its file."""
    path = tmp_path / f'{stem}.py'
    path.write_text(effect_source(term, ['a record']))
    spec = importlib.util.spec_from_file_location(stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return next(v for k, v in vars(module).items() if k.startswith('Discovered'))


def _discovered(equation: str, coefficient: dict) -> Discovered:
    name = BY_EQUATION[equation].name
    return Discovered(effect=name, params=coefficient, stderr={k: 1e-3 for k in coefficient},
                      fixed={}, base_params={}, score=None, error_reduction=0.5,
                      channel_reduction={}, n_params=2, problems=[], config=None,
                      correlation=None, converged=True, seconds=0.0, acts_on='both',
                      summary='', equation=equation, screened_reduction=0.5,
                      interpretation='')


def test_an_emitted_lagging_transmitter_reads_as_the_package_one(tmp_path):
    """A lag operator on p_a is a sensor error over the record's arrays: the emitted file
    computes what the package's correction does, and it reads p_a late."""
    name = BY_EQUATION['measurement_p_a'].name
    coefficient = {f'{name}.lag_20ms_p_a_coefficient': 0.5}
    cls = _emitted(_discovered('measurement_p_a', coefficient), tmp_path, 'lagging')
    t = np.arange(0.0, 0.2, 1e-3)
    signals = {'t_s': t, 'p_a_pa': 3e5 + 2e5 * (t >= 0.05)}
    correction = BY_EQUATION['measurement_p_a']
    package = correction.sensor_error({**correction.neutral, 'lag_20ms_p_a_coefficient': 0.5},
                                      signals, ModelConfig.paper().core)['p_a_pa']
    emitted = cls.sensor_error(cls.example, signals, ModelConfig.paper().core)['p_a_pa']
    assert np.allclose(package, emitted, rtol=0, atol=1e-9)
    assert emitted[60] < -5e4 and emitted[0] == 0.0, 'the reading lags the step'


def test_an_emitted_memory_correction_simulates_as_the_package_one(tmp_path):
    """--emit-effect writes the hook from the same text: a valve hysteresis term (the
    command's memory, a state of the effect) and a modulation (the package evaluates those in
    one loop, the emitted file as their expression) simulate identically to the
    correction."""
    name = BY_EQUATION['valve_input'].name
    coefficient = {f'{name}.command_direction_coefficient': -0.08,
                   f'{name}.constant_coefficient': 0.01,
                   f'{name}.command_times_pressure_difference_coefficient': 3e-7}
    cls = _emitted(_discovered('valve_input', coefficient), tmp_path, 'hyst')
    assert [s.name for s in cls.states] == ['command_memory_v']
    with registry.registered(cls):
        t = np.arange(0.0, 1.0, 1e-3)
        u = 5.0 + 0.4 * np.sign(np.sin(2 * np.pi * 3 * t))
        package = ModelConfig.paper().with_effect(name, {
            k.partition('.')[2]: v for k, v in coefficient.items()})
        emitted = ModelConfig.paper().with_effect(cls.name, cls.example)
        a, b = simulate(package, t, u), simulate(emitted, t, u)
        plain = simulate(ModelConfig.paper(), t, u)
    assert np.allclose(a.states[:, :4], b.states[:, :4], rtol=0, atol=1e-9)
    assert np.abs(a.states[:, 2] - plain.states[:, 2]).max() > 1e3, 'the term acts'
    assert C_U != K_GAIN  # layout names the generated code imports exist


def test_a_correction_at_zero_is_skipped_and_changes_nothing():
    """The discovery host carries every correction at zero. The compiled model calls a
    stateless one only while a coefficient is set (its call costs as much as a short hook)
    and then predicts exactly what the model without it predicts; a correction with the
    command's memory is always called, so its memory moves as before."""
    from pneumatic_servo.model.kernel_cache import module_source

    def with_corrections(cfg, equations):
        for eq in equations:
            cfg = cfg.with_effect(BY_EQUATION[eq].name, BY_EQUATION[eq].neutral)
        return cfg

    base = ModelConfig.paper()
    layout = Model(with_corrections(base, ['moment_balance', 'mass_balance_a'])).layout
    calls = {cls.name: line for line in module_source(layout).splitlines()
             for i, cls in enumerate(layout.classes) if f'_hook_{i}_' in line}
    assert calls['correction_moment_balance'].startswith('        _hook')  # under its if
    assert calls['correction_mass_balance_a'].startswith('    _hook')  # it has a memory
    host = with_corrections(base, ['moment_balance', 'measurement_supply'])
    model = Model(host)
    t = np.arange(0.0, 0.3, 1e-3)
    command = 5.0 + 0.4 * np.sin(20 * t)
    plain = simulate(Model(base), t, command).states
    np.testing.assert_array_equal(simulate(model, t, command).states, plain)
    torque = with_values(host, ['correction_moment_balance.constant_coefficient'], [0.05])
    moved = simulate(model, t, command, config=torque).states
    assert np.abs(moved[:, 0] - plain[:, 0]).max() > 1e-4


def test_a_sensors_own_terms_are_those_of_its_reading_alone():
    """Discovery seeks a sensor's error first in its own reading's terms (its value, memory,
    lag or rate, and constants); the balance equations have none."""
    own = {eq.name: [t.name for t in eq.own] for eq in EQUATIONS}
    assert {'constant', 'gauge_p_a', 'p_a', 'rate_p_a', 'lag_20ms_p_a'} <= set(
        own['measurement_p_a'])
    assert not {'p_b', 'pressure_difference', 'sqrt_pressure_difference', 'velocity'} & set(
        own['measurement_p_a'])
    assert {'angle', 'motion_direction', 'window_0'} <= set(own['measurement_angle'])
    assert 'velocity' not in own['measurement_angle']
    assert own['measurement_supply'] == ['constant', 'gauge_supply', 'supply']
    assert all(not own[name] for name in ('moment_balance', 'mass_balance_a',
                                          'mass_balance_b', 'valve_input'))
