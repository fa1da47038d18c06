"""What a correction depends on, tested variable by variable (``analysis.diagnosis.dependence``).

Two records whose missing physics is a term of the vocabulary, hidden in the generator like
any effect, in a design unlike the open-world sets (a closed-loop sine under sliding-mode
control at 1 kHz with laboratory sensors, through the tight integrator):

* a flow into chamber a that follows the speed. In closed loop the command follows the
  speed, and a flow that follows the command is a proxy of it (a torque read so was the
  proxy discovery found before the moment balance stopped offering the command): given
  that proxy, the test must say that the flow also depends on the speed, and that the
  proxy adds nothing beside a free function of the speed (it depends on the speed alone);
* the weight of an arm (a torque in the sine of the angle), found as itself: the test must
  say that it depends on nothing more, and it is skipped where the options say so;
* a damping given as a damping over part of the stroke: where the truth damps over all of
  it, the correction depends on the speed and not on the angle (and p_a, which follows the
  speed in this loop, is not said beside it); where the truth is that window, on both; and
  where a small damping in an open-loop sine leaves either variable's free functions as
  good, the records cannot tell which, and both are kept.
"""
from dataclasses import replace

import numpy as np
import pytest

from pneumatic_servo.analysis.diagnosis import DiagnoseOptions, diagnose
from pneumatic_servo.analysis.diagnosis.coverage import (
    coverage,
    least_moved,
    moved_share,
    next_record,
)
from pneumatic_servo.analysis.diagnosis.dependence import probe_dependence, words
from pneumatic_servo.analysis.diagnosis.discovery import (
    ScreenedEquation,
    confirm,
    correction_host,
)
from pneumatic_servo.analysis.diagnosis.interpret import depends_on
from pneumatic_servo.analysis.diagnosis.pipeline import make_trial, prepare
from pneumatic_servo.analysis.diagnosis.verdict import rank
from pneumatic_servo.effects.corrections import BY_EQUATION, coefficient_name
from pneumatic_servo.effects.variables import BY_VARIABLE, RIG_RANGES, apart_span
from pneumatic_servo.model import ModelConfig
from pneumatic_servo.model.assembly import Model
from pneumatic_servo.prediction.inputs import smoothed_signals
from pneumatic_servo.synth.designs import DESIGNS, make_experiment
from pneumatic_servo.synth.plan import GAIN, next_designs
from pneumatic_servo.synth.varied import Record, make_record

RECORD = Record('closed_sine', 1000.0, 10.0, grade='laboratory', controller='smc',
                integrator='tight')


def _diagnosed(term: str, value: float, seed: int, **options):
    hidden = {BY_EQUATION['moment_balance'].name: {coefficient_name(term): value}}
    return diagnose([make_record(replace(RECORD, effects=hidden, seed=seed))],
                    options=DiagnoseOptions(**options))


def _given(record: Record, equation: str, term: str, start: float, named: dict = None):
    """(trial of ``record``, the correction ``term`` of ``equation`` fitted through the
    simulator from ``start``): on the model as given, or on it with the ``named`` effect
    (name -> values) whose parameters are refitted with it."""
    options = DiagnoseOptions()
    data, base, free = prepare([make_record(record)], ModelConfig.paper(), (), options)
    trial = make_trial(data, base, free, options, 1)
    for effect, values in (named or {}).items():
        base = replace(base, config=base.config.with_effect(effect, values))
        free = [f'{effect}.{k}' for k in values]
    host = correction_host(base.config)
    key = f'{BY_EQUATION[equation].name}.{coefficient_name(term)}'
    return trial, confirm(ScreenedEquation(equation, [key], {key: start}, 0.0), host,
                          Model(host), base, data, free, options)


