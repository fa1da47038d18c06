"""Reading the files a user names: checked to be regular, readable text, and YAML read the way
engineers write it. Every problem is one line that names the file and the fix.

* A FIFO, a device or a socket in place of a file would block or stream forever:
  refused before it is opened.
* Text must be UTF-8 (ASCII included); a binary file, latin-1 or UTF-16 is named as
  such.
* YAML: numbers written without a dot (``5e-6``, ``1e-8``, ``7e5``) are numbers, as
  YAML 1.2 reads them; PyYAML follows YAML 1.1, where they are strings.
"""
from __future__ import annotations

import re
import stat
from pathlib import Path

import yaml

from .errors import ConfigError, PneumaticServoError

#: [bytes] the largest text file read whole (configs, metadata, tables); a larger one is not
#: what these files are, and reading it could take minutes
MAX_TEXT_BYTES = 64 * 1024 * 1024


def regular_file(path, what: str = 'file', error=PneumaticServoError) -> Path:
    """``path`` if it is an existing regular file, else ``error`` with the reason."""
    path = Path(path)
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        raise error(f'cannot read {what} {path}: no such file; check the path') from None
    except OSError as exc:
        raise error(f'{path}: cannot read the {what} ({exc.strerror})') from None
    if stat.S_ISDIR(mode):
        raise error(f'{path} is a directory, not a {what}')
    if not stat.S_ISREG(mode):
        kind = ('a named pipe (FIFO)' if stat.S_ISFIFO(mode) else
                'a device' if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else
                'a socket' if stat.S_ISSOCK(mode) else 'not a regular file')
        raise error(f'{path} is {kind}, not a {what}; give a regular file')
    return path


def read_text(path, what: str = 'file', error=PneumaticServoError,
              max_bytes: int = MAX_TEXT_BYTES) -> str:
    """The UTF-8 text of regular file ``path``."""
    path = regular_file(path, what, error)
    size = path.stat().st_size
    if size > max_bytes:
        raise error(f'{path}: {size / 1e6:.0f} MB is too large for a {what} (at most '
                    f'{max_bytes / 1e6:.0f} MB); is it the right file?')
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise error(f'{path}: cannot read the {what} ({exc.strerror})') from None
    if data.startswith((b'\xff\xfe', b'\xfe\xff')):
        raise error(f'{path} is UTF-16 text; save the {what} as UTF-8')
    if b'\x00' in data[:4096]:
        raise error(f'{path} is a binary file, not a {what}')
    try:
        return data.decode('utf-8-sig')
    except UnicodeDecodeError:
        raise error(f'{path} is not UTF-8 text (latin-1?); save the {what} as UTF-8') from None


class _Loader(yaml.SafeLoader):
    """SafeLoader that reads ``1e-6``, ``7e5`` and ``+1E3`` as floats (YAML 1.2)."""


_Loader.add_implicit_resolver(
    'tag:yaml.org,2002:float',
    re.compile(r'''^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
                |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
                |\.[0-9_]+(?:[eE][-+]?[0-9]+)?
                |[-+]?\.(?:inf|Inf|INF)
                |\.(?:nan|NaN|NAN))$''', re.X),
    list('-+0123456789.'))


def parse_yaml(text: str, where: str, error=ConfigError):
    """YAML ``text`` (from ``where``) as data; a syntax error is one line with its place."""
    try:
        return yaml.load(text, Loader=_Loader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        place = f' line {mark.line + 1}' if mark else ''
        problem = getattr(exc, 'problem', None) or 'not valid YAML'
        if problem == 'found unhashable key':       # [a, b]: or {a: 1}: where a name belongs
            problem += ' (a list or mapping where a name belongs; write the key as text)'
        raise error(f'{where}{place}: {problem}; fix the YAML') from None


def load_yaml(path, what: str = 'YAML file', error=ConfigError):
    """The data of YAML file ``path`` (checked as :func:`read_text`)."""
    return parse_yaml(read_text(path, what, error), str(path), error)


def bundled(name: str, marker: str, regenerate: str, error=PneumaticServoError) -> Path:
    """``bags/NAME`` of the source tree (or of the working directory), recognised by its file
    ``marker``; ``error`` names the command ``regenerate`` that remakes it if it is missing."""
    for root in (Path(__file__).resolve().parents[1], Path.cwd()):
        path = root / 'bags' / name
        if (path / marker).exists():
            return path
    raise error(f'bundled data bags/{name} not found; regenerate it with {regenerate!r} from '
                'the source tree')
