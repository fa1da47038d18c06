"""The closed loop over DDS, for the README's main job: lockstep simulation of the paper's rig,
PID and the model-based controller on the same profile, a bag recorded with the recorder,
the tracking figures computed from that bag, and a plot.

Profile (sim time): hold 40 deg; step to 150 deg at 0.5 s; at 3.0 s a 0.5 Hz sine of
45 deg amplitude around 105 deg (starting at its 150 deg peak) for three periods.
Figures: settling time into +/-1 deg and overshoot of the step, steady-state error
(mean |error| over 2.5-3.0 s), RMS and largest error on the sine after its first
second.
"""
from __future__ import annotations

import math
import os
import time
from pathlib import Path

DEG = math.pi / 180.0
STEP_AT_S, STEP_FROM_DEG, STEP_TO_DEG = 0.5, 40.0, 150.0
SINE_AT_S, SINE_CENTRE_DEG, SINE_AMPLITUDE_DEG, SINE_HZ, SINE_PERIODS = 3.0, 105.0, 45.0, 0.5, 3
END_S = SINE_AT_S + SINE_PERIODS / SINE_HZ + 0.5


def profile_points():
    """The demo's trajectory: a step, then a sine that starts at its peak."""
    from ..control.reference import TrajectoryPoint
    pts = [TrajectoryPoint(STEP_AT_S, STEP_TO_DEG * DEG)]
    w = 2.0 * math.pi * SINE_HZ
    n = int(round(SINE_PERIODS / SINE_HZ / 0.01))
    for k in range(n + 1):
        tau = k * 0.01
        pts.append(TrajectoryPoint(
            SINE_AT_S + tau, (SINE_CENTRE_DEG + SINE_AMPLITUDE_DEG * math.cos(w * tau)) * DEG,
            -SINE_AMPLITUDE_DEG * DEG * w * math.sin(w * tau),
            -SINE_AMPLITUDE_DEG * DEG * w * w * math.cos(w * tau)))
    return pts


def _bring_up(points, ctrl, plant):
    """A node that does a lifecycle manager's job for the demo: it sends the trajectory to
    the controller, and configures and activates the plant once the controller has it (a
    deterministic run needs the trajectory there before sim time starts)."""
    from rclpy.lifecycle import TransitionCallbackReturn
    from rclpy.node import Node
    from trajectory_msgs.msg import JointTrajectory

    from . import common

    class BringUp(Node):
        def __init__(self):
            super().__init__('pneumatic_servo_demo')
            self.pub = self.create_publisher(JointTrajectory, common.TRAJECTORY,
                                             common.COMMAND_QOS)
            self.sent = False

        def next_deadline(self) -> float:
            return time.monotonic() + 0.01 if plant.state == 'unconfigured' else math.inf

        def tick(self, now: float) -> None:
            if plant.state != 'unconfigured':
                return
            if not self.sent and self.pub.get_subscription_count() >= 1:
                self.pub.publish(common.joint_trajectory(points, ctrl.joint))
                self.sent = True
            if ctrl.trajectory is not None and not plant.halt_reason \
                    and plant.trigger_configure() == TransitionCallbackReturn.SUCCESS:
                plant.trigger_activate()
    return BringUp()


