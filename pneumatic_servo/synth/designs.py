"""Experiment designs: every experiment of the paper, run on a model through realistic sensors.

Each design is a function ``(ctx) -> Experiment``; :func:`make_experiment`
runs one by name on any :class:`~pneumatic_servo.model.ModelConfig` (with
or without catalogue effects), so other generators (e.g. hidden-effect test
data) reuse the designs and sensors unchanged.

Supply pressures follow MODEL_NOTES 1: the paper's 0.5/0.6/0.7/0.83 MPa are
gauge readings; the model and the recorded signals use absolute pressure.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import ConfigError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.circuits import steady_outputs
from ..model.config import ModelConfig
from ..model.simulate import Stepper, initial_state, simulate
from . import sensors as S

#: paper's servo and charge/discharge supply [Pa, gauge]
SERVO_SUPPLY_GAUGE_PA = 0.6e6
#: paper's flow-rate test supplies [Pa, gauge] (Section 5.1 at 0.6, Section 6.1 the others)
FLOW_SUPPLIES_GAUGE_PA = (0.5e6, 0.6e6, 0.7e6, 0.83e6)
#: Table 5 voltages of the closed-port test [V]
CLOSED_PORT_VOLTS = (5.0, 5.1, 5.3, 5.5, 5.75, 6.0, 6.5, 7.0, 8.0, 9.0, 10.0)
#: friction runs (paper Fig. 17 at 5.07 V, and others) [V]
FRICTION_VOLTS = (5.07, 5.12, 5.2, 5.3, 5.45, 5.7)
#: the supply transmitter for tests above 0.6 MPa gauge has a 1 MPa range [Pa]
HIGH_RANGE_FS_PA = 1.0e6


@dataclass
class Context:
    """What a design needs: the rig's model and config, noise source, sensors, options."""

    config: ModelConfig
    model: Model
    rng: np.random.Generator
    sensors: S.SensorModel
    options: dict = field(default_factory=dict)

    @property
    def core(self) -> dict:
        return self.config.core

    def supply(self, gauge_pa: float) -> float:
        """Absolute supply pressure [Pa] of a gauge reading."""
        return gauge_pa + self.core['atmospheric_pressure_pa']

    def time(self, duration_s: float) -> np.ndarray:
        rate = self.sensors.rate_hz
        return np.arange(int(round(duration_s * rate)) + 1) / rate


@dataclass(frozen=True)
class Design:
    """One experiment of the library: how it is run and what it is for."""

    name: str
    circuit: str
    static: bool
    summary: str
    run: Callable[[Context], Experiment]
    #: storage of the generated bag (the library mixes sqlite3 and MCAP)
    storage: str = 'mcap'


# ------------------------------------------------------------------------ helpers
def _blocked_config(ctx: Context, angle_rad: float) -> ModelConfig:
    cfg = ctx.config.copy()
    cfg.core['blocked_angle_rad'] = float(angle_rad)
    return cfg


def _settle_blocked(ctx: Context, cfg: ModelConfig, command_v: float, supply_pa: float,
                    angle_rad: float, settle_s: float = 1.5) -> np.ndarray:
    """State of the held pistons after ``command_v`` [V] for ``settle_s`` [s] (p and T settled)."""
    t = np.arange(0.0, settle_s + 1e-9, 5e-3)
    pe = ctx.core['atmospheric_pressure_pa']
    x0 = initial_state(ctx.model, angle_rad=angle_rad, p_a_pa=0.5 * (supply_pa + pe),
                       p_b_pa=0.5 * (supply_pa + pe), command_v=command_v, supply_pa=supply_pa,
                       config=cfg)
    res = simulate(ctx.model, t, command_v, supply_pa, x0=x0, circuit='blocked', config=cfg)
    x = res.states[-1].copy()
    x[1] = 0.0
    return x


