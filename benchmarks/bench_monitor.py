"""The monitor beside a free-running 1 kHz sim plant (this is not a test: it prints what it
measures).

* the plant's achieved rate and period jitter (its own /diagnostics) with the PID controller
  in another process, first without the monitor, then with it: the monitor must not slow
  the loop down;
* the wall time from the monitor's start to its first verdicts (default options: the
  paper's model, a 20 s baseline, no floor file), against the issue's 30 s;
* the monitor's CPU share (its node process, and the judge and fit processes it starts, from
  /proc), and whether it keeps up with 1 kHz: windows judged, skipped (decimation, which it
  reports), incomplete, and samples missing;
* the WARNs it raised on the healthy free-running plant;
* (``--lockstep S``) beside lockstep plant and controller in one process: the loop's speed
  and the share of the windows the monitor judges (at its default nice 10 it decimates);
* (``--figure PNG``, alone) a recorded monitored run with a seal leak switched on, drawn:
  ``docs/figures/monitor.png``.

The machine's load average is printed too: these are wall-clock and CPU figures on shared
cores, with other work running.

Usage::

    python benchmarks/bench_monitor.py [--seconds S] [--lockstep S] [--json PATH]
    python benchmarks/bench_monitor.py --figure docs/figures/monitor.png
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / 'tests' / 'ros'))

MONITOR = 'pneumatic_servo_monitor'
TICK = os.sysconf('SC_CLK_TCK')


def cpu_seconds(pid: int) -> float:
    """User + system CPU time [s] of process ``pid`` (0 if it is gone)."""
    try:
        fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / TICK


def children(pid: int) -> list[int]:
    out = []
    for stat in Path('/proc').glob('[0-9]*/stat'):
        try:
            fields = stat.read_text().rsplit(')', 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            out.append(int(stat.parent.name))
    return out


def node_status(probe):
    """The monitor's own latest status (not a channel's)."""
    for _, st in reversed(probe.diagnostics):
        if st.name == f'{MONITOR}: monitor':
            return st
    return None


def plant_timing(probe, since: float) -> dict:
    """The plant's latest rate and jitter (its /diagnostics) received after ``since``."""
    st = probe.diag(': plant', since)
    if st is None:
        return {}
    v = probe.diag_values(st)
    return {k: float(v[k]) for k in ('achieved_rate_hz', 'jitter_p50_ms', 'jitter_p99_ms',
                                     'overruns') if k in v}


def start_free_loop(procs, probe, *plant_args, first_move_s: float, moves: int) -> None:
    """The PID controller and a free-running sim plant (``plant_args`` added) in processes of
    their own, then a move to a random angle every second from ``first_move_s`` after the
    plant's first sample. The plant's watchdog is 1 s: on shared, loaded cores a starved
    controller must not trip the 100 ms one mid-run (as tests/ros/test_rig_io.py does)."""
    import numpy as np

    from pneumatic_servo.control.reference import TrajectoryPoint
    from pneumatic_servo.ros import common
    procs.start('controller', name='controller')
    procs.start('plant', *plant_args, '--set', 'initial_angle_rad=1.0', '--set',
                'watchdog_s=1.0', name='plant')
    probe.spin_until(lambda: probe.joint, 60.0, 'the plant')
    t0 = probe.joint[-1][0]
    rng = np.random.default_rng(0)
    probe.send(probe.trajectory_pub, common.joint_trajectory(
        [TrajectoryPoint(t0 + first_move_s + k, float(rng.uniform(0.6, 2.6)), 0.0, 0.0)
         for k in range(moves)], 'actuator_joint'))


