"""The experiments' runs, before any sensor: a model driven by a test's signals from the state
a rig starts in, giving the true trajectories. :mod:`.designs` measures them through sensors
(the registry of experiments); the paper's figures draw them as they are.

One run per kind of experiment:

* :func:`sine_run`: the paper's open-loop servo test, a sine valve command (Section 6.3);
* :func:`blocked_run`: the pistons held, the valve (and supply) following a schedule: the
  charge/discharge (Section 6.2), heat-transfer (Fig. 12) and hidden-effect step tests;
* :func:`static_response`: a static circuit settling in time at a held voltage;
* :func:`closed_loop`: a control law of :mod:`pneumatic_servo.control` run at the DAQ rate
  on what the sensors show, the plant a :class:`~pneumatic_servo.model.Stepper`;

and :func:`start_state`, the states a rig is found in (:data:`STARTS`). Pressures are
absolute [Pa]; the paper's supplies are gauge readings (docs/model.md, section 1).
"""
from __future__ import annotations

import numpy as np

from ..control.measurement import Measurement
from ..control.reference import Reference
from ..effects.layout import OMEGA, P_A, P_B, THETA
from ..errors import SimulationError
from ..model.assembly import Model
from ..model.circuits import PAPER_SUPPLY_GAUGE_PA, STATIC_CIRCUITS, gauge_supply_pa
from ..model.config import ModelConfig
from ..model.simulate import SimResult, Stepper, as_model, initial_state, measured_states, simulate
from . import sensors as S

#: the states a run can start from (``start`` of :func:`start_state`)
STARTS = {
    'initial': 'at rest, both chambers at the mean of supply and atmosphere, gas at room '
               'temperature (the paper gives no start state)',
    'held': 'pistons held at the start angle, both chambers settled at the first command',
    'free': 'the shaft free from the start angle, settled at the first command for 3 s',
    'vented_a': 'chamber a vented to the atmosphere, chamber b charged to supply, gas at room '
                'temperature',
}


def held_at(config: ModelConfig, angle_rad: float) -> ModelConfig:
    """``config`` with the pistons held at ``angle_rad`` [rad] (the blocked circuit)."""
    cfg = config.copy()
    cfg.core['blocked_angle_rad'] = float(angle_rad)
    return cfg


def start_state(model: Model, config: ModelConfig, start: str, angle_rad: float | None,
                command_v: float, supply_pa: float) -> np.ndarray:
    """The state [SI] a run starts from: ``start`` one of :data:`STARTS`, at ``angle_rad``
    [rad] (None: mid-stroke), the valve at ``command_v`` [V], supply ``supply_pa`` [Pa]."""
    core = config.core
    if start == 'initial':
        return initial_state(model, angle_rad=angle_rad, command_v=command_v,
                             supply_pa=supply_pa, config=config)
    if start == 'vented_a':
        return initial_state(model, angle_rad=angle_rad, p_a_pa=core['atmospheric_pressure_pa'],
                             p_b_pa=supply_pa, command_v=command_v, supply_pa=supply_pa,
                             config=config)
    if start == 'held':
        held = held_at(config, angle_rad)
        mid = 0.5 * (supply_pa + core['atmospheric_pressure_pa'])
        x0 = initial_state(model, angle_rad=angle_rad, p_a_pa=mid, p_b_pa=mid,
                           command_v=command_v, supply_pa=supply_pa, config=held)
        t = np.arange(0.0, 1.5 + 1e-9, 5e-3)
        x = simulate(model, t, command_v, supply_pa, x0=x0, circuit='blocked',
                     config=held).states[-1].copy()
        x[OMEGA] = 0.0
        return x
    if start == 'free':
        x0 = initial_state(model, angle_rad=angle_rad, command_v=command_v, supply_pa=supply_pa,
                           config=config)
        # the physical state, not what a delayed measurement shows: the state the rig holds
        return simulate(model, np.arange(600) / 200.0, command_v, supply_pa, x0=x0,
                        config=config, measured=False).states[-1].copy()
    raise SimulationError(f'unknown start {start!r}; use one of {", ".join(STARTS)}')


def _grid(duration_s: float, sample_s: float) -> np.ndarray:
    if not (duration_s > 0 and sample_s > 0 and duration_s / sample_s >= 1):
        raise SimulationError('duration_s and sample_s must be positive, duration >= sample')
    return np.arange(int(round(duration_s / sample_s)) + 1) * sample_s


def _paper_supply(config: ModelConfig, supply_pa: float | None) -> float:
    return gauge_supply_pa(PAPER_SUPPLY_GAUGE_PA, config) if supply_pa is None else supply_pa