def _servo_start(ctx: Context, command_v: float, supply_pa: float, angle_rad: float
                 ) -> np.ndarray:
    """The shaft at rest at ``angle_rad`` with the pressures ``command_v`` settles to, held."""
    cfg = _blocked_config(ctx, angle_rad)
    return _settle_blocked(ctx, cfg, command_v, supply_pa, angle_rad)


def _series(ctx: Context, t, res, keep, name, circuit, u, ps, extra_meta=None,
            velocity=True) -> Experiment:
    true = {'command_v': u, 'supply_pa': ps}
    for key in keep:
        true[key] = res[key]
    sig = S.measure(t, true, ctx.rng, ctx.sensors, velocity=velocity and 'angle_rad' in keep)
    return Experiment(t, sig, circuit, name, False, dict(extra_meta or {}))


# ------------------------------------------------------------------------ static tables
def _flow_table(gauge_pa: float):
    def run(ctx: Context) -> Experiment:
        ps = ctx.supply(gauge_pa)
        volts = np.round(np.arange(5.0, 10.0 + 1e-9, ctx.options.get('step_v', 0.25)), 3)
        rows = [steady_outputs(ctx.model, 'flow', float(v), ps, ctx.config) for v in volts]
        true = {'command_v': volts, 'supply_pa': np.full(len(volts), ps),
                'p_a_pa': np.array([r['p_a_pa'] for r in rows]),
                'm4_kg_s': np.array([r['m4_kg_s'] for r in rows]),
                'm5_kg_s': np.array([r['m5_kg_s'] for r in rows]),
                't_s_k': np.full(len(volts), ctx.core['supply_temperature_k'])}
        sig = S.measure_static(true, ctx.rng, ctx.sensors.with_full_scale(HIGH_RANGE_FS_PA))
        return Experiment(np.arange(len(volts), dtype=float), sig, 'flow', '', True,
                          {'supply_gauge_pa': gauge_pa})
    return run


def _closed_port(ctx: Context) -> Experiment:
    volts, supplies = [], []
    for gauge in (0.5e6, 0.7e6, 0.83e6):
        volts += list(CLOSED_PORT_VOLTS)
        supplies += [ctx.supply(gauge)] * len(CLOSED_PORT_VOLTS)
    rows = [steady_outputs(ctx.model, 'closed_port', v, p, ctx.config)
            for v, p in zip(volts, supplies)]
    true = {'command_v': np.array(volts), 'supply_pa': np.array(supplies),
            'p_a_pa': np.array([r['p_a_pa'] for r in rows]),
            't_s_k': np.full(len(volts), ctx.core['supply_temperature_k'])}
    sig = S.measure_static(true, ctx.rng, ctx.sensors.with_full_scale(HIGH_RANGE_FS_PA))
    return Experiment(np.arange(len(volts), dtype=float), sig, 'closed_port', '', True, {})


# ------------------------------------------------------------------ blocked circuit
def _heat_transfer(ctx: Context) -> Experiment:
    """Fig. 12: chamber a (pistons held with a at its largest) charged, then discharged."""
    angle = ctx.core['stroke_rad']
    cfg = _blocked_config(ctx, angle)
    ps = ctx.supply(SERVO_SUPPLY_GAUGE_PA)
    charge_v = ctx.options.get('charge_v', 7.0)
    discharge_v = ctx.options.get('discharge_v', 4.3)
    t = ctx.time(ctx.options.get('duration_s', 2.5))
    u = np.where(t < 0.2, charge_v, discharge_v)
    x0 = _settle_blocked(ctx, cfg, charge_v, ps, angle)
    res = simulate(ctx.model, t, u, ps, x0=x0, circuit='blocked', config=cfg)
    return _series(ctx, t, res, ('p_a_pa', 'p_b_pa', 't_a_k', 't_b_k'), '', 'blocked', u,
                   np.full_like(t, ps), {'blocked_angle_rad': angle})


