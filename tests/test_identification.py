"""Identification recovers the known truth from the noisy synthetic experiments.

Targets (issue 4): C1 within 5 % at each tested voltage; h within 10 %;
F_s and F_c within 10 %, theta'_s and B within 25 %. The truth differs from
the paper's values, so returning the defaults fails. The library in bags/
is used as recorded (rosbag2 and CSV, read back), and a second, freshly
generated set with other noise checks that the result is not one lucky seed.
"""
from pathlib import Path

import numpy as np
import pytest

from pneumatic_servo.identification.flow_coefficient import (
    POLY_KEYS,
    flow_coefficients,
    identify_flow_coefficient,
)
from pneumatic_servo.identification.friction import identify_friction
from pneumatic_servo.identification.heat_transfer import H_KEY, identify_heat_transfer
from pneumatic_servo.identification.identify import identify, refinement_report
from pneumatic_servo.identification.output_error import fit_output_error
from pneumatic_servo.io import read_experiment
from pneumatic_servo.model import ModelConfig
from pneumatic_servo.physics.valve import flow_coefficient
from pneumatic_servo.synth import LIBRARY, TRUTH_VALUES, make_experiment, synthetic_rig

BAGS = Path(__file__).resolve().parents[1] / 'bags'
FRICTION = ('static_friction_n', 'coulomb_friction_n', 'stribeck_velocity_rad_s',
            'viscous_friction_n_s_per_rad')
TOLERANCE = {'static_friction_n': 0.10, 'coulomb_friction_n': 0.10,
             'stribeck_velocity_rad_s': 0.25, 'viscous_friction_n_s_per_rad': 0.25}


@pytest.fixture(scope='module')
def library():
    if not (BAGS / 'truth.yaml').exists():
        pytest.skip('bags/ not generated (pneumatic-servo generate bags/)')
    exps = {p.name if p.is_dir() else p.stem: read_experiment(p) for p in sorted(BAGS.iterdir())
            if (p / 'metadata.yaml').exists() or p.suffix == '.csv'}
    return exps, ModelConfig.load(BAGS / 'truth.yaml')


@pytest.fixture(scope='module')
def fresh():
    """The identification designs again, with other noise (seed 7)."""
    cfg = synthetic_rig()
    names = [n for n in LIBRARY if n.startswith(('flow_', 'friction_', 'heat_transfer'))]
    from pneumatic_servo.model import Model
    model = Model(cfg)
    return {n: make_experiment(cfg, n, 7, model=model) for n in names}, cfg


def truth_c1(truth: ModelConfig, volts):
    coeffs = [truth.get(k) for k in POLY_KEYS]
    x = np.abs(truth.core['spool_gain_m_per_v'] * (np.asarray(volts) - 5.0))
    return np.array([flow_coefficient(xi, *coeffs) for xi in x])


def test_truth_differs_from_paper(library):
    _, truth = library
    paper = ModelConfig.paper()
    for key, value in TRUTH_VALUES.items():
        assert truth.get(key) == pytest.approx(value)
        assert abs(value / paper.get(key) - 1) > 0.04, key
    # C1 itself differs by more than the 5 % tolerance at every tested voltage
    volts = np.arange(5.0, 10.01, 0.25)
    assert np.all(np.abs(truth_c1(truth, volts) / truth_c1(paper, volts) - 1) > 0.05)


def _check_c1(exps, truth):
    flows = [e for name, e in exps.items() if name.startswith('flow_')]
    assert len(flows) == 4
    result = identify_flow_coefficient(flows, ModelConfig.paper())
    per_v = result.per_voltage()
    volts = np.array(list(per_v))
    c1 = np.array(list(per_v.values()))
    err = c1 / truth_c1(truth, volts) - 1
    assert np.all(np.abs(err) < 0.05), dict(zip(volts, err))
    # each point, at every supply, and the Eq. 40 polynomial
    assert np.all(np.abs(result.c1 / truth_c1(truth, result.voltage_v) - 1) < 0.05)
    poly_err = result.polynomial(result.spool_m) / truth_c1(truth, result.voltage_v) - 1
    assert np.all(np.abs(poly_err) < 0.05)
    return np.max(np.abs(err))


def test_flow_coefficient_library(library):
    exps, truth = library
    worst = _check_c1(exps, truth)
    print(f'C1 worst error over voltages: {worst:.2%}')


def test_flow_coefficient_fresh_noise(fresh):
    exps, truth = fresh
    _check_c1(exps, truth)


