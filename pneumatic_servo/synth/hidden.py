"""Test data with hidden effects: what a rig with one (or two) unmodelled effects records.

The records are experiments of the registry (:mod:`.designs`) run on the model *with* the
hidden catalogue effects added, then measured with realistic sensors, so that the diagnosis
tools can be checked against a known truth. This module holds what is particular to them:
the hidden values, which designs a set runs and how (:data:`SET_DESIGNS`), and the writer.

* ``sine``: the paper's open-loop servo test (design ``sine_2hz``), 5 +/- 0.35 V at 2 Hz,
  from where the free shaft came to rest at mid-stroke, recorded from the start. The actuator
  integrates, so with some hidden effects it drifts to an end stop.
* ``closed_loop``: a PD position loop (design ``closed_loop_mixed``, run at the record rate on
  the measured, quantised angle) tracking steps and a slow sine between the stops; the steps
  are large enough to open the valve nearly fully.
* ``blocked``: the pistons held at an end (design ``blocked_steps``), the valve stepped about
  its centre and to nearly full opening, and the supply regulator stepped with the valve
  held open. A supply step is what tells a command delay from a measurement delay: only the
  latter lags the response to supply.
* ``closed_port``, ``flow`` and ``blocked_table``: static tables (CSV) of steady pressures and
  flows at held voltages, each row settled in time (designs ``*_settled``).

Magnitudes are each effect's declared ``example`` values (the effect class
says them): realistic for a small rotary actuator and inside each parameter's
plausible range. Sensors are those of the
library (:mod:`pneumatic_servo.synth.sensors`): 20,000 P/R encoder, 0.1 % FS
pressure transmitters (600 Pa), averaged flow meters, at 1 kHz by default
(the committed test sets: 250 Hz, short records). No velocity is recorded.

Regenerate the committed sets and the demo bags::

    python -m pneumatic_servo.synth.hidden tests/data/hidden
    python -m pneumatic_servo.synth.hidden --demo bags

The same seeds give the committed sine, blocked and table records: the same signals, the
tables byte for byte (a bag's files also carry the version of the writer). Regenerating gives
statistically equivalent, not identical, closed-loop records (``closed_loop``, the demo bags,
``bags/fleet_demo`` of :mod:`.fleet`): the loop now runs its plant through the
:class:`~pneumatic_servo.model.Stepper` (each period's first stage evaluated afresh) and its
law through :class:`~pneumatic_servo.control.PidController`, and the records carry their
setpoint; the committed ones are kept as they are.
"""
from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from .. import effects as registry
from ..errors import ConfigError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.circuits import PAPER_SUPPLY_GAUGE_PA, gauge_supply_pa
from ..model.config import ModelConfig
from . import designs as D
from . import sensors as S

#: supply of the paper's servo and charge/discharge tests, 0.6 MPa gauge [Pa, absolute]
SUPPLY_PA = gauge_supply_pa(PAPER_SUPPLY_GAUGE_PA)
#: the instruments: the library's (paper Tables 1 and 3), 1 kHz
SENSORS = S.SensorModel()
RATE_HZ = SENSORS.rate_hz
TIME_DESIGNS = ('sine', 'closed_loop', 'blocked')
STATIC_DESIGNS = ('closed_port', 'flow')
#: static tables that are not in every data set: the blocked circuit's settled pressures
TABLE_DESIGNS = {'closed_port': 'closed_port', 'flow': 'flow', 'blocked_table': 'blocked'}
#: default record lengths [s]
DURATIONS = {'sine': 4.0, 'closed_loop': 8.0, 'blocked': 3.0}
#: a set's records: name -> (design of :data:`.designs.DESIGNS`, options besides the length)
SET_DESIGNS = {
    'sine': ('sine_2hz', {'start': 'free', 'run_in_s': 0.0}),
    'closed_loop': ('closed_loop_mixed', {}),
    'blocked': ('blocked_steps', {}),
    **{name: (f'{circuit}_settled', {}) for name, circuit in TABLE_DESIGNS.items()},
}


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


def truth(effects) -> dict[str, dict[str, float]]:
    """Hidden parameter values [SI] of ``effects`` (names, each at its ``example`` values, or
    name -> values)."""
    if isinstance(effects, dict):
        return {k: dict(v) for k, v in effects.items()}
    return {name: example_values(name) for name in effects}