# --------------------------------------------------------------------------- the sine
def sine_command(t: np.ndarray, mean_v: float = 5.0, amplitude_v: float = 0.35,
                 frequency_hz: float = 2.0) -> np.ndarray:
    """Valve command [V] of the paper's servo verification: mean + amplitude sin(2 pi f t)."""
    return mean_v + amplitude_v * np.sin(2.0 * np.pi * frequency_hz * np.asarray(t))


def sine_run(model: Model, config: ModelConfig, t: np.ndarray, supply_pa: float,
             start='initial', angle_rad: float | None = None, mean_v: float = 5.0,
             amplitude_v: float = 0.35, frequency_hz: float = 2.0,
             method: str = 'adaptive') -> SimResult:
    """The open-loop servo under :func:`sine_command` at times ``t`` [s], from ``start`` (one
    of :data:`STARTS` at ``angle_rad``, settled at ``mean_v``; or a state vector)."""
    u = sine_command(t, mean_v, amplitude_v, frequency_hz)
    x0 = start if not isinstance(start, str) else \
        start_state(model, config, start, angle_rad, mean_v, supply_pa)
    return simulate(model, t, u, supply_pa, x0=x0, method=method, config=config)


def sine_response(model=None, supply_pa: float | None = None, mean_v: float = 5.0,
                  amplitude_v: float = 0.35, frequency_hz: float = 2.0,
                  duration_s: float = 10.0, sample_s: float = 1e-3, x0=None,
                  method: str = 'adaptive', config: ModelConfig | None = None) -> SimResult:
    """Open-loop servo response to a sine valve command (Section 6.3, Figs 24-26).

    Parameters
    ----------
    model : Model, ModelConfig or None
        The model (None: the paper's).
    supply_pa : float [Pa, absolute]
        Supply pressure; default 0.6 MPa gauge.
    mean_v, amplitude_v : float [V]
        Command mean and amplitude (paper: 5 +/- 0.35 V, i.e. 4.65-5.35 V).
    frequency_hz : float [Hz]
        Command frequency (paper: 2 Hz).
    duration_s, sample_s : float [s]
        Length of the record and sample period (1 kHz by default).
    x0 : array, optional
        Initial state; default the ``initial`` start of :data:`STARTS` at mid-stroke.
    method : str
        'adaptive' (offline) or 'fixed' (real-time RK4).
    config : ModelConfig, optional
        Parameter values for the same composition.

    Returns
    -------
    SimResult
        Circuit 'servo'.
    """
    model = as_model(model)
    cfg = config or model.config
    return sine_run(model, cfg, _grid(duration_s, sample_s), _paper_supply(cfg, supply_pa),
                    'initial' if x0 is None else x0, None, mean_v, amplitude_v, frequency_hz,
                    method)


# ------------------------------------------------------------------ the blocked circuit
def blocked_run(model: Model, config: ModelConfig, t: np.ndarray, command_v, supply_pa,
                angle_rad: float, start: str = 'held', method: str = 'adaptive') -> SimResult:
    """The pistons held at ``angle_rad`` [rad], the valve following ``command_v`` [V] and the
    supply ``supply_pa`` [Pa] (scalars or arrays like ``t`` [s]), from ``start`` (one of
    :data:`STARTS`) at the first command and supply."""
    cfg = held_at(config, angle_rad)
    x0 = start_state(model, cfg, start, angle_rad, float(np.ravel(command_v)[0]),
                     float(np.ravel(supply_pa)[0]))
    return simulate(model, t, command_v, supply_pa, x0=x0, circuit='blocked', method=method,
                    config=cfg)


def charge_discharge(model=None, supply_pa: float | None = None, start_v: float = 5.0,
                     step_v: float = 5.5, step_time_s: float = 0.1, duration_s: float = 6.0,
                     sample_s: float = 1e-3, method: str = 'adaptive',
                     config: ModelConfig | None = None) -> SimResult:
    """Charge/discharge test (Figs 21-23): pistons held, valve stepped ``start_v`` -> ``step_v``.

    Parameters
    ----------
    start_v, step_v : float [V]
        Valve command before and after the step (paper: 5 V -> 5.5 V).
    step_time_s : float [s]
        Time of the step.
    model, supply_pa, duration_s, sample_s, method, config
        As :func:`sine_response` (supply default 0.6 MPa gauge, as in the paper).

    Returns
    -------
    SimResult
        Circuit 'blocked'; pistons at ``core.blocked_angle_rad``.

    Notes
    -----
    The paper withholds the start values of p_a and p_b. The run starts from ``vented_a``
    (:data:`STARTS`): the state of a rig where a was vented and b charged before the test,
    so that a charges and b discharges over the whole record. The short hold at
    ``start_v`` shows the (already unbalanced) centre before the step.
    """
    model = as_model(model)
    cfg = config or model.config
    t = _grid(duration_s, sample_s)
    return blocked_run(model, cfg, t, np.where(t < step_time_s, start_v, step_v),
                       _paper_supply(cfg, supply_pa), cfg.core['blocked_angle_rad'],
                       'vented_a', method)


