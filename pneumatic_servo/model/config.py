"""Model configuration: which component fills each slot, which effects are added,
and every parameter value in SI units. Loads and saves YAML.

YAML layout::

    core:          {piston_area_m2: 3.4636e-4, ...}      # geometry, environment
    components:    {orifice_flow: {...}, clearance_flow: {...},
                    wall_heat_transfer: {...}, stribeck_friction: {...}}
    effects:       {external_leakage: {leak_area_a_m2: 1e-8, ...}}

Any value may be a number in the SI unit its name ends with, or a string
with a unit ('0.6 MPa gauge', '5 cm^3'). Omitted values take defaults.
"""
from __future__ import annotations

import copy
import difflib
import math
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from .. import effects as registry
from ..effects.base import Component, Param
from ..effects.layout import CORE_PARAMS
from ..errors import ConfigError
from ..files import load_yaml
from .units import to_si, unit_hint

SLOTS = ('orifice', 'clearance', 'thermal', 'friction')


def _check_values(owner: str, params: tuple[Param, ...], given: dict, atmospheric_pa: float):
    """Defaults overlaid with ``given``, converted to SI and checked against bounds."""
    if given is None:
        given = {}
    if not isinstance(given, dict):
        raise ConfigError(f'{owner}: expected a mapping of parameter: value, got {given!r}')
    by_name = {p.name: p for p in params}
    out = {p.name: p.default for p in params}
    for key, raw in given.items():
        if key not in by_name:
            close = difflib.get_close_matches(str(key), list(by_name), n=1, cutoff=0.5)
            hint = (f"; did you mean '{close[0]}' (in {by_name[close[0]].unit})?" if close
                    else f'; known: {", ".join(by_name) or "none"}')
            raise ConfigError(f'unknown parameter {owner}.{key}{hint}')
        p = by_name[key]
        value = to_si(raw, p.unit, f'{owner}.{key}', atmospheric_pa)
        if not math.isfinite(value) or not (p.lower <= value <= p.upper):
            raise ConfigError(f'{owner}.{key} = {value:g} {p.unit} is outside [{p.lower:g}, '
                              f'{p.upper:g}] {p.unit}; {unit_hint(p.unit)}')
        out[key] = value
    return out


def _copied(section: dict) -> dict:
    """A copy of a section of owner -> values whose values are numbers (anything else is
    deep-copied)."""
    return {owner: {k: v if isinstance(v, (int, float)) else copy.deepcopy(v)
                    for k, v in values.items()} for owner, values in section.items()}


def _name(key, section: str) -> str:
    """A component name from a config key; ConfigError if it is not a string."""
    if not isinstance(key, str):
        raise ConfigError(f'{section}: {key!r} is not a component name; write the name as text '
                          "(e.g. external_leakage, or 'package.module:Class')")
    return key


