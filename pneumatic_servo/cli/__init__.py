"""The ``pneumatic-servo`` command: a thin adapter over the core (and the ROS nodes).

Each verb lives in its own module with ``add_parser(subparsers)`` and
``run(args) -> int``. Bad input ends with a one-line reason and exit code 2,
never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys

from ..errors import PneumaticServoError

#: verb -> module in this package
VERBS = ('demo', 'simulate', 'compare', 'verify', 'identify', 'diagnose', 'generate', 'up',
         'record', 'plant', 'controller', 'monitor', 'fleet')


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (the usage is one ``--help`` away)."""

    def error(self, message: str):
        self.exit(2, f'{self.prog}: error: {message}; see {self.prog} --help\n')


def one_line(text: str) -> str:
    """``text`` on one line: a message from a library may span several."""
    return ' '.join(str(text).split())


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command-line parser; with ``only``, just that verb's (importing every verb's
    module costs a second of start-up, for scipy and matplotlib)."""
    parser = Parser(
        prog='pneumatic-servo',
        description='Model, identify and diagnose a pneumatic rotary position servo; run its '
                    'ROS 2 nodes.')
    sub = parser.add_subparsers(dest='verb', metavar='VERB')
    sub.required = True
    for verb in (only,) if only in VERBS else VERBS:
        importlib.import_module(f'{__name__}.{verb}').add_parser(sub)
    return parser


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else [str(a) for a in argv]
    parser = build_parser(argv[0] if argv else None)
    args, extra = parser.parse_known_args(argv)
    if extra:
        print(f'pneumatic-servo {args.verb}: error: unrecognized arguments: {" ".join(extra)}; '
              f'see pneumatic-servo {args.verb} --help', file=sys.stderr)
        return 2
    try:
        return int(args.run(args) or 0)
    except PneumaticServoError as exc:
        print(f'pneumatic-servo {args.verb}: error: {one_line(exc)}', file=sys.stderr)
        return 2
    except (OSError, UnicodeError) as exc:
        # a file the user named cannot be read or written: their input, one line
        print(f'pneumatic-servo {args.verb}: error: {one_line(exc)}; check the path and its '
              'permissions', file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except Exception as exc:  # a bug: one line for the user, the traceback on request
        if os.environ.get('PNEUMATIC_SERVO_DEBUG'):
            raise
        print(f'pneumatic-servo {args.verb}: internal error: {type(exc).__name__}: '
              f'{one_line(exc)}; please report it (PNEUMATIC_SERVO_DEBUG=1 shows the '
              'traceback)', file=sys.stderr)
        return 3


if __name__ == '__main__':
    sys.exit(main())