def figure(png: Path, leak_after_s: float = 25.0, record_s: float = 40.0) -> dict:
    """A monitored free-running run with a seal leak switched on, recorded with the
    monitor's topics and drawn (pneumatic_servo.monitor.figure): returns what happened."""
    from rostest_helpers import Probe, Procs, level

    from pneumatic_servo.monitor.figure import plot_run
    domain = 100 + (os.getpid() + 1) % 100
    tmp = Path(tempfile.mkdtemp(prefix='monitor_figure_'))
    cfg = tmp / 'plant.yaml'
    cfg.write_text('effects:\n  piston_seal_leakage: {seal_leak_area_m2: 0.0}\n')
    procs, probe = Procs(domain, tmp), Probe(domain, 'figure')
    try:
        start_free_loop(procs, probe, '--config', cfg, first_move_s=2.5, moves=600)
        probe.spin_until(lambda: 'commanding' in (probe.diag(': plant').message
                                                  if probe.diag(': plant') else ''),
                         60.0, 'the plant commanding')
        procs.start('monitor', '--baseline', '10', '--track', 'piston_seal_leakage', '--floor',
                    tmp / 'floor.yaml', '--set', 'fit_window_s=5', '--set', 'fit_period_s=5',
                    name='monitor')
        probe.spin_until(lambda: node_status(probe) is not None, 60.0, 'the monitor')
        bag = tmp / 'run'
        rec = procs.start('record', bag, '--duration', record_s, '--monitor', name='record')
        start = time.monotonic()
        probe.spin(leak_after_s)
        leak_stamp = probe.joint[-1][0]
        probe.set_parameters('pneumatic_servo_plant',
                             sim_values='piston_seal_leakage.seal_leak_area_m2=3e-8')
        rec.wait(record_s + 60)
        plant = probe.diag(': plant')
        if plant is None or level(plant) >= 2:
            raise RuntimeError(f'the plant faulted during the run: {plant and plant.message}; '
                               'run it again on a less loaded machine')
        from pneumatic_servo.monitor.figure import read_run
        first = read_run(bag)['t0']
        plot_run(bag, png, change_s=leak_stamp - first,
                 title='The monitor beside a free-running simulated rig: a piston seal leak '
                       '(3e-8 m^2) switched on in the running plant')
        return {'bag': str(bag), 'leak_at_s': leak_stamp - first, 'png': str(png),
                'recorded_after_s': time.monotonic() - start}
    finally:
        procs.cleanup()
        probe.close()


