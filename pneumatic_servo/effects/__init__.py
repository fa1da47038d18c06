"""Registry of model components by name: the paper's parts and the effect catalogue.

A user adds an effect without editing the package by subclassing
:class:`Component` and either calling :func:`register`, declaring an entry
point in group ``pneumatic_servo.effects``, or naming it in a config file as
``"package.module:ClassName"``.
"""
from __future__ import annotations

import difflib
import importlib
import importlib.util
import sys
from contextlib import contextmanager
from importlib.metadata import entry_points
from pathlib import Path

from .._jit import is_compiled, njit
from ..errors import ConfigError
from .base import STAGES, Component, Param, State
from .catalogue import CATALOGUE
from .corrections import CORRECTIONS
from .paper import PAPER_COMPONENTS, PAPER_DEFAULTS

__all__ = ['Component', 'Param', 'State', 'register', 'registered', 'get', 'names',
           'CATALOGUE_NAMES', 'PAPER_DEFAULTS']

_REGISTRY: dict[str, type[Component]] = {}
CATALOGUE_NAMES = tuple(c.name for c in CATALOGUE)
#: classes imported by "module:Class" name, under that name (registered under their own)
_IMPORTED: dict[str, type[Component]] = {}
_entry_points_loaded = False


def register(cls: type[Component]) -> type[Component]:
    """Register a component class under ``cls.name``; usable as a decorator.

    Hooks written as plain Python functions are compiled here (with numba, when
    it is on), so a user's effect needs no decorator of its own.
    """
    if not (isinstance(cls, type) and issubclass(cls, Component)) or not cls.name:
        raise ConfigError(f'{cls!r} is not a Component subclass with a name; subclass '
                          'pneumatic_servo.effects.Component and set name')
    if cls.slot is None and not (cls.params or cls.states or any(
            cls.hook(s) for s in STAGES)) \
            and cls.input_delay_s is Component.input_delay_s \
            and cls.output_delay_s is Component.output_delay_s and cls.sensor_error is None:
        raise ConfigError(f'effect {cls.name!r} adds nothing: give it a hook, a delay or a '
                          'sensor error')
    for stage in STAGES:
        hook = cls.hook(stage)  # inherited too: a subclass of an unregistered effect
        if hook is not None and not is_compiled(hook):
            setattr(cls, stage, njit(hook))
    _REGISTRY[cls.name] = cls
    return cls


@contextmanager
def registered(cls: type[Component]):
    """``cls`` registered for the block and unregistered after it: to try an effect in a
    session without leaving it a candidate of every later diagnosis."""
    register(cls)
    try:
        yield cls
    finally:
        _REGISTRY.pop(cls.name, None)


def _load_entry_points() -> None:
    global _entry_points_loaded
    if _entry_points_loaded:
        return
    _entry_points_loaded = True
    for ep in entry_points(group='pneumatic_servo.effects'):
        try:
            register(ep.load())
        except Exception as exc:  # a broken plug-in must not break the package
            raise ConfigError(f'entry point {ep.name!r} ({ep.value}) failed to load: {exc}')


def _import_module(module: str):
    """A module by dotted name, or from a ``.py`` file path (a file that ``diagnose
    --emit-effect`` wrote)."""
    if module.endswith('.py'):
        path = Path(module)
        spec = importlib.util.spec_from_file_location(path.stem, path)
        if spec is None or not path.is_file():
            raise ImportError(f'no Python file {module}')
        mod = importlib.util.module_from_spec(spec)
        sys.modules[path.stem] = mod
        spec.loader.exec_module(mod)
        return mod
    return importlib.import_module(module)


def get(name: str) -> type[Component]:
    """The component class registered as ``name``, or one imported on demand from
    ``"package.module:Class"`` or ``"path/to/file.py:Class"``; a class so imported keeps
    that name in ``source``, so that a saved config imports it again."""
    if name in _REGISTRY:
        return _REGISTRY[name]
    if name in _IMPORTED:
        return _IMPORTED[name]
    if ':' in name:
        module, _, attr = name.rpartition(':')
        try:
            cls = getattr(_import_module(module), attr)
        except Exception as exc:  # a user's module: any error it raises is the user's to fix
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise ConfigError(f'cannot import effect class {name!r}: {reason}; check the '
                              'module path and the class name') from None
        cls = register(cls)
        cls.source = name
        _IMPORTED[name] = cls
        return cls
    _load_entry_points()
    if name in _REGISTRY:
        return _REGISTRY[name]
    close = difflib.get_close_matches(name, list(_REGISTRY), n=1)
    named = [n for n in names() if not _REGISTRY[n].generic]
    hint = (f"; did you mean '{close[0]}'?" if close else
            f'; known: {", ".join(named)} (and the generic correction_<equation> terms)')
    raise ConfigError(f'unknown effect or component {name!r}{hint}')


def names() -> list[str]:
    """All registered component names."""
    _load_entry_points()
    return sorted(_REGISTRY)


for _cls in PAPER_COMPONENTS + CATALOGUE + CORRECTIONS:
    register(_cls)