@dataclass
class ModelConfig:
    """A complete model: slot choices, added effects and all parameter values (SI)."""

    core: dict[str, float] = field(default_factory=lambda: {p.name: p.default
                                                            for p in CORE_PARAMS})
    #: slot component name -> values, one per slot
    components: dict[str, dict[str, float]] = field(default_factory=dict)
    #: added effect name -> values, in order
    effects: dict[str, dict[str, float]] = field(default_factory=dict)

    # ----------------------------------------------------------------- build
    @classmethod
    def paper(cls) -> 'ModelConfig':
        """The paper's model with its published parameters and the defaults of docs/model.md."""
        return cls.from_dict({})

    @classmethod
    def from_dict(cls, data: dict) -> 'ModelConfig':
        if data is None:
            data = {}
        if not isinstance(data, dict):
            raise ConfigError('model config must be a mapping with core, components, effects')
        unknown = set(data) - {'core', 'components', 'effects', 'metadata'}
        if unknown:
            raise ConfigError(f'unknown top-level key(s) {sorted(map(str, unknown))} in model '
                              'config; use core, components, effects')
        core_given = data.get('core') or {}
        pe_raw = core_given.get('atmospheric_pressure_pa', 101325.0) \
            if isinstance(core_given, dict) else 101325.0
        pe = to_si(pe_raw, 'Pa', 'core.atmospheric_pressure_pa')
        core = _check_values('core', CORE_PARAMS, core_given, pe)
        comps: dict[str, dict[str, float]] = {}
        given_comps = data.get('components') or {}
        if not isinstance(given_comps, dict):
            raise ConfigError('components: expected a mapping of component name: parameters')
        chosen = dict(registry.PAPER_DEFAULTS)
        for name in given_comps:
            cls_ = registry.get(_name(name, 'components'))
            if cls_.slot is None:
                raise ConfigError(f'{name!r} is an effect, not a slot component; list it under '
                                  'effects:')
            chosen[cls_.slot] = name
        for slot in SLOTS:
            cls_ = registry.get(chosen[slot])
            comps[cls_.name] = _check_values(cls_.name, cls_.params,
                                             given_comps.get(cls_.name), pe)
        effs: dict[str, dict[str, float]] = {}
        given_effects = data.get('effects') or {}
        if isinstance(given_effects, list):
            given_effects = {_name(n, 'effects'): {} for n in given_effects}
        if not isinstance(given_effects, dict):
            raise ConfigError('effects: expected a mapping of effect name: parameters')
        for name, values in given_effects.items():
            cls_ = registry.get(_name(name, 'effects'))
            if cls_.slot is not None:
                raise ConfigError(f'{name!r} fills the {cls_.slot} slot; list it under '
                                  'components:')
            # keyed by the class's own name ("module:Class" is kept on the class, for saving)
            effs[cls_.name] = _check_values(cls_.name, cls_.params, values, pe)
        cfg = cls(core=core, components=comps, effects=effs)
        cfg.validate()
        return cfg

    @classmethod
    def load(cls, path) -> 'ModelConfig':
        """Read a YAML config file; errors name the file and the fix."""
        path = Path(path)
        data = load_yaml(path, 'config')
        try:
            return cls.from_dict(data)
        except ConfigError as exc:
            raise ConfigError(f'{path}: {exc}') from None

    def to_dict(self) -> dict:
        """The config as plain data; a user's effect imported by ``"module:Class"`` is keyed
        by that, so that loading the saved file imports it again."""
        return {'core': dict(self.core),
                'components': {k: dict(v) for k, v in self.components.items()},
                'effects': {registry.get(k).source or k: dict(v)
                            for k, v in self.effects.items()}}

    def save(self, path, header: str = '') -> None:
        """Write YAML that :meth:`load` (and the nodes) take as it is."""
        text = '# pneumatic_servo model (SI units, absolute pressures)\n'
        if header:
            text += ''.join(f'# {line}\n' for line in header.splitlines())
        text += yaml.safe_dump(self.to_dict(), sort_keys=False)
        Path(path).write_text(text)

    def validate(self) -> None:
        for name, values in self.components.items():
            registry.get(name).validate(values)
        for name, values in self.effects.items():
            registry.get(name).validate(values)
        if self.core['sleeve_bore_diameter_m'] <= self.core['spool_diameter_m']:
            raise ConfigError('core.sleeve_bore_diameter_m must exceed core.spool_diameter_m '
                              '(the clearance h0 = (d_h - d_s)/2 must be positive)')

    # --------------------------------------------------------------- variants
    def copy(self) -> 'ModelConfig':
        # the values are numbers: copying each section's dict copies them all (a deep copy
        # is slow, and a diagnosis builds a config for every trial value)
        return type(self)(dict(self.core), _copied(self.components), _copied(self.effects))

    def with_effect(self, name: str, values: dict | None = None) -> 'ModelConfig':
        """A copy with effect ``name`` added (or its values updated)."""
        cls_ = registry.get(name)
        out = self.copy()
        if cls_.slot is not None:
            return out.with_slot(cls_.name, values)
        merged = {**out.effects.get(cls_.name, {}), **(values or {})}
        out.effects[cls_.name] = _check_values(cls_.name, cls_.params, merged,
                                               out.core['atmospheric_pressure_pa'])
        cls_.validate(out.effects[cls_.name])
        return out

    def with_slot(self, name: str, values: dict | None = None) -> 'ModelConfig':
        """A copy with component ``name`` in its slot (e.g. 'adiabatic')."""
        cls_ = registry.get(name)
        if cls_.slot is None:
            raise ConfigError(f'{name!r} is an effect; use with_effect')
        out = self.copy()
        for old in [n for n in out.components if registry.get(n).slot == cls_.slot]:
            del out.components[old]
        out.components[cls_.name] = _check_values(cls_.name, cls_.params, values,
                                                  out.core['atmospheric_pressure_pa'])
        out.components = {n: out.components[n] for n in sorted(
            out.components, key=lambda n: SLOTS.index(registry.get(n).slot))}
        return out

    def component_classes(self) -> list[type[Component]]:
        """Slot components (in slot order) then effects (in order added)."""
        return [registry.get(n) for n in self.components] + [registry.get(n) for n in self.effects]

    def values_of(self, name: str) -> dict[str, float]:
        if name == 'core':
            return self.core
        return self.components.get(name, self.effects.get(name))

    # ------------------------------------------------- flat 'owner.param' keys
    def get(self, key: str) -> float:
        owner, _, name = key.partition('.')
        values = self.values_of(owner)
        if values is None or name not in values:
            raise ConfigError(f'no parameter {key!r} in this model')
        return values[name]

    def set(self, key: str, value: float) -> None:
        """Set parameter ``owner.name`` to ``value`` [SI], within its declared bounds."""
        owner, _, name = key.partition('.')
        values = self.values_of(owner)
        if values is None or name not in values:
            raise ConfigError(f'no parameter {key!r} in this model')
        value = float(value)
        p = self.param(key)
        if not (math.isfinite(value) and p.lower <= value <= p.upper):
            raise ConfigError(f'{key} = {value:.6g} {p.unit} is outside its bounds '
                              f'[{p.lower:g}, {p.upper:g}] {p.unit}')
        values[name] = value

    def param(self, key: str) -> Param:
        """The declaration (unit, bounds) of parameter ``owner.name``."""
        owner, _, name = key.partition('.')
        params = CORE_PARAMS if owner == 'core' else registry.get(owner).params
        for p in params:
            if p.name == name:
                return p
        raise ConfigError(f'no parameter {key!r}')