def run_lockstep_session(controller: str, bag_dir, end_s: float = END_S, points=None,
                         initial_angle_rad: float = STEP_FROM_DEG * DEG,
                         storage: str = 'sqlite3', controller_overrides: dict | None = None,
                         timeout_s: float = 120.0, domain_id: int | None = None) -> dict:
    """Plant (lockstep), controller, recorder and the trajectory in one process and one event
    loop (:func:`.loop.run_nodes`), over DDS, until the plant's sim time reaches ``end_s``.

    Returns ``{'bag', 'sim_s', 'wall_s', 'speed', 'counts'}``.
    """
    from .common import sim_time
    from .controller_node import ControllerNode
    from .loop import run_nodes
    from .plant_node import PlantNode
    from .recorder import RecorderNode
    sim = sim_time()
    points = profile_points() if points is None else points
    overrides = {'controller': controller, **(controller_overrides or {})}
    n = {}

    def make(key, factory):
        def made():
            n[key] = factory()
            return n[key]
        return made

    factories = [
        make('ctrl', lambda: ControllerNode(overrides=overrides, parameter_overrides=sim)),
        make('rec', lambda: RecorderNode(bag_dir, storage, parameter_overrides=sim)),
        make('plant', lambda: PlantNode(overrides={
            'clock_mode': 'lockstep', 'initial_angle_rad': initial_angle_rad,
            'wait_subscribers': 2, 'autostart': False})),
        make('bring_up', lambda: _bring_up(points, n['ctrl'], n['plant'])),
    ]
    run = {'boot_end': time.monotonic() + 10.0}

    def stop_when() -> str:
        plant, now = n['plant'], time.monotonic()
        if plant.state == 'unconfigured':
            return (f'plant: {plant.halt_reason}' if plant.halt_reason else
                    'the controller did not receive the trajectory'
                    if now > run['boot_end'] else '')
        if 'settled' in run:  # the plant stopped at end_s; the recorder drains the rest
            return 'done' if now >= run['settled'] else ''
        if plant.state != 'active':
            return f'plant stopped: {plant.halt_reason or plant.state}'
        if 't0' not in run and plant.started:
            run.update(t0=now, k0=plant.samples, deadline=now + timeout_s)
        if plant.samples * plant.period_s >= end_s:
            run.update(wall_s=now - run['t0'], sim_s=(plant.samples - run['k0'])
                       * plant.period_s, settled=now + 0.3)
            plant.shutdown('demo done')
        elif now > run.get('deadline', math.inf):
            return f'lockstep run did not finish in {timeout_s:g} s'
        return ''

    reason = run_nodes(factories, stop_when=stop_when, domain_id=domain_id)
    if reason != 'done':
        raise RuntimeError(f'closed-loop run stopped: {reason}')
    return {'bag': str(bag_dir), 'sim_s': run['sim_s'], 'wall_s': run['wall_s'],
            'speed': run['sim_s'] / run['wall_s'], 'counts': dict(n['rec'].counts)}


def read_run(bag_dir) -> dict:
    """Arrays from a demo bag (:func:`pneumatic_servo.io.read_series`): the angle at its
    header stamps, the commands at their record times [s]."""
    from ..io import read_series
    series, _ = read_series(bag_dir)
    (t, angle), (t_cmd, command) = series['angle_rad'], series['command_v']
    return {'t': t * 1e-9, 'angle': angle, 't_cmd': t_cmd * 1e-9, 'command': command}


def figures(run: dict, points=None) -> dict:
    """Tracking figures (degrees, seconds) of a demo run."""
    import numpy as np

    from ..control.metrics import step_metrics, tracking_rms
    from ..control.reference import Reference, Trajectory
    traj = Trajectory(profile_points() if points is None else points)
    t, y = run['t'], run['angle']
    ref = np.array([(traj.sample(tt) or Reference(STEP_FROM_DEG * DEG)).position for tt in t])
    step = t < SINE_AT_S
    sm = step_metrics(t[step], y[step], STEP_AT_S, STEP_FROM_DEG * DEG, STEP_TO_DEG * DEG,
                      final_window_s=0.5)
    tr = tracking_rms(t, y, ref, SINE_AT_S + 1.0, SINE_AT_S + SINE_PERIODS / SINE_HZ)
    return {'step_settling_time_s': sm['settling_time_s'],
            'step_overshoot_deg': sm['overshoot_rad'] / DEG,
            'step_overshoot_percent': sm['overshoot_percent'],
            'step_rise_time_s': sm['rise_time_s'],
            'steady_state_error_deg': sm['steady_state_error_rad'] / DEG,
            'sine_rms_error_deg': tr['rms_error_rad'] / DEG,
            'sine_max_error_deg': tr['max_error_rad'] / DEG,
            'samples': int(len(t)), 'reference': ref}


