"""Does the record the tool asks for next let the dependence test say what it missed?

On the records of ``bench_dependence.py`` (generic corrections hidden at a rig's size, so
the variables each depends on are known), each record whose best correction is in the right
equation and misses a truth variable is diagnosed; the design
:func:`~pneumatic_servo.synth.plan.next_designs` ranks first, simulated on the fitted
model, is then generated with the truth hidden (through the record's own sensors, the
rig's paper parameters), and the two records are diagnosed together. Printed per case: the
variable named, the design, the share it was to move the variable over and the share the
records moved it over before, the variables said before and after against the truth.

The planner names the variable the records moved least apart from those the correction
depends on, which need not be the one the truth adds: the count of truth variables said
after is the figure, with the variables wrongly said beside it.

Run: ``.venv/bin/python benchmarks/bench_next_record.py [--only TERM] [--json PATH]``.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def planned_record(found, hidden: dict, rec):
    """(the first design :func:`~pneumatic_servo.synth.plan.next_designs` plans for
    ``found``, its record generated with the ``hidden`` effects through ``rec``'s sensors),
    or None where no design is planned."""
    from pneumatic_servo.synth.designs import make_experiment
    from pneumatic_servo.synth.hidden import hidden_config
    from pneumatic_servo.synth.plan import next_designs
    plans = next_designs(found)
    if not plans:
        return None
    return plans[0], make_experiment(hidden_config(hidden), plans[0].design,
                                     seed=rec.seed + 100, sensors=rec.sensors())


def case(equation: str, term: str, value: float, label: str, rec) -> dict | None:
    """The case of ``term`` hidden in ``rec``: None where the first diagnosis is not in the
    right equation or misses nothing."""
    from pneumatic_servo.analysis.diagnosis import diagnose
    from pneumatic_servo.effects.corrections import BY_EQUATION, coefficient_name
    from pneumatic_servo.effects.terms import BY_NAME
    from pneumatic_servo.synth.varied import make_record
    hidden = {BY_EQUATION[equation].name: {coefficient_name(term): value}}
    rec = replace(rec, effects=hidden)
    truth = set(BY_NAME[term].depends_on)
    first = make_record(rec)
    before = diagnose([first])
    best = before.discovered[0] if before.discovered else None
    if best is None or best.equation != equation or truth <= set(best.depends_on):
        return None
    made = planned_record(best, hidden, rec)
    out = {'term': term, 'record': label, 'equation': equation, 'truth': sorted(truth),
           'before': list(best.depends_on), 'plan': made[0].to_json() if made else None}
    if made is None:
        return out
    after = diagnose([first, made[1]])
    # judged in the right equation only: a variable said of another equation is not the truth's
    best_after = next((d for d in after.discovered[:1] if d.equation == equation), None)
    out.update(equation_after=best_after.equation if best_after else None,
               after=list(best_after.depends_on) if best_after else [],
               tests_after=[t.to_json() for t in best_after.dependence] if best_after else [])
    return out


def main(argv=None) -> int:
    from bench_dependence import TRUTHS, records
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--only', help='truth terms, comma-separated')
    ap.add_argument('--json', help='write every case as JSON')
    args = ap.parse_args(argv)
    rows = []
    for index, (equation, term, value) in enumerate(TRUTHS):
        if args.only and term not in args.only.split(','):
            continue
        for label, rec in records(index):
            t0 = time.perf_counter()
            row = case(equation, term, value, label, rec)
            if row is None:
                continue
            rows.append(row)
            plan = row['plan']
            said = ('no design moves it further' if plan is None else
                    f"{plan['design']} to move {plan['variable']} over {100 * plan['share']:.0f}"
                    f" % (was {100 * plan['now']:.0f} %): said after {row['after']} "
                    f"({row['equation_after']})")
            print(f"{term:<26} {label:<12} truth {row['truth']} before {row['before']}; "
                  f"{said} {time.perf_counter() - t0:.0f} s", flush=True)
            if args.json:
                Path(args.json).write_text(json.dumps({'rows': rows}, indent=1))
    planned = [r for r in rows if r['plan']]

    def count(key, wrong=False):
        """Truth variables said (or, ``wrong``, others said) in the rows' ``key`` sets."""
        return sum(len(set(r[key]) - set(r['truth']) if wrong else set(r[key]) & set(r['truth']))
                   for r in planned)
    print(f"\n{len(rows)} records missed a truth variable, {len(planned)} with a design "
          f"(load {os.getloadavg()[0]:.1f}). Truth variables said, of "
          f"{sum(len(r['truth']) for r in planned)}: {count('before')} before, "
          f"{count('after')} with the design's record; variables said that the truth does not "
          f"depend on: {count('before', True)} before, {count('after', True)} with it")
    return 0


if __name__ == '__main__':
    sys.exit(main())
