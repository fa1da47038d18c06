"""What a correction depends on, tested variable by variable (``analysis.diagnosis.dependence``).

Two records whose missing physics is a term of the vocabulary, hidden in the generator like
any effect, in a design unlike the open-world sets (a closed-loop sine under sliding-mode
control at 1 kHz with laboratory sensors, through the tight integrator):

* damping that grows with chamber a's pressure. In closed loop the command follows the
  speed, and the correction found is a torque that follows the command; the test must say
  that it also depends on the speed;
* the weight of an arm (a torque in the sine of the angle), found as itself: the test must
  say that it depends on nothing more, and it is skipped where the options say so.
"""
from dataclasses import replace

from pneumatic_servo.analysis.diagnosis import DiagnoseOptions, diagnose
from pneumatic_servo.analysis.diagnosis.interpret import depends_on
from pneumatic_servo.effects.corrections import BY_EQUATION, coefficient_name
from pneumatic_servo.synth.varied import Record, make_record

RECORD = Record('closed_sine', 1000.0, 10.0, grade='laboratory', controller='smc',
                integrator='tight')


def _diagnosed(term: str, value: float, seed: int, **options):
    hidden = {BY_EQUATION['moment_balance'].name: {coefficient_name(term): value}}
    return diagnose([make_record(replace(RECORD, effects=hidden, seed=seed))],
                    options=DiagnoseOptions(**options))


def test_a_torque_read_through_a_proxy_of_the_speed_is_found_to_depend_on_the_speed():
    result = _diagnosed('velocity_times_gauge_p_a', -1.5e-7, 32)
    best = result.discovered[0]
    assert best.equation == 'moment_balance'
    assert 'velocity' not in depends_on(best.terms, best.leading)  # before the test
    said = [t for t in best.dependence if t.depends]
    # the first variable said is the speed (a second round may add the angle, which p_a
    # follows in these steps: benchmarks/bench_dependence.py counts such statements)
    assert said and said[0].variable == 'velocity', [t.to_json() for t in best.dependence]
    assert said[0].p_value <= said[0].level
    assert 'velocity' in best.depends_on
    assert 'velocity' in best.to_json()['depends_on']
    assert 'also depends on the shaft speed' in best.interpretation


def test_a_correction_that_is_the_whole_truth_is_said_to_depend_on_nothing_more():
    result = _diagnosed('sin_angle', 0.2, 31)
    best = result.discovered[0]
    assert best.leading == 'sin_angle'
    assert best.dependence and not any(t.depends for t in best.dependence)
    assert best.depends_on == ['angle'] and 'also depends' not in best.interpretation


def test_the_test_can_be_skipped():
    result = _diagnosed('sin_angle', 0.2, 31, test_dependence=False)
    assert result.discovered[0].leading == 'sin_angle'
    assert not result.discovered[0].dependence and 'dependence' not in result.timings
