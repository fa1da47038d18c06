"""What is behind the plant node: the simulated model, a rig through a DAQ driver, or a
recorded bag. Pure (no rclpy): the node only sees :class:`Backend`.

A stepping backend (sim, rig) is driven once per period: ``step(u)`` applies
the gated valve voltage ``u`` [V] for the next period and returns the
measurement at its end. ``apply(u)`` writes a fresh command at once where a
real valve is (the rig), so it acts within the period it arrives in.
Replay is not stepped: it yields the bag's measurements at their recorded
times.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..control.measurement import Measurement
from ..errors import ConfigError, ExperimentError
from ..io import read_series
from ..io.topics import CELSIUS_K, SIGNAL_TOPIC
from ..io.validate import check_series

JOINT_STATES = SIGNAL_TOPIC['angle_rad']
PRESSURE_A, PRESSURE_B, PRESSURE_SUPPLY = (SIGNAL_TOPIC[s] for s in ('p_a_pa', 'p_b_pa',
                                                                    'supply_pa'))
TEMPERATURE_A, TEMPERATURE_B = SIGNAL_TOPIC['t_a_k'], SIGNAL_TOPIC['t_b_k']
COMMAND = SIGNAL_TOPIC['command_v']


class Backend:
    """Interface of a stepping backend."""

    kind = ''
    description = ''
    #: a stable identifier of the hardware for /diagnostics (the description is free text)
    hardware_id = ''
    period_s = 1e-3

    def start(self) -> Measurement:
        """The measurement at time 0."""
        raise NotImplementedError

    def step(self, command_v: float) -> Measurement:
        raise NotImplementedError

    def apply(self, command_v: float) -> None:
        """Write a command now (only where a real output exists)."""

    def safe(self) -> None:
        """Drive the valve to the safe voltage now."""

    def close(self) -> None:
        self.safe()


def torque_of(model_config) -> float:
    """[m^3] pneumatic torque per pascal of p_a - p_b: A d_f (the core's moment balance)."""
    core = model_config.core
    return core['piston_area_m2'] * core['pinion_pitch_diameter_m']


class SimBackend(Backend):
    """The nonlinear model stepped in real time (a :class:`~pneumatic_servo.model.Stepper`).

    Parameters
    ----------
    model_config : ModelConfig
        Components, effects and parameter values.
    period_s : float [s]
    initial_angle_rad : float [rad], NaN for mid-stroke
    supply_pa : float [Pa, absolute], NaN for the config's
    method : str
        Stepper integrator: 'adaptive' (error-controlled substeps, capped work per period;
        more accurate and cheaper on average) or 'fixed' (RK4, constant cost).
    """

    kind = 'sim'

    def __init__(self, model_config, period_s: float, initial_angle_rad: float = math.nan,
                 supply_pa: float = math.nan, method: str = 'adaptive'):
        from ..model import Model, Stepper, initial_state
        self.model = Model(model_config)
        self.config = model_config
        self.period_s = float(period_s)
        ps = None if not math.isfinite(supply_pa) else float(supply_pa)
        angle = None if not math.isfinite(initial_angle_rad) else float(initial_angle_rad)
        x0 = initial_state(self.model, angle_rad=angle, supply_pa=ps)
        self.stepper = Stepper(self.model, period_s=self.period_s, x0=x0, supply_pa=ps,
                               method=method)
        # compile the kernels now (seconds with numba), not in the first real-time period
        Stepper(self.model, period_s=self.period_s, x0=x0, supply_pa=ps, method=method).step(5.0)
        self._k = torque_of(model_config)
        effects = ', '.join(model_config.effects) or 'none'
        self.description = f'simulated plant (model effects: {effects})'
        self.hardware_id = 'sim'
        self.t = 0.0

    def _measure(self, x) -> Measurement:
        return Measurement(self.t, x[0], x[1], x[2], x[3], self.stepper.supply_pa, x[4], x[5],
                           self._k * (x[2] - x[3]))

    def start(self) -> Measurement:
        return self._measure(self.stepper.x)

    def set_values(self, text: str) -> None:
        """Set model parameters of the running plant from ``'owner.name=value, ...'`` [SI]
        (parameters of the model_config's components only: the compiled composition does
        not change; an effect put in model_config at its neutral value is switched on
        this way). From the next period on; ConfigError names a bad item, and then
        nothing changes."""
        cfg = self.config.copy()
        for key, value in parse_values(text).items():
            cfg.set(key, value)
        self.stepper.params = self.model.param_vector(cfg)
        self.values = text

    def step(self, command_v: float) -> Measurement:
        x = self.stepper.step(command_v)
        self.t = self.stepper.t
        return self._measure(x)


def parse_values(text: str) -> dict[str, float]:
    """``'owner.name=value, ...'`` -> {key: value} [SI]; ConfigError names a bad item."""
    out = {}
    for item in (t.strip() for t in str(text).split(',')):
        if not item:
            continue
        key, sep, raw = item.partition('=')
        try:
            value = float(raw)
        except ValueError:
            value = math.nan
        if not sep or '.' not in key or not math.isfinite(value):
            raise ConfigError(f'sim_values: {item!r}: write owner.name=number in SI, e.g. '
                              'piston_seal_leakage.seal_leak_area_m2=3e-8')
        out[key.strip()] = value
    return out


class RigBackend(Backend):
    """A rig through :class:`~pneumatic_servo.rig.RigIO` and a DAQ driver."""

    kind = 'rig'

    def __init__(self, rig_config, daq: str, period_s: float, model_config=None,
                 initial_angle_rad: float = math.nan):
        from ..rig import RigIO, make_driver
        self.period_s = float(period_s)
        angle = None if not math.isfinite(initial_angle_rad) else initial_angle_rad
        driver = make_driver(rig_config, daq, self.period_s, model=model_config,
                             initial_angle_rad=angle)
        self.io = RigIO(rig_config, driver, self.period_s)
        self._k = torque_of(model_config) if model_config is not None else math.nan
        self.description = driver.description
        self.hardware_id = f'{daq}:{rig_config.device}'
        self.t = 0.0

    def _read(self) -> Measurement:
        m = self.io.read(self.t)
        m.effort_n_m = self._k * (m.p_a_pa - m.p_b_pa)
        return m

    def start(self) -> Measurement:
        self.io.write(self.io.config.valve.safe_v)
        return self._read()

    def apply(self, command_v: float) -> None:
        self.io.write(command_v)

    def step(self, command_v: float) -> Measurement:
        self.io.write(command_v)
        self.t += self.period_s
        return self._read()

    def safe(self) -> None:
        self.io.safe()

    def close(self) -> None:
        self.io.close()


# ------------------------------------------------------------------------------- replay
@dataclass
class ReplayEvent:
    """One recorded measurement message: its time [ns], topic and fields."""

    t_ns: int
    topic: str
    value: float
    velocity: float = math.nan
    effort: float = math.nan


#: replayed measurement signals -> (topic, field); joint_states carries three
REPLAYED = {'p_a_pa': PRESSURE_A, 'p_b_pa': PRESSURE_B, 'supply_pa': PRESSURE_SUPPLY,
            't_a_k': TEMPERATURE_A, 't_b_k': TEMPERATURE_B}


def read_replay_events(path, joint_name: str, with_command: bool = False
                       ) -> list[ReplayEvent]:
    """The measurements of a rosbag2 (sqlite3 or MCAP), in time order, each at its own
    recorded stamp, read and checked by :func:`pneumatic_servo.io.read_series` (the
    package's bag reader; no resampling, and no topic required but joint_states: a replay
    needs no valve command). ``with_command``: the recorded valve commands too, at their
    record times (for a monitor beside a replay without a controller).

    Temperatures go out in degC, as ``sensor_msgs/Temperature`` carries them. Raises
    ExperimentError with the fix.
    """
    series, meta = read_series(path, joint=joint_name)
    check_series(str(path), series, meta)  # as analysis refuses it: units, gauge, ranges
    if 'angle_rad' not in series:
        raise ExperimentError(f'bag {path} has no joint_states of joint {joint_name!r}; record '
                              'joint_states (and the pressures) to replay it')
    events = []
    if with_command and 'command_v' in series:
        stamps, values = series['command_v']
        events += [ReplayEvent(int(t), COMMAND, float(v))
                   for t, v in zip(stamps.tolist(), values.tolist())]
    for sig, topic in REPLAYED.items():
        if sig in series:
            offset = CELSIUS_K if sig.startswith('t_') else 0.0
            stamps, values = series[sig]
            events += [ReplayEvent(int(t), topic, float(v) - offset)
                       for t, v in zip(stamps.tolist(), values.tolist())]
    stamps, angle = series['angle_rad']
    nan = (stamps, np.full(len(stamps), math.nan))
    velocity, effort = (series.get(s, nan)[1] for s in ('velocity_rad_s', 'effort_n_m'))
    events += [ReplayEvent(int(t), JOINT_STATES, float(a), float(v), float(e))
               for t, a, v, e in zip(stamps.tolist(), angle, velocity, effort)]
    # stable: at one stamp the scalars go first, then joint_states (it triggers the
    # controller), then a command recorded at that time (it answered that sample)
    rank = {JOINT_STATES: 1, COMMAND: 2}
    events.sort(key=lambda e: (e.t_ns, rank.get(e.topic, 0)))
    return events


class ReplaySource:
    """Walks a bag's measurement events in their own time, ``rate`` times real time."""

    kind = 'replay'

    def __init__(self, path, joint_name: str, rate: float = 1.0, loop: bool = False,
                 with_command: bool = False):
        if not rate > 0:
            raise ConfigError(f'replay_rate = {rate!r} must be > 0')
        self.path = Path(path)
        self.events = read_replay_events(path, joint_name, with_command)
        self.rate, self.loop = float(rate), bool(loop)
        self.description = f'replay of {self.path.name} ({len(self.events)} measurements)'
        self.hardware_id = f'replay:{self.path.name}'
        self.t0_ns = self.events[0].t_ns
        self.duration_ns = self.events[-1].t_ns - self.t0_ns
        self.index = 0
        self.laps = 0

    @property
    def finished(self) -> bool:
        return self.index >= len(self.events) and not self.loop

    def next_offset_s(self) -> float:
        """Wall seconds from the start of the current lap to the next event; 0 at the end
        (the caller then finishes or starts the next lap)."""
        if self.index >= len(self.events):
            return 0.0
        return (self.events[self.index].t_ns - self.t0_ns) / 1e9 / self.rate

    def due(self, offset_s: float) -> list[ReplayEvent]:
        """Events due by ``offset_s`` wall seconds into the current lap."""
        out = []
        while self.index < len(self.events):
            e = self.events[self.index]
            if (e.t_ns - self.t0_ns) / 1e9 / self.rate > offset_s:
                break
            out.append(e)
            self.index += 1
        return out

    def lap_offset_ns(self) -> int:
        """Shift added to recorded stamps on repeated laps, so time never runs backwards."""
        return self.laps * (self.duration_ns + 1_000_000)