def test_paper_eq38_is_biased_when_unchoked(library):
    """As printed, Eq. 38 takes the flow as choked; with the flow meter's back pressure it
    is not at high voltages, and C1 comes out low there."""
    exps, truth = library
    r = flow_coefficients([exps['flow_0.6MPa']], ModelConfig.paper())
    high = r.pressure_ratio > 0.7
    assert high.any()
    assert np.all(r.c1_choked[high] < 0.97 * truth_c1(truth, r.voltage_v[high]))


def _check_h(exp, truth):
    res = identify_heat_transfer(exp, ModelConfig.paper())
    h = truth.get(H_KEY)
    assert res.h_lsq == pytest.approx(h, rel=0.10)
    assert res.h_mean == pytest.approx(h, rel=0.10)
    assert np.isfinite(res.h_curve[res.valid]).all() and res.valid.sum() > 500
    return res


def test_heat_transfer_library(library):
    exps, truth = library
    res = _check_h(exps['heat_transfer'], truth)
    print(f'h = {res.h_lsq:.3f} (mean {res.h_mean:.3f}, paper Eq. 42 {res.h_paper:.3f}), '
          f'truth {truth.get(H_KEY)}')
    # the paper's Eq. 42 without the supply gas's enthalpy overestimates h on this rig
    assert res.h_paper > 1.1 * truth.get(H_KEY)


def test_heat_transfer_fresh_noise(fresh):
    exps, truth = fresh
    _check_h(exps['heat_transfer'], truth)


def _check_friction(exps, truth):
    runs = [e for name, e in exps.items() if name.startswith('friction_')]
    result = identify_friction(runs, ModelConfig.paper())
    kinds = {p.kind for p in result.points}
    assert kinds == {'steady', 'slip', 'breakaway'}
    errors = {}
    for fit in (result.geometric, result.least_squares):
        got = dict(zip(FRICTION, (fit.static_friction_n, fit.coulomb_friction_n,
                                  fit.stribeck_velocity_rad_s, fit.viscous_friction_n_s_per_rad)))
        for name in FRICTION:
            true = truth.get(f'stribeck_friction.{name}')
            errors[fit.method, name] = got[name] / true - 1
            assert abs(errors[fit.method, name]) < TOLERANCE[name], (fit.method, name, got[name])
    assert result.least_squares.correlation.shape == (4, 4)
    assert all(np.isfinite(v) for v in result.least_squares.stderr.values())
    return errors


def test_friction_library(library):
    exps, truth = library
    errors = _check_friction(exps, truth)
    print('friction errors:', {f'{m}.{n}': f'{e:+.1%}' for (m, n), e in errors.items()})


def test_friction_fresh_noise(fresh):
    exps, truth = fresh
    _check_friction(exps, truth)


def test_identify_writes_a_config_the_model_takes(library, tmp_path):
    exps, truth = library
    result = identify(list(exps.values()), ModelConfig.paper())
    assert set(result.used) == {'flow', 'heat', 'friction'}
    path = tmp_path / 'identified.yaml'
    result.config.save(path, header=result.header())
    loaded = ModelConfig.load(path)
    assert loaded.get(H_KEY) == pytest.approx(truth.get(H_KEY), rel=0.10)
    for name in FRICTION:
        key = f'stribeck_friction.{name}'
        assert loaded.get(key) == pytest.approx(truth.get(key), rel=TOLERANCE[name])
    assert 'correlation' not in result.summary()  # no refinement asked for
    assert result.to_dict()['heat_transfer']['h'] == pytest.approx(result.heat_h)


def test_output_error_refinement_reports_uncertainty(library):
    """Output error over two records together recovers F_c and B from the paper's values,
    with standard errors and the correlation matrix that shows how they trade off."""
    exps, truth = library
    start = truth.copy()
    start.set('stribeck_friction.coulomb_friction_n', 6.03)
    start.set('stribeck_friction.viscous_friction_n_s_per_rad', 0.85)
    keys = ['stribeck_friction.coulomb_friction_n',
            'stribeck_friction.viscous_friction_n_s_per_rad']
    fit = fit_output_error(start, [exps['friction_5.30V'], exps['friction_5.45V']], keys,
                           max_nfev=15)
    assert fit.values[keys[0]] == pytest.approx(truth.get(keys[0]), rel=0.05)
    assert fit.values[keys[1]] == pytest.approx(truth.get(keys[1]), rel=0.15)
    assert fit.correlation.shape == (2, 2) and fit.correlation[0, 1] < -0.5
    text = refinement_report(fit)
    assert '+/-' in text and 'correlation' in text and 'cannot separate them' in text
