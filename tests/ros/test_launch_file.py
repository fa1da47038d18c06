"""The launch file, checked without ``ros2 launch`` (not installable from PyPI): it parses,
launches the plant as a LifecycleNode driven by transition events with a logged failure and
the monitor beside it, and every launch argument is a declared node parameter (defaults come
from there)."""
import ast
from pathlib import Path

from pneumatic_servo.ros.controller_node import CONTROLLER_SPECS
from pneumatic_servo.ros.monitor_specs import MONITOR_SPECS
from pneumatic_servo.ros.plant_specs import PLANT_SPECS

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ROOT / 'launch' / 'pneumatic_servo.launch.py'


def calls(tree, name: str) -> list[ast.Call]:
    return [n for n in ast.walk(tree) if isinstance(n, ast.Call)
            and getattr(n.func, 'id', getattr(n.func, 'attr', None)) == name]


def constant(tree, name: str):
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and getattr(node.targets[0], 'id', '') == name:
            return ast.literal_eval(node.value)
    raise AssertionError(f'{name} not in the launch file')


def lifecycle_nodes(tree) -> dict:
    """name -> keywords of every LifecycleNode the launch file starts."""
    out = {}
    for call in calls(tree, 'LifecycleNode'):
        kw = {k.arg: k.value for k in call.keywords}
        out[ast.literal_eval(kw['name'])] = kw
    return out


def test_launch_file_uses_a_lifecycle_node_with_checked_transitions():
    tree = ast.parse(LAUNCH.read_text())
    nodes = lifecycle_nodes(tree)
    assert set(nodes) == {'pneumatic_servo_plant', 'pneumatic_servo_monitor'}
    kw = nodes['pneumatic_servo_plant']
    assert ast.literal_eval(kw['executable']) == 'pneumatic-servo'
    handlers = calls(tree, 'OnStateTransition')
    goals = {k.value.value for h in handlers for k in h.keywords
             if k.arg == 'goal_state' and isinstance(k.value, ast.Constant)}
    assert 'inactive' in goals  # activated once configured
    assert 'failed' in LAUNCH.read_text() and calls(tree, 'LogInfo')  # failures are logged
    assert calls(tree, 'ChangeState')


def test_launch_arguments_are_declared_node_parameters_and_files_exist():
    tree = ast.parse(LAUNCH.read_text())
    assert set(constant(tree, 'PLANT_ARGS')) <= {s.name for s in PLANT_SPECS}
    assert set(constant(tree, 'CONTROLLER_ARGS')) <= {s.name for s in CONTROLLER_SPECS}
    assert set(constant(tree, 'MONITOR_ARGS')) <= {s.name for s in MONITOR_SPECS}
    for name in ('plant_sim.yaml', 'controller.yaml', 'monitor.yaml'):
        assert f"'{name}'" in LAUNCH.read_text() and (ROOT / 'config' / name).exists()


def test_the_monitor_is_launched_beside_the_plant_and_can_be_left_out():
    tree = ast.parse(LAUNCH.read_text())
    kw = lifecycle_nodes(tree)['pneumatic_servo_monitor']
    assert [ast.literal_eval(a) for a in kw['arguments'].elts] == ['monitor']
    assert 'condition' in kw and calls(tree, 'IfCondition')
