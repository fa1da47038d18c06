"""Property-based fuzzing (hypothesis) of what users feed the package: configs, static CSV
tables and bag contents. Whatever the input: a clear error (``PneumaticServoError``, the
one-line reason the command line prints) or a result, never another exception, never a
hang (a deadline per case); and a valid input gives a finite, physical result."""
import math
import string
import tempfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pneumatic_servo.analysis.compare import compare
from pneumatic_servo.errors import PneumaticServoError
from pneumatic_servo.experiment import Experiment
from pneumatic_servo.io import read_experiment, write_experiment
from pneumatic_servo.model.config import ModelConfig

FUZZ = settings(max_examples=40, deadline=120_000, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**9, 10**9))
texts = st.text(alphabet=string.printable, max_size=12)
scalars = st.one_of(numbers, texts, st.booleans(), st.none(),
                    st.sampled_from(['0.6 MPa gauge', '5 mm^2', '1e-8', '7e5', 'nan', '-1 bar']))
values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                       st.dictionaries(texts, inner, max_size=3)),
                      max_leaves=6)
KEYS = ['supply_pressure_pa', 'stroke_rad', 'core', 'components', 'effects', 'thermal',
        'external_leakage', 'leak_area_a_m2', 'piston_seal_leakage', 'nonsense']


@st.composite
def configs(draw):
    doc = {}
    for section in draw(st.lists(st.sampled_from(['core', 'components', 'effects', 'other']),
                                 max_size=3, unique=True)):
        doc[section] = draw(st.dictionaries(st.one_of(st.sampled_from(KEYS), texts, numbers),
                                            values, max_size=4))
    return doc


@FUZZ
@given(doc=configs())
def test_any_config_is_loaded_or_refused_with_a_reason(doc, tmp_path):
    path = tmp_path / 'cfg.yaml'
    path.write_text(yaml.safe_dump(doc, allow_unicode=True))
    try:
        ModelConfig.load(path)
    except PneumaticServoError as exc:
        assert str(exc) and '\n' not in str(exc).strip()


@st.composite
def valid_configs(draw):
    """Every core value and every effect's values anywhere within the declared bounds."""
    cfg = ModelConfig.paper()
    for name in draw(st.lists(st.sampled_from(['external_leakage', 'piston_seal_leakage',
                                               'external_load_torque', 'dead_volume']),
                              max_size=2, unique=True)):
        cfg = cfg.with_effect(name)
        for key in [k for k in cfg.effects[name]]:
            p = cfg.param(f'{name}.{key}')
            cfg.set(f'{name}.{key}', draw(st.floats(p.lower, p.upper)))
    return cfg


@pytest.mark.study
@FUZZ
@given(cfg=valid_configs(), volts=st.floats(0.0, 10.0))
def test_valid_configs_simulate_to_finite_physical_states(cfg, volts):
    from pneumatic_servo.model.assembly import Model
    from pneumatic_servo.model.simulate import simulate
    t = np.arange(0.0, 0.1, 1e-3)
    res = simulate(Model(cfg), t, command_v=volts)
    for sig in (res.angle_rad, res.p_a_pa, res.p_b_pa):
        assert np.all(np.isfinite(sig))
    assert 0.0 <= res.angle_rad.min() and res.angle_rad.max() <= cfg.core['stroke_rad'] + 1e-9
    assert res.p_a_pa.min() > 0 and res.p_a_pa.max() < 1.05 * cfg.core['supply_pressure_pa']


cells = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr),
                  st.integers(-10**7, 10**7).map(str), texts.filter(lambda s: ',' not in s
                                                                     and '\n' not in s
                                                                     and '\r' not in s),
                  st.just(''))
COLUMNS = ['circuit', 'voltage_v', 'supply_pa', 'p_a_pa', 't_s_k', 'p_b_pa', 'm4_kg_s', 'x']


@FUZZ
@given(header=st.lists(st.sampled_from(COLUMNS), min_size=1, max_size=6, unique=True),
       rows=st.lists(st.lists(cells, min_size=6, max_size=6), max_size=8))
def test_any_csv_is_read_or_refused_with_a_reason(header, rows, tmp_path):
    path = tmp_path / 'table.csv'
    lines = [','.join(header)] + [','.join(r[:len(header)]) for r in rows]
    path.write_text('\n'.join(lines) + '\n')
    try:
        exp = read_experiment(path)
    except PneumaticServoError as exc:
        assert str(exc) and '\n' not in str(exc).strip()
        return
    for values in exp.signals.values():
        assert np.all(np.isfinite(values))


@FUZZ
@given(volts=st.lists(st.floats(5.0, 10.0), min_size=2, max_size=6),
       supply_gauge_mpa=st.floats(0.3, 0.8))
def test_valid_closed_port_tables_compare_to_finite_numbers(volts, supply_gauge_mpa, tmp_path):
    supply = 101325.0 + supply_gauge_mpa * 1e6
    lines = ['circuit,voltage_v,supply_pa,p_a_pa,t_s_k']
    lines += [f'closed_port,{v:.3f},{supply:.0f},{0.5 * (supply + 101325.0):.0f},293.15'
              for v in volts]
    path = tmp_path / 'table.csv'
    path.write_text('\n'.join(lines) + '\n')
    result = compare(read_experiment(path))
    assert all(math.isfinite(m['rmse']) for m in result['channels'].values())


@FUZZ
@given(angle=st.lists(st.floats(allow_nan=True, allow_infinity=True, width=32),
                      min_size=2, max_size=30),
       pressure=st.floats(allow_nan=True, allow_infinity=True),
       dt=st.sampled_from([1e-3, 0.0, -1e-3, 1e9]))
def test_any_bag_contents_are_read_or_refused_with_a_reason(angle, pressure, dt, tmp_path):
    n = len(angle)
    t = np.arange(n) * dt if dt else np.zeros(n)
    signals = {'command_v': np.full(n, 5.0), 'angle_rad': np.array(angle, dtype=float),
               'p_a_pa': np.full(n, pressure), 'p_b_pa': np.full(n, 5e5),
               'supply_pa': np.full(n, 7e5)}
    try:
        exp = Experiment(t, signals, 'servo', 'fuzz')
        path = write_experiment(exp, Path(tempfile.mkdtemp(dir=tmp_path)) / 'bag', 'sqlite3')
    except PneumaticServoError:
        return  # refused before it could be written: nothing to read
    try:
        got = read_experiment(path)
    except PneumaticServoError as exc:
        assert str(exc) and '\n' not in str(exc).strip()
        return
    assert np.all(np.isfinite(signals['angle_rad'])) and math.isfinite(pressure)
    for values in got.signals.values():
        assert np.all(np.isfinite(values))


@pytest.fixture(autouse=True)
def _no_scipy_warnings_as_errors():
    with np.errstate(all='ignore'):
        yield
