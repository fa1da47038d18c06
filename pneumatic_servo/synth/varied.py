"""Records of varied designs, unlike the hidden-effect sets: to check that the diagnosis's
statements hold their stated error rates on data the project was not tuned on.

A :class:`Record` says how one record is made: the excitation (open-loop sine, chirp or
steps; closed-loop steps or sine under the package's PID or model-based controller, at
any gains), the sample rate, the sensor grade and encoder, the length, the integrator
that generates it (the predictor's adaptive Dormand-Prince, a tighter tolerance, or the
real-time stepper's fixed RK4) and any hidden effects. The closed loop runs the
controller at the record rate on the quantised encoder angle and the noisy pressures
(:class:`~pneumatic_servo.control.ControlLaw`), the plant through
:class:`~pneumatic_servo.model.Stepper`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..control.measurement import Measurement
from ..control.model_based import SlidingModeController
from ..control.pid import PidController
from ..control.reference import Reference
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import DEFAULT_RTOL, Stepper, initial_state, measured_states, simulate
from . import sensors as S
from .hidden import SUPPLY_PA, hidden_config

#: sensor grades: (pressure noise as a fraction of full scale, ADC bits)
GRADES = {'laboratory': (3e-4, 16), 'industrial': (1e-3, 16), 'low_cost': (3e-3, 12)}
#: integrators: name -> (method, relative tolerance factor); 'rk4' is the real-time
#: stepper's fixed-step Runge-Kutta at :data:`RK4_STEP_S`, as accurate as the predictor
INTEGRATORS = {'predictor': ('adaptive', 1.0), 'tight': ('adaptive', 0.01),
               'rk4': ('fixed', 1.0)}
#: [s] step of the fixed-step integrator (10 per sample at 1 kHz leave 0.5 deg of open-loop
#: error over 20 s; 40 leave 0.02 deg, as the adaptive one)
RK4_STEP_S = 25e-6


def rk4_substeps(rate_hz: float) -> int:
    """Fixed steps per sample interval at ``rate_hz`` [Hz]."""
    return max(1, int(math.ceil(1.0 / (rate_hz * RK4_STEP_S))))
EXCITATIONS = ('sine', 'chirp', 'steps', 'closed_steps', 'closed_sine')


@dataclass(frozen=True)
class Record:
    """How one record is made (SI units)."""

    excitation: str = 'closed_steps'
    rate_hz: float = 1000.0
    duration_s: float = 10.0
    grade: str = 'industrial'
    encoder_counts_per_rev: int = 20000
    controller: str = 'pid'
    #: controller parameters (names of the law's specs), e.g. {'kp': 4.0}
    gains: dict = field(default_factory=dict)
    integrator: str = 'predictor'
    effects: dict = field(default_factory=dict)
    seed: int = 0

    @property
    def label(self) -> str:
        loop = f' {self.controller}{self.gains or ""}' if self.excitation.startswith(
            'closed') else ''
        hidden = f' +{",".join(self.effects)}' if self.effects else ''
        return (f'{self.excitation}{loop} {self.rate_hz:g} Hz {self.duration_s:g} s '
                f'{self.grade}/{self.encoder_counts_per_rev} {self.integrator}{hidden}')

    def sensors(self) -> S.SensorModel:
        noise, bits = GRADES[self.grade]
        return replace(S.SensorModel(), rate_hz=self.rate_hz, pressure_noise_fraction=noise,
                       adc_bits=bits, encoder_counts_per_rev=self.encoder_counts_per_rev)


def _setpoint(rec: Record, stroke: float):
    """Setpoint [rad] and its rate [rad/s] as functions of time [s]."""
    if rec.excitation == 'closed_sine':
        return (lambda t: 0.5 * stroke + 0.25 * stroke * math.sin(math.pi * t),
                lambda t: 0.25 * stroke * math.pi * math.cos(math.pi * t))
    levels = np.random.default_rng(rec.seed).uniform(0.2, 0.8, 64) * stroke
    return (lambda t: float(levels[int(t // 1.0) % len(levels)]), lambda t: 0.0)


def _open_loop_command(rec: Record, t: np.ndarray) -> np.ndarray:
    """Valve command [V] of an open-loop record: small, so the actuator stays in its stroke."""
    if rec.excitation == 'sine':
        return 5.0 + 0.3 * np.sin(2.0 * np.pi * 0.5 * t)
    if rec.excitation == 'chirp':  # 0.5 -> 4 Hz
        f = 0.5 + 3.5 * t / t[-1]
        return 5.0 + 0.3 * np.sin(2.0 * np.pi * np.cumsum(f) * (t[1] - t[0]))
    levels = np.random.default_rng(rec.seed).uniform(4.75, 5.25, 64)
    return levels[(t // 0.5).astype(int) % len(levels)]


def _law(rec: Record, model: Model):
    if rec.controller == 'smc':
        return SlidingModeController(model, SUPPLY_PA, **rec.gains)
    return PidController(**rec.gains)


def _closed_loop(rec: Record, cfg: ModelConfig, model: Model, t: np.ndarray,
                 sensors: S.SensorModel, rng: np.random.Generator):
    """(command [V], physical states) of the loop run at the record rate."""
    method, factor = INTEGRATORS[rec.integrator]
    position, rate = _setpoint(rec, cfg.core['stroke_rad'])
    x0 = initial_state(model, angle_rad=position(0.0), command_v=5.0, supply_pa=SUPPLY_PA,
                       config=cfg)
    plant = Stepper(model, 1.0 / rec.rate_hz, x0=x0, command_v=5.0, supply_pa=SUPPLY_PA,
                    method=method, rtol=DEFAULT_RTOL * factor, max_substeps=20000,
                    substeps=rk4_substeps(rec.rate_hz))
    law = _law(rec, model)
    states, u = np.empty((len(t), len(x0))), np.empty(len(t))
    x = x0
    for k, tk in enumerate(t):
        states[k] = x
        m = Measurement(tk, S.quantise(x[0], sensors.encoder_step_rad),
                        p_a_pa=x[2] + rng.normal(0.0, sensors.pressure_noise_pa),
                        p_b_pa=x[3] + rng.normal(0.0, sensors.pressure_noise_pa),
                        supply_pa=SUPPLY_PA)
        u[k] = law.update(tk, Reference(position(tk), rate(tk)), m)
        x = plant.step(u[k])
    return u, states


def make_record(rec: Record, base: ModelConfig | None = None) -> Experiment:
    """The record ``rec`` describes, of the model ``base`` (default the paper's) with
    ``rec.effects`` hidden, measured through ``rec``'s sensors."""
    cfg = hidden_config(rec.effects, base)
    model = Model(cfg)
    sensors = rec.sensors()
    rng = np.random.default_rng(rec.seed)
    run_in = 1.0
    t = np.arange(int(round((rec.duration_s + run_in) * rec.rate_hz))) / rec.rate_hz
    if rec.excitation.startswith('closed'):
        u, states = _closed_loop(rec, cfg, model, t, sensors, rng)
    else:
        method, factor = INTEGRATORS[rec.integrator]
        u = _open_loop_command(rec, t)
        x0 = initial_state(model, angle_rad=0.5 * cfg.core['stroke_rad'], command_v=5.0,
                           supply_pa=SUPPLY_PA, config=cfg)
        states = simulate(model, t, u, SUPPLY_PA, x0=x0, config=cfg, measured=False,
                          method='adaptive' if method == 'adaptive' else 'fixed',
                          rtol=DEFAULT_RTOL * factor, substeps=rk4_substeps(rec.rate_hz)).states
    # the hidden effects' sensor errors, over the whole record (the loop's controller sees the
    # physical angle and pressures: a sensor error does not act back through it here)
    states = measured_states(model, cfg, t, states, u, np.full(len(t), SUPPLY_PA))
    keep = slice(int(round(run_in * rec.rate_hz)), None)
    t_rec = t[keep] - t[keep][0]
    true = {'supply_pa': np.full(len(t_rec), SUPPLY_PA), 'angle_rad': states[keep, 0],
            'p_a_pa': states[keep, 2], 'p_b_pa': states[keep, 3]}
    sig = S.measure(t_rec, true, rng, sensors, velocity=False)
    exp = Experiment(t_rec, {'command_v': u[keep], **sig}, 'servo', rec.label)
    exp.metadata.update(synthetic='true', generator='pneumatic_servo.synth.varied')
    return exp


def clean_study(count: int = 50, seed: int = 1) -> list[Record]:
    """``count`` clean records drawn over every axis of variation (reproducibly)."""
    rng = np.random.default_rng(seed)
    pid_gains = ({}, {'kp': 2.0}, {'kp': 8.0, 'kd': 0.1}, {'kp': 4.0, 'ki': 4.0})
    out = []
    for i in range(count):
        excitation = EXCITATIONS[i % len(EXCITATIONS)]
        controller = 'smc' if excitation.startswith('closed') and i % 4 == 0 else 'pid'
        out.append(Record(
            excitation=excitation, rate_hz=float(rng.choice([250.0, 500.0, 1000.0])),
            duration_s=float(rng.choice([10.0, 20.0, 30.0, 60.0], p=[0.5, 0.3, 0.1, 0.1])),
            grade=str(rng.choice(list(GRADES))),
            encoder_counts_per_rev=int(rng.choice([4096, 20000])),
            controller=controller,
            gains={} if controller == 'smc' else pid_gains[int(rng.integers(len(pid_gains)))],
            integrator=str(rng.choice(list(INTEGRATORS))), seed=1000 + i))
    return out
