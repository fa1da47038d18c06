"""Test data with hidden effects: what a rig with one (or two) unmodelled effects records.

The generator simulates the model *with* the hidden catalogue effects added,
then measures it with realistic sensors, so that the diagnosis tools can be
checked against a known truth:

* ``sine``: the paper's open-loop servo test, 5 +/- 0.35 V at 2 Hz. The
  actuator integrates, so with some hidden effects it drifts to an end stop.
* ``closed_loop``: a PD position loop (run at the record rate on the
  measured, quantised angle) tracking steps and a slow sine between the
  stops; the steps are large enough to open the valve nearly fully.
* ``blocked``: the pistons held at an end (charge/discharge circuit), the
  valve stepped about its centre and to nearly full opening, and the supply
  regulator stepped with the valve held open. A supply step is what tells a
  command delay from a measurement delay: only the latter lags the response
  to supply.
* ``closed_port`` and ``flow``: static tables (CSV) of steady pressures and
  flows at held voltages.

Magnitudes are each effect's declared ``example`` values (the effect class
says them): realistic for a small rotary actuator and inside each parameter's
plausible range. Sensors are those of the
library (:mod:`pneumatic_servo.synth.sensors`): 20,000 P/R encoder, 0.1 % FS
pressure transmitters (600 Pa), averaged flow meters, at 1 kHz by default
(the committed test sets: 250 Hz, short records). No velocity is recorded.

Regenerate the committed sets and the demo bag (same seeds, same records)::

    python -m pneumatic_servo.synth.hidden tests/data/hidden
    python -m pneumatic_servo.synth.hidden --demo bags
"""
from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from .. import effects as registry
from ..effects.layout import N_CONTEXT, P_A, P_B, THETA
from ..errors import ConfigError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import DEFAULT_RTOL, initial_state, measured_states, simulate
from . import sensors as S

#: supply of the paper's servo and charge/discharge tests, 0.6 MPa gauge [Pa, absolute]
SUPPLY_PA = 701325.0
#: the instruments: the library's (paper Tables 1 and 3), 1 kHz
SENSORS = S.SensorModel()
RATE_HZ = SENSORS.rate_hz
TIME_DESIGNS = ('sine', 'closed_loop', 'blocked')
STATIC_DESIGNS = ('closed_port', 'flow')
#: static tables that are not in every data set: the blocked circuit's settled pressures
TABLE_DESIGNS = {'closed_port': 'closed_port', 'flow': 'flow', 'blocked_table': 'blocked'}
#: default record lengths [s]
DURATIONS = {'sine': 4.0, 'closed_loop': 8.0, 'blocked': 3.0}


def hidden_config(effects, base: ModelConfig | None = None) -> ModelConfig:
    """``base`` (default the paper's model) with the hidden effects added.

    Parameters
    ----------
    effects : iterable of str, or dict of str to dict
        Effect names (each at its class's ``example`` values), or name -> values [SI].
    base : ModelConfig, optional
        The model the effects are added to.
    """
    cfg = (base or ModelConfig.paper()).copy()
    for name, values in truth(effects).items():
        cfg = cfg.with_effect(name, values)
    return cfg


def example_values(name: str) -> dict[str, float]:
    """The realistic values [SI] effect ``name`` declares for generated data."""
    example = registry.get(name).example
    if example is None:
        raise ConfigError(f'effect {name!r} declares no example values; give its class an '
                          "'example' dict, or pass the values to hide")
    return dict(example)


# ----------------------------------------------------------------------------- sensors
def measure_servo(t: np.ndarray, angle: np.ndarray, p_a: np.ndarray, p_b: np.ndarray,
                  supply: np.ndarray, rng: np.random.Generator,
                  sensors: S.SensorModel = SENSORS) -> dict[str, np.ndarray]:
    """Measured signals of the true ones: encoder angle and velocity [rad, rad/s],
    transmitter pressures [Pa, absolute]."""
    true = {'supply_pa': supply, 'angle_rad': angle, 'p_a_pa': p_a, 'p_b_pa': p_b}
    rate = 1.0 / float(t[1] - t[0])
    if abs(rate - sensors.rate_hz) > 1e-6 * rate:
        sensors = replace(sensors, rate_hz=rate)
    # no velocity: many rigs record none (INTERFACES.md), and it is noise in the bag
    return S.measure(t, true, rng, sensors, velocity=False)


