"""The monitor node: the identified model beside the running rig, judging it as it runs.

Subscribes (best effort, deep queues: it can never slow a publisher down) to the
interface topics of any plant backend, sim, rig or replay: ``joint_states``,
``chamber_a/pressure``, ``chamber_b/pressure``, ``supply/pressure``, the two temperatures
when published, and ``valve/command``. It publishes nothing a plant or a controller reads:

* ``model/joint_states``, ``model/chamber_a/pressure``, ``model/chamber_b/pressure``: what
  the model predicted, k-step from the measured state, stamped like the measurements it
  predicts (overlay them in a plot);
* ``monitor/residuals`` (std_msgs/Float64MultiArray, columns
  :data:`.monitor_messages.RESIDUAL_FIELDS`): per channel the departure in units of the
  floor, the RMS residual and floor, the CUSUM, its threshold and p-value;
* ``monitor/effects`` (std_msgs/Float64MultiArray, columns
  :data:`.monitor_messages.EFFECT_FIELDS`): the tracked effects' estimates with standard
  errors;
* ``/diagnostics``: ``<node>: monitor`` (the monitor itself), ``<node>: monitor angle|p_a|p_b``
  (OK / WARN / ERROR per channel, with the departure, the regime and the p-value) and
  ``<node>: monitor <effect.parameter>`` (WARN when it trends), hardware_id ``monitor``.

The work is done in worker processes (:mod:`pneumatic_servo.monitor.worker`); this node only
takes messages, pairs commands with measurements (:mod:`pneumatic_servo.monitor.assemble`),
hands samples over and publishes what comes back. A lifecycle node with ``autostart``, as
the plant.
"""
from __future__ import annotations

import math
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import FluidPressure, JointState, Temperature
from std_msgs.msg import Float64, Float64MultiArray

from ..errors import ConfigError, PneumaticServoError
from ..text import comma_list
from . import cdr, common, monitor_messages as messages, private
from .monitor_specs import MONITOR_SPECS

monotonic = time.monotonic
#: the monitor's topics (relative: a namespace moves them with the rig's; ros/common.py)
MODEL_JOINT_STATES = common.MODEL_JOINT_STATES
MODEL_PRESSURE_A = common.MODEL_PRESSURE_A
MODEL_PRESSURE_B = common.MODEL_PRESSURE_B
RESIDUALS = common.MONITOR_RESIDUALS
EFFECTS = common.MONITOR_EFFECTS
#: [s] wall time between hand-overs of finished samples to the judge
SEND_PERIOD_S = 0.02
#: messages taken per subscription and turn at most (a turn stays short)
TAKE_LIMIT = 2000
#: deep best-effort queues: the monitor may lag a burst, a publisher never waits for it
LISTEN_QOS = QoSProfile(depth=5000, history=HistoryPolicy.KEEP_LAST,
                        reliability=ReliabilityPolicy.BEST_EFFORT)
MODEL_QOS = QoSProfile(depth=200, history=HistoryPolicy.KEEP_LAST,
                       reliability=ReliabilityPolicy.BEST_EFFORT)
REPORT_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)




