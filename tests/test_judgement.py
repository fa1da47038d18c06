"""Calibrated judgement (issue 15): every status is a test against the record's own prediction
floor, checked on records unlike the hidden-effect sets (``pneumatic_servo.synth.varied``:
other sample rates, sensor grades, encoders, controllers and integrators).

The full false-alarm and power study is ``benchmarks/bench_judgement.py``; this is its small
version.
"""
from dataclasses import replace

import numpy as np
import pytest

from pneumatic_servo.analysis.diagnosis import DiagnoseOptions, diagnose
from pneumatic_servo.analysis.diagnosis.criteria import Levels, Status, gain_p_value
from pneumatic_servo.analysis.diagnosis.floor import Floor, quantum
from pneumatic_servo.analysis.diagnosis.candidates import screen_effect, try_effect
from pneumatic_servo.analysis.diagnosis.discovery import Discovered
from pneumatic_servo.analysis.diagnosis.pipeline import look_for_terms
from pneumatic_servo.analysis.diagnosis.refit import restarted
from pneumatic_servo.analysis.diagnosis.status import best_generic, clearly_better
from pneumatic_servo.analysis.diagnosis.verdict import rank
from pneumatic_servo.analysis.diagnosis.scoring import Score
from pneumatic_servo.synth.hidden import example_values
from pneumatic_servo.synth.varied import Record, make_record

#: clean records of designs the project's thresholds were never tuned on
CLEAN = [
    Record('closed_steps', 500.0, 10.0, 'laboratory', 4096, 'pid', {'kp': 8.0, 'kd': 0.1},
           'rk4', seed=3),
    Record('closed_sine', 250.0, 10.0, 'low_cost', 20000, 'smc', seed=4),
    Record('chirp', 1000.0, 10.0, 'industrial', 4096, integrator='tight', seed=5),
]


@pytest.mark.study
@pytest.mark.parametrize('rec', CLEAN, ids=lambda r: r.label)
def test_clean_records_of_varied_designs_are_consistent(rec):
    result = diagnose([make_record(rec)], options=DiagnoseOptions(discover=False))
    assert result.status == Status.CONSISTENT, result.reason
    assert result.verdict == 'none'
    tests = result.to_json()['tests']['base']
    assert not tests['departs'] and 'overall' in tests


@pytest.mark.study
def test_an_effect_in_one_channel_alone_is_not_consistent():
    """A load torque on a pressure-controlled loop shows in the angle first; the pooled
    residual, dominated by two pressure channels, must not hide it."""
    rec = Record('closed_steps', 500.0, 10.0, 'industrial', 20000, 'pid', {'kp': 2.0},
                 effects={'payload_inertia': {'payload_inertia_kg_m2': 2e-4}}, seed=7)
    result = diagnose([make_record(rec)], effects=['external_leakage', 'dead_volume'],
                      options=DiagnoseOptions(discover=False))
    assert result.status != Status.CONSISTENT, result.reason
    base = result.to_json()['tests']['base']
    assert base['departs']


@pytest.mark.study
def test_a_whole_answer_is_judged_with_its_fits_scatter():
    """A leak of 0.4 x the example size in a closed loop (a record of the power study): the
    rough stick-slip cost leaves the fitted areas 8 % and 16 % off, and against a floor that
    scores fixed values the angle departs (1.9 x). Refitted on whole replicas, the fit
    scatters as much, so the leak is the whole answer, and the JSON says what was added."""
    values = {k: 0.4 * v for k, v in example_values('external_leakage').items()}
    rec = Record('closed_steps', 500.0, 10.0, effects={'external_leakage': values}, seed=52)
    result = diagnose([make_record(rec)])
    assert result.status == Status.EXPLAINED, result.reason
    assert result.verdict == 'external_leakage'
    floor = result.to_json()['tests']['remainder']['floor']
    assert floor['refits'] == 3
    assert floor['refit_inflation']['angle'] > 1.5
    fixed = result.trial.departures(result.winner.score, result.trial.floor_of(
        result.winner.config))
    assert fixed.departs  # the same remainder against the floor of fixed values


@pytest.mark.study
def test_a_generic_term_must_beat_a_named_effect_fitted_where_its_own_cost_is_lowest():
    """A load torque of 0.7 x the example size (0.175 N.m): on the rough stick-slip cost the
    named effect's fit can stop in a local minimum a few per cent off (from 0.182 N.m it
    polishes to about 0.183), where a generic constant torque, fitted from another start,
    lands at 0.177 and beats it clearly on the held-out data. Restarted either side of its
    values, the named fit lands lower on its own fit cost, near the truth, and the generic
    no longer beats it: the torque is the whole answer, not a partial fit."""
    key = 'external_load_torque.load_torque_n_m'
    values = {k: 0.7 * v for k, v in example_values('external_load_torque').items()}
    rec = Record('closed_steps', 500.0, 10.0, effects={'external_load_torque': values},
                 seed=53)
    result = diagnose([make_record(rec)])
    assert result.status == Status.EXPLAINED, result.reason
    assert result.verdict == 'external_load_torque'
    trial = result.trial
    named = next(c for c in result.ranking if c.effect == 'external_load_torque')
    assert abs(named.params[key] / 0.175 - 1.0) < 0.02, named.params
    # the poor landing, and the restart out of it: the generic corrections the diagnosis
    # ranked beside the named effects (an explained status does not report them)
    joint = rank(result.ranking + look_for_terms(trial, trial.base), trial)
    found = best_generic(trial, [c for c in joint if isinstance(c, Discovered)])
    screen = screen_effect('external_load_torque', trial.base, trial.data)
    stuck = try_effect(replace(screen, start={key: 0.182}), trial.base, trial.data,
                       list(trial.free), trial.options, bracket=False)
    assert stuck.params[key] > 0.18 and clearly_better(trial, found, stuck), stuck.params
    again = restarted(trial, stuck)
    assert abs(again.params[key] - 0.175) < abs(stuck.params[key] - 0.175) - 0.002, again.params
    assert not clearly_better(trial, found, again)


