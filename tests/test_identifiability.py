"""What the data cannot determine is said so, never reported as known; and what one
experiment shows is checked on another (issue: identifiability and validation)."""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from pneumatic_servo.analysis.diagnosis import diagnose
from pneumatic_servo.fitting.identifiability import identifiability
from pneumatic_servo.identification.output_error import fit_output_error
from pneumatic_servo.io import read_experiment
from pneumatic_servo.model import Model, ModelConfig
from pneumatic_servo.model.circuits import predict_static

ROOT = Path(__file__).resolve().parents[1]
DEMO = ROOT / 'bags' / 'validation_demo'


@pytest.mark.study
def test_a_parameter_outside_the_circuit_is_not_determined():
    """Closed-port data hold chamber a only: chamber b's leak is reported as not identifiable,
    with the reason and the record that would determine it, and left out of the criterion."""
    result = diagnose([read_experiment(DEMO / 'closed_port.csv')],
                      effects=['external_leakage', 'valve_null_offset'])
    leak = next(c for c in result.ranking if c.effect == 'external_leakage')
    key_b = 'external_leakage.leak_area_b_m2'
    assert leak.stderr[key_b] is None
    assert 'chamber b is not part of the closed_port circuit' in leak.undetermined[key_b]
    assert 'blocked' in leak.undetermined[key_b]  # the record that would determine it
    assert leak.n_params == 1  # only leak_area_a counts in the information criterion
    assert leak.stderr['external_leakage.leak_area_a_m2'] > 0
    data = json.loads(json.dumps(result.to_json(), default=float))
    entry = next(c for c in data['ranking'] if c['effect'] == 'external_leakage')
    assert entry['stderr'][key_b] is None and key_b in entry['undetermined']
    assert np.all(np.isnan(np.asarray(leak.correlation, float)[1]))


def test_apply_never_writes_an_undetermined_value_as_fitted(tmp_path):
    out = tmp_path / 'fitted.yaml'
    proc = subprocess.run(
        [sys.executable, '-c', 'import sys; from pneumatic_servo.cli import main; '
         'sys.exit(main())', 'diagnose', str(DEMO / 'closed_port.csv'), '--effects',
         'external_leakage,valve_null_offset', '--apply', str(out), '--quiet'],
        capture_output=True, text=True, timeout=600, env=dict(os.environ))
    assert proc.returncode == 0, proc.stderr
    text = out.read_text()
    assert 'leak_area_b_m2 = 0: NOT FITTED, left at its neutral value' in text
    assert yaml.safe_load(text)['effects']['external_leakage']['leak_area_b_m2'] == 0.0


def test_a_sum_is_reported_as_one_combination():
    """The core dead volume and the dead-volume effect's extra volume only appear as their
    sum: one combination, neither with a standard error."""
    exp = read_experiment(ROOT / 'bags' / 'charge_discharge')
    cfg = ModelConfig.paper().with_effect('dead_volume', {'extra_dead_volume_a_m3': 1e-6})
    keys = ['core.dead_volume_a_m3', 'dead_volume.extra_dead_volume_a_m3']
    fit = fit_output_error(cfg, [exp], keys, channels=['p_a'], max_nfev=8)
    combos = fit.identifiability.combinations
    assert len(combos) == 1 and set(combos[0].keys) == set(keys)
    assert combos[0].kind == 'sum'
    assert 'dead_volume_a_m3 + extra_dead_volume_a_m3' in combos[0].text()
    assert all(fit.stderr[k] is None for k in keys)


def test_a_product_is_reported_as_one_combination():
    """Two parameters that enter only as their product have proportional Jacobian columns."""
    rng = np.random.default_rng(1)
    g = rng.normal(size=200)
    p1, p2, p3 = 2.0, 5.0, 1.0
    jac = np.column_stack([p2 * g, p1 * g, rng.normal(size=200)])
    ident = identifiability(['a.p1', 'a.p2', 'a.p3'], np.array([p1, p2, p3]), jac,
                            np.array([p1, p2, p3]))
    assert ident.rank == 2
    assert [c.kind for c in ident.combinations] == ['product']
    assert set(ident.combinations[0].keys) == {'a.p1', 'a.p2'}
    assert ident.reason('a.p3') is None


def test_blocked_static_table_is_read_and_predicted():
    exp = read_experiment(DEMO / 'blocked_table.csv')
    assert exp.circuit == 'blocked' and exp.static
    assert {'p_a_pa', 'p_b_pa', 'command_v', 'supply_pa'} <= set(exp.signals)
    truth = json.loads((DEMO / 'truth.json').read_text())['hidden_effects']
    cfg = ModelConfig.paper().with_effect('external_leakage', truth['external_leakage'])
    pred = predict_static(Model(cfg), exp, cfg)
    for sig in ('p_a_pa', 'p_b_pa'):
        assert np.max(np.abs(pred[sig] - exp[sig])) < 3e3, sig  # within sensor noise


@pytest.fixture(scope='module')
def validated():
    """The leak found on the closed-port table, validated on the blocked table."""
    return diagnose([read_experiment(DEMO / 'closed_port.csv')],
                    validate_on=[read_experiment(DEMO / 'blocked_table.csv')])


@pytest.mark.study
def test_found_on_one_circuit_confirmed_on_another(validated):
    result = validated
    assert result.verdict == 'external_leakage' and result.status == 'explained'
    val = result.winner.validation
    assert val.error_reduction > 0.5  # the other experiment improves too
    assert any('leak_area_b_m2 = leak_area_a_m2' in a for a in val.assumptions)
    assert result.ladder[-1]['validation']['overall'] < 0.5 * result.ladder[0]['validation'][
        'overall']
    assert result.validated_on == ['blocked_table']


@pytest.mark.study
def test_an_effect_that_only_overfits_one_experiment_is_flagged(validated):
    offset = next(c for c in validated.ranking if c.effect == 'valve_null_offset')
    assert offset.error_reduction > 0.2  # it helps the diagnosed table
    assert offset.validation.hurts  # and makes the other worse
    data = json.loads(json.dumps(validated.to_json(), default=float))
    entry = next(c for c in data['ranking'] if c['effect'] == 'valve_null_offset')
    assert entry['validation']['hurts'] is True
