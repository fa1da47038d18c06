"""The test, variable by variable, of what a discovered correction depends on (issue 16,
``analysis.diagnosis.dependence``), on records whose missing physics is exactly a term of
the vocabulary, so that the variables it depends on are known without judgement.

Each truth is a generic correction hidden in the generator like any effect, at a size a
rig shows, in records unlike those the test was developed on (the twelve of
``open_world_set`` at 500 Hz, industrial sensors, PID steps and a chirp): a closed-loop
sine under sliding-mode control at 1 kHz with laboratory sensors through the tight
integrator, and an open-loop sine at 250 Hz with low-cost sensors through fixed-step RK4.

For each record it prints the status, the best correction's equation and leading term, the
variables tried (``+`` added, ``-`` not), and what it is said to depend on against the
truth's variables. Then the counts: variables said that the truth does not depend on (the
test's false statements; its stated rate is at most the candidate level per correction,
a fraction of a per cent), the truth's variables missed before and after the test, and the
leading terms found not needed beside the variables said or beside their own variables but
one (and truth variables so dropped).

Run: ``.venv/bin/python benchmarks/bench_dependence.py [--only TERM] [--json PATH]``.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

#: (equation, term, coefficient [SI]): a weight on an arm, damping that grows with p_a,
#: a vent from chamber a over part of the stroke, crosstalk of p_a into p_b's reading,
#: a valve whose effective command grows with its distance from centre
TRUTHS = (('moment_balance', 'sin_angle', 0.2),
          ('moment_balance', 'velocity_times_gauge_p_a', -1.5e-7),
          ('mass_balance_a', 'sqrt_drop_a_in_window_1', -3e-8),
          ('measurement_p_b', 'p_a', 0.01),
          ('valve_input', 'abs_command', 0.08))


def records(index: int):
    """(label, Record) of the two records of truth number ``index``."""
    from pneumatic_servo.synth.varied import Record
    return [('closed loop', Record('closed_sine', 1000.0, 10.0, grade='laboratory',
                                   controller='smc', integrator='tight', seed=31 + index)),
            ('open loop', Record('sine', 250.0, 10.0, grade='low_cost', integrator='rk4',
                                 seed=41 + index))]


def row(equation: str, term: str, result) -> dict:
    """What the diagnosis said of a record with ``term`` hidden in ``equation``."""
    from pneumatic_servo.analysis.diagnosis.interpret import depends_on
    from pneumatic_servo.effects.terms import BY_NAME
    truth = set(BY_NAME[term].depends_on)
    out = {'term': term, 'status': result.status, 'truth': sorted(truth)}
    if not result.discovered or result.discovered[0].equation != equation:
        return {**out, 'equation': result.discovered[0].equation if result.discovered
                else None, 'judged': False}
    best = result.discovered[0]
    before = set(depends_on(best.terms, best.leading))
    tests = [t.to_json() for t in best.dependence]
    said = {t['variable'] for t in tests if t['depends']}
    dropped = best.lead_test is not None and not best.lead_test.needed
    return {**out, 'equation': equation, 'judged': True, 'leading': best.leading,
            'before': sorted(before), 'after': best.depends_on, 'tests': tests,
            'false': sorted(said - truth), 'missed_before': sorted(truth - before),
            'missed_after': sorted(truth - set(best.depends_on)), 'lead_dropped': dropped,
            'truth_dropped': sorted((before & truth) - set(best.depends_on))}


def main(argv=None) -> int:
    from dataclasses import replace

    from pneumatic_servo.analysis.diagnosis import diagnose
    from pneumatic_servo.effects.corrections import BY_EQUATION, coefficient_name
    from pneumatic_servo.synth.varied import make_record
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--only', help='truth terms, comma-separated')
    ap.add_argument('--json', help='write every row as JSON')
    args = ap.parse_args(argv)
    rows = []
    for index, (equation, term, value) in enumerate(TRUTHS):
        if args.only and term not in args.only.split(','):
            continue
        hidden = {BY_EQUATION[equation].name: {coefficient_name(term): value}}
        for loop, rec in records(index):
            t0 = time.perf_counter()
            r = row(equation, term, diagnose([make_record(replace(rec, effects=hidden))]))
            r.update(record=loop, seconds=time.perf_counter() - t0)
            rows.append(r)
            tried = ' '.join(f"{'+' if t['depends'] else '-'}{t['variable']}"
                             for t in r.get('tests', ()))
            print(f"{term:<28} {loop:<12} {r['status']:<17} {str(r['equation']):<16} "
                  f"{r.get('leading', ''):<30} said {r.get('after', '-')} truth {r['truth']} "
                  f"tried [{tried}] {r['seconds']:.0f} s", flush=True)
            if args.json:
                Path(args.json).write_text(json.dumps({'rows': rows}, indent=1, default=str))
    judged = [r for r in rows if r['judged']]
    tests = sum(len(r['tests']) for r in judged)
    print(f'\n{len(rows)} records, {len(judged)} with the right equation (load '
          f'{os.getloadavg()[0]:.1f}); of those:')
    print(f"  variables said that the truth does not depend on: "
          f"{sum(len(r['false']) for r in judged)} in {tests} tests")
    for k in ('missed_before', 'missed_after'):
        print(f"  truth variables {k.replace('_', ' ')} the test: "
              f"{sum(len(r[k]) for r in judged)} of {sum(len(r['truth']) for r in judged)}")
    print(f"  leading terms found not needed beside the variables said or their own but one: "
          f"{sum(r['lead_dropped'] for r in judged)}, dropping a truth variable: "
          f"{sum(len(r['truth_dropped']) for r in judged)}")
    return 0


if __name__ == '__main__':
    sys.exit(main())
