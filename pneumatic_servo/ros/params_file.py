"""ROS 2 parameter files generated from the node declarations (``control.params.Spec``), so
that ``config/*.yaml`` can never drift from what the nodes declare.

Keyed by ``/**`` (every node name, any namespace): a node under a namespace or with a
remapped name still takes the file, where a file keyed by the node's name would be
silently ignored. Regenerate with ``python -m pneumatic_servo.ros.params_file config``;
``tests/ros/test_params_file.py`` checks the committed files are what this writes.
"""
from __future__ import annotations

import math
import sys
import textwrap
from pathlib import Path

from ..control.params import SpecSet

HEADERS = {
    'plant_sim.yaml': ('Plant node parameters (ROS 2 parameter file; ros2 launch, or\n'
                       'pneumatic-servo plant --ros-args --params-file config/plant_sim.yaml).\n'
                       'Every parameter with its default, unit and range: the simulated paper '
                       'rig at 1 kHz.\nRead-only ones are fixed at start-up, safety ones while '
                       'the node is active;\nthe others can be set at run time.'),
    'controller.yaml': ('Controller node parameters (ROS 2 parameter file; ros2 launch, or\n'
                        'pneumatic-servo controller --ros-args --params-file '
                        'config/controller.yaml).\nDefaults tuned on the simulated paper rig '
                        '(docs/ros.md): the PID gains act on rad and V;\nsmc_* tune the '
                        'model-based sliding mode.'),
    'monitor.yaml': ('Monitor node parameters (ROS 2 parameter file; ros2 launch, or\n'
                     'pneumatic-servo monitor --ros-args --params-file config/monitor.yaml).\n'
                     'The model beside the running rig: every window judged against its own '
                     'prediction\nfloor, a CUSUM per channel at a stated false-alarm rate '
                     'per hour (docs/ros.md).'),
}


def _value(v) -> str:
    if isinstance(v, bool):
        return 'true' if v else 'false'
    if isinstance(v, float):
        return '.nan' if math.isnan(v) else repr(v)
    if isinstance(v, str):
        return "'" + v.replace("'", "''") + "'"
    return repr(v)


def render(specs: SpecSet, header: str) -> str:
    """The parameter file of ``specs``: each parameter with its description as a comment."""
    lines = [f'# {line}' for line in header.splitlines()]
    lines += ['/**:', '  ros__parameters:']
    for spec in specs:
        note = spec.describe()
        note += ' (read-only)' if spec.read_only else ''
        note += ' (safety: fixed while active)' if spec.safety else ''
        lines += textwrap.wrap(note, 99, initial_indent='    # ', subsequent_indent='    # ')
        lines.append(f'    {spec.name}: {_value(spec.default)}')
    return '\n'.join(lines) + '\n'


def files() -> dict[str, str]:
    """File name -> content of every generated parameter file."""
    from .controller_node import CONTROLLER_SPECS
    from .monitor_specs import MONITOR_SPECS
    from .plant_specs import PLANT_SPECS
    return {'plant_sim.yaml': render(PLANT_SPECS, HEADERS['plant_sim.yaml']),
            'controller.yaml': render(CONTROLLER_SPECS, HEADERS['controller.yaml']),
            'monitor.yaml': render(MONITOR_SPECS, HEADERS['monitor.yaml'])}


def main(argv=None) -> int:
    """``python -m pneumatic_servo.ros.params_file DIR``: write the files into DIR."""
    out = Path((argv or sys.argv[1:] or ['config'])[0])
    for name, text in files().items():
        (out / name).write_text(text)
        print(out / name)
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