def lockstep(sim_s: float) -> dict:
    """The monitor (a floor file from a first run, so it judges at once) beside lockstep
    plant and controller in one process (``up --processes 1``): the loop's speed with the
    monitor running, and the share of the windows it judges."""
    import numpy as np
    from rostest_helpers import Probe, Procs

    from pneumatic_servo.control.reference import TrajectoryPoint
    from pneumatic_servo.ros import common
    domain = 100 + (os.getpid() + 2) % 100
    tmp = Path(tempfile.mkdtemp(prefix='monitor_lockstep_'))
    procs, probe = Procs(domain, tmp), Probe(domain, 'lockstep')
    try:
        procs.start('monitor', '--baseline', '5', name='monitor')
        probe.spin_until(lambda: node_status(probe) is not None, 60.0, 'the monitor')
        procs.start('up', '--clock', 'lockstep', '--processes', 1, '--plant-set',
                    'initial_angle_rad=1.0', '--plant-set', 'wait_subscribers=3', name='up')
        rng = np.random.default_rng(0)
        probe.send(probe.trajectory_pub, common.joint_trajectory(
            [TrajectoryPoint(0.5 + k, float(rng.uniform(0.6, 2.6)), 0.0, 0.0)
             for k in range(int(sim_s) + 5)], 'actuator_joint'), wait_subscribers=60.0)
        probe.spin_until(lambda: probe.joint, 60.0, 'the plant')
        wall0, sim0 = time.monotonic(), probe.joint[-1][0]
        probe.spin_until(lambda: probe.joint[-1][0] - sim0 >= sim_s, 600.0, 'the run')
        speed = (probe.joint[-1][0] - sim0) / (time.monotonic() - wall0)
        probe.spin(5.0)
        v = probe.diag_values(node_status(probe))
        judged = int(v['windows_judged'])
        return {'sim_s': sim_s, 'speed': speed, 'windows_judged': judged,
                'windows_of_data': (probe.joint[-1][0] - probe.joint[0][0] - 5.0) / 0.2,
                'skipped': int(v['windows_skipped']),
                'incomplete': int(v['windows_incomplete']),
                'samples_missing': int(v['samples_lost']),
                'node_status': node_status(probe).message}
    finally:
        procs.cleanup()
        probe.close()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--seconds', type=float, default=30.0,
                    help='seconds of each measurement (default 30)')
    ap.add_argument('--json', metavar='PATH', help='write the figures as JSON')
    ap.add_argument('--lockstep', type=float, default=60.0, metavar='S',
                    help='also S simulated seconds of lockstep beside the monitor (0: no)')
    ap.add_argument('--figure', metavar='PNG', help='only draw the figure of a recorded '
                    'monitored run with a seal leak switched on (docs/figures/monitor.png)')
    args = ap.parse_args(argv)
    if args.figure:
        print(figure(Path(args.figure)))
        return 0
    from rostest_helpers import Probe, Procs, level

    domain = 100 + os.getpid() % 100
    tmp = Path(tempfile.mkdtemp(prefix='bench_monitor_'))
    procs, probe = Procs(domain, tmp), Probe(domain, 'bench_monitor')
    out = {'load_average': os.getloadavg(), 'seconds': args.seconds}
    try:
        start_free_loop(procs, probe, first_move_s=0.5, moves=3600)
        start = time.monotonic()
        probe.spin(args.seconds)
        out['without_monitor'] = plant_timing(probe, start)
        print(f'plant alone:        {out["without_monitor"]}', flush=True)

        started = time.monotonic()
        mon = procs.start('monitor', '--floor', tmp / 'floor.yaml', name='monitor')

        def first_verdict():
            for t, st in probe.diagnostics:
                if st.name.startswith(f'{MONITOR}: monitor ') and t >= started:
                    v = probe.diag_values(st)
                    if v.get('windows', '0') not in ('0', ''):
                        return t
            return None
        probe.spin_until(lambda: first_verdict() is not None, 120.0, 'the first verdicts')
        out['first_verdict_s'] = first_verdict() - started
        print(f'first verdicts {out["first_verdict_s"]:.1f} s after the monitor started '
              '(target 30 s)', flush=True)
        probe.spin(3.0)
        pids = [mon.pid] + children(mon.pid)
        cpu0 = {p: cpu_seconds(p) for p in pids}
        start = time.monotonic()
        node0 = probe.diag_values(node_status(probe))
        probe.spin(args.seconds)
        wall = time.monotonic() - start
        cpu = {p: (cpu_seconds(p) - cpu0[p]) / wall for p in pids}
        node1 = probe.diag_values(node_status(probe))
        out['with_monitor'] = plant_timing(probe, start)
        out['cpu_share'] = {'node': cpu[mon.pid],
                            'workers': sum(v for p, v in cpu.items() if p != mon.pid),
                            'total': sum(cpu.values())}
        delta = {k: int(node1[k]) - int(node0[k]) for k in (
            'windows_judged', 'windows_skipped', 'windows_incomplete', 'samples_lost',
            'samples_dropped', 'samples_sent')}
        data_windows = args.seconds / 0.2
        out['keeps_up'] = {**delta, 'windows_of_data': data_windows,
                           'judged_share': delta['windows_judged'] / data_windows,
                           'node_status': node_status(probe).message}
        warns = sorted({st.name for t, st in probe.diagnostics if t >= started
                        and st.name.startswith(f'{MONITOR}: monitor ') and level(st) >= 1})
        out['warn_statuses'] = warns
        print(f'plant with monitor: {out["with_monitor"]}')
        print(f'monitor CPU share of one core: node {cpu[mon.pid]:.1%}, judge and fits '
              f'{out["cpu_share"]["workers"]:.1%}, total {out["cpu_share"]["total"]:.1%}')
        print(f'keeps up with 1 kHz: judged {delta["windows_judged"]} of {data_windows:.0f} '
              f'windows of data, skipped {delta["windows_skipped"]} (decimation), incomplete '
              f'{delta["windows_incomplete"]}, samples missing {delta["samples_lost"]}, '
              f'dropped {delta["samples_dropped"]}')
        print(f'monitor says: {out["keeps_up"]["node_status"]}')
        print(f'WARN on the healthy plant: {warns or "none"}')
        plant = probe.diag(': plant')
        out['plant_status'] = plant.message if plant is not None else ''
        faults = probe.diag_values(plant).get('faults', '') if plant is not None else ''
        print(f'plant says: {out["plant_status"]} (faults: {faults or "none"})')
    finally:
        procs.cleanup()
        probe.close()
    if args.lockstep > 0:
        ls = out['lockstep'] = lockstep(args.lockstep)
        print(f'lockstep (plant and controller in one process) with the monitor: '
              f'{ls["speed"]:.1f}x real time; judged {ls["windows_judged"]} of '
              f'{ls["windows_of_data"]:.0f} windows of data (skipped {ls["skipped"]}, '
              f'incomplete {ls["incomplete"]}, samples missing {ls["samples_missing"]})')
        print(f'monitor says: {ls["node_status"]}')
    print(f'load average at the start {out["load_average"]}, now {os.getloadavg()}')
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2, default=str))
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
