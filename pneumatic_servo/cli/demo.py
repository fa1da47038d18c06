"""``pneumatic-servo demo``: the main job. Simulate the paper's experiments, write the plots
and a summary (``summary.json`` and a printed table).

The demo is a list of stages, run in order:

1. ``paper_figures``: the paper's experiments and the switchable parts (figures);
2. ``closed_loop``: a closed loop over DDS (``pneumatic_servo.ros.closed_loop_demo``);
3. ``diagnosis``: the model-discrepancy workflow (``pneumatic_servo.workflow``);
4. ``fleet``: the bundled synthetic fleet on a local Dask cluster (``pneumatic_servo.fleet``).
"""
from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional

from ..errors import ConfigError, PneumaticServoError
from ..jsonable import dumps
from ..workflow import run_discrepancy_demo
from .options import output_dir


@dataclass(frozen=True)
class Stage:
    """One step of the demo: ``run(out_dir, config, log) -> dict`` and the flag that skips it."""

    name: str
    title: str
    run: Callable
    skip_flag: Optional[str] = None


def _paper_figures(out_dir: Path, config, log) -> dict:
    from ..synth.paper_figures import run_paper_figures
    result = run_paper_figures(out_dir / 'figures', config, log=log)
    result['status'] = 'ok' if result['charge_discharge']['all_hold'] and result['finite'] \
        else 'failed'
    return result


def _closed_loop(out_dir: Path, config, log) -> dict:
    from ..ros.closed_loop_demo import run_closed_loop_demo  # rclpy is loaded only for this stage
    return run_closed_loop_demo(out_dir / 'closed_loop')


def _diagnosis(out_dir: Path, config, log) -> dict:
    return run_discrepancy_demo(out_dir / 'diagnosis')


def _fleet(out_dir: Path, config, log) -> dict:
    from ..fleet.bundled import run_fleet_demo  # Dask is loaded only for this stage
    return run_fleet_demo(out_dir / 'fleet', log)


STAGES = (
    Stage('paper_figures', "paper's experiments and switchable parts", _paper_figures),
    Stage('closed_loop', 'closed loop over DDS', _closed_loop, 'skip_ros'),
    Stage('diagnosis', 'model-discrepancy workflow', _diagnosis, 'skip_diagnosis'),
    Stage('fleet', 'a fleet of rigs on Dask: verify, track, alert', _fleet, 'skip_fleet'),
)


def add_parser(sub) -> argparse.ArgumentParser:
    """Register the ``demo`` verb."""
    p = sub.add_parser(
        'demo', help="simulate the paper's experiments; write plots and a summary",
        description="Simulate the paper's experiments (charge/discharge, 2 Hz sine, static "
                    'tests, switchable parts), then the closed loop over DDS and the '
                    'discrepancy workflow where built. Writes PNG figures, summary.json and '
                    'prints a table.')
    p.add_argument('--out', default='out', metavar='DIR', type=output_dir,
                   help='output directory (default: out)')
    p.add_argument('--config', metavar='CFG',
                   help="model config YAML (default: the paper's model, as in "
                        'config/paper_rig.yaml)')
    p.add_argument('--skip-ros', action='store_true', help='skip the closed loop over DDS')
    p.add_argument('--skip-diagnosis', action='store_true',
                   help='skip the model-discrepancy workflow')
    p.add_argument('--skip-fleet', action='store_true', help='skip the fleet on Dask')
    p.set_defaults(run=run)
    return p


def _out_dir(path: str) -> Path:
    out = Path(path)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ConfigError(f'cannot create output directory {out}: {exc.strerror}; '
                          'choose another --out') from None
    return out


def run(args) -> int:
    """Run every stage; 0 if all that ran succeeded, 1 otherwise."""
    from ..model import ModelConfig  # heavy imports only when the verb runs
    config = ModelConfig.load(args.config) if args.config else ModelConfig.paper()
    out = _out_dir(args.out)
    summary = {'out_dir': str(out), 'config': args.config or 'paper (built-in)', 'stages': {}}
    for stage in STAGES:
        summary['stages'][stage.name] = _run_stage(stage, args, out, config)
    path = out / 'summary.json'
    path.write_text(dumps(summary, indent=2) + '\n')
    print_summary(summary)
    print(f'\nsummary: {path}')
    failed = [n for n, s in summary['stages'].items() if s.get('status') == 'failed']
    return 1 if failed else 0


def _run_stage(stage: Stage, args, out: Path, config) -> dict:
    print(f'== {stage.name}: {stage.title}', flush=True)
    if stage.skip_flag and getattr(args, stage.skip_flag, False):
        print(f'   skipped: --{stage.skip_flag.replace("_", "-")}')
        return {'status': 'skipped', 'reason': f'--{stage.skip_flag.replace("_", "-")}'}
    start = time.perf_counter()
    try:
        result = dict(stage.run(out, config, lambda line: print(f'   {line}', flush=True)))
    except ImportError as exc:
        print(f'   skipped: cannot import what it needs ({exc})')
        return {'status': 'skipped', 'reason': f'cannot import: {exc}'}
    except PneumaticServoError as exc:
        print(f'   failed: {exc}')
        return {'status': 'failed', 'reason': str(exc)}
    result.setdefault('status', 'ok')
    result['seconds'] = round(time.perf_counter() - start, 2)
    return result