def _charge_discharge(ctx: Context) -> Experiment:
    """Section 6.2: pistons held at an end, 0.6 MPa, valve 5 V -> 5.5 V."""
    angle = ctx.options.get('angle_rad', 0.0)
    cfg = _blocked_config(ctx, angle)
    ps = ctx.supply(SERVO_SUPPLY_GAUGE_PA)
    t = ctx.time(ctx.options.get('duration_s', 2.0))
    u = np.where(t < 0.2, 5.0, 5.5)
    x0 = _settle_blocked(ctx, cfg, 5.0, ps, angle)
    res = simulate(ctx.model, t, u, ps, x0=x0, circuit='blocked', config=cfg)
    return _series(ctx, t, res, ('p_a_pa', 'p_b_pa', 't_a_k', 't_b_k'), '', 'blocked', u,
                   np.full_like(t, ps), {'blocked_angle_rad': angle})


# ---------------------------------------------------------------- servo, open loop
def _friction(volts: float):
    def run(ctx: Context) -> Experiment:
        """Fig. 17: from rest at the a end (pushed there at 4 V), the valve held at ``volts``."""
        ps = ctx.supply(SERVO_SUPPLY_GAUGE_PA)
        push_v = 4.0 if volts > 5.0 else 6.0
        start = 0.0 if volts > 5.0 else ctx.core['stroke_rad']
        duration = ctx.options.get('duration_s', _friction_duration(volts))
        t = ctx.time(duration)
        u = np.where(t < 0.2, push_v, volts)
        x0 = _servo_start(ctx, push_v, ps, start)
        res = simulate(ctx.model, t, u, ps, x0=x0, config=ctx.config)
        return _series(ctx, t, res, ('angle_rad', 'p_a_pa', 'p_b_pa'), '', 'servo', u,
                       np.full_like(t, ps), {'held_voltage_v': volts})
    return run


def _friction_duration(volts: float) -> float:
    """Record length [s]: long enough for steady motion, short of the far end stop."""
    return {5.07: 1.6, 5.12: 1.6, 5.2: 1.6, 5.3: 1.5, 5.45: 1.1, 5.7: 0.8}.get(volts, 1.5)


def _sine(ctx: Context) -> Experiment:
    """Section 6.3: 0.6 MPa, valve 5 +/- 0.35 V at 2 Hz, recorded after a 1 s run-in."""
    ps = ctx.supply(SERVO_SUPPLY_GAUGE_PA)
    pre = ctx.options.get('run_in_s', 1.0)
    t_all = ctx.time(pre + ctx.options.get('duration_s', 4.0))
    u_all = 5.0 + ctx.options.get('amplitude_v', 0.35) * np.sin(2.0 * math.pi * 2.0 * t_all)
    x0 = _servo_start(ctx, 5.0, ps, ctx.options.get('angle_rad', 0.45 * ctx.core['stroke_rad']))
    res = simulate(ctx.model, t_all, u_all, ps, x0=x0, config=ctx.config)
    # the record starts once the oscillation has settled, as a DAQ started mid-run does
    k0 = int(round(pre * ctx.sensors.rate_hz))
    t = t_all[k0:] - t_all[k0]
    true = {'command_v': u_all[k0:], 'supply_pa': np.full_like(t, ps),
            'angle_rad': res.angle_rad[k0:], 'p_a_pa': res.p_a_pa[k0:],
            'p_b_pa': res.p_b_pa[k0:]}
    return Experiment(t, S.measure(t, true, ctx.rng, ctx.sensors), 'servo', '', False, {})


# -------------------------------------------------------------- servo, closed loop
@dataclass
class PID:
    """Position PID at the DAQ rate on the encoder angle: u = 5 V + Kp e + Ki int(e) - Kd w."""

    kp: float = 2.0        # [V/rad]
    ki: float = 1.0        # [V/(rad.s)]
    kd: float = 0.05       # [V.s/rad], on the encoder velocity, not on the error
    null_v: float = 5.0
    integral_limit_v: float = 0.5
    integral: float = 0.0

    def __call__(self, setpoint: float, angle: float, velocity: float, dt: float) -> float:
        error = setpoint - angle
        self.integral = min(max(self.integral + self.ki * error * dt, -self.integral_limit_v),
                            self.integral_limit_v)
        u = self.null_v + self.kp * error + self.integral - self.kd * velocity
        return min(max(u, 0.0), 10.0)