# ------------------------------------------------------------------------ excitations
def _time(duration_s: float, rate_hz: float) -> np.ndarray:
    return np.arange(int(round(duration_s * rate_hz))) / rate_hz


def _settled_state(model: Model, cfg: ModelConfig, command_v: float, supply_pa: float,
                   angle_rad: float, settle_s: float = 3.0) -> np.ndarray:
    """State after holding ``command_v`` [V] for ``settle_s`` [s]: the rig at rest."""
    t = _time(settle_s, 200.0)
    x0 = initial_state(model, angle_rad=angle_rad, command_v=command_v, supply_pa=supply_pa,
                       config=cfg)
    # the physical state, not what a delayed measurement shows: the state the rig holds
    return simulate(model, t, command_v, supply_pa, x0=x0, config=cfg,
                    measured=False).states[-1].copy()


def sine_experiment(cfg: ModelConfig, rng: np.random.Generator, duration_s: float = 4.0,
                    rate_hz: float = RATE_HZ, model: Model | None = None) -> Experiment:
    """Open-loop 2 Hz sine, 5 +/- 0.35 V, from rest at mid-stroke (paper Section 6.3)."""
    model = model or Model(cfg)
    t = _time(duration_s, rate_hz)
    u = 5.0 + 0.35 * np.sin(2.0 * np.pi * 2.0 * t)
    ps = np.full_like(t, SUPPLY_PA)
    x0 = _settled_state(model, cfg, 5.0, SUPPLY_PA, 0.5 * cfg.core['stroke_rad'])
    res = simulate(model, t, u, ps, x0=x0, config=cfg)
    sig = measure_servo(t, res.angle_rad, res.p_a_pa, res.p_b_pa, ps, rng)
    exp = Experiment(t, {'command_v': u, **sig}, 'servo', 'sine')
    exp.metadata['true_states'] = res.states
    return exp


