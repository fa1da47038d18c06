"""Registry of model components by name: the paper's parts and the effect catalogue.

A user adds an effect without editing the package by subclassing
:class:`Component` and either calling :func:`register`, declaring an entry
point in group ``pneumatic_servo.effects``, or naming it in a config file as
``"package.module:ClassName"``.
"""
from __future__ import annotations

import difflib
import importlib
from importlib.metadata import entry_points

from ..errors import ConfigError
from .base import Component, Param, State
from .catalogue import CATALOGUE
from .corrections import CORRECTIONS
from .paper import PAPER_COMPONENTS, PAPER_DEFAULTS

__all__ = ['Component', 'Param', 'State', 'register', 'get', 'names', 'CATALOGUE_NAMES',
           'PAPER_DEFAULTS']

_REGISTRY: dict[str, type[Component]] = {}
CATALOGUE_NAMES = tuple(c.name for c in CATALOGUE)
_entry_points_loaded = False


def register(cls: type[Component]) -> type[Component]:
    """Register a component class under ``cls.name``; usable as a decorator."""
    if not (isinstance(cls, type) and issubclass(cls, Component)) or not cls.name:
        raise ConfigError(f'{cls!r} is not a Component subclass with a name; subclass '
                          'pneumatic_servo.effects.Component and set name')
    if cls.slot is None and not (cls.params or cls.states or any(
            cls.hook(s) for s in ('valve', 'supply', 'geometry', 'flows', 'heat',
                                  'mechanics', 'finish'))) \
            and cls.input_delay_s is Component.input_delay_s \
            and cls.output_delay_s is Component.output_delay_s and cls.sensor_error is None:
        raise ConfigError(f'effect {cls.name!r} adds nothing: give it a hook, a delay or a '
                          'sensor error')
    _REGISTRY[cls.name] = cls
    return cls


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


def get(name: str) -> type[Component]:
    """The component class registered as ``name``, or ``"module:Class"`` imported on demand."""
    if name in _REGISTRY:
        return _REGISTRY[name]
    if ':' in name:
        module, _, attr = name.partition(':')
        try:
            cls = getattr(importlib.import_module(module), attr)
        except (ImportError, AttributeError) as exc:
            raise ConfigError(f'cannot import effect class {name!r}: {exc}')
        return register(cls)
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
