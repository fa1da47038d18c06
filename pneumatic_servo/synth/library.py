"""The bundled experiment library (``bags/``): every design of :data:`LIBRARY` on the
synthetic rig, written as rosbag2 (sqlite3 and MCAP) and static CSV, with a README.

``pneumatic-servo generate OUTDIR`` calls :func:`generate_library`; the same
seed gives the same records, except the two closed-loop runs: since their PID became the
package's :class:`~pneumatic_servo.control.PidController` (anti-windup, no integral on the
first sample), regenerating gives statistically equivalent, not identical, closed-loop
records; the committed ones are kept as they are.
"""
from __future__ import annotations

import shutil
from pathlib import Path

import yaml

from .. import __version__
from ..errors import ConfigError
from ..io import write_experiment_bag, write_static_csv
from ..model.assembly import Model
from ..model.config import ModelConfig
from .designs import DESIGNS, LIBRARY, make_experiment
from .sensors import SensorModel
from .truth import TRUTH_VALUES, synthetic_rig

DEFAULT_SEED = 2019  # the paper's year; any fixed seed makes the library reproducible
TRUTH_FILE = 'truth.yaml'


def _paths(outdir: Path, name: str, static: bool) -> list[Path]:
    if static:
        return [outdir / f'{name}.csv', outdir / f'{name}.meta.yaml']
    return [outdir / name]


def generate_library(outdir, designs=None, seed: int = DEFAULT_SEED,
                     config: ModelConfig | None = None, sensors: SensorModel | None = None,
                     overwrite: bool = False, log=print) -> list[Path]:
    """Generate the experiment library into ``outdir``.

    Parameters
    ----------
    outdir : str or Path
        Target directory (created if missing).
    designs : iterable of str, optional
        Names from :data:`DESIGNS` (default those of :data:`LIBRARY`): the others are the
        designs the hidden-effect sets and the record planner (:mod:`.plan`) use.
    seed : int
        Base seed; design i uses ``seed + i`` so records are independent.
    config : ModelConfig, optional
        The rig (default :func:`synthetic_rig`, the library's ground truth).
    overwrite : bool
        Replace existing records of the same names.
    """
    outdir = Path(outdir)
    names = list(designs) if designs else list(LIBRARY)
    unknown = [n for n in names if n not in DESIGNS]
    if unknown:
        raise ConfigError(f'unknown design(s) {", ".join(unknown)}; use {", ".join(DESIGNS)}')
    cfg = config or synthetic_rig()
    sensors = sensors or SensorModel()
    outdir.mkdir(parents=True, exist_ok=True)
    for name in names:
        for p in _paths(outdir, name, DESIGNS[name].static):
            if p.exists() and not overwrite:
                raise ConfigError(f'{p} exists; pass --force to replace the library records')
    if log:  # after the checks: a refused call prints only its reason
        log(f'generating into {outdir}:')
    model = Model(cfg)
    written = []
    for i, name in enumerate(_seed_order()):
        if name not in names:
            continue
        design = DESIGNS[name]
        exp = make_experiment(cfg, name, seed + i, sensors, model)
        meta = _metadata(exp, seed + i)
        for p in _paths(outdir, name, design.static):
            if p.is_dir():
                shutil.rmtree(p)
            elif p.exists():
                p.unlink()
        if design.static:
            path = write_static_csv(exp, outdir / f'{name}.csv', meta)
        else:
            path = write_experiment_bag(exp, outdir / name, design.storage, meta,
                                        compress=design.storage == 'mcap')
        written.append(path)
        if log:
            log(f'  {path.name:<22} {design.summary}')
    (outdir / TRUTH_FILE).write_text(
        '# Ground truth of the synthetic rig the library was generated from (SI units).\n'
        '# Identified parameters differ from the paper on purpose; see README.md.\n'
        + yaml.safe_dump(cfg.to_dict(), sort_keys=False))
    write_readme(outdir, cfg, sensors, seed)
    return written


def _seed_order() -> list[str]:
    """Every design in the order of its seed offset: the library's first, with the seeds
    they always had, then the others."""
    return [*LIBRARY, *(n for n in DESIGNS if n not in LIBRARY)]


def _metadata(exp, seed: int) -> dict:
    """custom_data / sidecar entries: labelled synthetic, how it was made, the truth."""
    m = exp.metadata
    return {
        'synthetic': True,
        'design': m['design'],
        'description': m['description'],
        'generator': f'pneumatic-servo generate (pneumatic_servo {__version__}, '
                     f'design {m["design"]}, seed {seed})',
        'seed': seed,
        'truth_identified': TRUTH_VALUES,
        'truth': m['truth'],
        'sensors': m['sensors'],
        **{k: m[k] for k in ('blocked_angle_rad', 'held_voltage_v', 'supply_gauge_pa')
           if k in m},
    }