def _setpoints(duration_s: float, stroke: float):
    """Setpoint [rad] as a function of time: steps, then a slow sine, within the stroke."""
    levels = np.array([0.2, 0.8, 0.35, 0.65, 0.5]) * stroke
    hold = duration_s / 8.0

    def setpoint(tk: float) -> float:
        i = int(tk // hold)
        if i < 5:
            return float(levels[i])
        return float(0.5 * stroke + 0.2 * stroke * np.sin(2.0 * np.pi * 0.6 * (tk - 5 * hold)))
    return setpoint


class _History:
    """Linear interpolation into a uniformly sampled, growing record (as ``delayed`` does)."""

    def __init__(self, first, dt: float):
        self.rows = [np.asarray(first, dtype=float)]
        self.dt = dt

    def append(self, row):
        self.rows.append(np.asarray(row, dtype=float))

    def at(self, tq: float):
        j = tq / self.dt
        if j <= 0.0:
            return self.rows[0]
        i = min(int(j), len(self.rows) - 1)
        if i + 1 >= len(self.rows):
            return self.rows[i]
        f = j - i
        return (1.0 - f) * self.rows[i] + f * self.rows[i + 1]


def closed_loop_experiment(cfg: ModelConfig, rng: np.random.Generator,
                           duration_s: float = 8.0, rate_hz: float = RATE_HZ,
                           model: Model | None = None, kp: float = 2.0, kd: float = 0.02,
                           preroll_s: float = 1.0, deadband_rad: float = 0.0) -> Experiment:
    """A PD position loop at ``rate_hz`` on the measured angle, tracking steps and a sine.

    The plant is integrated accurately (Dormand-Prince, as ``simulate``)
    over each sample interval; command and measurement delays of the
    hidden effects act as they do in ``simulate``. The controller sees the
    quantised angle (and the measurement delay), so the record is what a
    real rig logs. The loop runs ``preroll_s`` [s] before the record starts,
    so the record begins under control. Gains ``kp`` [V/rad], ``kd`` [V.s/rad]. Sensor
    errors of the hidden effects are in what the controller sees.
    """
    model = model or Model(cfg)

    def reading(rows, commands):
        """What the sensors show of physical state ``rows`` (n, n_states)."""
        return measured_states(model, cfg, np.zeros(len(rows)), rows, commands,
                               np.full(len(rows), SUPPLY_PA))

    dt = 1.0 / rate_hz
    skip = int(round(preroll_s * rate_hz))
    t = _time(duration_s + preroll_s, rate_hz)
    n = len(t)
    targets = _setpoints(duration_s, cfg.core['stroke_rad'])
    setpoint = (lambda tk: targets(max(tk - preroll_s, 0.0)))
    P = model.param_vector(cfg)
    d_in, d_out = model.delays(cfg)
    x = _settled_state(model, cfg, 5.0, SUPPLY_PA, setpoint(0.0))
    kern = model.kernels['adaptive_interval']
    c = np.zeros(N_CONTEXT)
    w = np.zeros((9, model.n_states))
    states = _History(x.copy(), dt)
    commands = None
    u = np.empty(n)
    angle_meas = np.empty(n)
    step = 1e-5
    prev, vel = None, 0.0
    for k in range(n):
        seen = reading(states.at(t[k] - d_out)[None], np.array([u[k - 1] if k else 5.0]))[0]
        angle_meas[k] = S.quantise(seen[THETA], SENSORS.encoder_step_rad)
        if prev is not None:  # velocity from the encoder, first-order filtered (10 ms)
            vel += ((angle_meas[k] - prev) / dt - vel) * dt / 0.01
        prev = angle_meas[k]
        err = setpoint(t[k]) - angle_meas[k]
        err = 0.0 if abs(err) <= deadband_rad else err - math.copysign(deadband_rad, err)
        u[k] = min(max(5.0 + kp * err - kd * vel, 0.0), 10.0)
        if commands is None:
            commands = _History(u[0], dt)
        else:
            commands.append(u[k])
        if k == n - 1:
            break
        u_valve = float(commands.at(t[k] - d_in))
        status, step = kern(t[k], x, u_valve, SUPPLY_PA, P, 0, dt, step, DEFAULT_RTOL,
                            model.abs_tol, c, w, 1_000_000)
        step = min(step, 1.0)
        if status != 0:
            raise RuntimeError(f'closed-loop run failed at t = {t[k]:.4f} s')
        states.append(x.copy())
    true = reading(np.array([states.at(tk - d_out) for tk in t]),
                   np.concatenate([[5.0], u[:-1]]))[skip:]
    t_rec = t[skip:] - t[skip]
    ps = np.full(len(t_rec), SUPPLY_PA)
    sig = measure_servo(t_rec, true[:, THETA], true[:, P_A], true[:, P_B], ps, rng)
    assert np.array_equal(sig['angle_rad'], angle_meas[skip:])  # what the controller saw
    exp = Experiment(t_rec, {'command_v': u[skip:], **sig}, 'servo', 'closed_loop')
    exp.metadata['true_states'] = np.array([states.at(tk) for tk in t])[skip:]
    return exp


#: phases of the blocked design: (valve command [V], supply target below nominal [Pa])
_BLOCKED_PHASES = ((5.0, 0.0), (5.6, 0.0), (5.6, 2e5), (5.6, 0.0), (4.4, 0.0), (4.4, 2e5),
                   (4.4, 0.0), (9.0, 0.0), (1.0, 0.0), (5.0, 0.0), (6.0, 0.0), (6.0, 2e5),
                   (4.0, 2e5), (4.0, 0.0))


def blocked_experiment(cfg: ModelConfig, rng: np.random.Generator, duration_s: float = 3.0,
                       rate_hz: float = RATE_HZ, model: Model | None = None) -> Experiment:
    """Pistons held at an end: the valve stepped about its centre and to nearly full
    opening, and the supply regulator stepped with the valve held open to either side,
    spread over the whole record.

    The supply follows its target with a 20 ms lag and is measured like the
    chambers. Supply steps are what tell a measurement delay from a command
    delay.
    """
    model = model or Model(cfg)
    t = _time(duration_s, rate_hz)
    phase = np.minimum((t / duration_s * len(_BLOCKED_PHASES)).astype(int),
                       len(_BLOCKED_PHASES) - 1)
    u = np.array([_BLOCKED_PHASES[i][0] for i in phase])
    target = SUPPLY_PA - np.array([_BLOCKED_PHASES[i][1] for i in phase])
    ps = np.empty_like(target)
    ps[0] = target[0]
    alpha = (1.0 / rate_hz) / 0.02
    for k in range(1, len(t)):
        ps[k] = ps[k - 1] + alpha * (target[k] - ps[k - 1])
    pe = cfg.core['atmospheric_pressure_pa']
    x0 = initial_state(model, angle_rad=cfg.core['blocked_angle_rad'],
                       p_a_pa=0.5 * (SUPPLY_PA + pe), p_b_pa=0.5 * (SUPPLY_PA + pe),
                       command_v=5.0, supply_pa=SUPPLY_PA, config=cfg)
    res = simulate(model, t, u, ps, x0=x0, circuit='blocked', config=cfg)
    sig = measure_servo(t, res.angle_rad, res.p_a_pa, res.p_b_pa, ps, rng)
    del sig['angle_rad']  # the pistons are held: no encoder
    exp = Experiment(t, {'command_v': u, **sig}, 'blocked', 'blocked')
    exp.metadata['true_states'] = res.states
    return exp


def static_table(cfg: ModelConfig, circuit: str, rng: np.random.Generator,
                 model: Model | None = None) -> Experiment:
    """Steady closed-port pressures, flow-test flows, or the two chamber pressures of the
    blocked circuit, at held voltages and two supplies.

    Each row is simulated in time until it settles (independently of the
    steady-state solver the diagnosis uses), then measured.
    """
    from ..model.circuits import static_response
    model = model or Model(cfg)
    blocked = circuit == 'blocked'
    volts = (np.round(np.linspace(4.0, 6.0, 9), 3) if blocked else
             np.round(np.concatenate([np.linspace(4.0, 6.0, 21), [6.5, 7.0, 8.0, 10.0]]), 3))
    rows = []
    for supply in (SUPPLY_PA - 1e5, SUPPLY_PA + 1e5):
        for v in volts:
            # the blocked chambers near the centre fill through the valve's small leaks
            res = static_response(model, circuit, float(v), supply,
                                  duration_s=12.0 if blocked else 1.0, sample_s=2e-3,
                                  config=cfg)
            rows.append((v, supply, res.p_a_pa[-1], res.p_b_pa[-1], res['m4_kg_s'][-1],
                         res['m5_kg_s'][-1]))
    rows = np.array(rows)
    n = len(rows)
    true = {'command_v': rows[:, 0], 'supply_pa': rows[:, 1], 'p_a_pa': rows[:, 2]}
    if blocked:
        true['p_b_pa'] = rows[:, 3]
    if circuit == 'flow':
        true.update(m4_kg_s=rows[:, 4], m5_kg_s=rows[:, 5])
    sig = S.measure_static(true, rng, SENSORS)
    return Experiment(np.arange(n, dtype=float), sig, circuit, f'{circuit}_table' if blocked
                      else circuit, static=True)


# ---------------------------------------------------------------------------- data sets
def make_hidden_set(effects, seed: int = 0, designs=TIME_DESIGNS, durations=None,
                    rate_hz: float = RATE_HZ, base: ModelConfig | None = None
                    ) -> list[Experiment]:
    """Experiments of a rig with the hidden ``effects`` (names, or name -> values).

    Parameters
    ----------
    effects : iterable of str or dict
        Hidden effects; empty for a clean rig.
    seed : int
        Seed of the measurement noise.
    designs : iterable of str
        Any of ``TIME_DESIGNS`` and ``STATIC_DESIGNS``.
    durations : dict, optional
        design -> record length [s] (default :data:`DURATIONS`).
    rate_hz : float [Hz]
        Sample rate of the time series.
    base : ModelConfig, optional
        The rig's model without the hidden effects (default the paper's).
    """
    cfg = hidden_config(effects, base)
    model = Model(cfg)
    rng = np.random.default_rng(seed)
    durations = {**DURATIONS, **(durations or {})}
    makers = {'sine': sine_experiment, 'closed_loop': closed_loop_experiment,
              'blocked': blocked_experiment}
    out = []
    for design in designs:
        if design in makers:
            exp = makers[design](cfg, rng, durations[design], rate_hz, model=model)
        elif design in TABLE_DESIGNS:
            exp = static_table(cfg, TABLE_DESIGNS[design], rng, model=model)
        else:
            raise ConfigError(f'unknown design {design!r}; use one of '
                              f'{", ".join(TIME_DESIGNS + tuple(TABLE_DESIGNS))}')
        exp.metadata['hidden_effects'] = {k: dict(v) for k, v in cfg.effects.items()}
        out.append(exp)
    return out


def truth(effects) -> dict[str, dict[str, float]]:
    """Hidden parameter values [SI] of ``effects`` (names, each at its ``example`` values, or
    name -> values)."""
    if isinstance(effects, dict):
        return {k: dict(v) for k, v in effects.items()}
    return {name: example_values(name) for name in effects}



# ------------------------------------------------------------------------- on disk
def designs_for(name: str) -> tuple[str, ...]:
    """The designs that show effect ``name``: the time series, and the static tables where it
    acts in a static circuit and shows in steady states (its class says both)."""
    cls_ = registry.get(name)
    shows = cls_.steady and set(cls_.circuits) & set(STATIC_DESIGNS)
    return TIME_DESIGNS + (STATIC_DESIGNS if shows else ())


def _datasets() -> dict[str, tuple[tuple[str, ...], tuple[str, ...], int]]:
    """The committed test data sets: name -> (hidden effects, designs, seed); see
    :func:`generate_test_data`."""
    out = {'none': ((), TIME_DESIGNS, 100)}
    for i, name in enumerate(registry.CATALOGUE_NAMES):
        out[name] = ((name,), designs_for(name), 101 + i)
    out['two_external_load_torque+piston_seal_leakage'] = (
        ('external_load_torque', 'piston_seal_leakage'), TIME_DESIGNS, 200)
    return out


DATASETS = _datasets()
#: record lengths [s] and rate [Hz] of the committed data sets: short and at 250 Hz, because
#: they are committed (noise does not compress) and diagnosed in the tests
TEST_DURATIONS = {'sine': 2.0, 'closed_loop': 4.0, 'blocked': 2.8}
TEST_RATE_HZ = 250.0


def write_dataset(out_dir, effects, seed: int = 0, designs=TIME_DESIGNS, durations=None,
                  rate_hz: float = RATE_HZ, storage: str = 'mcap',
                  base: ModelConfig | None = None) -> Path:
    """Generate a hidden-effect data set and write it: bags, CSV tables and ``truth.json``.

    Parameters
    ----------
    out_dir : path
        New directory; each time series becomes a bag directory named after
        its design, each table ``<design>.csv``.
    effects, seed, designs, durations, rate_hz, base
        As :func:`make_hidden_set`.
    storage : {'mcap', 'sqlite3'}
        Bag storage (MCAP is zstd-compressed).

    Returns
    -------
    Path
        ``out_dir``.
    """
    from ..io import write_experiment
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=False)
    hidden = truth(effects)
    meta = {'synthetic': 'true', 'generator': 'pneumatic_servo.synth.hidden', 'seed': seed,
            'hidden_effects': hidden}
    for exp in make_hidden_set(effects, seed, designs, durations, rate_hz, base):
        exp.metadata.pop('true_states', None)
        if exp.static:
            write_experiment(exp, out_dir / f'{exp.name}.csv', metadata=meta)
        else:
            write_experiment(exp, out_dir / exp.name, storage, meta, compress=True)
    (out_dir / 'truth.json').write_text(json.dumps(
        {'synthetic': True, 'hidden_effects': hidden, 'seed': seed, 'designs': list(designs),
         'durations_s': {**DURATIONS, **(durations or {})}, 'rate_hz': rate_hz}, indent=1))
    return out_dir