# ------------------------------------------------------------------------- records
def _context(cfg: ModelConfig, rng: np.random.Generator, rate_hz: float,
             model: Model | None) -> D.Context:
    """How the sets are recorded: the library's sensors at ``rate_hz``, no velocity (many rigs
    record none, and it is noise in the bag), records of exactly duration x rate samples."""
    return D.Context(cfg, model or Model(cfg), rng, replace(SENSORS, rate_hz=rate_hz),
                     velocity=False, endpoint=False)


def record(name: str, cfg: ModelConfig, rng: np.random.Generator,
           duration_s: float | None = None, rate_hz: float = RATE_HZ,
           model: Model | None = None, **options) -> Experiment:
    """Record ``name`` of a set (a key of :data:`SET_DESIGNS`) on the rig ``cfg``, its noise
    drawn from ``rng``; ``duration_s`` [s] (default :data:`DURATIONS`) for a time series."""
    if name not in SET_DESIGNS:
        raise ConfigError(f'unknown design {name!r}; use one of {", ".join(SET_DESIGNS)}')
    design, fixed = SET_DESIGNS[name]
    opts = {**fixed, **options}
    if name == 'sine':
        opts.setdefault('angle_rad', 0.5 * cfg.core['stroke_rad'])
    if name in DURATIONS:
        opts['duration_s'] = DURATIONS[name] if duration_s is None else duration_s
    ctx = D.with_options(_context(cfg, rng, rate_hz, model), **opts)
    exp = D.run(design, ctx)
    exp.name = name
    return exp


def sine_experiment(cfg: ModelConfig, rng: np.random.Generator, duration_s: float = 4.0,
                    rate_hz: float = RATE_HZ, model: Model | None = None) -> Experiment:
    """The ``sine`` record: open-loop 2 Hz sine, 5 +/- 0.35 V, from rest at mid-stroke."""
    return record('sine', cfg, rng, duration_s, rate_hz, model)


def closed_loop_experiment(cfg: ModelConfig, rng: np.random.Generator,
                           duration_s: float = 8.0, rate_hz: float = RATE_HZ,
                           model: Model | None = None, kp: float = 2.0,
                           kd: float = 0.02) -> Experiment:
    """The ``closed_loop`` record: a PD loop (gains ``kp`` [V/rad], ``kd`` [V.s/rad]) at
    ``rate_hz`` on the measured angle, tracking steps and a sine. The controller sees what
    the sensors show (the quantised angle, the hidden effects' measurement delays and sensor
    errors); the loop runs 1 s before the record starts, so the record begins under control."""
    return record('closed_loop', cfg, rng, duration_s, rate_hz, model,
                  pid={'kp': kp, 'kd': kd})


def blocked_experiment(cfg: ModelConfig, rng: np.random.Generator, duration_s: float = 3.0,
                       rate_hz: float = RATE_HZ, model: Model | None = None) -> Experiment:
    """The ``blocked`` record: pistons held, valve and supply steps."""
    return record('blocked', cfg, rng, duration_s, rate_hz, model)


def static_table(cfg: ModelConfig, circuit: str, rng: np.random.Generator,
                 model: Model | None = None) -> Experiment:
    """Steady closed-port pressures, flow-test flows, or the two chamber pressures of the
    blocked circuit (``blocked_table``), at held voltages and two supplies."""
    return record('blocked_table' if circuit == 'blocked' else circuit, cfg, rng, model=model)


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
        Keys of :data:`SET_DESIGNS`: any of ``TIME_DESIGNS`` and ``TABLE_DESIGNS``.
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
    out = []
    for design in designs:
        exp = record(design, cfg, rng, durations.get(design), rate_hz, model)
        exp.metadata['hidden_effects'] = {k: dict(v) for k, v in cfg.effects.items()}
        out.append(exp)
    return out


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
                                description='Regenerate hidden-effect test data (same seeds).')
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


__all__ = ['example_values', 'designs_for', 'TIME_DESIGNS', 'STATIC_DESIGNS', 'SET_DESIGNS',
           'DATASETS', 'SUPPLY_PA', 'hidden_config', 'record', 'make_hidden_set',
           'write_dataset', 'generate_test_data', 'write_demo_bag', 'sine_experiment',
           'closed_loop_experiment', 'blocked_experiment', 'static_table', 'truth',
           'DEMO_EFFECTS']


if __name__ == '__main__':
    raise SystemExit(main())