def closed_loop(ctx: Context, setpoint: np.ndarray, start_rad: float, pid: PID | None = None
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run the plant (the model's Stepper) under a PID at the DAQ rate.

    The controller sees what the rig records: the quantised encoder angle
    and the encoder velocity (:func:`sensors.encoder_velocity`). Returns the
    time [s], command [V] and the measured-state rows (n, n_states).
    """
    pid = pid or PID(**ctx.options.get('pid', {}))
    ps = ctx.supply(SERVO_SUPPLY_GAUGE_PA)
    dt = 1.0 / ctx.sensors.rate_hz
    n = len(setpoint)
    x0 = _servo_start(ctx, 5.0, ps, start_rad)
    # error-controlled substeps; a generous cap, because the stick/slip switching is stiff
    # the Stepper takes its parameter values from its model's config: build one for this config
    # (the compiled kernels are shared, so this costs nothing)
    plant = Stepper(Model(ctx.config), dt, x0=x0, command_v=5.0, supply_pa=ps,
                    max_substeps=20000)
    window = max(1, int(round(ctx.sensors.velocity_window_s * ctx.sensors.rate_hz)))
    states = np.empty((n, len(x0)))
    u = np.empty(n)
    angles = np.empty(n)
    x = x0
    for k in range(n):
        states[k] = x
        angles[k] = S.quantise(x[0], ctx.sensors.encoder_step_rad)
        back = min(k, window)
        vel = (angles[k] - angles[k - back]) / (back * dt) if back else 0.0
        u[k] = pid(setpoint[k], angles[k], vel, dt)
        x = plant.step(u[k])
    return np.arange(n) * dt, u, states


def _steps(ctx: Context) -> Experiment:
    """Closed-loop steps between setpoints inside the stroke."""
    levels = ctx.options.get('levels_rad', (0.8, 2.0, 1.2, 2.4))
    hold = ctx.options.get('hold_s', 1.0)
    t = ctx.time(hold * len(levels))
    sp = np.array([levels[min(int(tk // hold), len(levels) - 1)] for tk in t])
    return _closed_loop_experiment(ctx, sp, levels[0])


def _sine_tracking(ctx: Context) -> Experiment:
    """Closed-loop tracking of a 0.5 Hz sine setpoint about mid-stroke."""
    t = ctx.time(ctx.options.get('duration_s', 4.0))
    mid = 0.5 * ctx.core['stroke_rad']
    sp = mid + ctx.options.get('amplitude_rad', 0.6) * np.sin(2.0 * math.pi * 0.5 * t)
    return _closed_loop_experiment(ctx, sp, mid)


def _closed_loop_experiment(ctx: Context, setpoint: np.ndarray, start: float) -> Experiment:
    # a run-in at the first setpoint, not recorded: the record starts with the loop settled
    pre = int(round(ctx.options.get('run_in_s', 0.5) * ctx.sensors.rate_hz))
    t, u, X = closed_loop(ctx, np.concatenate([np.full(pre, setpoint[0]), setpoint]), start)
    t, u, X = t[pre:] - t[pre], u[pre:], X[pre:]
    ps = np.full_like(t, ctx.supply(SERVO_SUPPLY_GAUGE_PA))
    true = {'command_v': u, 'supply_pa': ps, 'angle_rad': X[:, 0], 'p_a_pa': X[:, 2],
            'p_b_pa': X[:, 3]}
    sig = S.measure(t, true, ctx.rng, ctx.sensors)
    sig['setpoint_rad'] = setpoint
    return Experiment(t, sig, 'servo')


# -------------------------------------------------------------------------- registry
def _designs() -> dict[str, Design]:
    out = {}

    def add(d: Design):
        out[d.name] = d

    for gauge in FLOW_SUPPLIES_GAUGE_PA:
        label = f'{gauge / 1e6:g}'
        add(Design(f'flow_{label}MPa', 'flow', True,
                   f'flow-rate test (Fig. 10), supply {label} MPa gauge, 5-10 V in 0.25 V steps: '
                   'M4, M5, p_a, T_s', _flow_table(gauge)))
    add(Design('closed_port', 'closed_port', True,
               'closed-port test (Table 5): steady p_a at 5-10 V, supplies 0.5/0.7/0.83 MPa '
               'gauge', _closed_port))
    add(Design('heat_transfer', 'blocked', False,
               'heat-transfer test (Fig. 12): pistons held with chamber a largest, a charged at '
               '7 V then discharged at 4.3 V; p_a, p_b, T_a, T_b', _heat_transfer,
               storage='sqlite3'))
    add(Design('charge_discharge', 'blocked', False,
               'charge/discharge (Section 6.2): pistons held at theta = 0, 0.6 MPa, 5 V -> 5.5 V',
               _charge_discharge))
    for volts in FRICTION_VOLTS:
        # the library mixes storages: the shortest friction run is a sqlite3 bag
        add(Design(f'friction_{volts:.2f}V', 'servo', False,
                   f'friction run (Fig. 17): from rest at theta = 0, valve held at {volts:.2f} V, '
                   '0.6 MPa', _friction(volts),
                   storage='sqlite3' if volts == FRICTION_VOLTS[-1] else 'mcap'))
    add(Design('sine_2hz', 'servo', False,
               'open-loop servo verification (Section 6.3): 5 +/- 0.35 V at 2 Hz, 0.6 MPa',
               _sine))
    add(Design('closed_loop_steps', 'servo', False,
               'closed-loop PID steps 0.8 -> 2.0 -> 1.2 -> 2.4 rad, 1 s each', _steps))
    add(Design('closed_loop_sine', 'servo', False,
               'closed-loop PID tracking 1.66 +/- 0.6 rad at 0.5 Hz', _sine_tracking))
    return out


DESIGNS = _designs()


def make_experiment(config: ModelConfig, design_name: str, seed: int = 0,
                    sensors: S.SensorModel | None = None, model: Model | None = None,
                    **options) -> Experiment:
    """Run design ``design_name`` on ``config`` and measure it with ``sensors``.

    Parameters
    ----------
    config : ModelConfig
        The rig: any composition, including catalogue effects.
    design_name : str
        A key of :data:`DESIGNS`.
    seed : int
        Seed of the measurement noise (same seed, same record).
    sensors : SensorModel, optional
        Instruments (default: the paper's rig, :class:`SensorModel`).
    model : Model, optional
        A compiled model of ``config``'s composition, to reuse (saves ~4 s).
    options
        Design options (e.g. ``duration_s``, ``discharge_v``, ``pid={...}``).

    Returns
    -------
    Experiment
        Measured signals, labelled synthetic, with the design and truth in metadata.
    """
    if design_name not in DESIGNS:
        raise ConfigError(f'unknown experiment design {design_name!r}; use one of '
                          f'{", ".join(DESIGNS)}')
    design = DESIGNS[design_name]
    sensors = sensors or S.SensorModel()
    if model is None or model.layout.classes != tuple(config.component_classes()):
        model = Model(config)
    ctx = Context(config, model, np.random.default_rng(seed), sensors, dict(options))
    exp = design.run(ctx)
    exp.name = design.name
    exp.metadata.update({
        'synthetic': True, 'design': design.name, 'description': design.summary,
        'seed': int(seed), 'options': _plain(options), 'sensors': sensors.describe(),
        'truth': config.to_dict(),
        'generator': 'pneumatic_servo.synth.make_experiment (pneumatic-servo generate)'})
    return exp


def _plain(value):
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value