# ----------------------------------------------------------------------------- printing
def _mpa(pa: float) -> str:
    return f'{pa * 1e-6:.4f}'


def _yes(flag: bool) -> str:
    return 'yes' if flag else 'NO'


def _paper_rows(cd: dict) -> list[tuple[str, str, str]]:
    return [
        ('p_a rises', _yes(cd['p_a_rises']),
         f'{_mpa(cd["p_a_at_step_pa"])} -> {_mpa(cd["p_a_final_pa"])} MPa'),
        ('p_a stays below supply', _yes(cd['p_a_stays_below_supply']),
         f'max {_mpa(cd["p_a_max_pa"])} < supply {_mpa(cd["supply_pa"])} MPa'),
        ('p_b falls', _yes(cd['p_b_falls']),
         f'{_mpa(cd["p_b_at_step_pa"])} -> {_mpa(cd["p_b_final_pa"])} MPa'),
        ('p_b stays above atmosphere', _yes(cd['p_b_stays_above_atmosphere']),
         f'min {_mpa(cd["p_b_min_pa"])} > atm. {_mpa(cd["atmospheric_pa"])} MPa'),
        ('T_a jumps', _yes(cd['t_a_jumps']), f'peak {cd["t_a_peak_k"]:.1f} K'),
        ('T_a recovers', _yes(cd['t_a_recovers']),
         f'final {cd["t_a_final_k"]:.2f} K (room {cd["room_temperature_k"]:.2f} K)'),
        ('T_b dips', _yes(cd['t_b_dips']), f'lowest {cd["t_b_lowest_k"]:.1f} K'),
        ('T_b recovers', _yes(cd['t_b_recovers']), f'final {cd["t_b_final_k"]:.2f} K'),
    ]


def _table(header: tuple[str, ...], rows: list[tuple[str, ...]]) -> str:
    widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
    line = (lambda r: '| ' + ' | '.join(str(c).ljust(w) for c, w in zip(r, widths)) + ' |')
    return '\n'.join([line(header), '|' + '|'.join('-' * (w + 2) for w in widths) + '|']
                     + [line(r) for r in rows])


def _print_paper(res: dict) -> None:
    cd = res['charge_discharge']
    print('\nCharge/discharge, pistons held, 0.6 MPa gauge, 5 V -> 5.5 V (Figs 22-23):')
    print(_table(('paper claim', 'holds', 'simulated'), _paper_rows(cd)))
    s = res['sine']
    deg = 180.0 / math.pi
    print(f'\nSine 5 +/- 0.35 V at 2 Hz (Figs 24-26), from {s["window_start_s"]:g} s: angle '
          f'{s["angle_rad_min"] * deg:.1f}-{s["angle_rad_max"] * deg:.1f} deg, p_a '
          f'{_mpa(s["p_a_pa_min"])}-{_mpa(s["p_a_pa_max"])} MPa, p_b '
          f'{_mpa(s["p_b_pa_min"])}-{_mpa(s["p_b_pa_max"])} MPa')
    rows = []
    for part, variants in res['variants'].items():
        for label, v in variants.items():
            if part == 'friction':
                rows.append((part, label, f'angle p-p {v["angle_peak_to_peak_deg"]:.2f} deg'))
            else:
                rows.append((part, label, f'p_a final {_mpa(v["p_a_final_pa"])} MPa, p_b final '
                             f'{_mpa(v["p_b_final_pa"])} MPa, T_a peak {v["t_a_peak_k"]:.1f} K, '
                             f'T_b lowest {v["t_b_lowest_k"]:.1f} K'))
    print('\nSwitchable parts:')
    print(_table(('part', 'variant', 'result'), rows))
    print('\nFigures:')
    for name, path in res['figures'].items():
        print(f'  {name}: {path}')


def print_summary(summary: dict) -> None:
    """Print the stage table, then each stage's own results."""
    rows = []
    for name, res in summary['stages'].items():
        rows.append((name, res.get('status', '?'), str(res.get('seconds', '')),
                     str(res.get('reason', ''))))
    print()
    print(_table(('stage', 'status', 'seconds', 'note'), rows))
    paper = summary['stages'].get('paper_figures', {})
    if 'charge_discharge' in paper:
        _print_paper(paper)
    for name, res in summary['stages'].items():
        if name == 'paper_figures' or res.get('status') == 'skipped':
            continue
        scalars = [(k, str(v)) for k, v in res.items()
                   if isinstance(v, (int, float, str, bool)) and k not in ('status', 'seconds')]
        if scalars:
            print(f'\n{name}:')
            print(_table(('result', 'value'), scalars))
