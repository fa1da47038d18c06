"""Assemble a model from its components: parameter vector, state layout, compiled kernels.

The right-hand side is composed from the components' stage hooks into one compiled
function per composition, so any set of components, including a user's own, runs as
fast as a hand-written model. ``kernel_cache`` compiles each composition once per machine.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..effects.base import Component, switched
from ..effects.layout import (
    CIRCUITS,
    CORE_PARAMS,
    CORE_STATE_ABS_TOL,
    CORE_STATE_NAMES,
    N_CONTEXT,
    N_CORE_STATES,
)
from .. import _jit
from . import compile_ahead, culprit, kernel_cache
from .config import SLOTS, ModelConfig

_KERNELS: dict[tuple, dict] = {}


@dataclass(frozen=True)
class Layout:
    """Where each component's parameters and states sit in the flat vectors (a
    :func:`switched` component's slice ends with its switch)."""

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
            n = len(comp.params) + switched(comp)
            slices.append((p, p + n))
            offsets.append(s)
            p += n
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
    """Compiled rhs and integrators for this composition (kept per process, cached on disk)."""
    if layout.classes not in _KERNELS:  # guarded: a failing hook is named (culprit)
        compile_ahead.wait(kernel_cache.module_name(layout))  # a helper compiling it: load it
        _KERNELS[layout.classes] = culprit.guarded(layout, kernel_cache.load(layout))
    return _KERNELS[layout.classes]


def compile_in_background(configs) -> None:
    """Have a helper process compile the compositions of ``configs`` (:mod:`.compile_ahead`)
    that are not compiled yet: those of the package's own components only, as a user's effect
    may not be importable in another process."""
    if not _jit.ENABLED:
        return
    jobs = []
    for config in configs:
        layout = Layout.of(config.component_classes())
        if layout.classes not in _KERNELS and not kernel_cache.on_disk(layout) and all(
                c.__module__.startswith('pneumatic_servo.') for c in layout.classes):
            jobs.append((kernel_cache.module_name(layout), config.to_dict()))
    compile_ahead.start(jobs)


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

    @cached_property
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
            if switched(comp):
                vec.append(float(any(values[k] != v for k, v in comp.neutral.items())))
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

    def evaluate(self, x: np.ndarray, command_v: float, supply_pa: float,
                 circuit: str | int = 'servo', *, params: np.ndarray | None = None,
                 t: float = 0.0, out: tuple[np.ndarray, np.ndarray] | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
        """One evaluation of the compiled right-hand side: (context, derivative) at state ``x``.

        Parameters
        ----------
        x : numpy.ndarray
            Full state vector [SI] (``state_names``).
        command_v : float [V]
            Valve command.
        supply_pa : float [Pa, absolute]
            Supply pressure.
        circuit : str or int
            A circuit name (``servo``, ``blocked``, ``closed_port``, ``flow``) or its index
            in ``effects.layout.CIRCUITS``.
        params : numpy.ndarray, optional
            Parameter vector (``param_vector``): other values for the same composition
            (default this model's config's).
        t : float [s]
            Time, for hooks that read it.
        out : (context, derivative), optional
            Arrays to fill instead of new ones (an inner loop that evaluates often).

        Returns
        -------
        (context, derivative) : tuple of numpy.ndarray
            The named totals of ``effects.layout`` (flows, torque, inertia, volumes, ...)
            and dx/dt [SI per s].
        """
        c, dx = out if out is not None else (np.zeros(N_CONTEXT), np.zeros(self.n_states))
        self.kernels['rhs'](t, x, float(command_v), float(supply_pa),
                            self.params if params is None else params,
                            CIRCUITS[circuit] if isinstance(circuit, str) else circuit, c, dx)
        return c, dx

    def delays(self, config: ModelConfig | None = None) -> tuple[float, float]:
        """(input delay, output delay) [s] summed over the components."""
        config = config or self.config
        d_in = d_out = 0.0
        for comp in self.layout.classes:
            values = config.values_of(comp.name)
            d_in += comp.input_delay_s(values)
            d_out += comp.output_delay_s(values)
        return d_in, d_out
