"""The component interface: what every physical effect declares and provides.

The balance laws (mass and energy per chamber, moment balance) are fixed in
``pneumatic_servo.model.core``. A component never rewrites an equation: it
adds into named totals of the context vector ``c`` (mass and enthalpy flow
into each chamber, heat into each chamber, torque and inertia on the shaft,
friction) or modifies a named input (spool position, supply pressure,
volumes), and may own extra states.

Hook signature (numba-compatible plain function, or ``None``)::

    hook(t, x, s, p, P, c, dx)

t   time [s]; x the state vector; s index of the component's first own
    state in x; p the component's own parameter values (array, order of
    ``params``); P the whole parameter vector (core parameters first, see
    ``layout``); c the context vector (see ``layout``); dx the derivative
    vector, where a component writes the derivatives of its own states.

Hooks run in stage order: valve, supply, geometry, flows, heat, mechanics,
finish.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, ClassVar, Optional

STAGES = ('valve', 'supply', 'geometry', 'flows', 'heat', 'mechanics', 'finish')


@dataclass(frozen=True)
class Param:
    """A named, bounded physical parameter in SI units.

    ``lower``/``upper`` are hard bounds (a config outside them is rejected and
    fits are confined to them). ``plausible`` is the narrower range a real
    rig shows; a fitted value outside it is flagged as implausible. ``fit``
    says whether diagnosis frees this parameter when the component is tried.
    """

    name: str
    unit: str
    default: float
    lower: float
    upper: float
    description: str
    fit: bool = True
    plausible: Optional[tuple[float, float]] = None
    #: the part of the rig it belongs to, where that is narrower than its component's
    #: (e.g. 'chamber b'), and the circuits that part is in (None: the component's)
    part: str = ''
    circuits: Optional[tuple[str, ...]] = None
    #: a parameter of the same component that mirrors this one (chamber a's twin of a
    #: chamber-b value): where the data cannot determine this one, symmetry is the
    #: assumption offered
    mirror: str = ''

    def plausible_range(self) -> tuple[float, float]:
        return self.plausible if self.plausible is not None else (self.lower, self.upper)


@dataclass(frozen=True)
class State:
    """An extra state owned by a component, with the absolute tolerance the solver uses."""

    name: str
    unit: str
    abs_tol: float
    description: str


class Component:
    """Base class of every model component (paper parts and catalogue effects).

    Subclasses set the class attributes below and any hooks. Register a
    subclass with ``pneumatic_servo.effects.register`` (or an entry point in
    group ``pneumatic_servo.effects``) to make it available by ``name``.
    """

    name: ClassVar[str] = ''
    #: ``"module:Class"`` (or ``"file.py:Class"``) the class was imported from by name, so that
    #: a saved config names what imports it; empty for classes registered otherwise
    source: ClassVar[str] = ''
    #: 'orifice', 'clearance', 'thermal' or 'friction' for the paper's
    #: switchable parts (one per slot); None for an additive effect.
    slot: ClassVar[Optional[str]] = None
    summary: ClassVar[str] = ''
    reference: ClassVar[str] = ''
    params: ClassVar[tuple[Param, ...]] = ()
    states: ClassVar[tuple[State, ...]] = ()
    #: Which equation a missing instance of this effect shows up in:
    #: 'angle' (moment balance), 'pressure' (mass balance) or 'both'.
    acts_on: ClassVar[str] = 'both'
    #: Order within a stage (lower runs first), e.g. a null offset before spool dynamics.
    order: ClassVar[int] = 50
    #: Parameter values at which this effect adds exactly nothing (None if none exist,
    #: e.g. a spool lag or a supply line cannot be made ideal).
    neutral: ClassVar[Optional[dict[str, float]]] = None
    #: Realistic values [SI] of a rig that has this effect: what generated test data hide
    #: and what diagnosis must recover (parameters not named keep their defaults).
    example: ClassVar[Optional[dict[str, float]]] = None
    #: Circuits whose equations it acts in ('servo', 'blocked', 'closed_port', 'flow').
    circuits: ClassVar[tuple[str, ...]] = ('servo', 'blocked', 'closed_port', 'flow')
    #: Whether it shows in steady states (static tables); a lag or a delay does not.
    steady: ClassVar[bool] = True
    #: Whether it may sit switched off (at ``neutral``) in a compiled host model shared by
    #: several candidates: true for effects whose hooks cost next to nothing there (short,
    #: or ``skipped_at_neutral``), since each composition takes seconds to compile.
    shares_host: ClassVar[bool] = False
    #: Whether the compiled model calls its hooks only while a parameter differs from
    #: ``neutral``: for a component that sits at neutral in most simulations and costs
    #: something there, like a leak's orifice flow or a generic correction's terms. The
    #: test reads one number, the switch that ends its slice of the parameter vector
    #: (:func:`switched`). A component with states is called always (skipped, they would
    #: stop moving, which changes the step control); its hook may read the switch itself,
    #: as a generic correction's does to skip its terms.
    skipped_at_neutral: ClassVar[bool] = False
    #: The experiment that excites this effect more than its look-alikes, in words.
    excitation: ClassVar[str] = ''
    #: Look-alike effect name -> the experiment that tells the two apart, where a specific
    #: one is known (otherwise both effects' ``excitation`` is suggested).
    separated_from: ClassVar[dict[str, str]] = {}
    #: A generic correction term (``effects.corrections``), not a named physical effect:
    #: diagnosis fits it in its discovery step, never as a named candidate.
    generic: ClassVar[bool] = False

    valve: ClassVar[Optional[Callable]] = None
    supply: ClassVar[Optional[Callable]] = None
    geometry: ClassVar[Optional[Callable]] = None
    flows: ClassVar[Optional[Callable]] = None
    heat: ClassVar[Optional[Callable]] = None
    mechanics: ClassVar[Optional[Callable]] = None
    finish: ClassVar[Optional[Callable]] = None
    #: Measurement error ``sensor_error(values, signals, core) -> {signal: error}`` [SI]: what
    #: this component adds to the sensors' readings, from the physical ``signals`` (arrays:
    #: ``angle_rad``, ``velocity_rad_s``, ``p_a_pa``, ``p_b_pa``, ``command_v``,
    #: ``supply_pa``, and ``t_s`` the sample times [s]) and the core parameters; plain
    #: numpy, applied after the simulation (to each k-step segment on its own), so it never
    #: feeds back into the physics. None if it adds none.
    sensor_error: ClassVar[Optional[Callable]] = None

    @classmethod
    def defaults(cls) -> dict[str, float]:
        return {p.name: p.default for p in cls.params}

    @classmethod
    def initial_state(cls, values: dict[str, float], command_v: float,
                      supply_pa: float, core: dict[str, float]) -> list[float]:
        """Initial values of the component's own states, in the order of ``states``."""
        return [0.0] * len(cls.states)

    @classmethod
    def input_delay_s(cls, values: dict[str, float]) -> float:
        """Pure delay [s] this component adds between command and valve."""
        return 0.0

    @classmethod
    def output_delay_s(cls, values: dict[str, float]) -> float:
        """Pure delay [s] this component adds between physical state and measurement."""
        return 0.0

    @classmethod
    def refit_keys(cls, values: dict[str, float]) -> list[str]:
        """Parameters refitted when a model holding this component is diagnosed again."""
        return [p.name for p in cls.params if p.fit]

    @classmethod
    def validate(cls, values: dict[str, float]) -> None:
        """Raise ``ConfigError`` if the values are inconsistent with each other."""

    @classmethod
    def hook(cls, stage: str) -> Optional[Callable]:
        return getattr(cls, stage)


def switched(comp: type[Component]) -> bool:
    """Whether ``comp``'s slice of the parameter vector ends with its switch: 1.0 while one of
    its parameters differs from ``neutral``, else 0.0. The compiled model then tests one
    number at each evaluation, not every parameter: the generic corrections have over a
    hundred each, and testing them all made a simulation with every correction at zero
    five times slower than one without them (two to three times with the switch, as the
    corrections with a memory still run; measured on the discovery's screening batch)."""
    return bool(comp.skipped_at_neutral and comp.neutral)
