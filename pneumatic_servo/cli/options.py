"""Argument types of the verbs: every number checked to be finite and in range, every output
path checked to be writable before any work is done.

Each is an ``argparse`` ``type=``: a bad value ends the command at once with one line
naming the option, the value and what to give instead (exit 2).
"""
from __future__ import annotations

import argparse
import math
import os
import tempfile
from pathlib import Path


def number(lo: float | None = None, hi: float | None = None, *, above: bool = False,
           integer: bool = False, infinite_ok: bool = False, unit: str = ''):
    """A number in [lo, hi] (``above``: strictly above ``lo``), finite unless
    ``infinite_ok`` allows +inf, an integer if ``integer``."""
    def parse(text: str):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            kind = 'a whole number' if integer else 'a number'
            raise argparse.ArgumentTypeError(f'{text!r} is not {kind}') from None
        if math.isnan(value) or (math.isinf(value) and not (infinite_ok and value > 0)):
            raise argparse.ArgumentTypeError(f'{text!r}: give a finite number')
        low_ok = lo is None or (value > lo if above else value >= lo)
        if not low_ok or (hi is not None and value > hi):
            rng = ('(' if above else '[') + f'{lo:g}, ' + (f'{hi:g}]' if hi is not None
                                                            else 'inf)')
            raise argparse.ArgumentTypeError(f'{text} is outside {rng} {unit}'.rstrip())
        return value
    return parse


#: common kinds
positive_seconds = number(0.0, above=True, unit='s')
positive_seconds_or_inf = number(0.0, above=True, infinite_ok=True, unit='s')
seconds = number(0.0, unit='s')
fraction = number(0.0, 1.0)


def _can_create_in(directory: Path) -> bool:
    """True if a file can really be created in ``directory`` (tried: permission bits say
    nothing for root, nor for read-only mounts)."""
    try:
        with tempfile.NamedTemporaryFile(dir=directory):
            return True
    except OSError:
        return False


def output_file(text: str) -> str:
    """A file to write: its directory must exist and take a new file, it must not be a
    directory itself, and an existing file must be writable (checked now, not after the
    work)."""
    path = Path(text)
    if path.is_dir():
        raise argparse.ArgumentTypeError(f'{text} is a directory; give a file name')
    parent = path.parent if str(path.parent) else Path('.')
    if not parent.is_dir():
        raise argparse.ArgumentTypeError(f'directory {parent} does not exist; create it first')
    if not _can_create_in(parent) or (path.exists() and not os.access(path, os.W_OK)):
        raise argparse.ArgumentTypeError(f'{text} cannot be written (permission denied); '
                                         'choose another place')
    return text


def output_dir(text: str) -> str:
    """A directory to write into (created if missing): it must not be a file, and the
    nearest existing parent must take new files."""
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f'{text} is a file; give a directory')
    probe = path
    while not probe.exists():
        probe = probe.parent if str(probe.parent) != str(probe) else Path('.')
    if not probe.is_dir() or not _can_create_in(probe):
        raise argparse.ArgumentTypeError(f'{text} cannot be written (permission denied in '
                                         f'{probe}); choose another place')
    return text


def new_path(text: str) -> str:
    """A path to create (a bag directory, a table): it must not exist yet."""
    if Path(text).exists():
        raise argparse.ArgumentTypeError(f'{text} exists; choose a new path')
    output_dir(str(Path(text).parent) if str(Path(text).parent) else '.')
    return text