def generate_test_data(root, names=None, rate_hz: float = TEST_RATE_HZ) -> list[Path]:
    """Write the data sets of :data:`DATASETS` (or ``names`` of them) under ``root``."""
    root = Path(root)
    out = []
    for name in names or DATASETS:
        effects, designs, seed = DATASETS[name]
        out.append(write_dataset(root / name, list(effects), seed, designs, TEST_DURATIONS,
                                 rate_hz))
    return out


#: the bundled demo record: closed loop on a rig with two hidden effects
DEMO_EFFECTS = ('external_load_torque', 'external_leakage')


def write_demo_bag(bags_dir, seed: int = 7) -> Path:
    """Write ``bags/hidden_effect_demo``: a 10 s, 1 kHz closed-loop record of a rig with
    :data:`DEMO_EFFECTS` hidden (their values are in the bag's custom data)."""
    from ..io import write_experiment
    cfg = hidden_config(DEMO_EFFECTS)
    exp = closed_loop_experiment(cfg, np.random.default_rng(seed), 10.0)
    exp.metadata.pop('true_states', None)
    meta = {'synthetic': 'true', 'generator': 'pneumatic_servo.synth.hidden', 'seed': seed,
            'hidden_effects': truth(DEMO_EFFECTS), 'design': 'closed_loop'}
    return write_experiment(exp, Path(bags_dir) / 'hidden_effect_demo', 'mcap', meta,
                            compress=True)


