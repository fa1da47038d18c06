"""Assemble a model from its components: parameter vector, state layout, compiled kernels.

The right-hand side is composed from the components' stage hooks as a chain
of small compiled closures, so any set of components, including a user's
own, compiles into one fast function. Kernels are cached per composition.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _jit
from .._jit import njit
from ..effects.base import STAGES, Component
from ..effects.layout import CORE_PARAMS, CORE_STATE_ABS_TOL, CORE_STATE_NAMES, N_CORE_STATES
from .config import SLOTS, ModelConfig
from .core import core_begin, core_end
from .integrators import make_integrators

_KERNELS: dict[tuple, dict] = {}


@njit
def _noop(t, x, P, c, dx):
    pass


def _bind(hook, s, p0, p1):
    @njit
    def bound(t, x, P, c, dx):
        hook(t, x, s, P[p0:p1], P, c, dx)
    return bound


def _chain(first, second):
    @njit
    def both(t, x, P, c, dx):
        first(t, x, P, c, dx)
        second(t, x, P, c, dx)
    return both


def _stage(calls):
    fn = _noop
    for call in calls:
        fn = call if fn is _noop else _chain(fn, call)
    return fn


def _make_rhs(stages):
    valve, supply, geometry, flows, heat, mechanics, finish = (stages[s] for s in STAGES)

    @njit
    def rhs(t, x, u, ps, P, circuit, c, dx):
        core_begin(t, x, u, ps, P, circuit, c, dx)
        valve(t, x, P, c, dx)
        supply(t, x, P, c, dx)
        geometry(t, x, P, c, dx)
        flows(t, x, P, c, dx)
        heat(t, x, P, c, dx)
        mechanics(t, x, P, c, dx)
        finish(t, x, P, c, dx)
        core_end(t, x, P, circuit, c, dx)
    return rhs if _jit.ENABLED else _nan_on_math_error(rhs)


def _nan_on_math_error(rhs):
    """Plain Python raises where compiled code yields NaN (the square root of a negative
    temperature in a wild trial step): make it NaN too, so the integrator reports a failed
    simulation instead of the process dying."""
    def safe(t, x, u, ps, P, circuit, c, dx):
        try:
            rhs(t, x, u, ps, P, circuit, c, dx)
        except (ValueError, ZeroDivisionError, OverflowError):
            dx[:] = np.nan
    return safe


@dataclass(frozen=True)
class Layout:
    """Where each component's parameters and states sit in the flat vectors."""

    classes: tuple[type[Component], ...]
    param_slices: tuple[tuple[int, int], ...]
    state_offsets: tuple[int, ...]
    n_params: int
    n_states: int

    @classmethod
    def of(cls, classes) -> 'Layout':
        p = len(CORE_PARAMS)
        s = N_CORE_STATES
        slices, offsets = [], []
        for comp in classes:
            slices.append((p, p + len(comp.params)))
            offsets.append(s)
            p += len(comp.params)
            s += len(comp.states)
        return cls(tuple(classes), tuple(slices), tuple(offsets), p, s)

    def hook_order(self):
        """Components in the order their hooks run: slot parts first, then by ``order``."""
        def key(i):
            comp = self.classes[i]
            return (0 if comp.slot else 1, SLOTS.index(comp.slot) if comp.slot else 0,
                    comp.order, i)
        return sorted(range(len(self.classes)), key=key)


def kernels_for(layout: Layout) -> dict:
    """Compiled rhs and integrators for this composition (cached)."""
    key = layout.classes
    if key not in _KERNELS:
        stages = {}
        for stage in STAGES:
            calls = []
            for i in layout.hook_order():
                hook = layout.classes[i].hook(stage)
                if hook is not None:
                    p0, p1 = layout.param_slices[i]
                    calls.append(_bind(hook, layout.state_offsets[i], p0, p1))
            stages[stage] = _stage(calls)
        rhs = _make_rhs(stages)
        kern = make_integrators(rhs, layout.n_states)
        kern['rhs'] = rhs
        _KERNELS[key] = kern
    return _KERNELS[key]


class Model:
    """A configured model: flat parameter vector, state names, tolerances and kernels."""

    def __init__(self, config: ModelConfig | None = None):
        self.config = config if config is not None else ModelConfig.paper()
        self.layout = Layout.of(self.config.component_classes())
        self.kernels = kernels_for(self.layout)
        self.params = self.param_vector(self.config)

    @property
    def n_states(self) -> int:
        return self.layout.n_states

    @property
    def state_names(self) -> list[str]:
        names = list(CORE_STATE_NAMES)
        for comp in self.layout.classes:
            names += [f'{comp.name}.{s.name}' for s in comp.states]
        return names

    @property
    def abs_tol(self) -> np.ndarray:
        tol = list(CORE_STATE_ABS_TOL)
        for comp in self.layout.classes:
            tol += [s.abs_tol for s in comp.states]
        return np.array(tol)

    def param_vector(self, config: ModelConfig) -> np.ndarray:
        """Flat parameter vector of ``config`` (which must have this model's components)."""
        vec = [config.core[p.name] for p in CORE_PARAMS]
        for comp in self.layout.classes:
            values = config.values_of(comp.name)
            vec += [values[p.name] for p in comp.params]
        return np.array(vec, dtype=float)

    def param_index(self, key: str) -> int:
        """Index of ``owner.name`` in the parameter vector."""
        owner, _, name = key.partition('.')
        if owner == 'core':
            return [p.name for p in CORE_PARAMS].index(name)
        for comp, (p0, _) in zip(self.layout.classes, self.layout.param_slices):
            if comp.name == owner:
                return p0 + [p.name for p in comp.params].index(name)
        raise KeyError(key)

    def delays(self, config: ModelConfig | None = None) -> tuple[float, float]:
        """(input delay, output delay) [s] summed over the components."""
        config = config or self.config
        d_in = d_out = 0.0
        for comp in self.layout.classes:
            values = config.values_of(comp.name)
            d_in += comp.input_delay_s(values)
            d_out += comp.output_delay_s(values)
        return d_in, d_out
