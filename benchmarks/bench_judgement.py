"""False alarms and power of the diagnosis's statements (issue 15), on records unlike the
hidden-effect sets the project was developed on (``pneumatic_servo.synth.varied``).

* **False alarms**: clean records drawn over every axis (250 Hz / 500 Hz / 1 kHz; three
  sensor grades and two encoders; PID at several gains and the model-based controller;
  open-loop sines, chirps and steps, closed-loop steps and sines; 10-60 s; generated with
  the predictor's integrator, a tighter tolerance, or fixed-step RK4). A false alarm is any
  status but ``consistent``. Target: at most 5 %.
* **Power**: catalogue effects hidden at five sizes (fractions of their ``example`` values)
  in closed-loop records: how often the status is not ``consistent``, and how often it is
  ``explained`` with the right name.

Prints each record as it is diagnosed, then the rates beside their targets, with the load.
Run: ``.venv/bin/python benchmarks/bench_judgement.py [--clean N] [--power]``.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

FALSE_ALARM_TARGET = 0.05
EFFECTS = ('external_leakage', 'piston_seal_leakage', 'external_load_torque',
           'valve_null_offset')
SIZES = (0.1, 0.2, 0.4, 0.7, 1.0)


def _diagnose(rec):
    from pneumatic_servo.analysis.diagnosis import diagnose
    from pneumatic_servo.synth.varied import make_record
    t0 = time.perf_counter()
    result = diagnose([make_record(rec)])
    base = result.trial.departures(result.baseline.score).tests['overall']
    print(f'  {rec.label:<72} {result.status:<17} {result.verdict:<22} '
          f'{base.ratio:5.2f} x floor  {time.perf_counter() - t0:5.0f} s', flush=True)
    return result


def false_alarms(count: int) -> float:
    from pneumatic_servo.synth.varied import clean_study
    print(f'false alarms on {count} clean records of varied designs:')
    alarms = sum(_diagnose(rec).status != 'consistent' for rec in clean_study(count))
    rate = alarms / count
    print(f'false alarms: {alarms} of {count} = {100 * rate:.1f} % '
          f'(target <= {100 * FALSE_ALARM_TARGET:.0f} %)')
    return rate


def power() -> None:
    from pneumatic_servo.synth.hidden import example_values
    from pneumatic_servo.synth.varied import Record
    print('power: closed-loop steps, PID, 500 Hz, 10 s, industrial sensors')
    for effect in EFFECTS:
        row = []
        for i, size in enumerate(SIZES):
            values = {k: v * size for k, v in example_values(effect).items()}
            rec = Record('closed_steps', 500.0, 10.0, effects={effect: values}, seed=50 + i)
            result = _diagnose(rec)
            row.append((result.status != 'consistent',
                        result.status == 'explained' and result.verdict == effect))
        print(f'{effect:<24} detected ' + ' '.join(f'{s:g}:{"yes" if d else "no"}'
                                                  for s, (d, _) in zip(SIZES, row))
              + '  explained by name ' + ' '.join(f'{s:g}:{"yes" if e else "no"}'
                                                  for s, (_, e) in zip(SIZES, row)))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('--clean', type=int, default=50, help='clean records (default 50)')
    p.add_argument('--power', action='store_true', help='also the power study')
    args = p.parse_args(argv)
    print(f'load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores')
    if args.clean:
        false_alarms(args.clean)
    if args.power:
        power()
    print(f'load average {os.getloadavg()[0]:.1f}')
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