def write_readme(outdir: Path, cfg: ModelConfig, sensors: SensorModel, seed: int) -> Path:
    """``README.md`` of the library: what each record is, how it was made, the truth."""
    rows = []
    for i, name in enumerate(_seed_order()):
        d = DESIGNS[name]
        if d.static:
            fname, fmt = f'{name}.csv', 'CSV (+ .meta.yaml)'
        else:
            fname, fmt = f'{name}/', d.storage + (' (zstd)' if d.storage == 'mcap' else '')
        if not (outdir / fname.rstrip('/')).exists():
            continue
        rows.append(f'| `{fname}` | {d.circuit} | {fmt} | {seed + i} | {d.summary} |')
    truth_rows = [f'| `{k}` | {v:g} | {cfg.param(k).default:g} |' for k, v in
                  TRUTH_VALUES.items()]
    s = sensors.describe()
    text = f"""# Experiment library (SYNTHETIC)

**Every record in this directory is synthetic.** None comes from a real rig: each
was generated from the model (`pneumatic_servo.synth`) and measured through
simulated sensors. Each bag says so in its `metadata.yaml`
(`custom_data: pneumatic_servo.synthetic: 'true'`, with
`pneumatic_servo.generator`, `pneumatic_servo.design`, `pneumatic_servo.seed`,
`pneumatic_servo.sensors` and the full ground truth in `pneumatic_servo.truth`);
each CSV says so in its `.meta.yaml` sidecar.

Regenerate (same seed, same records):

    pneumatic-servo generate bags/ --force            # all records
    pneumatic-servo generate bags/ --force --designs sine_2hz,heat_transfer

## Records

| record | circuit | format | seed | how it was made |
|---|---|---|---|---|
{chr(10).join(rows)}

Bags follow the interface contract (docs/interfaces.md): `valve/command` (Float64, timed by record time),
`joint_states` (position; velocity from the encoder), `chamber_a/pressure`,
`chamber_b/pressure`, `supply/pressure` (FluidPressure, absolute Pa, timed by
`header.stamp`), `chamber_a/temperature`, `chamber_b/temperature` (blocked
records, degC), and `setpoint` (closed-loop records). `custom_data` gives the
circuit (`pneumatic_servo.circuit`) and, for blocked records, where the pistons
were held (`pneumatic_servo.blocked_angle_rad`). Sensor messages are recorded
0.2 ms after their stamp. Supplies are the paper's gauge readings (0.5, 0.6, 0.7,
0.83 MPa) converted to absolute pressure.

## Ground truth

The rig is the paper's model (`ModelConfig.paper()`, Table 2 geometry) with
these identified parameters changed, so that an identification that returned
the paper's values would fail its tests (`truth.yaml` has the full config):

| parameter | truth | paper default |
|---|---|---|
{chr(10).join(truth_rows)}

## Sensors

- DAQ: {s['rate_hz']:g} Hz, one clock for all channels; commands are exact.
- Encoder: {s['encoder_counts_per_rev']} P/R, angle quantised to
  {s['encoder_step_rad']:.3g} rad; velocity = encoder difference over
  {s['velocity_window_s'] * 1e3:g} ms (causal).
- Pressure transmitters: 0-{s['pressure_full_scale_pa'] * 1e-6:g} MPa gauge (1 MPa for the
  static tables at up to 0.83 MPa), noise {s['pressure_noise_fraction'] * 100:g} % FS
  = {s['pressure_noise_pa']:g} Pa (1 sigma), {s['adc_bits']}-bit ADC step
  {s['pressure_quantum_pa']:.3g} Pa.
- Thermocouples: first-order lag {s['thermocouple_time_constant_s']:g} s, noise
  {s['temperature_noise_k']:g} K, step {s['temperature_quantum_k']:g} K.
- Flow meters (static tables): FESTO SFAB for M4 (3 % o.m.v. + 0.3 % of 200 L/min) and
  SFAH for M5 (2 % o.m.v. + 1 % of 5 L/min), taken as 2 sigma per reading, each row the
  mean of {s['readings_per_point']} readings; pressures likewise averaged.

## What the records are for

- `flow_*MPa.csv`: C1 per voltage (Eq. 38) and the Eq. 40 polynomial
  (`pneumatic-servo identify bags/ --steps flow`), flow verification (Section 6.1).
- `closed_port.csv`: Table 5 (steady p_a at held voltages).
- `heat_transfer/`: h from Eqs 41-42 (Section 5.2).
- `charge_discharge/`: Section 6.2, pressures and temperatures with the pistons held.
- `friction_*V/`: friction runs (Fig. 17) for Eq. 43 and the Stribeck fit (Fig. 16).
- `sine_2hz/`: the paper's servo verification (Section 6.3):
  `pneumatic-servo verify bags/sine_2hz --config bags/truth.yaml` passes,
  with the paper's parameters it fails.
- `closed_loop_steps/`, `closed_loop_sine/`: closed-loop PID runs (1 kHz, on the
  encoder angle) for comparison in both views (open loop, k-step).
"""
    path = outdir / 'README.md'
    path.write_text(text)
    return path
