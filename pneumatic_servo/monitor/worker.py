"""The monitor's work in other processes: the windows' verdicts in one, the tracked fits in
another, so that whoever feeds the samples (the ROS node) never waits. Pure (no rclpy).

::

    node --samples--> [judge process: Monitor]
         <--windows, reports, floor, fit data--
         --fit data--> [fit process: Tracker]
         <--estimates--

Both are started with ``spawn`` (never ``fork`` a process that runs DDS threads), use one
core at most (numba's thread pool set to one), and end when their parent dies (Linux
``PR_SET_PDEATHSIG``, and a check of the parent). Queues are unbounded on the sender's
side, so ``put`` never blocks; the node drops samples rather than let the queue to the
judge grow beyond :data:`MAX_QUEUED` chunks, and says so.

Messages to the node, ``(kind, payload)``:

* ``('windows', [(stamps_ns, {channel: predicted}), ...])``: what the model predicted;
* ``('report', dict)``: :meth:`Monitor.report`, about once per ``report_period_s`` (of data,
  or of wall time while no window is judged);
* ``('floor', {'path', 'data'})``: the floor measured on the baseline, saved to ``path``;
* ``('estimates', {key: series})``: the tracked parameters after a fit
  (:meth:`Tracker.fit`), from the fit process;
* ``('error', text)``: the judge could not start or failed; it stops.
"""
from __future__ import annotations

import multiprocessing as mp
import os
import queue
import time

#: chunks of samples (about 20 ms each) the node lets wait for the judge before it drops new
#: ones: the judge skips windows long before (decimation); this is for a judge that hangs
MAX_QUEUED = 1500
#: [s] wall time between reports while no window is judged (waiting, baseline)
IDLE_REPORT_S = 1.0


def _die_with_parent(parent: int) -> None:
    """Ask Linux to end this process when its parent dies (even by SIGKILL)."""
    import ctypes
    import signal
    try:
        libc = ctypes.CDLL('libc.so.6', use_errno=True)
        libc.prctl(1, signal.SIGTERM, 0, 0, 0)  # 1 = PR_SET_PDEATHSIG
    except OSError:  # not Linux: the loop checks the parent instead
        pass
    if os.getppid() != parent:
        os._exit(0)


def _one_core() -> None:
    os.environ['NUMBA_NUM_THREADS'] = '1'
    try:
        import numba
        numba.set_num_threads(1)
    except (ImportError, ValueError):
        pass


def _ignore_interrupts() -> None:
    """The node handles the stop signals and stops its workers; a Ctrl-C sent to the whole
    process group must not kill a worker mid-write."""
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def judge_main(config: dict, options: dict, sensors: dict | None, floor_period_s,
               floor_out: str, inbox, outbox, parent: int) -> None:
    """The judge process (see module doc)."""
    _die_with_parent(parent)
    _ignore_interrupts()
    _one_core()
    try:
        from ..model.config import ModelConfig
        from .core import Monitor
        from .floorfile import save_floor
        from .judge import Sensors
        from .options import MonitorOptions
        opts = MonitorOptions.from_dict(options)
        cfg = ModelConfig.from_dict(config)
        mon = Monitor(cfg, opts, Sensors.from_dict(sensors) if sensors else None,
                      floor_period_s=floor_period_s)
        mon.warm_up()
    except Exception as exc:  # noqa: BLE001 - the node must hear why, in one line
        outbox.put(('error', f'monitor could not start: {type(exc).__name__}: '
                             f'{" ".join(str(exc).split())}'))
        return
    outbox.put(('ready', {}))
    last_report = time.monotonic()
    stop = False
    try:
        while not stop:
            if os.getppid() != parent:
                return
            got = False
            while True:  # everything waiting, first: the queue never grows behind compute
                try:
                    msg = inbox.get_nowait()
                except queue.Empty:
                    break
                got = True
                if msg[0] == 'stop':
                    stop = True
                    outbox.cancel_join_thread()  # end now, whatever the node still reads
                    break
                mon.add(msg[1], msg[2])
            out = mon.process()
            if out['predictions']:
                outbox.put(('windows', out['predictions']))
            if out['floor'] and floor_out:
                try:
                    path = save_floor(floor_out, mon.floor_data())
                    outbox.put(('floor', {'path': str(path), 'data': mon.floor_data()}))
                except OSError as exc:
                    outbox.put(('floor', {'path': '', 'error': f'{floor_out}: {exc}',
                                          'data': mon.floor_data()}))
            now = time.monotonic()
            if mon.report_due() or now - last_report >= IDLE_REPORT_S:
                outbox.put(('report', mon.report()))
                last_report = now
            req = mon.fit_request()
            if req is not None:
                outbox.put(('fit_request', req))
            if not got and not out['windows']:
                time.sleep(0.01)
    except Exception as exc:  # noqa: BLE001 - a bug must still reach the node, in one line
        outbox.put(('error', f'monitor failed: {type(exc).__name__}: '
                             f'{" ".join(str(exc).split())}'))


