"""Simulation: the accurate offline run over a recorded or designed input, and the
fixed-step real-time stepper the plant node calls once per control period.

Inputs are sampled signals held constant between samples (zero-order hold),
as a DAQ outputs them. Units: s, V, Pa absolute, rad, K.
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from ..effects.base import switched
from ..effects.layout import (
    BLOCKED,
    CIRCUITS,
    CORE_STATE_NAMES,
    N_CONTEXT,
    N_CORE_STATES,
    OMEGA,
    OUTPUT_NAMES,
    P_A,
    P_B,
    T_A,
    T_B,
    THETA,
)
from ..errors import SimulationError
from . import culprit
from .assembly import Model
from .config import ModelConfig
from .integrators import STEP_CAP

#: default relative tolerance of the offline integrator (see benchmarks/ for its accuracy)
DEFAULT_RTOL = 1e-7
_STATUS = {1: 'a state became non-finite', 2: 'the step size collapsed',
           3: 'more substeps were needed than allowed'}


@dataclass
class SimResult:
    """Sampled trajectory: ``states`` (n, n_states) and context ``outputs`` at ``t``."""

    t: np.ndarray
    states: np.ndarray
    state_names: list[str]
    outputs: np.ndarray
    circuit: str = 'servo'
    inputs: dict = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        if name in self.state_names:
            return self.states[:, self.state_names.index(name)]
        if name in OUTPUT_NAMES:
            return self.outputs[:, OUTPUT_NAMES.index(name)]
        if name in self.inputs:
            return self.inputs[name]
        raise KeyError(name)

    angle_rad = property(lambda self: self.states[:, THETA])
    velocity_rad_s = property(lambda self: self.states[:, OMEGA])
    p_a_pa = property(lambda self: self.states[:, P_A])
    p_b_pa = property(lambda self: self.states[:, P_B])
    t_a_k = property(lambda self: self.states[:, T_A])
    t_b_k = property(lambda self: self.states[:, T_B])


def as_model(model) -> Model:
    """Accept a Model, a ModelConfig or None (the paper's model)."""
    if isinstance(model, Model):
        return model
    return Model(model if model is not None else ModelConfig.paper())


def initial_state(model: Model, angle_rad: float = None, p_a_pa: float = None,
                  p_b_pa: float = None, t_a_k: float = None, t_b_k: float = None,
                  velocity_rad_s: float = 0.0, command_v: float = 5.0,
                  supply_pa: float = None, config: ModelConfig = None,
                  circuit: str = 'servo', params: np.ndarray | None = None) -> np.ndarray:
    """Full state vector [SI]; unspecified values default to mid-stroke, mid pressure, room T.

    In the static circuits the b side of the valve is a dead end (ports 2
    and 3 closed), so its default pressure is the supply. Effect-owned
    states start from each component's ``initial_state`` and are then
    settled to their own steady state for this command and supply, so that
    e.g. a spool lag starts at rest even with a null offset. ``params``: the config's
    parameter vector, where the caller has it.
    """
    cfg = config or model.config
    core = cfg.core
    ps = core['supply_pressure_pa'] if supply_pa is None else supply_pa
    mid = 0.5 * (ps + core['atmospheric_pressure_pa'])
    if p_b_pa is None and CIRCUITS[circuit] > BLOCKED:
        p_b_pa = ps
    x = [0.5 * core['stroke_rad'] if angle_rad is None else angle_rad, velocity_rad_s,
         mid if p_a_pa is None else p_a_pa, mid if p_b_pa is None else p_b_pa,
         core['room_temperature_k'] if t_a_k is None else t_a_k,
         core['room_temperature_k'] if t_b_k is None else t_b_k]
    for comp in model.layout.classes:
        if comp.states:  # (this runs for every predicted segment: skip the stateless)
            x += list(comp.initial_state(cfg.values_of(comp.name), command_v, ps, core))
    x = np.array(x, dtype=float)
    _settle_effect_states(model, x, command_v, ps,
                          model.param_vector(cfg) if params is None else params,
                          CIRCUITS[circuit])
    return x


def sensing(model: Model, config: ModelConfig) -> tuple:
    """The components of ``model`` whose sensor errors can add to the readings under
    ``config``: each with a ``sensor_error``, but a switched one at its neutral values,
    where it adds exactly nothing (:func:`..effects.base.switched`: a generic correction
    not in use). A prediction asks once per configuration, not once per segment."""
    return tuple(comp for comp in model.layout.classes if comp.sensor_error is not None
                 and not (switched(comp) and _at_neutral(config.values_of(comp.name),
                                                         comp.neutral)))


def _at_neutral(values: dict, neutral: dict) -> bool:
    """Whether ``values`` hold every parameter of ``neutral`` at it (a component's fixed
    parameters, such as a free function's span, do not switch it on)."""
    return all(values[k] == v for k, v in neutral.items())


def sensor_errors(model: Model, config: ModelConfig, signals: dict,
                  components: tuple | None = None) -> dict[str, np.ndarray]:
    """What the components' sensor errors add to the readings [SI], summed per signal, from
    the physical ``signals`` (see ``Component.sensor_error``); empty if none has one.
    ``components``: :func:`sensing`'s answer for ``config``, where the caller has it."""
    out: dict[str, np.ndarray] = {}
    for comp in sensing(model, config) if components is None else components:
        for sig, err in comp.sensor_error(config.values_of(comp.name), signals,
                                          config.core).items():
            out[sig] = out.get(sig, 0.0) + err
    return out


def measured_states(model: Model, config: ModelConfig, t: np.ndarray, states: np.ndarray,
                    command_v: np.ndarray, supply_pa: np.ndarray,
                    components: tuple | None = None) -> np.ndarray:
    """The states as the sensors show them: the components' sensor errors added to the
    physical ``states`` (n, n_states) at times ``t``. ``components``: as for
    :func:`sensor_errors`."""
    if components == ():
        return states
    signals = {name: states[:, i] for i, name in enumerate(CORE_STATE_NAMES)}
    errors = sensor_errors(model, config, {**signals, 'command_v': command_v,
                                           'supply_pa': supply_pa, 't_s': t}, components)
    if not errors:
        return states
    out = states.copy()
    for sig, err in errors.items():
        out[:, CORE_STATE_NAMES.index(sig)] += err
    return out


def context(model: Model, x: np.ndarray, command_v: float, supply_pa: float,
            config: ModelConfig = None, circuit: str = 'servo') -> np.ndarray:
    """The context vector (see ``effects.layout``: named totals such as the torque and the
    inertia on the shaft, flows, volumes) after one evaluation of the right-hand side at
    state ``x`` [SI], with every component's contribution."""
    cfg = config or model.config
    return model.evaluate(np.asarray(x, float), command_v, supply_pa, circuit,
                          params=model.param_vector(cfg))[0]


def _settle_effect_states(model: Model, x: np.ndarray, command_v: float, supply_pa: float,
                          P: np.ndarray, circuit: int, iterations: int = 30) -> None:
    """Newton on the effect-owned states (diagonal Jacobian) with the core states held."""
    first = N_CORE_STATES
    if model.n_states == first:
        return
    out = np.zeros(N_CONTEXT), np.zeros(model.n_states)
    dx = out[1]
    tol = model.abs_tol
    for _ in range(iterations):
        model.evaluate(x, command_v, supply_pa, circuit, params=P, out=out)
        f = dx[first:].copy()
        if not f.any():  # at rest already (a memory at its command): nothing to step
            return
        moved = False
        for j, i in enumerate(range(first, model.n_states)):
            h = 1e-6 * max(abs(x[i]), tol[i] * 1e3)
            x[i] += h
            model.evaluate(x, command_v, supply_pa, circuit, params=P, out=out)
            x[i] -= h
            slope = (dx[i] - f[j]) / h
            if slope < 0.0:  # a stable own state: step to where its derivative vanishes
                step = -f[j] / slope
                x[i] += step
                moved = moved or abs(step) > tol[i] * 1e-3
        if not moved:
            return


def delayed(t: np.ndarray, values: np.ndarray, delay: float) -> np.ndarray:
    """``values`` (n,) or (n, k) seen ``delay`` [s] later, linearly interpolated; held at start."""
    if delay <= 0.0:
        return values
    tq = t - delay
    if values.ndim == 1:
        return np.interp(tq, t, values)
    return np.column_stack([np.interp(tq, t, values[:, j]) for j in range(values.shape[1])])


def _check_inputs(t, command_v, supply_pa):
    t = np.asarray(t, dtype=float)
    u = np.broadcast_to(np.asarray(command_v, dtype=float), t.shape).copy()
    ps = np.broadcast_to(np.asarray(supply_pa, dtype=float), t.shape).copy()
    if t.ndim != 1 or len(t) < 2:
        raise SimulationError('time vector must be 1-D with at least two samples')
    if not np.all(np.diff(t) > 0):
        raise SimulationError('sample times must increase strictly')
    for name, arr in (('time', t), ('valve command', u), ('supply pressure', ps)):
        if not np.all(np.isfinite(arr)):
            raise SimulationError(f'{name} contains NaN or inf; clean the input first')
    if np.any(ps <= 0):
        raise SimulationError('supply pressure must be absolute and positive [Pa]')
    return t, u, ps


def simulate(model=None, t=None, command_v=5.0, supply_pa=None, x0=None,
             circuit: str = 'servo', method: str = 'adaptive', rtol: float = DEFAULT_RTOL,
             atol_scale: float = 1.0, substeps: int = 10, config: ModelConfig = None,
             measured: bool = True) -> SimResult:
    """Simulate ``model`` at sample times ``t`` [s] with ZOH valve ``command_v`` [V]
    and supply ``supply_pa`` [Pa abs] (scalars or arrays like ``t``).

    ``method`` is 'adaptive' (Dormand-Prince 5(4), ``rtol`` and per-state
    absolute tolerances times ``atol_scale``) or 'fixed' (RK4, ``substeps``
    per sample interval, as the real-time stepper). ``config`` overrides the
    parameter values (same components) without recompiling. The states are what
    the sensors show (``measured``: the components' measurement delays applied),
    or the physical states.
    """
    model = as_model(model)
    cfg = config or model.config
    if circuit not in CIRCUITS:
        raise SimulationError(f'unknown circuit {circuit!r}; use one of {", ".join(CIRCUITS)}')
    if supply_pa is None:
        supply_pa = cfg.core['supply_pressure_pa']
    t, u, ps = _check_inputs(t, command_v, supply_pa)
    d_in, d_out = model.delays(cfg)
    u_valve = delayed(t, u, d_in)
    if x0 is None:
        x0 = initial_state(model, command_v=u_valve[0], supply_pa=ps[0], config=cfg,
                           circuit=circuit)
    x0 = np.asarray(x0, dtype=float)
    if x0.shape != (model.n_states,):
        raise SimulationError(f'initial state needs {model.n_states} values '
                              f'({", ".join(model.state_names)})')
    P = model.param_vector(cfg)
    X = np.full((len(t), model.n_states), np.nan)  # NaN: the rows recorded show a failure's place
    Y = np.empty((len(t), len(OUTPUT_NAMES)))
    args = (_kernel_array(x0), _kernel_array(t), _kernel_array(u_valve), _kernel_array(ps),
            _kernel_array(P), CIRCUITS[circuit], method == 'adaptive', rtol,
            model.abs_tol * atol_scale, int(substeps))
    status, k = model.kernels['run'](*args, X, Y)
    if status != 0:
        why = culprit.explain_status(model.layout, *args, X)  # which hook, if one is to blame
        raise SimulationError(f'simulation failed at t = {t[k]:.6g} s: {_STATUS[status]}{why}')
    if measured:
        X = delayed(t, measured_states(model, cfg, t, X, u_valve, ps), d_out)
    return SimResult(t, X, model.state_names, Y, circuit,
                     {'command_v': u, 'supply_pa': ps})


def _kernel_array(values) -> np.ndarray:
    """``values`` as the integrators take every array: float, C-contiguous and writable (a
    read-only view, as ``np.broadcast_to`` gives, is another type to numba: copied)."""
    return np.require(values, dtype=float, requirements=['C', 'W'])


def simulate_batch(model: Model, t, command_v, supply_pa, x0s, param_matrix,
                   circuit='servo', method='adaptive', rtol=DEFAULT_RTOL, substeps=10,
                   lengths=None):
    """Simulate one trajectory per row of ``param_matrix`` in parallel (no delays applied).

    ``command_v``/``supply_pa`` are (n,) shared or (m, n) per row; ``x0s`` is
    (m, n_states); ``lengths`` (m,) the samples each row is simulated over (default all
    n; beyond them its states are NaN). Returns states (m, n, n_states), outputs and a
    status per row (0 = ok).
    """
    t = _kernel_array(t)
    pm = _kernel_array(param_matrix)
    m = pm.shape[0]
    U = _kernel_array(np.broadcast_to(command_v, (m, len(t))))
    PS = _kernel_array(np.broadcast_to(supply_pa, (m, len(t))))
    X0 = _kernel_array(np.broadcast_to(x0s, (m, model.n_states)))
    XB = np.full((m, len(t), model.n_states), np.nan)  # a failed row shows where it stopped
    YB = np.empty((m, len(t), len(OUTPUT_NAMES)))
    status = np.zeros(m, dtype=np.int64)
    N = np.full(m, len(t), dtype=np.int64) if lengths is None else np.minimum(
        np.asarray(lengths, dtype=np.int64), len(t))
    model.kernels['run_batch'](X0, t, U, PS, pm, CIRCUITS[circuit], method == 'adaptive',
                               rtol, model.abs_tol, int(substeps), XB, YB, status, N)
    return XB, YB, status


class _Lag:
    """A sampled signal seen ``periods`` sample periods late (a whole number or not): linearly
    interpolated between the two samples around it, as :func:`delayed` does offline; before
    the first sample it holds ``first``. A whole number of periods returns a sample itself."""

    def __init__(self, periods: float, first):
        whole = int(math.floor(periods + 1e-9))
        self.whole, self.fraction = whole, max(periods - whole, 0.0)
        if self.fraction < 1e-9:
            self.fraction = 0.0
        self._buf = deque([first] * (whole + 2), maxlen=whole + 2)

    def push(self, value):
        """Append the newest sample; returns the value seen now."""
        self._buf.append(value)
        now = self._buf[-1 - self.whole]
        if not self.fraction:
            return now
        return (1.0 - self.fraction) * now + self.fraction * self._buf[-2 - self.whole]

    @property
    def seen(self):
        """The value seen now (after the last :meth:`push`)."""
        now = self._buf[-1 - self.whole]
        if not self.fraction:
            return now
        return (1.0 - self.fraction) * now + self.fraction * self._buf[-2 - self.whole]


class Stepper:
    """Real-time plant: one :meth:`step` call advances one fixed control period.

    ``method='fixed'``: ``substeps`` classical RK4 substeps per period, at
    constant cost. ``method='adaptive'``: Dormand-Prince 5(4) substeps with
    error control (``rtol``), capped at ``max_substeps`` per period so the
    worst-case cost is bounded; more accurate and usually cheaper (see
    benchmarks/bench_model.py). A period that would need more than
    ``max_substeps`` is redone with fixed RK4 (``4 * substeps`` substeps), so
    the plant never stops; ``capped_periods`` counts such periods. Command
    and measurement delays of the components are applied as :func:`simulate`
    applies them, to any fraction of a period: the valve sees the command of
    ``d_in`` ago and :meth:`step` returns the state of ``d_out`` ago, each
    linearly interpolated between the samples around it (a delay of whole periods
    is exactly those samples). Before the start the valve sees ``command_v`` and
    the sensors the initial state. ``config`` gives other parameter values for
    the model's composition (default the model's own).
    """

    def __init__(self, model=None, period_s: float = 1e-3, substeps: int = 10,
                 x0=None, circuit: str = 'servo', command_v: float = 5.0,
                 supply_pa: float = None, method: str = 'adaptive',
                 rtol: float = DEFAULT_RTOL, max_substeps: int = 200,
                 config: ModelConfig = None):
        self.model = as_model(model)
        if not (period_s > 0 and substeps >= 1 and max_substeps >= 1):
            raise SimulationError('period_s must be > 0, substeps and max_substeps >= 1')
        if method not in ('fixed', 'adaptive'):
            raise SimulationError(f"unknown stepper method {method!r}; use 'fixed' or 'adaptive'")
        self.method, self.rtol, self.max_substeps = method, float(rtol), int(max_substeps)
        self._dt = period_s / 4
        self.capped_periods = 0
        self._atol = self.model.abs_tol
        self.period_s, self.substeps = float(period_s), int(substeps)
        self.circuit = CIRCUITS[circuit]
        cfg = config or self.model.config
        self.params = self.model.param_vector(cfg) if config is not None else self.model.params
        self.supply_pa = cfg.core['supply_pressure_pa'] if supply_pa is None else supply_pa
        self.x = (initial_state(self.model, command_v=command_v, supply_pa=self.supply_pa,
                                config=cfg, circuit=circuit)
                  if x0 is None else np.array(x0, dtype=float))
        self.t = 0.0
        self._c = np.zeros(N_CONTEXT)
        self._w = np.zeros((9, self.model.n_states))
        d_in, d_out = self.model.delays(cfg)
        self._command = _Lag(d_in / self.period_s, float(command_v))
        self._measured = _Lag(d_out / self.period_s, self.x.copy())

    def step(self, command_v: float, supply_pa: float = None) -> np.ndarray:
        """Advance one period with ``command_v`` [V]; returns the measured state."""
        if supply_pa is not None:
            self.supply_pa = supply_pa
        u = float(self._command.push(float(command_v)))
        k = self.model.kernels
        t0, x0 = self.t, self.x.copy()
        if self.method == 'fixed':
            status = k['fixed_interval'](self.t, self.x, u, self.supply_pa, self.params,
                                         self.circuit, self.period_s, self.substeps, self._c,
                                         self._w)
        else:
            before = x0
            k['rhs'](self.t, self.x, u, self.supply_pa, self.params, self.circuit, self._c,
                     self._w[0])
            status, self._dt = k['adaptive_interval'](
                self.t, self.x, u, self.supply_pa, self.params, self.circuit, self.period_s,
                min(self._dt, self.period_s), self.rtol, self._atol, self._c, self._w,
                self.max_substeps)
            if status == STEP_CAP:  # bounded work: finish this period at fixed cost
                self.capped_periods += 1
                self.x[:] = before
                self._dt = self.period_s / 4
                status = k['fixed_interval'](self.t, self.x, u, self.supply_pa, self.params,
                                             self.circuit, self.period_s, 4 * self.substeps,
                                             self._c, self._w)
        if status != 0:
            why = culprit.explain_status(
                self.model.layout, x0, np.array([t0, t0 + self.period_s]), np.array([u, u]),
                np.array([self.supply_pa] * 2, float), self.params, self.circuit,
                self.method == 'adaptive', self.rtol, self._atol, self.substeps)
            raise SimulationError(f'stepper failed at t = {self.t:.6g} s: {_STATUS[status]}'
                                  f'{why}')
        self.t += self.period_s
        return self._measured.push(self.x.copy())

    @property
    def measured(self) -> dict[str, float]:
        x = self._measured.seen
        return dict(zip(CORE_STATE_NAMES, x[:len(CORE_STATE_NAMES)]))