# -------------------------------------------------------------------- static circuits
def static_response(model=None, circuit: str = 'closed_port', voltage_v: float = 5.0,
                    supply_pa: float | None = None, duration_s: float = 1.0,
                    sample_s: float = 1e-3, method: str = 'adaptive',
                    config: ModelConfig | None = None) -> SimResult:
    """A static circuit simulated in time from atmosphere at a held ``voltage_v`` [V].

    The valve chamber starts at atmospheric pressure and room temperature
    (chamber b, held still, at supply); the record approaches the steady
    state of :func:`pneumatic_servo.model.circuits.steady_state`.
    """
    model = as_model(model)
    cfg = config or model.config
    if circuit not in STATIC_CIRCUITS:
        raise SimulationError(f'static_response needs {" or ".join(STATIC_CIRCUITS)}, '
                              f'not {circuit!r}')
    ps = cfg.core['supply_pressure_pa'] if supply_pa is None else supply_pa
    pe = cfg.core['atmospheric_pressure_pa']
    x0 = initial_state(model, p_a_pa=pe, p_b_pa=ps, t_b_k=cfg.core['supply_temperature_k'],
                       command_v=voltage_v, supply_pa=ps, config=cfg)
    return simulate(model, _grid(duration_s, sample_s), voltage_v, ps, x0=x0,
                    circuit=circuit, method=method, config=cfg)


# ------------------------------------------------------------------------ closed loop
def closed_loop(model: Model, config: ModelConfig, setpoint_rad: np.ndarray, x0: np.ndarray,
                law, rate_hz: float, supply_pa: float, sensors: S.SensorModel,
                velocity: bool = True, command_v: float = 5.0
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A position loop: ``law`` (a :class:`~pneumatic_servo.control.ControlLaw`) run at
    ``rate_hz`` [Hz] towards ``setpoint_rad`` (one value per sample), the plant a
    :class:`~pneumatic_servo.model.Stepper` of ``config`` started at ``x0`` with the valve
    at ``command_v`` [V].

    The law sees what the sensors show (the components' measurement delays and sensor
    errors, each evaluated at the sample alone; the recorded ``shown`` states evaluate them
    over the whole record, so a sensor error with memory, such as play, is recorded with
    it): the quantised encoder angle, the encoder velocity over
    ``sensors.velocity_window_s`` if the DAQ computes one (``velocity``; otherwise the law
    differentiates the angle), the chamber pressures without their noise, and the supply.

    Returns
    -------
    (command, shown, physical) : numpy.ndarray
        Command [V] per sample, the states (n, n_states) the sensors show before their noise,
        and the physical states.
    """
    dt = 1.0 / rate_hz
    n = len(setpoint_rad)
    # error-controlled substeps with a generous cap: the stick/slip switching is stiff
    plant = Stepper(model, dt, x0=x0, command_v=command_v, supply_pa=supply_pa,
                    max_substeps=20000, config=config)
    errors = any(c.sensor_error is not None for c in model.layout.classes)
    window = max(1, int(round(sensors.velocity_window_s * rate_hz)))
    u, angles = np.empty(n), np.empty(n)
    shown, physical = np.empty((n, model.n_states)), np.empty((n, model.n_states))
    seen, before = np.array(x0, dtype=float), command_v
    seen_all = np.empty((n, model.n_states))
    for k in range(n):
        physical[k], seen_all[k] = plant.x, seen
        shown[k] = measured_states(model, config, np.zeros(1), seen[None], np.array([before]),
                                   np.array([supply_pa]))[0] if errors else seen
        angles[k] = S.quantise(shown[k, THETA], sensors.encoder_step_rad)
        back = min(k, window)
        omega = (angles[k] - angles[k - back]) / (back * dt) if back else 0.0
        m = Measurement(k * dt, angles[k], omega if velocity else np.nan, shown[k, P_A],
                        shown[k, P_B], supply_pa)
        u[k] = before = law.update(k * dt, Reference(float(setpoint_rad[k])), m)
        if k < n - 1:
            seen = plant.step(u[k])
    if errors:  # over the whole record: the same values where an error has no memory
        shown = measured_states(model, config, np.arange(n) * dt, seen_all,
                                np.concatenate([[command_v], u[:-1]]),
                                np.full(n, supply_pa))
    return u, shown, physical


__all__ = ['STARTS', 'start_state', 'held_at', 'sine_command', 'sine_run', 'sine_response',
           'blocked_run', 'charge_discharge', 'static_response', 'closed_loop']