def plot(runs: dict, path) -> None:
    """Step response, sine tracking error and valve command of each controller."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(9, 9.5))
    colours = {'pid': 'tab:blue', 'smc': 'tab:red'}
    first = next(iter(runs.values()))
    ax[0].plot(first['t'], first['figures']['reference'] / DEG, 'k--', lw=1, label='reference')
    for name, r in runs.items():
        f = r['figures']
        label = (f'{name}: settles {f["step_settling_time_s"]:.3f} s, overshoot '
                 f'{f["step_overshoot_deg"]:.2f} deg, sine RMS {f["sine_rms_error_deg"]:.3f} deg')
        ax[0].plot(r['t'], r['angle'] / DEG, color=colours.get(name), lw=1.2, label=label)
        e = (f['reference'] - r['angle']) / DEG
        ax[1].plot(r['t'], e, color=colours.get(name), lw=1, label=name)
        ax[2].plot(r['t_cmd'], r['command'], color=colours.get(name), lw=0.8, label=name)
    ax[0].set_ylabel('angle [deg]')
    ax[0].set_title('Closed loop over DDS, lockstep simulation of the paper rig')
    ax[0].legend(fontsize=8, loc='lower right')
    ax[1].set_ylabel('reference - angle [deg]')
    ax[1].set_ylim(-2.0, 2.0)
    ax[1].axhline(1.0, color='grey', lw=0.5, ls=':')
    ax[1].axhline(-1.0, color='grey', lw=0.5, ls=':')
    ax[1].legend(fontsize=8)
    ax[2].set_ylabel('valve command [V]')
    ax[2].set_xlabel('sim time [s]')
    ax[2].legend(fontsize=8)
    for a in ax:
        a.grid(alpha=0.3)
        a.set_xlim(0.0, END_S)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _domain_id() -> int:
    env = os.environ.get('ROS_DOMAIN_ID')
    if env:
        return int(env)
    return 100 + os.getpid() % 100  # away from the usual 0 and from the tests' 40-99


def run_closed_loop_demo(out_dir, controllers=('pid', 'smc'), storage: str = 'sqlite3') -> dict:
    """Run the demo into ``out_dir``; returns the figures per controller and the paths.

    Each controller's run is recorded to ``out_dir/bag_<controller>``; the figures come
    from the bag; the plot is ``out_dir/tracking.png``.
    """
    from . import require_rclpy
    require_rclpy()
    import shutil

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    runs, result = {}, {'controllers': {}}
    for name in controllers:
        bag = out / f'bag_{name}'
        if bag.exists():
            shutil.rmtree(bag)
        session = run_lockstep_session(name, bag, storage=storage, domain_id=_domain_id())
        run = read_run(bag)
        run['figures'] = figures(run)
        runs[name] = run
        f = {k: v for k, v in run['figures'].items() if k != 'reference'}
        f.update({'bag': str(bag), 'lockstep_speed': session['speed'],
                  'messages_recorded': sum(session['counts'].values())})
        result['controllers'][name] = f
    png = out / 'tracking.png'
    plot(runs, png)
    best = min(result['controllers'], key=lambda n: result['controllers'][n]['sine_rms_error_deg'])
    ok = all(math.isfinite(f['step_settling_time_s']) and f['steady_state_error_deg'] <= 0.2
             for f in result['controllers'].values())
    for name, f in result['controllers'].items():
        # one printable line per controller for the demo's summary table
        result[name] = (f'step settles {f["step_settling_time_s"]:.3f} s, overshoot '
                        f'{f["step_overshoot_deg"]:.3f} deg, steady-state '
                        f'{f["steady_state_error_deg"]:.3f} deg; sine RMS '
                        f'{f["sine_rms_error_deg"]:.3f} deg (max {f["sine_max_error_deg"]:.2f}); '
                        f'lockstep {f["lockstep_speed"]:.1f}x real time')
    result.update({'plot': str(png), 'best': best, 'status': 'ok' if ok else 'failed',
                   'profile': f'step {STEP_FROM_DEG:g}->{STEP_TO_DEG:g} deg at {STEP_AT_S:g} s; '
                              f'{SINE_HZ:g} Hz sine, {SINE_AMPLITUDE_DEG:g} deg amplitude '
                              f'around {SINE_CENTRE_DEG:g} deg from {SINE_AT_S:g} s'})
    return result


def main() -> None:  # pragma: no cover - python -m pneumatic_servo.ros.closed_loop_demo OUT
    from ..jsonable import dumps
    import sys
    res = run_closed_loop_demo(sys.argv[1] if len(sys.argv) > 1 else 'out/closed_loop')
    print(dumps(res, indent=2))


if __name__ == '__main__':  # pragma: no cover
    main()
