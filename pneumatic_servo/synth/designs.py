"""Experiment designs: every experiment the package generates, run on a model through
realistic sensors. :data:`DESIGNS` is the one registry of them.

Each design is a function ``(ctx) -> Experiment`` built on the runs of :mod:`.runs`;
:func:`make_experiment` runs one by name on any :class:`~pneumatic_servo.model.ModelConfig`
(with or without catalogue effects). The bundled library (``bags/``) is the designs with
``library`` set, on the synthetic rig; the hidden-effect sets (:mod:`.hidden`) run the 2 Hz
sine with their own start and the designs made for them (``library`` unset) on rigs with
effects hidden, sharing one noise source through :func:`run`.

Supply pressures follow docs/model.md (section 1): the paper's 0.5/0.6/0.7/0.83 MPa are
gauge readings; the model and the recorded signals use absolute pressure.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from ..control.pid import PidController
from ..errors import ConfigError
from ..experiment import Experiment
from ..jsonable import plain
from ..model.assembly import Model
from ..model.circuits import (
    PAPER_FLOW_SUPPLIES_GAUGE_PA,
    PAPER_SUPPLY_GAUGE_PA,
    PAPER_TABLE5_VOLTAGES_V,
    steady_outputs,
)
from ..model.config import ModelConfig
from ..model.simulate import simulate
from . import runs
from . import sensors as S

#: paper's flow-rate test supplies [Pa, gauge] (Section 5.1 at 0.6, Section 6.1 the others)
FLOW_SUPPLIES_GAUGE_PA = tuple(sorted((PAPER_SUPPLY_GAUGE_PA,) + PAPER_FLOW_SUPPLIES_GAUGE_PA))
#: friction runs (paper Fig. 17 at 5.07 V, and others) [V]
FRICTION_VOLTS = (5.07, 5.12, 5.2, 5.3, 5.45, 5.7)
#: the supply transmitter for tests above 0.6 MPa gauge has a 1 MPa range [Pa]
HIGH_RANGE_FS_PA = 1.0e6
#: the library's closed loop: position PID at the DAQ rate on the encoder angle, derivative on
#: the DAQ's encoder velocity, integral within +/- 0.5 V (names of ``control.PID_SPECS``)
LIBRARY_PID = {'kp': 2.0, 'ki': 1.0, 'kd': 0.05, 'integral_limit_v': 0.5,
               'integral_zone_rad': 10.0, 'kdp': 0.0, 'kv': 0.0, 'friction_v': 0.0,
               'velocity_filter_s': 0.0}
#: the hidden-effect sets' closed loop: PD on the encoder angle, its velocity the angle's
#: difference through a 10 ms first-order filter (rate-dependent: see :func:`_mixed`)
HIDDEN_PD = {'kp': 2.0, 'ki': 0.0, 'kd': 0.02, 'kdp': 0.0, 'kv': 0.0, 'friction_v': 0.0}


@dataclass
class Context:
    """What a design needs: the rig's model and config, noise source, sensors, options, and
    how the DAQ records: whether it computes a velocity from the encoder (``velocity``) and
    whether a record of ``d`` seconds ends at ``t = d`` (``endpoint``) or a sample before."""

    config: ModelConfig
    model: Model
    rng: np.random.Generator
    sensors: S.SensorModel
    options: dict = field(default_factory=dict)
    velocity: bool = True
    endpoint: bool = True

    @property
    def core(self) -> dict:
        return self.config.core

    def supply(self, gauge_pa: float = PAPER_SUPPLY_GAUGE_PA) -> float:
        """Absolute supply pressure [Pa] of a gauge reading (default the paper's 0.6 MPa)."""
        return gauge_pa + self.core['atmospheric_pressure_pa']

    def time(self, duration_s: float) -> np.ndarray:
        rate = self.sensors.rate_hz
        return np.arange(int(round(duration_s * rate)) + int(self.endpoint)) / rate


@dataclass(frozen=True)
class Design:
    """One experiment: how it is run and what it is for."""

    name: str
    circuit: str
    static: bool
    summary: str
    run: Callable[[Context], Experiment]
    #: storage of the generated bag (the library mixes sqlite3 and MCAP)
    storage: str = 'mcap'
    #: a record of the bundled library (``bags/``, :func:`.library.generate_library`)
    library: bool = True


# ------------------------------------------------------------------------ helpers
def _series(ctx: Context, t, res, keep, circuit, extra_meta=None, start: int = 0
            ) -> Experiment:
    """The record of run ``res`` from sample ``start``: command, supply and ``keep`` measured."""
    rec = slice(start, None)
    true = {'command_v': res['command_v'][rec], 'supply_pa': res['supply_pa'][rec]}
    for key in keep:
        true[key] = res[key][rec]
    sig = S.measure(t, true, ctx.rng, ctx.sensors,
                    velocity=ctx.velocity and 'angle_rad' in keep)
    return Experiment(t, sig, circuit, '', False, dict(extra_meta or {}))


def _table(ctx: Context, circuit: str, true: dict, full_scale_pa: float | None = None,
           meta=None) -> Experiment:
    sensors = ctx.sensors if full_scale_pa is None else ctx.sensors.with_full_scale(full_scale_pa)
    sig = S.measure_static(true, ctx.rng, sensors)
    n = len(true['command_v'])
    return Experiment(np.arange(n, dtype=float), sig, circuit, '', True, dict(meta or {}))


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
        return _table(ctx, 'flow', true, HIGH_RANGE_FS_PA, {'supply_gauge_pa': gauge_pa})
    return run


def _closed_port(ctx: Context) -> Experiment:
    volts, supplies = [], []
    for gauge in PAPER_FLOW_SUPPLIES_GAUGE_PA:
        volts += list(PAPER_TABLE5_VOLTAGES_V)
        supplies += [ctx.supply(gauge)] * len(PAPER_TABLE5_VOLTAGES_V)
    rows = [steady_outputs(ctx.model, 'closed_port', v, p, ctx.config)
            for v, p in zip(volts, supplies)]
    true = {'command_v': np.array(volts), 'supply_pa': np.array(supplies),
            'p_a_pa': np.array([r['p_a_pa'] for r in rows]),
            't_s_k': np.full(len(volts), ctx.core['supply_temperature_k'])}
    return _table(ctx, 'closed_port', true, HIGH_RANGE_FS_PA)


def _settled_table(circuit: str):
    def run(ctx: Context) -> Experiment:
        """Each row simulated in time until it settles (independently of the steady-state
        solver the diagnosis uses), at held voltages and two supplies 0.1 MPa either side
        of the paper's."""
        blocked = circuit == 'blocked'
        volts = (np.round(np.linspace(4.0, 6.0, 9), 3) if blocked else
                 np.round(np.concatenate([np.linspace(4.0, 6.0, 21), [6.5, 7.0, 8.0, 10.0]]),
                          3))
        rows = []
        for supply in (ctx.supply() - 1e5, ctx.supply() + 1e5):
            for v in volts:
                # the blocked chambers near the centre fill through the valve's small leaks
                res = runs.static_response(ctx.model, circuit, float(v), supply,
                                           duration_s=12.0 if blocked else 1.0, sample_s=2e-3,
                                           config=ctx.config)
                rows.append((v, supply, res.p_a_pa[-1], res.p_b_pa[-1], res['m4_kg_s'][-1],
                             res['m5_kg_s'][-1]))
        rows = np.array(rows)
        true = {'command_v': rows[:, 0], 'supply_pa': rows[:, 1], 'p_a_pa': rows[:, 2]}
        if blocked:
            true['p_b_pa'] = rows[:, 3]
        if circuit == 'flow':
            true.update(m4_kg_s=rows[:, 4], m5_kg_s=rows[:, 5])
        return _table(ctx, circuit, true)
    return run


# ------------------------------------------------------------------ blocked circuit
def _heat_transfer(ctx: Context) -> Experiment:
    """Fig. 12: chamber a (pistons held with a at its largest) charged, then discharged."""
    angle = ctx.core['stroke_rad']
    t = ctx.time(ctx.options.get('duration_s', 2.5))
    u = np.where(t < 0.2, ctx.options.get('charge_v', 7.0), ctx.options.get('discharge_v', 4.3))
    res = runs.blocked_run(ctx.model, ctx.config, t, u, ctx.supply(), angle)
    return _series(ctx, t, res, ('p_a_pa', 'p_b_pa', 't_a_k', 't_b_k'), 'blocked',
                   {'blocked_angle_rad': angle})


def _charge_discharge(ctx: Context) -> Experiment:
    """Section 6.2: pistons held at an end, 0.6 MPa, valve 5 V -> 5.5 V."""
    angle = ctx.options.get('angle_rad', 0.0)
    t = ctx.time(ctx.options.get('duration_s', 2.0))
    res = runs.blocked_run(ctx.model, ctx.config, t, np.where(t < 0.2, 5.0, 5.5), ctx.supply(),
                           angle)
    return _series(ctx, t, res, ('p_a_pa', 'p_b_pa', 't_a_k', 't_b_k'), 'blocked',
                   {'blocked_angle_rad': angle})


#: phases of the blocked steps: (valve command [V], supply target below nominal [Pa])
BLOCKED_PHASES = ((5.0, 0.0), (5.6, 0.0), (5.6, 2e5), (5.6, 0.0), (4.4, 0.0), (4.4, 2e5),
                  (4.4, 0.0), (9.0, 0.0), (1.0, 0.0), (5.0, 0.0), (6.0, 0.0), (6.0, 2e5),
                  (4.0, 2e5), (4.0, 0.0))


def _blocked_steps(ctx: Context) -> Experiment:
    """Pistons held at the config's angle: the valve stepped about its centre and to nearly
    full opening, and the supply regulator stepped with the valve held open to either side,
    spread over the whole record; from mid pressures (the ``initial`` start).

    The supply follows its target with a 20 ms lag and is measured like the chambers. Supply
    steps are what tell a measurement delay from a command delay: only the latter lags the
    response to supply."""
    duration = ctx.options.get('duration_s', 3.0)
    t = ctx.time(duration)
    phase = np.minimum((t / duration * len(BLOCKED_PHASES)).astype(int),
                       len(BLOCKED_PHASES) - 1)
    u = np.array([BLOCKED_PHASES[i][0] for i in phase])
    target = ctx.supply() - np.array([BLOCKED_PHASES[i][1] for i in phase])
    ps = np.empty_like(target)
    ps[0] = target[0]
    alpha = (1.0 / ctx.sensors.rate_hz) / 0.02
    for k in range(1, len(t)):
        ps[k] = ps[k - 1] + alpha * (target[k] - ps[k - 1])
    angle = ctx.core['blocked_angle_rad']
    res = runs.blocked_run(ctx.model, ctx.config, t, u, ps, angle, 'initial')
    return _series(ctx, t, res, ('p_a_pa', 'p_b_pa'), 'blocked', {'blocked_angle_rad': angle})


# ---------------------------------------------------------------- servo, open loop
def _friction(volts: float):
    def run(ctx: Context) -> Experiment:
        """Fig. 17: from rest at the a end (pushed there at 4 V), the valve held at ``volts``."""
        push_v = 4.0 if volts > 5.0 else 6.0
        start = 0.0 if volts > 5.0 else ctx.core['stroke_rad']
        t = ctx.time(ctx.options.get('duration_s', _friction_duration(volts)))
        u = np.where(t < 0.2, push_v, volts)
        x0 = runs.start_state(ctx.model, ctx.config, 'held', start, push_v, ctx.supply())
        res = simulate(ctx.model, t, u, ctx.supply(), x0=x0, config=ctx.config)
        return _series(ctx, t, res, ('angle_rad', 'p_a_pa', 'p_b_pa'), 'servo',
                       {'held_voltage_v': volts})
    return run


def _friction_duration(volts: float) -> float:
    """Record length [s]: long enough for steady motion, short of the far end stop."""
    return {5.07: 1.6, 5.12: 1.6, 5.2: 1.6, 5.3: 1.5, 5.45: 1.1, 5.7: 0.8}.get(volts, 1.5)


def _sine(ctx: Context) -> Experiment:
    """Section 6.3: 0.6 MPa, valve 5 +/- 0.35 V at 2 Hz, recorded after a run-in.

    Options: ``start`` (:data:`.runs.STARTS`, default ``held``) at ``angle_rad`` (default
    0.45 of the stroke), ``run_in_s`` [s] of sine before the record starts (default 1, as a
    DAQ started mid-run), ``duration_s``, ``amplitude_v``."""
    o = ctx.options
    pre = o.get('run_in_s', 1.0)
    t_all = ctx.time(pre + o.get('duration_s', 4.0))
    res = runs.sine_run(ctx.model, ctx.config, t_all, ctx.supply(), o.get('start', 'held'),
                        o.get('angle_rad', 0.45 * ctx.core['stroke_rad']),
                        amplitude_v=o.get('amplitude_v', 0.35))
    k0 = int(round(pre * ctx.sensors.rate_hz))
    return _series(ctx, t_all[k0:] - t_all[k0], res, ('angle_rad', 'p_a_pa', 'p_b_pa'),
                   'servo', start=k0)


# -------------------------------------------------------------- servo, closed loop
def _closed_loop_experiment(ctx: Context, t: np.ndarray, setpoint: np.ndarray, law: dict,
                            run_in_s: float, start: str) -> Experiment:
    """The loop of :func:`.runs.closed_loop` under a :class:`~pneumatic_servo.control.
    PidController` of ``law`` (updated by the ``pid`` option), from rest at the first
    setpoint (``start`` of :data:`.runs.STARTS`), run ``run_in_s`` [s] at the first setpoint
    before the record starts, so that the record starts with the loop settled."""
    pre = int(round(ctx.options.get('run_in_s', run_in_s) * ctx.sensors.rate_hz))
    ps = ctx.supply()
    x0 = runs.start_state(ctx.model, ctx.config, start, float(setpoint[0]), 5.0, ps)
    law = PidController(**{**law, **ctx.options.get('pid', {})})
    u, shown, _ = runs.closed_loop(ctx.model, ctx.config,
                                   np.concatenate([np.full(pre, setpoint[0]), setpoint]), x0,
                                   law, ctx.sensors.rate_hz, ps, ctx.sensors, ctx.velocity)
    res = {'command_v': u, 'supply_pa': np.full(len(u), ps), 'angle_rad': shown[:, 0],
           'p_a_pa': shown[:, 2], 'p_b_pa': shown[:, 3]}
    exp = _series(ctx, t, res, ('angle_rad', 'p_a_pa', 'p_b_pa'), 'servo', start=pre)
    exp.signals['setpoint_rad'] = np.asarray(setpoint, float)
    return exp


def _steps(ctx: Context) -> Experiment:
    """Closed-loop steps between setpoints inside the stroke."""
    levels = ctx.options.get('levels_rad', (0.8, 2.0, 1.2, 2.4))
    hold = ctx.options.get('hold_s', 1.0)
    t = ctx.time(hold * len(levels))
    sp = np.array([levels[min(int(tk // hold), len(levels) - 1)] for tk in t])
    return _closed_loop_experiment(ctx, t, sp, LIBRARY_PID, 0.5, 'held')


def _sine_tracking(ctx: Context) -> Experiment:
    """Closed-loop tracking of a 0.5 Hz sine setpoint about mid-stroke."""
    t = ctx.time(ctx.options.get('duration_s', 4.0))
    mid = 0.5 * ctx.core['stroke_rad']
    sp = mid + ctx.options.get('amplitude_rad', 0.6) * np.sin(2.0 * np.pi * 0.5 * t)
    return _closed_loop_experiment(ctx, t, sp, LIBRARY_PID, 0.5, 'held')


def _mixed(ctx: Context) -> Experiment:
    """Steps between 0.2 and 0.8 of the stroke over 5/8 of the record, then a 0.6 Hz sine of
    0.2 of the stroke about mid-stroke, under the PD loop :data:`HIDDEN_PD`; the steps are
    large enough to open the valve nearly fully."""
    duration = ctx.options.get('duration_s', 8.0)
    stroke = ctx.core['stroke_rad']
    levels = np.array([0.2, 0.8, 0.35, 0.65, 0.5]) * stroke
    hold = duration / 8.0
    t = ctx.time(duration)
    sp = np.array([levels[int(tk // hold)] if tk < 5 * hold else
                   0.5 * stroke + 0.2 * stroke * np.sin(2.0 * np.pi * 0.6 * (tk - 5 * hold))
                   for tk in t])
    # a filter of 10 ms in the Euler form the loop was written in: alpha = dt / 10 ms
    tau = max(0.01 - 1.0 / ctx.sensors.rate_hz, 0.0)
    return _closed_loop_experiment(ctx, t, sp, {**HIDDEN_PD, 'velocity_filter_s': tau}, 1.0,
                                   'free')


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
    # made for the hidden-effect sets (synth.hidden), not in the library
    add(Design('blocked_steps', 'blocked', False,
               'pistons held: valve steps about the centre and to nearly full opening, supply '
               'steps with the valve open; p_a, p_b, supply', _blocked_steps, library=False))
    add(Design('closed_loop_mixed', 'servo', False,
               'closed-loop PD: steps over 0.2-0.8 of the stroke, then a 0.6 Hz sine',
               _mixed, library=False))
    for circuit in ('closed_port', 'flow', 'blocked'):
        add(Design(f'{circuit}_settled', circuit, True,
                   f'{circuit} circuit settled in time at held voltages, supplies 0.5 and 0.7 '
                   'MPa gauge', _settled_table(circuit), library=False))
    return out


DESIGNS = _designs()
#: the designs of the bundled library, in its order (its seeds follow it)
LIBRARY = tuple(name for name, d in DESIGNS.items() if d.library)


def run(design_name: str, ctx: Context) -> Experiment:
    """Run design ``design_name`` in ``ctx`` (its noise source, sensors and options): the
    measured record, named after the design."""
    if design_name not in DESIGNS:
        raise ConfigError(f'unknown experiment design {design_name!r}; use one of '
                          f'{", ".join(DESIGNS)}')
    exp = DESIGNS[design_name].run(ctx)
    exp.name = design_name
    return exp


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
    sensors = sensors or S.SensorModel()
    if model is None or model.layout.classes != tuple(config.component_classes()):
        model = Model(config)
    ctx = Context(config, model, np.random.default_rng(seed), sensors, dict(options))
    exp = run(design_name, ctx)
    exp.metadata.update({
        'synthetic': True, 'design': design_name,
        'description': DESIGNS[design_name].summary, 'seed': int(seed),
        'options': plain(options), 'sensors': sensors.describe(), 'truth': config.to_dict(),
        'generator': 'pneumatic_servo.synth.make_experiment (pneumatic-servo generate)'})
    return exp


def with_options(ctx: Context, **options) -> Context:
    """``ctx`` (the same noise source) with other design options."""
    return replace(ctx, options=dict(options))