def fit_main(config: dict, options: dict, inbox, outbox, parent: int) -> None:
    """The fit process: one tracked fit at a time (:class:`~.tracking.Tracker`)."""
    _die_with_parent(parent)
    _ignore_interrupts()
    _one_core()
    try:
        from ..model.assembly import Model
        from ..model.config import ModelConfig
        from .options import MonitorOptions
        from .tracking import Tracker
        opts = MonitorOptions.from_dict(options)
        tracker = Tracker(ModelConfig.from_dict(config), opts.track, opts.horizon_s)
        Model(tracker.config)  # compile the tracked composition now, not at the first fit
    except Exception as exc:  # noqa: BLE001
        outbox.put(('fit_error', f'tracked fits could not start: {type(exc).__name__}: '
                             f'{" ".join(str(exc).split())}'))
        return
    outbox.put(('estimates', {k: s.to_json() for k, s in tracker.series.items()}))
    while os.getppid() == parent:
        try:
            msg = inbox.get(timeout=0.5)
        except queue.Empty:
            continue
        if msg[0] == 'stop':
            outbox.cancel_join_thread()
            return
        req = msg[1]
        t0 = time.monotonic()
        try:
            series = tracker.fit(req['t_ns'] * 1e-9, req['signals'], req['dt'])
            outbox.put(('estimates', {**series, '_seconds': time.monotonic() - t0,
                                      '_t_ns': req['t_ns']}))
        except Exception as exc:  # noqa: BLE001 - a failed fit is reported, not fatal
            outbox.put(('fit_error', f'{type(exc).__name__}: {" ".join(str(exc).split())}'))


class _Process:
    """A spawned worker with an inbox and an outbox."""

    def __init__(self, target, args):
        ctx = mp.get_context('spawn')
        self.inbox, self.outbox = ctx.Queue(), ctx.Queue()
        self.proc = ctx.Process(target=target, args=(*args, self.inbox, self.outbox,
                                                     os.getpid()), daemon=True)
        self.proc.start()

    def poll(self, limit: int = 1000) -> list:
        out = []
        while len(out) < limit:
            try:
                out.append(self.outbox.get_nowait())
            except (queue.Empty, OSError, ValueError):
                break
        return out

    @property
    def alive(self) -> bool:
        return self.proc.is_alive()

    def close(self, timeout: float = 5.0) -> None:
        """Ask the process to stop, reading what it still sends meanwhile (a process whose
        queue is full cannot end), and end it if it does not."""
        try:
            self.inbox.put(('stop',))
        except (OSError, ValueError):
            pass
        end = time.monotonic() + timeout
        while self.proc.is_alive() and time.monotonic() < end:
            _Process.poll(self)
            self.proc.join(0.05)
        if self.proc.is_alive():
            self.proc.terminate()
            self.proc.join(2.0)
        for q in (self.inbox, self.outbox):
            q.cancel_join_thread()
            q.close()


class Fitter(_Process):
    """The fit process: one request in flight at most, the latest one waiting."""

    def __init__(self, config: dict, options: dict):
        super().__init__(fit_main, (config, options))
        self.idle = False  # until it has compiled and said so
        self.waiting = None

    def submit(self, request: dict) -> None:
        """Fit ``request`` now if idle, else after the fit in flight (replacing any older
        request still waiting: the latest data are the ones worth fitting)."""
        if self.idle:
            self.idle = False
            self.inbox.put(('fit', request))
        else:
            self.waiting = request

    def poll(self, limit: int = 1000) -> list:
        out = super().poll(limit)
        if out:
            self.idle = True
            if self.waiting is not None:
                request, self.waiting = self.waiting, None
                self.submit(request)
        return out


class MonitorWorker(_Process):
    """The judge process, as the node sees it.

    Parameters
    ----------
    config : ModelConfig
    options : MonitorOptions
    floor : dict, optional
        A loaded floor file (:func:`.floorfile.load_floor`): judge from the first window.
    floor_out : str
        Where to save the floor measured on the baseline ('' : nowhere).
    """

    def __init__(self, config, options, floor: dict | None = None, floor_out: str = ''):
        from dataclasses import asdict
        sensors = floor['sensors'].to_dict() if floor else None
        period = floor['period_s'] if floor else None
        super().__init__(judge_main, (config.to_dict(), asdict(options), sensors, period,
                                      str(floor_out)))
        self.fitter = Fitter(config.to_dict(), asdict(options)) if options.track else None
        self.dropped = 0

    def poll(self, limit: int = 1000) -> list:
        """Messages of the judge and the fit process; fit requests go to the fit process."""
        out = []
        for msg in super().poll(limit):
            if msg[0] == 'fit_request':
                if self.fitter is not None:
                    self.fitter.submit(msg[1])
            else:
                out.append(msg)
        if self.fitter is not None:
            out += self.fitter.poll(limit)
        return out

    def close(self, timeout: float = 5.0) -> None:
        if self.fitter is not None:
            self.fitter.close(timeout)
        super().close(timeout)

    def send(self, stamps_ns, columns: dict) -> bool:
        """Queue samples for the judge; False (and counted) if too many wait already."""
        try:
            if self.inbox.qsize() >= MAX_QUEUED:
                self.dropped += len(stamps_ns)
                return False
        except NotImplementedError:  # pragma: no cover - macOS has no qsize
            pass
        self.inbox.put(('samples', stamps_ns, columns))
        return True