def test_a_proxy_of_the_speed_is_found_to_depend_on_the_speed():
    name = BY_EQUATION['mass_balance_a'].name
    record = replace(RECORD, seed=32, effects={name: {coefficient_name('velocity'): 1e-5}})
    trial, proxy = _given(record, 'mass_balance_a', 'command', 1e-6)
    assert depends_on(proxy.terms, proxy.leading) == ['command']  # before the test
    best = probe_dependence(trial, rank([proxy], trial)[0])
    said = [t for t in best.dependence if t.depends]
    # the first variable said is the speed; the angle and the pressures, which follow it in
    # this loop, pass beside it in the first round and add nothing in the second
    assert [t.variable for t in said] == ['velocity'], [t.to_json() for t in best.dependence]
    assert said[0].p_value <= said[0].level
    assert 'also depends on the shaft speed' in best.interpretation
    # and the proxy adds nothing clearly beside a free function of the speed: it stood for
    # the speed, and the correction depends on the speed alone
    assert best.lead_test is not None and not best.lead_test.needed, best.lead_test
    assert best.depends_on == ['velocity'] == best.to_json()['depends_on']
    assert 'its leading term stood for them' in best.interpretation
    # each variable tried says how far it moved over the records (a variable that barely
    # moves cannot be said): p_a's span is the record's, in kPa where words show it
    p_a = next(t for t in best.dependence if t.variable == 'p_a')
    held = np.concatenate([smoothed_signals(e)['p_a_pa'] for e in trial.data.experiments])
    assert p_a.span == pytest.approx((held.min(), held.max()))
    assert p_a.to_json()['span'] == list(p_a.span)
    assert (f'p_a p = {p_a.p_value:.2g} over {held.min() / 1e3:.3g} to '
            f'{held.max() / 1e3:.3g} kPa abs') in words(best)
    # and the record that would test further is the one that moves the variable the records
    # moved over the least share of the rig's range (the speed has no such range)
    core = best.config.core
    shares = {t.variable: coverage(t.variable, t.span[1] - t.span[0], core)
              for t in best.dependence if not t.depends}
    least = least_moved(best)
    assert shares.pop('velocity', None) is None and least.variable in shares
    assert shares[least.variable] == min(shares.values()) < 1.0
    assert next_record(best).startswith(f'These records moved {least.variable} over ')
    # a variable the records moved only with one the correction depends on is named so:
    # its share is what they moved it over apart from that one
    width = least.span[1] - least.span[0]
    mirrored = replace(least, apart=0.01 * width, apart_from=('velocity',))
    held = replace(best, dependence=tuple(mirrored if t is least else t
                                          for t in best.dependence))
    assert least_moved(held) is mirrored
    assert moved_share(mirrored, core) == pytest.approx(0.01 * shares[least.variable])
    assert (f'and {100 * 0.01 * shares[least.variable]:.0f} % of it apart from velocity: a '
            f'record that moves {least.variable} apart from velocity would test'
            ) in next_record(held)


def test_a_correction_that_is_the_whole_truth_is_said_to_depend_on_nothing_more():
    result = _diagnosed('sin_angle', 0.2, 31)
    best = result.discovered[0]
    assert best.leading == 'sin_angle'
    assert best.dependence and not any(t.depends for t in best.dependence)
    assert best.lead_test is None  # nothing said: its own terms are not put in question
    assert best.depends_on == ['angle'] and 'also depends' not in best.interpretation
    # the JSON says which record would test it further, as the CLI and the report do
    assert result.to_json()['discovered'][0]['next_record'] == next_record(best) != ''
    # and which designs would, best first, each moving the variable further than these
    # records did: a torque shows only where the shaft moves, so no held-piston design
    least = least_moved(best)
    plans = next_designs(best)
    assert plans and [d.share for d in plans] == sorted((d.share for d in plans), reverse=True)
    core = best.config.core
    for d in plans:
        assert d.variable == least.variable and d.now == moved_share(least, core)
        assert d.now + GAIN <= d.share <= 1.0
        assert DESIGNS[d.design].circuit == 'servo' and d.design in d.words()
    # the first design, generated on the fitted model, moves the variable at least that far
    # (its plain span, read from the record's own signal, holds the span apart from others)
    record = make_experiment(best.config, plans[0].design, seed=0)
    signal = smoothed_signals(record)[BY_VARIABLE[least.variable].signal]
    low, high = RIG_RANGES[least.variable](core)
    assert np.ptp(signal) >= plans[0].share * (high - low) * (1 - 1e-9)


#: a small damping in an open-loop sine through low-cost sensors (bench_dependence's other
#: record): neither the angle's nor the speed's free functions leave the window anything clear
_SINE = Record('sine', 250.0, 10.0, grade='low_cost', integrator='rk4')


@pytest.mark.parametrize('record, truth, size, goes', [
    (RECORD, 'velocity', -0.02, 'angle'), (RECORD, 'velocity_in_window_2', -0.02, ''),
    (_SINE, 'velocity', -0.005, 'either')])
