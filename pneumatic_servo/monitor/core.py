"""The monitor's core: live samples in; judged windows, reports and fit requests out. Pure.

:class:`Monitor` keeps a sliding buffer of samples on a uniform grid (:mod:`.grid`: a lost
sample is a gap; a stamp that goes back, or a gap over a second, starts it afresh), cuts it
into k-step windows of ``horizon_s``, and judges each against its own floor
(:func:`.judge.judge_windows`), a few windows per call so that a caller can interleave
other work. Per channel a CUSUM (:mod:`.cusum`) turns the windows' p-values into a verdict
with a stated false-alarm rate per hour; a report says, per channel, OK / WARN / ERROR, the
departure in units of the floor over the recent data, the CUSUM's p-value and the regime
where the departure concentrates (:mod:`pneumatic_servo.analysis.regimes`).

Without a floor file, judging starts after ``baseline_s`` of data, on which the sensors'
noise and quantisation are measured. When more data wait than ``max_backlog_s``, the
oldest windows are skipped (decimation), counted and reported: the monitor never falls
behind silently, and a judged window is never older than the backlog allows.

Units: stamps in integer nanoseconds, everything else SI.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.regimes import segment
from ..errors import PneumaticServoError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from . import cusum
from .channel import ChannelState
from .grid import SIGNALS, SampleGrid
from .judge import CHANNELS, OPTIONAL, REQUIRED, Sensors, judge_windows
from .options import MonitorOptions

#: samples whose stamps establish the sample period when no rate is given
PERIOD_SAMPLES = 200
LEVELS = ('ok', 'warn', 'error')


def clean_period(dt: float) -> float:
    """A sample period [s] estimated from stamps, snapped to a rate of whole tens of Hz
    when within one per cent of one (a 1 kHz plant whose ticks jitter is a 1 kHz plant)."""
    rate = 1.0 / dt
    tens = 10.0 * round(rate / 10.0)
    return 1.0 / tens if tens >= 10 and abs(rate - tens) <= 0.01 * rate else dt


class Monitor:
    """The model beside the running rig (see module doc).

    Parameters
    ----------
    config : ModelConfig
        The identified model.
    options : MonitorOptions
    sensors : Sensors, optional
        A floor loaded from a file: judging starts at once, no baseline.
    period_s : float [s], optional
        The sample period; None: from the first stamps.
    floor_period_s : float [s], optional
        The period the loaded ``sensors`` were measured at: data at another rate are
        judged on a new baseline instead (and the report says why).
    model : Model, optional
        ``config``'s composition compiled (else compiled here).
    """

    def __init__(self, config: ModelConfig, options: MonitorOptions | None = None,
                 sensors: Sensors | None = None, period_s: float | None = None,
                 model: Model | None = None, floor_period_s: float | None = None):
        self.config = config
        self.options = options or MonitorOptions()
        self.model = model or Model(config)
        self.sensors = sensors
        self.floor_source = 'file' if sensors is not None else 'baseline'
        self.dt = period_s
        self.rng = np.random.default_rng(self.options.seed)
        self.channels = {ch: ChannelState(cusum.Cusum(0.0)) for ch in CHANNELS}
        self._pending_t: list = []
        self._pending_cols: list = []
        self.counts = {'samples': 0, 'lost': 0, 'restarts': 0, 'judged': 0, 'skipped': 0,
                       'incomplete': 0, 'failed': 0}
        self.last_error = ''
        self.grid = SampleGrid()
        self.next_start = None
        self._last_report_ns = None
        self._next_fit = None
        self._fits = 0
        self.floor_rms: dict = {}
        self._baseline_info: dict = {}
        self.floor_period_s = floor_period_s
        if self.dt is not None:
            self._set_period(self.dt)

    def warm_up(self) -> None:
        """Judge one window of simulated data, so that loading the compiled kernels (and any
        first-call cost) happens now, not when the baseline ends."""
        from ..model.simulate import simulate
        dt = 1e-3
        t = np.arange(400) * dt
        u = 5.0 + 0.3 * np.sin(2 * np.pi * 2.0 * t)
        res = simulate(self.model, t, u, config=self.config)
        signals = {'command_v': u, 'angle_rad': res.angle_rad, 'p_a_pa': res.p_a_pa,
                   'p_b_pa': res.p_b_pa}
        sensors = Sensors({ch: 0.0 for ch in CHANNELS}, {ch: 0.0 for ch in CHANNELS})
        judge_windows(self.model, self.config, signals, [100], 201, 50, dt, sensors, 3,
                      np.random.default_rng(0))
        segment(Experiment(t, signals, 'servo', 'warm-up'), None, self.config)

    # ----------------------------------------------------------------- geometry
    def _set_period(self, dt: float) -> None:
        o = self.options
        self.dt = float(dt)
        self.win = max(2, int(round(o.horizon_s / self.dt)) + 1)
        self.lead = int(round(o.lead_s / self.dt))
        self.windows_per_hour = 3600.0 / ((self.win - 1) * self.dt)
        h = cusum.threshold(o.false_alarm_per_hour, self.windows_per_hour, len(CHANNELS))
        for ch in self.channels.values():
            ch.cusum.h = h
        if self.sensors is not None and self.floor_period_s is not None \
                and abs(self.floor_period_s / self.dt - 1.0) > 0.01:
            self.floor_source = (f'baseline (the floor file was measured at '
                                 f'{1 / self.floor_period_s:g} Hz, the data come at '
                                 f'{1 / self.dt:g} Hz)')
            self.sensors = None
        keep_s = max(o.recent_s, o.fit_window_s, 1.5 * o.baseline_s) + o.max_backlog_s + 1.0
        self.grid.dt_ns = int(round(self.dt * 1e9))
        self.grid.keep = int(round(keep_s / self.dt)) + 2 * self.lead + self.win

    @property
    def h(self) -> float:
        return self.channels['angle'].cusum.h

    def _restart(self) -> None:
        """A new run: an empty grid, nothing judged or measured on it yet."""
        self.grid = self.grid.restarted()
        self.next_start = None

    # ------------------------------------------------------------------ samples
    def add(self, stamps_ns, columns: dict) -> None:
        """Append samples in stamp order: ``stamps_ns`` (int ns) and ``columns``, signal ->
        values [SI] (a missing signal or NaN: not measured in that sample)."""
        stamps = np.asarray(stamps_ns, np.int64)
        if len(stamps) == 0:
            return
        n = len(stamps)
        cols = {s: np.asarray(columns[s], float) if s in columns else np.full(n, np.nan)
                for s in SIGNALS}
        self.counts['samples'] += n
        if self.dt is None:
            self._pending_t.append(stamps)
            self._pending_cols.append(cols)
            allt = np.concatenate(self._pending_t)
            if len(allt) < PERIOD_SAMPLES:
                return
            steps = np.diff(allt)
            steps = steps[steps > 0]
            if len(steps) == 0:
                return
            self._set_period(clean_period(float(np.median(steps)) * 1e-9))
            stamps = allt
            cols = {s: np.concatenate([c[s] for c in self._pending_cols]) for s in SIGNALS}
            self._pending_t, self._pending_cols = [], []
        self._append(stamps, cols)

    def _append(self, stamps: np.ndarray, cols: dict) -> None:
        """Place samples on the grid (:meth:`.grid.SampleGrid.index`); a new run where time
        goes back or jumps by more than :data:`.grid.MAX_GAP_S`."""
        # samples on an exact grid (lockstep sim time, a replay) were paired exactly
        cols = dict(cols)
        cols['command_alt_v'] = np.where(self.grid.on_grid(stamps), np.nan,
                                         cols['command_alt_v'])
        index = np.empty(len(stamps), np.int64)
        cut = 0
        for i, t in enumerate(stamps.tolist()):
            k = self.grid.index(t)
            if k is None:
                if i > cut:
                    self._place(stamps[cut:i], {s: v[cut:i] for s, v in cols.items()},
                                index[cut:i])
                self.counts['restarts'] += 1
                self._restart()
                cut = i
                k = self.grid.index(t)
            index[i] = k
        if len(stamps) > cut:
            self._place(stamps[cut:], {s: v[cut:] for s, v in cols.items()}, index[cut:])
        self.grid.trim()

    def _place(self, stamps, cols, index) -> None:
        self.counts['lost'] += self.grid.place(stamps, cols, index)
        if self.next_start is None:
            self.next_start = self.grid.epoch + 2 * self.lead

    # ----------------------------------------------------------------- baseline
    @property
    def state(self) -> str:
        if self.dt is None or self.grid.last_ns is None:
            return 'waiting for data'
        if self.sensors is None:
            return 'baseline'
        return 'judging'

    def _baseline(self) -> bool:
        """Measure the sensors once ``baseline_s`` worth of complete samples are in this
        buffer's run (the latest ones, gaps allowed); True when they were just measured."""
        if self.sensors is not None or self.dt is None:
            return False
        g = self.grid
        need = int(round(self.options.baseline_s / self.dt))
        start = max(g.epoch, g.base)
        if g.end - start < need:
            return False
        rows = g.rows(start, g.end)
        ok = np.flatnonzero(np.all([np.isfinite(g.cols[s][rows]) for s in REQUIRED],
                                   axis=0))
        if len(ok) < need:  # samples missing (a monitor that cannot keep up): wait for more
            return False
        ok = ok[-need:]
        self.sensors = Sensors.measure({s: g.cols[s][rows][ok] for s in CHANNELS.values()})
        self._baseline_info = {'start_ns': int(g.t_ns[rows][ok[0]]),
                               'seconds': float(need * self.dt), 'samples': int(len(ok))}
        self._next_fit = g.end  # the first tracked fit: the baseline itself
        # judging starts with the baseline's latest windows (those the backlog allows): the
        # older ones were data for the floor, not windows the monitor fell behind on
        step = self.win - 1
        keep = (self._backlog_windows() - 1) * step
        if self.next_start is not None and g.end - self.win - keep > self.next_start:
            self.next_start += (g.end - self.win - keep - self.next_start) // step * step
        return True

    def _backlog_windows(self) -> int:
        return int(math.ceil(self.options.max_backlog_s / ((self.win - 1) * self.dt)))

    # --------------------------------------------------------------- judging
    def due(self) -> list[int]:
        """Starts (absolute) of the windows complete in the buffer and not yet judged."""
        if self.next_start is None or self.sensors is None:
            return []
        step = self.win - 1
        last = self.grid.end - self.win
        if last < self.next_start:
            return []
        return list(range(self.next_start, last + 1, step))

    def process(self) -> dict:
        """Measure the baseline if due, then judge up to ``batch_windows`` waiting windows
        (skipping the oldest beyond ``max_backlog_s``). Returns what happened:
        ``{'floor': bool, 'windows': [...], 'predictions': [(stamps_ns, {channel:
        values})], 'alarms': [channel, ...]}``."""
        self._baseline()
        out = {'floor': False, 'windows': [], 'predictions': [], 'alarms': []}
        starts = self.due()
        if not starts:
            return out
        backlog = self._backlog_windows()
        if len(starts) > backlog:
            skipped = starts[:len(starts) - backlog]
            self.counts['skipped'] += len(skipped)
            starts = starts[len(skipped):]
        batch = starts[:self.options.batch_windows]
        self.next_start = batch[-1] + self.win - 1
        good = [a for a in batch if self.grid.complete(a - 2 * self.lead, a + self.win)]
        self.counts['incomplete'] += len(batch) - len(good)
        if not good:
            return out
        lo, hi = good[0] - 2 * self.lead, good[-1] + self.win
        rows = self.grid.rows(lo, hi)
        signals = {s: self.grid.cols[s][rows] for s in REQUIRED + ('command_alt_v',)}
        for s in OPTIONAL:
            if all(self.grid.complete(a - 2 * self.lead, a + self.win, (s,)) for a in good):
                signals[s] = self.grid.cols[s][rows]
        try:
            judged = judge_windows(self.model, self.config, signals, [a - lo for a in good],
                                   self.win, self.lead, self.dt, self.sensors,
                                   self.options.replicas, self.rng, first=lo)
        except PneumaticServoError as exc:
            self.counts['failed'] += len(good)
            self.last_error = ' '.join(str(exc).split())
            return out
        self.counts['judged'] += len(good)
        departing_before = self.departing
        for a, w, (idx, pred) in zip(good, judged.windows, judged.predictions):
            t0 = int(self.grid.t_ns[a - self.grid.base])
            for ch, c in self.channels.items():
                z = cusum.probit(w.p_value[ch])
                if c.cusum.update(z):
                    c.since_ns = t0
                    out['alarms'].append(ch)
                elif not c.cusum.alarm:
                    c.since_ns = None
                c.recent.append((a, t0, w.mean_square[ch], w.floor_mean_square[ch],
                                 w.p_value[ch], z))
                c.forget(self.grid.base + 2 * self.lead,
                         int(round(self.options.recent_s / self.dt)))
            stamps = self.grid.t_ns[self.grid.rows(a, a + self.win)]
            out['windows'].append(w)
            out['predictions'].append((stamps.copy(), {ch: v.copy() for ch, v in pred.items()}))
        if not self.floor_rms:
            self.floor_rms = self._recent_floor_rms()
            out['floor'] = self.floor_source.startswith('baseline')
        if out['alarms'] and self.options.track and self._fits and not departing_before:
            # a departure starts: fit once a whole fit window lies after it (a window
            # across the change would give a value between the two)
            self._next_fit = self.grid.end + int(round(self.options.fit_window_s / self.dt))
        return out

    def _recent_floor_rms(self) -> dict:
        eps = {ch: self.sensors.reading_variance(ch) for ch in CHANNELS}
        return {ch: float(math.sqrt(max(np.median([r[3] for r in c.recent]) - eps[ch], 0.0)))
                for ch, c in self.channels.items() if c.recent}

    # ---------------------------------------------------------------- reports
    def report_due(self) -> bool:
        """True when ``report_period_s`` of data have been judged since the last report."""
        last = self.last_judged_ns
        if last is None:
            return False
        return (self._last_report_ns is None
                or last - self._last_report_ns >= self.options.report_period_s * 1e9)

    @property
    def last_judged_ns(self) -> int | None:
        c = self.channels['angle']
        return c.recent[-1][1] if c.recent else None

    def report(self, regimes: bool = True) -> dict:
        """Where things stand (plain data, ready for a message or JSON): per channel its
        level, departure and the test; the counts; the floor."""
        self._last_report_ns = self.last_judged_ns
        o = self.options
        channels = {}
        shares = self._regime_shares() if regimes else {}
        for ch, c in self.channels.items():
            channels[ch] = c.report(ch, self.sensors, o, getattr(self, 'windows_per_hour', 0.0),
                                    shares.get(ch), self._waiting())
        judged, skipped = self.counts['judged'], self.counts['skipped']
        seen = judged + skipped + self.counts['incomplete'] + self.counts['failed']
        return {
            't_ns': self.last_judged_ns or self.grid.last_ns or 0,
            'state': self.state,
            'channels': channels,
            'counts': dict(self.counts),
            'judged_fraction': judged / seen if seen else float('nan'),
            'decimating': skipped > 0,
            'threshold': self.h if self.dt is not None else float('nan'),
            'windows_per_hour': getattr(self, 'windows_per_hour', float('nan')),
            'false_alarm_per_hour': o.false_alarm_per_hour,
            'floor_source': self.floor_source,
            'floor_rms': dict(self.floor_rms),
            'sensors': self.sensors.to_dict() if self.sensors is not None else None,
            'period_s': self.dt,
            'baseline_left_s': self._baseline_left(),
            'last_error': self.last_error,
        }

    def _baseline_left(self) -> float:
        if self.sensors is not None or self.dt is None or self.grid.last_ns is None:
            return 0.0 if self.sensors is not None else self.options.baseline_s
        rows = self.grid.rows(max(self.grid.epoch, self.grid.base), self.grid.end)
        have = int(np.all([np.isfinite(self.grid.cols[s][rows]) for s in REQUIRED], axis=0).sum())
        return max(self.options.baseline_s - have * self.dt, 0.0)

    def _waiting(self) -> str:
        if self.state == 'waiting for data':
            return 'waiting for data (joint_states, pressures and valve/command)'
        if self.state == 'baseline':
            return (f'measuring the floor on the baseline: {self._baseline_left():.0f} s of '
                    'data to go')
        return 'no window judged yet'

    def _regime_shares(self) -> dict:
        """Channel -> the regime where its departure (squared residual in units of each
        window's floor) concentrates most, over the recent judged windows; None if none
        stands out."""
        c0 = self.channels['angle']
        if not c0.recent or self.sensors is None:
            return {}
        starts = [r[0] for r in c0.recent if r[0] - 2 * self.lead >= self.grid.base]
        if not starts:
            return {}
        lo, hi = starts[0], starts[-1] + self.win
        rows = self.grid.rows(lo, hi)
        need = ('command_v', 'angle_rad', 'p_a_pa', 'p_b_pa')
        if not all(np.all(np.isfinite(self.grid.cols[s][rows])) for s in need):
            return {}
        signals = {s: self.grid.cols[s][rows] for s in need}
        if np.all(np.isfinite(self.grid.cols['supply_pa'][rows])):
            signals['supply_pa'] = self.grid.cols['supply_pa'][rows]
        exp = Experiment(np.arange(hi - lo) * self.dt, signals, 'servo', 'monitor')
        labels = segment(exp, None, self.config)
        return {ch: c.hot_spot(ch, labels, lo, hi, self.win) for ch, c in self.channels.items()}

    # ----------------------------------------------------------- tracked fits
    @property
    def departing(self) -> bool:
        return any(c.cusum.alarm for c in self.channels.values())

    def fit_request(self) -> dict | None:
        """The data for a tracked fit when one is due, else None: ``{'t_ns': end stamp,
        'dt': period, 'signals': {...}}`` over the latest ``fit_window_s`` of complete
        samples. Fits are due at the end of the baseline (the reference), once a whole
        window of data lies after the start of a departure, and then every
        ``fit_period_s`` of data while a channel departs: a rig the model describes is not
        fitted again, so its tracked parameters raise no alert."""
        o = self.options
        if not o.track or self.sensors is None or self._next_fit is None:
            return None
        g = self.grid
        if g.end < self._next_fit or not (self._fits == 0 or self.departing):
            return None
        n = int(round(o.fit_window_s / self.dt))
        hi = g.end
        lo = max(hi - n, g.base, g.epoch)
        rows = g.rows(lo, hi)
        ok = np.all([np.isfinite(g.cols[s][rows]) for s in REQUIRED], axis=0)
        # the longest complete stretch at the end
        bad = np.flatnonzero(~ok)
        first = lo + (bad[-1] + 1 if len(bad) else 0)
        if hi - first < 2 * self.win:
            return None
        self._fits += 1
        self._next_fit = hi + int(round(o.fit_period_s / self.dt))
        rows = g.rows(first, hi)
        signals = {s: g.cols[s][rows].copy() for s in REQUIRED}
        for s in OPTIONAL:
            if np.all(np.isfinite(g.cols[s][rows])):
                signals[s] = g.cols[s][rows].copy()
        return {'t_ns': int(g.t_ns[hi - 1 - g.base]), 'dt': self.dt, 'signals': signals}

    # ------------------------------------------------------------------ floor
    def floor_data(self) -> dict:
        """What a floor file holds (:mod:`.floorfile`)."""
        return {'period_s': self.dt, 'horizon_s': (self.win - 1) * self.dt,
                'measured_on': dict(self._baseline_info),
                'model': {'components': list(self.config.components),
                          'effects': list(self.config.effects)},
                'sensors': self.sensors.to_dict(),
                'floor_rms': {ch: float(v) for ch, v in self.floor_rms.items()}}