#: the bundled validation demo: a leak from both chambers, seen on two static tables
VALIDATION_EFFECTS = {'external_leakage': {'leak_area_a_m2': 2e-8, 'leak_area_b_m2': 2e-8}}


def write_validation_demo(bags_dir, seed: int = 12) -> Path:
    """Write ``bags/validation_demo``: a closed-port table (chamber a only) and a blocked
    table (both chambers settled) of a rig with a leak from each chamber to atmosphere; the
    leak is found on the first and confirmed on the second (``diagnose --validate-on``)."""
    return write_dataset(Path(bags_dir) / 'validation_demo', VALIDATION_EFFECTS, seed,
                         ('closed_port', 'blocked_table'))


def main(argv=None) -> int:
    """``python -m pneumatic_servo.synth.hidden OUT [--demo] [NAME ...]``."""
    import argparse
    p = argparse.ArgumentParser(prog='python -m pneumatic_servo.synth.hidden',
                                description='Regenerate hidden-effect test data (same seeds, '
                                            'same records).')
    p.add_argument('out', help='directory to write into (e.g. tests/data/hidden or bags)')
    p.add_argument('names', nargs='*', help=f'data sets (default all: {", ".join(DATASETS)})')
    p.add_argument('--demo', action='store_true',
                   help='write the bundled demo bag hidden_effect_demo and the validation '
                        'demo tables instead')
    args = p.parse_args(argv)
    if args.demo:
        print(write_demo_bag(args.out))
        print(write_validation_demo(args.out))
        return 0
    for path in generate_test_data(args.out, args.names or None):
        print(path)
    return 0


__all__ = ['example_values', 'designs_for', 'TIME_DESIGNS', 'STATIC_DESIGNS', 'DATASETS',
           'hidden_config',
           'make_hidden_set', 'write_dataset', 'generate_test_data', 'write_demo_bag',
           'sine_experiment', 'closed_loop_experiment', 'blocked_experiment', 'static_table',
           'measure_servo', 'truth', 'DEMO_EFFECTS']


if __name__ == '__main__':
    raise SystemExit(main())
