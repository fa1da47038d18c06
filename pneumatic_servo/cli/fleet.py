"""``pneumatic-servo fleet SOURCE... [--store ROWS]``: verify, track and diagnose many
recordings on Dask, and warn when a rig degrades.

SOURCE is a directory tree (every rosbag2 directory and static CSV under it), a glob, or a
manifest CSV with a path column (and optionally rig). Every recording is verified against
the model; --track E1,E2 also fits those effects (with --free base parameters) per
recording, and an alert is raised where a tracked parameter of a rig trends or steps
beyond its uncertainty (false-alarm rate 1 % per rig and parameter); --diagnose runs the
full diagnosis per recording. Rows stream to the --store file as they finish; a rerun
skips the recordings already there (keyed by content, config and options). Without
--store the rows go beside the --json file (NAME_rows.jsonl), else into the --report
directory, else into fleet_rows.jsonl here; the first line printed says where.
Runs on an embedded Dask LocalCluster (one worker per core), or on an existing cluster
with --scheduler. Exit status: 0 every recording read and passed, 1 one failed
verification or could not be read (its row says why), 2 bad input.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from ..jsonable import dumps
from ..text import comma_list
from .options import number, output_dir, output_file
from .verify import add_limit_arguments


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('fleet', help='check many recordings on Dask; alert when a rig '
                       'degrades', description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('sources', nargs='+', metavar='SOURCE',
                   help='directory tree, glob or manifest CSV of recordings')
    p.add_argument('--store', type=output_file, metavar='ROWS.jsonl',
                   help='row store: results stream here; a rerun resumes from it (default: '
                   f'beside --json as NAME{STORE_SUFFIX}, else in --report, else '
                   f'./{STORE_NAME})')
    p.add_argument('--config', metavar='CFG', help='model config YAML (default: the paper\'s)')
    p.add_argument('--track', metavar='E1,E2', type=comma_list, default=(),
                   help='effects to fit per recording and watch for change')
    p.add_argument('--free', metavar='K1,K2', type=comma_list, default=(),
                   help='base parameters (owner.name) fitted with the tracked effects')
    p.add_argument('--diagnose', action='store_true', help='run the full diagnosis per '
                   'recording (slow: minutes each)')
    add_limit_arguments(p)
    p.add_argument('--mode', choices=('open_loop', 'k_step'), default='open_loop',
                   help='prediction view whose errors are verified (default open_loop)')
    p.add_argument('--json', metavar='PATH', type=output_file, help='write every row and the '
                   'alerts as JSON')
    p.add_argument('--table', metavar='PATH', type=output_file,
                   help='write the table as .parquet or .csv')
    p.add_argument('--report', metavar='DIR', type=output_dir, help='write the fleet page '
                   '(fleet.html) here')
    p.add_argument('--scheduler', metavar='ADDRESS', help='run on this Dask scheduler '
                   '(default: an embedded local cluster)')
    p.add_argument('--workers', type=number(1, 1024, integer=True), metavar='N',
                   help='local workers (default: one per core)')
    p.add_argument('--no-progress', action='store_true', help='no progress bar')
    p.set_defaults(run=run)
    return p


#: the row store's name when --store is not given: beside --json (its stem + suffix), in
#: --report, or in the current directory
STORE_SUFFIX, STORE_NAME = '_rows.jsonl', 'fleet_rows.jsonl'


def default_store(args) -> tuple[Path, str]:
    """(row store, where it is and why) when --store is not given: beside the --json file,
    else in the --report directory, else in the current directory."""
    if args.json:
        json_path = Path(args.json)
        return json_path.with_name(json_path.stem + STORE_SUFFIX), 'beside --json'
    if args.report:
        return Path(args.report) / STORE_NAME, 'in the --report directory'
    return Path(STORE_NAME), 'in the current directory'


def _store(args) -> Path:
    """The row store: --store, or :func:`default_store` (checked as --store is, and said)."""
    from ..errors import ConfigError
    if args.store:
        return Path(args.store)
    path, why = default_store(args)
    if path.parent.is_dir():  # a --report directory not made yet takes any name
        try:
            output_file(str(path))
        except argparse.ArgumentTypeError as exc:
            raise ConfigError(f'the row store (no --store given: {why}): {exc}; name one '
                              'with --store') from None
    print(f'row store: {path} ({why}; a rerun resumes from it; --store puts it elsewhere)',
          flush=True)
    return path


def run(args) -> int:
    from ..analysis.compare import resolve_config
    from ..errors import ConfigError
    from ..fleet import FleetOptions, TaskOptions, find_recordings, run_fleet
    from ..fleet.report import write_report
    from ..fleet.cluster import parameter_names
    from ..fleet.table import write_table
    from .verify import limits_from
    if args.table and Path(args.table).suffix.lower() not in ('.parquet', '.csv'):
        raise ConfigError(f'--table {args.table}: name a .parquet or a .csv file')
    config = resolve_config(args.config)
    task = TaskOptions(track=args.track, free=args.free,
                       diagnose=args.diagnose, mode=args.mode, limits=limits_from(args))
    probe = resolve_config(config, list(task.track))  # unknown effects or keys: fail now
    for key in task.free:
        probe.get(key)
    recordings = find_recordings(args.sources)
    result = run_fleet(recordings, config, FleetOptions(
        _store(args), args.scheduler, args.workers, not args.no_progress, task))
    if args.json:
        Path(args.json).write_text(dumps(result.to_json(), indent=1))
    if args.table:
        write_table(result.rows, args.table)
    if args.report:
        write_report(args.report, result.rows, result.alerts,
                     parameter_names(config, task.track))
    _summary(result)
    return 1 if result.failed else 0


def _summary(result) -> None:
    from ..fleet.task import diagnosis_text
    rows = result.rows
    errors = [r for r in rows if r.status == 'error']
    failed = [r for r in rows if r.passed is False]
    print(f'{len(rows)} recordings of {len({r.rig for r in rows})} rigs '
          f'({result.computed} checked now, {len(rows) - result.computed} from the store): '
          f'{len(rows) - len(errors) - len(failed)} passed, {len(failed)} failed, '
          f'{len(errors)} errors')
    for r in errors:
        print(f'  error  {r.path}: {r.error}')
    for r in failed:
        print(f'  FAIL   {r.path}')
    for r in rows:  # with --diagnose: every recording whose model misses something
        if r.diagnosis and r.diagnosis['status'] != 'consistent':
            print(f'  model  {r.path}: {diagnosis_text(r.diagnosis)}')
    print(f'{len(result.alerts)} alerts' + (':' if result.alerts else ''))
    for a in result.alerts:
        print(f'  ALERT  {a.text}')