class MonitorNode(LifecycleNode):
    """Monitor node (see module doc). ``overrides`` preset parameter values (command line)."""

    def __init__(self, node_name: str = 'pneumatic_servo_monitor',
                 overrides: dict | None = None, **kwargs):
        super().__init__(node_name, **kwargs)
        self.p = common.declare(self, MONITOR_SPECS, overrides)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.state = 'unconfigured'
        self.worker = None
        self.halt_reason = ''
        self.hot_subscriptions = []  # drained in tick: the messages' source stamps matter
        self.listen = []
        self.pubs = {}
        self.report = None
        self.estimates = {}
        self.floor_note = ''
        self.fit_note = ''
        self.worker_error = ''
        self.published = 0
        self.sent = 0
        self._next_send = 0.0
        self._next_diag = 0.0
        self._last_levels = None
        self.assembler = None
        self._heard = (0, 0.0)  # (measurements received, wall time [s] the count last grew)
        self.diag_pub = self.create_publisher(DiagnosticArray, common.DIAGNOSTICS,
                                              common.DIAGNOSTICS_QOS)
        if self.p['autostart']:
            if self.trigger_configure() != TransitionCallbackReturn.SUCCESS:
                raise ConfigError(self.halt_reason or 'monitor: configure failed')
            if self.trigger_activate() != TransitionCallbackReturn.SUCCESS:
                raise ConfigError(f'monitor: {self.halt_reason or "activation failed"}')

    # -------------------------------------------------------------- parameters
    def _on_set_parameters(self, params):
        result = common.validate_update(MONITOR_SPECS, self.p, params)
        if result.successful:
            for prm in params:
                if prm.name in self.p:
                    self.p[prm.name] = MONITOR_SPECS[prm.name].coerce(prm.value)
        return result

    # --------------------------------------------------------------- lifecycle
    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        try:
            self._start_worker()
        except Exception as exc:  # noqa: BLE001 - the reason is logged and reported
            reason = str(exc) if isinstance(exc, PneumaticServoError) else \
                f'{type(exc).__name__}: {exc}'
            self.halt_reason = ' '.join(reason.split())
            self.get_logger().error(f'configure failed: {self.halt_reason}')
            return TransitionCallbackReturn.FAILURE
        self._make_topics()
        self.state = 'inactive'
        return TransitionCallbackReturn.SUCCESS

    def _start_worker(self) -> None:
        import os
        from pathlib import Path

        from ..model import ModelConfig
        from ..monitor.floorfile import default_floor_path, load_floor
        from ..monitor.options import MonitorOptions
        from ..monitor.worker import MonitorWorker
        from .paths import resolve
        p = self.p
        path = resolve(p['model_config']) if p['model_config'] else None
        self.config = ModelConfig.load(path) if path else ModelConfig.paper()
        self.options = MonitorOptions(
            horizon_s=p['horizon_s'], lead_s=p['lead_s'], replicas=p['replicas'],
            baseline_s=p['baseline_s'], false_alarm_per_hour=p['false_alarm_per_hour'],
            error_ratio=p['error_ratio'], recent_s=p['recent_s'],
            max_backlog_s=p['max_backlog_s'], track=comma_list(p['track']),
            fit_window_s=p['fit_window_s'], fit_period_s=p['fit_period_s'], seed=p['seed'])
        floor = None
        if p['floor_file'] and Path(p['floor_file']).exists():
            floor = load_floor(p['floor_file'])
            self.floor_out = ''
            self.floor_note = f'loaded from {p["floor_file"]}'
        else:
            self.floor_out = p['floor_file'] or str(default_floor_path(self.get_name()))
            self.floor_note = f'measured on the first {p["baseline_s"]:g} s of data'
        if p['nice'] > 0:  # the workers inherit it
            try:
                os.nice(max(p['nice'] - os.nice(0), 0))
            except OSError as exc:
                self.get_logger().warn(f'nice {p["nice"]} not set ({exc})')
        self.worker = MonitorWorker(self.config, self.options, floor, self.floor_out)
        self.get_logger().info(
            f'monitor: model {"from " + str(path) if path else "of the paper"} (effects: '
            f'{", ".join(self.config.effects) or "none"}); floor {self.floor_note}; tracking '
            f'{", ".join(self.options.track) or "nothing"}')

    def _make_topics(self) -> None:
        if self.pubs:
            return
        self.pubs = {
            MODEL_JOINT_STATES: self.create_publisher(JointState, MODEL_JOINT_STATES, MODEL_QOS),
            MODEL_PRESSURE_A: self.create_publisher(FluidPressure, MODEL_PRESSURE_A, MODEL_QOS),
            MODEL_PRESSURE_B: self.create_publisher(FluidPressure, MODEL_PRESSURE_B, MODEL_QOS),
            RESIDUALS: self.create_publisher(Float64MultiArray, RESIDUALS, REPORT_QOS),
            EFFECTS: self.create_publisher(Float64MultiArray, EFFECTS, REPORT_QOS),
        }
        # every subscription has a handler of (message, info): the event loop's executor
        # may take a message now and then, and must hand it over with its source stamp too
        topics = [(JointState, common.JOINT_STATES, self._on_joint),
                  (FluidPressure, common.PRESSURE_A, self._on_scalar('p_a_pa')),
                  (FluidPressure, common.PRESSURE_B, self._on_scalar('p_b_pa')),
                  (FluidPressure, common.PRESSURE_SUPPLY, self._on_scalar('supply_pa')),
                  (Temperature, common.TEMPERATURE_A, self._on_scalar('t_a_k', True)),
                  (Temperature, common.TEMPERATURE_B, self._on_scalar('t_b_k', True)),
                  (Float64, common.COMMAND, self._on_command),
                  (Float64, common.VALVE_APPLIED, self._on_applied)]
        self.listen = [self.create_subscription(kind, topic, cb, LISTEN_QOS, raw=True)
                       for kind, topic, cb in topics]
        if self.p['plant_status']:
            self.listen.append(self.create_subscription(
                DiagnosticArray, common.DIAGNOSTICS, self._on_plant_status,
                common.DIAGNOSTICS_QOS))
        self.valve_held = False
        self.held_note = ''

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        from ..monitor.assemble import Assembler
        self.assembler = Assembler()
        self.state = 'active'
        self.get_logger().info('active: judging the rig against its model')
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.state = 'inactive'
        self.assembler = None
        self._publish_diagnostics(force=True)
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._stop_worker()
        for sub in self.listen:
            self.destroy_subscription(sub)
        for pub in self.pubs.values():
            self.destroy_publisher(pub)
        self.listen, self.pubs = [], {}
        self.state = 'unconfigured'
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.shutdown('lifecycle shutdown')
        return TransitionCallbackReturn.SUCCESS

    def _stop_worker(self) -> None:
        if self.worker is not None:
            self.worker.close()
            self.worker = None

    def shutdown(self, reason: str) -> None:
        """Stop the workers and say so (the event loop calls this on signals and errors)."""
        if self.state == 'shut down':
            return
        self._stop_worker()
        self.state = 'shut down'
        try:
            self._publish_diagnostics(force=True, extra=f'shut down ({reason})')
        except Exception:  # the context may already be gone
            pass

    # ---------------------------------------------------------------- the loop
    def next_deadline(self) -> float:
        if self.state == 'active':
            return monotonic() + 0.005
        return self._next_diag

    def tick(self, now: float) -> None:
        if self.state == 'active':
            self._take()
            if now >= self._next_send:
                self._next_send = now + SEND_PERIOD_S
                self._send()
        if self.worker is not None:
            self._poll_worker()
        if now >= self._next_diag:
            self._publish_diagnostics()

    def _take(self) -> None:
        """Everything waiting on the subscriptions, into the assembler."""
        for sub in self.listen:
            for _ in range(TAKE_LIMIT):
                got = private.take_with_source(sub)
                if got is None:
                    break
                sub.callback(got[0], {'source_timestamp': got[1],
                                      'received_timestamp': got[2]})

    def _when(self, info) -> int:
        key = 'received_timestamp' if self.p['command_order'] == 'received' \
            else 'source_timestamp'
        return int(info[key])

    def _on_joint(self, data: bytes, info) -> None:
        if self.assembler is None:
            return
        try:
            js = cdr.unpack_joint_state(data, self.p['joint_name'])
        except (ValueError, IndexError):  # a malformed message is not a sample
            return
        if js is not None:
            self.assembler.joint(js[0], js[1], self._when(info))

    def _on_scalar(self, signal: str, celsius: bool = False):
        offset = common.CELSIUS_K if celsius else 0.0

        def cb(data: bytes, info) -> None:
            if self.assembler is None:
                return
            try:
                stamp, value = cdr.unpack_scalar(data)
            except (ValueError, IndexError):
                return
            self.assembler.scalar(signal, stamp, value + offset)
        return cb

    def _on_plant_status(self, msg, info) -> None:
        """The plant's gate: held safe (a latched fault, inactive) or commanding."""
        if self.assembler is None:
            return
        for st in msg.status:
            if st.name != self.p['plant_status']:
                continue
            values = {kv.key: kv.value for kv in st.values}
            held = bool(values.get('faults')) or values.get('state', 'active') != 'active' \
                or 'held at' in st.message
            if held != self.valve_held:
                what = 'holds its valve safe' if held else 'commands its valve again'
                self.get_logger().info(f'the plant {what}: {st.message}')
            self.valve_held = held
            self.held_note = st.message if held else ''
            stamp = msg.header.stamp
            self.assembler.valve_held(stamp.sec * 1_000_000_000 + stamp.nanosec, held)

    def _float64(self, data: bytes) -> float | None:
        """A std_msgs/Float64's value, or None (not assembling yet, or a malformed message)."""
        if self.assembler is None:
            return None
        try:
            return cdr.unpack_float64(data)
        except (ValueError, IndexError):
            return None

    def _on_applied(self, data: bytes, info) -> None:
        value = self._float64(data)
        if value is not None:
            # always by source: the plant published it, and the next sample, in this order
            self.assembler.applied(value, int(info['source_timestamp']))

    def _on_command(self, data: bytes, info) -> None:
        value = self._float64(data)
        if value is not None:
            self.assembler.command(value, self._when(info))

    def _send(self) -> None:
        got = self.assembler.take(time.time_ns())
        if got is not None and self.worker is not None:
            stamps, columns = got
            if self.worker.send(stamps, columns):
                self.sent += len(stamps)

    def _poll_worker(self) -> None:
        for kind, payload in self.worker.poll():
            if kind == 'windows':
                if self.p['publish_model'] and self.state == 'active':
                    self._publish_model(payload)
            elif kind == 'report':
                self.report = payload
                self._publish_residuals(payload)
                levels = tuple(c['level'] for c in payload['channels'].values())
                self._publish_diagnostics(force=levels != self._last_levels)
                self._last_levels = levels
            elif kind == 'estimates':
                self.estimates = {k: v for k, v in payload.items() if not k.startswith('_')}
                self.fit_note = (f'last fit took {payload["_seconds"]:.1f} s'
                                 if '_seconds' in payload else 'compiled, waiting')
                self._publish_effects()
                self._publish_diagnostics(force=True)
            elif kind == 'floor':
                if payload.get('path'):
                    self.floor_note = (f'measured on the baseline, saved to {payload["path"]}')
                    self.get_logger().info(f'floor {self.floor_note}')
                else:
                    self.floor_note = f'measured on the baseline; not saved: {payload["error"]}'
                    self.get_logger().warn(self.floor_note)
            elif kind == 'fit_error':
                self.fit_note = f'a tracked fit failed: {payload}'
                self.get_logger().warn(self.fit_note)
            elif kind == 'error':
                self.worker_error = payload
                self.get_logger().error(payload)
                self._publish_diagnostics(force=True)

    # -------------------------------------------------------------- publishing
    def _publish_model(self, windows) -> None:
        frame = b''
        name = self.p['joint_name'].encode()
        js, pa, pb = (self.pubs[t] for t in (MODEL_JOINT_STATES, MODEL_PRESSURE_A,
                                             MODEL_PRESSURE_B))
        for stamps, pred in windows:
            # the first sample of a window is its measured start: not a prediction
            for k in range(1, len(stamps)):
                sec, nsec = divmod(int(stamps[k]), 1_000_000_000)
                js.publish(cdr.pack_joint_state(sec, nsec, frame, name, float(pred['angle'][k])))
                pa.publish(cdr.pack_scalar(sec, nsec, frame, float(pred['p_a'][k])))
                pb.publish(cdr.pack_scalar(sec, nsec, frame, float(pred['p_b'][k])))
                self.published += 1

    def _publish_residuals(self, report: dict) -> None:
        self.pubs[RESIDUALS].publish(messages.residual_table(report))

    def _publish_effects(self) -> None:
        if self.estimates:
            self.pubs[EFFECTS].publish(messages.effect_table(self.estimates))

    def _publish_diagnostics(self, force: bool = False, extra: str = '') -> None:
        now = monotonic()
        if not force and now < self._next_diag:
            return
        self._next_diag = now + self.p['diagnostics_period_s']
        arr = DiagnosticArray()
        rep = self.report
        stamp = rep['t_ns'] if rep and rep.get('t_ns') else self.get_clock().now().nanoseconds
        common.set_stamp(arr.header.stamp, stamp)
        arr.status = [self._node_status(extra)]
        if rep is not None:
            arr.status += messages.channel_statuses(self.get_name(), rep)
        arr.status += messages.estimate_statuses(self.get_name(), self.estimates)
        self.diag_pub.publish(arr)

    def _silent_s(self) -> float:
        """[s] wall time since the last measurement came (0 before the first, or inactive)."""
        if self.assembler is None or not self.assembler.received['joint_states']:
            return 0.0
        count, now = self.assembler.received['joint_states'], monotonic()
        if count != self._heard[0]:
            self._heard = (count, now)
        return now - self._heard[1]

    def _node_status(self, extra: str = '') -> DiagnosticStatus:
        rep = self.report or {}
        counts = rep.get('counts', {})
        dropped = self.worker.dropped if self.worker is not None else 0
        if self.worker_error or self.halt_reason:
            level, words = 'error', [self.worker_error or self.halt_reason]
        elif self.worker is None and self.state not in ('unconfigured', 'shut down'):
            level, words = 'error', ['no worker']
        elif self.worker is not None and not self.worker.alive:
            level, words = 'error', ['the judging process died']
        else:
            no_commands = (self.assembler is not None
                           and self.assembler.received['commands'] == 0
                           and self.assembler.received['joint_states'] > 0)
            held = self.held_note if getattr(self, 'valve_held', False) else None
            level, words = messages.health(self.state, rep, dropped, held, no_commands,
                                           self._silent_s())
        if extra:
            words.insert(0, extra)
        sensors = rep.get('sensors') or {}
        values = {'state': self.state, 'judge': rep.get('state', ''),
                  'windows_judged': counts.get('judged', 0),
                  'windows_skipped': counts.get('skipped', 0),
                  'windows_incomplete': counts.get('incomplete', 0),
                  'windows_failed': counts.get('failed', 0),
                  'samples_lost': counts.get('lost', 0), 'samples_dropped': dropped,
                  'samples_sent': self.sent, 'predictions_published': self.published,
                  'judged_fraction': rep.get('judged_fraction', math.nan),
                  'false_alarm_per_hour': self.p['false_alarm_per_hour'],
                  'threshold': rep.get('threshold', math.nan),
                  'windows_per_hour': rep.get('windows_per_hour', math.nan),
                  'period_s': rep.get('period_s') or math.nan,
                  'floor': self.floor_note, 'floor_source': rep.get('floor_source', ''),
                  'tracked': ', '.join(self.options.track) if hasattr(self, 'options') else '',
                  'fits': self.fit_note,
                  'model_effects': ', '.join(self.config.effects) if hasattr(self, 'config')
                  else ''}
        for ch, v in (rep.get('floor_rms') or {}).items():
            values[f'floor_rms_{ch}'] = v
        for ch, v in (sensors.get('noise') or {}).items():
            values[f'noise_{ch}'] = v
        return messages.status(self.get_name(), 'monitor', level, '; '.join(words), values)
