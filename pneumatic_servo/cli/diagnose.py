"""``pneumatic-servo diagnose BAG [BAG ...]``: where the model fails and which physical effect
is missing.

Every candidate effect (the catalogue and any registered effect of your own)
is added to the model, fitted on alternate blocks of the data and scored on
the others. The verdict is the effect that cuts the held-out residual the
most with plausible values, or ``none``. ``--apply OUT.yaml`` writes the
model with the winner added and fitted; run diagnose again on OUT.yaml to
find the next effect.

JSON (``--json``): ``{"verdict": NAME or "none", "ranking": [{"effect", "params",
"error_reduction", ...}, ...], "ladder": [...], "where": {...}, ...}``.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from ..analysis.diagnosis import DiagnoseOptions, apply, diagnose, text
from ..analysis.diagnosis.emit import class_name, effect_source
from ..analysis.diagnosis.options import FALSE_ALARM_RATE, REPLICAS
from ..analysis.diagnosis_report import write_diagnosis_report
from ..errors import ConfigError
from ..io import read_experiment
from ..jsonable import dumps
from ..model.config import ModelConfig
from ..prediction import DIAGNOSIS_HORIZON_S
from ..synth.plan import next_designs
from ..text import comma_list
from .options import fraction, number, output_dir, output_file, positive_seconds


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('diagnose', help='find which physical effect the model is missing',
                       description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('bags', nargs='+', metavar='BAG',
                   help='rosbag2 directories (sqlite3 or MCAP) and/or static CSV tables, '
                        'diagnosed jointly')
    p.add_argument('--config', metavar='CFG', help="model config YAML (default: the paper's)")
    p.add_argument('--validate-on', nargs='+', metavar='OTHER', default=[],
                   help='other experiments (any circuit) on which every candidate and the '
                        'ladder are scored too: is what DATA shows confirmed elsewhere?')
    p.add_argument('--json', metavar='PATH', type=output_file, help='write the diagnosis as JSON')
    p.add_argument('--report', metavar='DIR', type=output_dir,
                   help='write an HTML report with plots into DIR')
    p.add_argument('--apply', metavar='OUT.yaml', type=output_file,
                   help='write the model with the winning effect added and fitted')
    p.add_argument('--emit-effect', metavar='PATH.py', type=output_file,
                   help='write the best discovered correction as a user effect class (a '
                        'Python file to rename and use as PATH.py:Class)')
    p.add_argument('--free', metavar='KEY,...', type=comma_list, default=(),
                   help="base parameters refitted with every candidate, e.g. "
                        "'stribeck_friction.coulomb_friction_n'")
    p.add_argument('--effects', metavar='E1,E2', type=comma_list, default=(),
                   help='candidate effects to try (default: all registered)')
    p.add_argument('--horizon', type=positive_seconds, default=None, metavar='S',
                   help='prediction horizon [s] from each measured state (default '
                        f'{DIAGNOSIS_HORIZON_S:g})')
    p.add_argument('--false-alarm-rate', type=fraction, default=FALSE_ALARM_RATE,
                   metavar='F', help='probability that a record of a correct model is called '
                   f'anything but consistent (default {FALSE_ALARM_RATE:g})')
    p.add_argument('--replicas', type=number(4, 1000, integer=True), default=REPLICAS,
                   metavar='N', help='replicas of the records simulated to measure their '
                   'prediction floor: more make the departure test more powerful at the '
                   f'same false-alarm rate, and the run slower (default {REPLICAS})')
    p.add_argument('--quiet', action='store_true', help='print only the verdict')
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    experiments = [read_experiment(p) for p in args.bags]
    config = ModelConfig.load(args.config) if args.config else ModelConfig.paper()
    if not 0.0 < args.false_alarm_rate < 1.0:
        raise ConfigError('--false-alarm-rate must be between 0 and 1, e.g. 0.01')
    options = DiagnoseOptions(horizon_s=args.horizon or DIAGNOSIS_HORIZON_S,
                              false_alarm_rate=args.false_alarm_rate,
                              replicas=args.replicas)
    say = (lambda *a: None) if args.quiet else print

    def progress(c):
        say(f'  tried {c.effect:<24} held-out error {100 * c.error_reduction:+6.1f} % '
            f'({c.seconds:.1f} s)')

    others = [read_experiment(p) for p in args.validate_on]
    result = diagnose(experiments, config, list(args.effects), list(args.free), options,
                      progress=progress, validate_on=others)
    # the designs that would test the first correction further: simulated only where shown
    shown = not args.quiet or args.json or args.report
    plans = next_designs(result.discovered[0]) if result.discovered and shown else []
    if not args.quiet:
        text.print_where(result, say)
        text.print_floor(result, say)
        text.print_ranking(result, say)
        text.print_discovered(result, say)
        print_next_designs(plans, say)
        text.print_ladder(result.ladder, say)
    text.print_verdict(result)
    if args.json:
        Path(args.json).write_text(dumps({**result.to_json(),
                                          'next_designs': [d.to_json() for d in plans]},
                                         indent=1))
        say(f'wrote {args.json}')
    if args.apply:
        if result.added is None:
            print(f'nothing to apply (status {result.status}); {args.apply} not written')
        else:
            apply(result).save(args.apply, header=text.apply_header(result))
            print(f'wrote {args.apply} (model + {result.added.effect})')
    if args.emit_effect:
        emit_effect(result, args.emit_effect)
    if args.report:
        applied = args.apply if args.apply and result.added is not None else None
        emitted = args.emit_effect if args.emit_effect and result.discovered else None
        say(f'wrote {write_diagnosis_report(args.report, result, applied, emitted, plans)}')
    return 0


def print_next_designs(plans, out=print) -> None:
    """The designs that would test the best correction's dependence further
    (:func:`~pneumatic_servo.synth.plan.next_designs`)."""
    if plans:
        out('records that would test further what the first correction depends on (designs '
            'of `pneumatic-servo generate --list`, simulated on the fitted model):')
        for d in plans:
            out(f'  {d.words()}')


def emit_effect(result, path: str) -> None:
    """Write the best discovered correction as a user effect (or say there is none)."""
    term = result.added if result.added in result.discovered else (
        result.discovered[0] if result.discovered else None)
    if term is None:
        print(f'no discovered correction to emit (status {result.status}); {path} not written')
        return
    Path(path).write_text(effect_source(term, result.experiments))
    print(f'wrote {path}: {class_name(term.equation)}, {term.interpretation}; use it as '
          f'{path}:{class_name(term.equation)}')
