"""Declarations of node parameters: name, default, unit, range, meaning. Pure.

One declaration feeds three places: the ROS parameter descriptors (with
ranges, so ``ros2 param describe`` shows them), the start-up and run-time
checks (a bad value is rejected with a reason that names the fix) and the
command line (``pneumatic-servo plant --set name=value``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Iterable, Optional

from ..errors import ConfigError


@dataclass(frozen=True)
class Spec:
    """One parameter. The type is the type of ``default`` (float, int, bool or str).

    ``lo``/``hi`` bound numbers (inclusive); ``choices`` lists the allowed
    strings; ``read_only`` parameters are fixed after start-up; ``safety`` ones
    (the watchdog, the clamp range, the safe voltage) are fixed while the node is
    active, so that no peer can loosen them under a running valve.
    """

    name: str
    default: object
    description: str
    unit: str = ''
    lo: Optional[float] = None
    hi: Optional[float] = None
    choices: tuple[str, ...] = ()
    read_only: bool = False
    allow_nan: bool = False
    safety: bool = False

    @property
    def kind(self) -> type:
        return type(self.default)

    def describe(self) -> str:
        """Description with unit and range, as shown by ``ros2 param describe``."""
        text = self.description
        if self.unit:
            text += f' [{self.unit}]'
        if self.lo is not None and self.hi is not None:
            text += f', {self.lo:g} to {self.hi:g}'
        if self.choices:
            text += f'; one of {", ".join(self.choices)}'
        if self.allow_nan:
            text += '; NaN = not set'
        return text

    def coerce(self, value):
        """``value`` as this parameter's type (int -> float allowed); ConfigError if impossible."""
        kind = self.kind
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            return float(value)
        if kind is float and isinstance(value, str):
            try:
                return float(value)
            except ValueError:
                pass
        if kind is int and isinstance(value, str) and value.strip().lstrip('-').isdigit():
            return int(value)
        if kind is bool and isinstance(value, str) and value.lower() in ('true', 'false'):
            return value.lower() == 'true'
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            raise ConfigError(f'parameter {self.name}: expected {kind.__name__}, got '
                              f'{type(value).__name__} {value!r}')
        return value

    def check(self, value) -> Optional[str]:
        """Why ``value`` (already of the right type) is not acceptable, or None."""
        if self.kind in (float, int):
            if isinstance(value, float) and math.isnan(value) and self.allow_nan:
                return None
            if not math.isfinite(value):
                return f'{self.name} must be finite, got {value!r}'
            if self.lo is not None and value < self.lo or self.hi is not None and value > self.hi:
                return (f'{self.name} = {value:g} {self.unit} is outside [{self.lo:g}, '
                        f'{self.hi:g}] {self.unit}'.replace('  ', ' '))
        if self.choices and value not in self.choices:
            return f'{self.name} = {value!r} is not one of {", ".join(self.choices)}'
        return None


class SpecSet:
    """An ordered set of :class:`Spec` with an optional cross-parameter check.

    ``cross(values) -> reason | None`` sees the full proposed value mapping.
    """

    def __init__(self, specs: Iterable[Spec],
                 cross: Callable[[dict], Optional[str]] | None = None):
        self.specs = {s.name: s for s in specs}
        self.cross = cross

    def __iter__(self):
        return iter(self.specs.values())

    def __getitem__(self, name: str) -> Spec:
        return self.specs[name]

    def __contains__(self, name: str) -> bool:
        return name in self.specs

    def defaults(self) -> dict:
        return {s.name: s.default for s in self}

    def validate(self, values: dict) -> Optional[str]:
        """Reason the whole mapping ``values`` is unacceptable, or None."""
        for name, value in values.items():
            spec = self.specs.get(name)
            if spec is None:
                continue
            try:
                value = spec.coerce(value)
            except ConfigError as exc:
                return str(exc)
            reason = spec.check(value)
            if reason:
                return reason
        if self.cross is not None:
            return self.cross(values)
        return None

    def parse_assignments(self, items: Iterable[str]) -> dict:
        """``['kp=20', 'controller=smc']`` -> typed values; ConfigError names the bad item."""
        out = {}
        for item in items or ():
            name, sep, raw = str(item).partition('=')
            name = name.strip()
            if not sep:
                raise ConfigError(f'--set {item!r}: write NAME=VALUE')
            if name not in self.specs:
                import difflib
                close = difflib.get_close_matches(name, list(self.specs), n=1)
                hint = f"; did you mean '{close[0]}'?" if close else ''
                raise ConfigError(f'--set: unknown parameter {name!r}{hint}')
            out[name] = self.specs[name].coerce(raw.strip())
        return out