def test_floor_test_has_its_stated_false_alarm_rate():
    """A mean square drawn like the replicas departs at the stated level (prediction-interval
    test on the log scale): simulated."""
    rng = np.random.default_rng(0)
    level, hits, trials = 0.01, 0, 4000
    for _ in range(trials):
        draws = np.exp(rng.normal(0.0, 0.4, 17))
        floor = Floor({'angle': draws[:16]}, draws[:16], units=10 ** 6)
        hits += floor.test(draws[16], 'angle').p_value <= level
    assert hits / trials == pytest.approx(level, abs=0.006)


def test_a_floor_of_zero_gives_a_ratio_not_nan():
    """A channel the model and every replica match exactly (an arm held at an end stop) has
    a floor of zero: an exact record is no departure, any residual an infinite one."""
    floor = Floor({'angle': np.zeros(16)}, np.zeros(16), units=100)
    assert floor.test(0.0, 'angle').ratio == 0.0
    assert floor.test(1e-6, 'angle').ratio == np.inf
    assert floor.test(1e-6, 'angle').p_value < 0.01


def test_floor_with_refits_keeps_its_false_alarm_rate():
    """What a refitted effect leaves is the replicas' mean square times the refit's own
    scatter. Against the floor with that scatter added (three refits), such a remainder departs
    at most at the stated level; against the floor without it, far more often: simulated."""
    rng = np.random.default_rng(1)
    level, trials = 0.01, 3000
    with_refits = without = 0
    for _ in range(trials):
        logs = rng.normal(0.0, 0.4, 17)
        refits = rng.normal(0.6, 0.3, 4)
        floor = Floor({'angle': np.exp(logs[:16])}, np.exp(logs[:16]), units=10 ** 6)
        remainder = float(np.exp(logs[16] + refits[3]))
        with_refits += floor.with_refits({'angle': refits[:3]}).test(
            remainder, 'angle').p_value <= level
        without += floor.test(remainder, 'angle').p_value <= level
    assert with_refits / trials <= 1.5 * level
    assert without / trials > 5 * level
    raised = floor.with_refits({'angle': refits[:3], 'overall': np.full(3, -1.0)})
    assert raised.rms('angle') == pytest.approx(floor.rms('angle')
                                                * np.exp(0.5 * max(refits[:3].mean(), 0.0)))
    assert raised.rms() == floor.rms()  # a refit never lowers the floor


def test_gain_test_and_levels():
    base = Score({'angle': 1.0}, 1.0)
    assert gain_p_value(base, Score({'angle': 0.5}, 0.5), 1, 40) < 1e-6
    assert gain_p_value(base, Score({'angle': 1.01}, 1.01), 1, 40) == 1.0
    levels = Levels.of(0.01, 3, 15)
    assert levels.departure == pytest.approx(0.005 / 4)
    assert levels.candidate == pytest.approx(0.005 / 15)


def test_quantum_of_an_encoder():
    step = 2 * np.pi / 4096
    angle = np.round(np.linspace(0.0, 0.2, 5000) / step) * step
    assert quantum(angle) == pytest.approx(step)
    assert quantum(np.random.default_rng(0).normal(size=5000)) == 0.0


@pytest.mark.parametrize('effect', ['external_leakage', 'external_load_torque',
                                    'valve_spool_dynamics'])
def test_a_candidates_floor_runs_on_the_composition_it_was_fitted_on(effect):
    """What a named effect leaves is judged against its own floor, simulated with the fit's
    own compiled composition (host_for): no other composition is compiled for it, and the
    fitted values are the candidate's."""
    from pneumatic_servo.analysis.diagnosis.hosts import fitted_on, host_for
    from pneumatic_servo.model import ModelConfig
    base = ModelConfig.paper()
    values = example_values(effect)
    config = base.with_effect(effect, values)
    config.core['stroke_rad'] *= 1.01  # a refitted base key travels with it
    host = fitted_on(base, config)
    assert ([c.name for c in host.component_classes()]
            == [c.name for c in host_for(base, effect).component_classes()])
    assert host.values_of(effect) == config.values_of(effect)
    assert host.core == config.core