def test_a_variable_of_the_leading_term_goes_only_where_the_others_do_without_it(
        record, truth, size, goes):
    name = BY_EQUATION['moment_balance'].name
    record = replace(record, seed=33, effects={name: {coefficient_name(truth): size}})
    trial, window = _given(record, 'moment_balance', 'velocity_in_window_2', size / 2)
    assert depends_on(window.terms, window.leading) == ['angle', 'velocity']  # before
    best = probe_dependence(trial, rank([window], trial)[0])
    assert not any(t.depends for t in best.dependence), [t.to_json() for t in best.dependence]
    if goes == 'angle':  # a free function of the speed does as well: not the angle (and
        # not p_a, which follows the speed in this loop, said for the window's missing part)
        lead = best.lead_test
        assert (lead.dropped, lead.kept, lead.needed) == ('angle', ('velocity',), False), lead
        assert best.depends_on == ['velocity'] == best.to_json()['depends_on']
        assert best.to_json()['lead_test']['dropped'] == 'angle'
        assert ('it depends on those, and the shaft angle, which its leading term also '
                'uses, adds nothing clearly beside them') in best.interpretation
        assert (f'its own terms beside free functions of velocity: p = {lead.p_value:.2g} '
                '(not needed)') in words(best)
        return
    # neither goes: none can (the truth's window), or either could and the records cannot
    # tell which
    assert best.lead_test is None and best.depends_on == ['angle', 'velocity']
    either = ('its own terms add nothing clearly beside free functions of the shaft speed, '
              'nor beside those of the shaft angle: these records cannot tell whether it '
              'depends on the shaft angle or on the shaft speed, and none of them is dropped')
    assert (either in best.interpretation) == (goes == 'either'), best.interpretation
    assert ('its own terms add nothing' in best.interpretation) == (goes == 'either')


def test_a_variable_that_mirrors_another_is_not_moved_apart_from_it():
    """What a record moved a variable over apart from another: nothing where it mirrors
    it (p_a against p_b through a four-way valve's sine), all of its span where they move
    independently."""
    core = ModelConfig.paper().core
    t = np.linspace(0.0, 10.0, 5001)
    p_b = 4e5 + 1e5 * np.sin(2.0 * np.pi * t)
    mirrored = {'t_s': t, 'p_a_pa': 8e5 - p_b, 'p_b_pa': p_b}
    apart = {'t_s': t, 'p_a_pa': 4e5 + 1e5 * np.sin(2.0 * np.pi * 0.37 * t), 'p_b_pa': p_b}
    assert apart_span([mirrored], core, 'p_a', ['p_b']) < 1.0  # [Pa], of a 200 kPa span
    assert apart_span([mirrored], core, 'p_a', []) == pytest.approx(2e5, rel=1e-3)
    assert apart_span([apart], core, 'p_a', ['p_b']) > 0.8 * 2e5
    # two records that each mirror p_b, about different sums, move p_a apart from it
    shifted = {**mirrored, 'p_a_pa': 7e5 - p_b}
    assert apart_span([mirrored, shifted], core, 'p_a', ['p_b']) > 0.9e5


def test_the_test_can_be_skipped():
    result = _diagnosed('sin_angle', 0.2, 31, test_dependence=False)
    assert result.discovered[0].leading == 'sin_angle'
    assert not result.discovered[0].dependence and 'dependence' not in result.timings


def test_a_correction_found_on_top_of_a_named_effect_is_tested_on_that_model():
    """Found on top of a named effect (``partly_explained``), a correction was fitted with
    that effect's parameters refitted: its probes are fitted on the same model (on the model
    as given, that effect's parameters do not exist)."""
    record = Record('closed_steps', 250.0, 6.0, integrator='rk4', seed=5, effects={
        'external_load_torque': {'load_torque_n_m': 0.3},
        BY_EQUATION['moment_balance'].name: {coefficient_name('sin_angle'): 0.15}})
    trial, on_top = _given(record, 'moment_balance', 'sin_angle', 0.1,
                           {'external_load_torque': {'load_torque_n_m': 0.3}})
    assert 'external_load_torque.load_torque_n_m' in on_top.base_params
    found = probe_dependence(trial, rank([on_top], trial)[0])
    assert found.dependence and found.depends_on[0] == 'angle'
