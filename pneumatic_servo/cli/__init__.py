"""The ``pneumatic-servo`` command: a thin adapter over the core (and the ROS nodes).

Each verb lives in its own module with ``add_parser(subparsers)`` and
``run(args) -> int``. Bad input ends with a one-line reason and exit code 2,
never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys

from ..errors import PneumaticServoError

#: verb -> module in this package
VERBS = ('demo', 'simulate', 'compare', 'verify', 'identify', 'diagnose', 'generate', 'up',
         'record', 'plant', 'controller')


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='pneumatic-servo',
        description='Model, identify and diagnose a pneumatic rotary position servo; run its '
                    'ROS 2 nodes.')
    sub = parser.add_subparsers(dest='verb', metavar='VERB')
    sub.required = True
    for verb in VERBS:
        try:
            module = importlib.import_module(f'{__name__}.{verb}')
        except ModuleNotFoundError as exc:
            if exc.name and exc.name.startswith(__name__):
                continue  # verb not built yet
            raise
        module.add_parser(sub)
    return parser



def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except PneumaticServoError as exc:
        print(f'pneumatic-servo {args.verb}: error: {exc}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == '__main__':
    sys.exit(main())
