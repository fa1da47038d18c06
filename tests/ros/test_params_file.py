"""The parameter files: generated from the node declarations, keyed ``/**``, and taken by a
node under a namespace (a file keyed by the node's name would be silently ignored there)."""
from pathlib import Path

import yaml

from pneumatic_servo.ros.params_file import files

ROOT = Path(__file__).resolve().parents[2]


def test_committed_files_are_what_the_declarations_generate():
    for name, text in files().items():
        assert (ROOT / 'config' / name).read_text() == text, (
            f'config/{name} is stale: python -m pneumatic_servo.ros.params_file config')
        assert list(yaml.safe_load(text)) == ['/**']


def get_parameter(probe, node: str, name: str):
    from rcl_interfaces.srv import GetParameters
    cli = probe.node.create_client(GetParameters, f'{node}/get_parameters')
    probe.spin_until(lambda: cli.service_is_ready(), 30.0, f'{node} parameters')
    reply = probe.call_idempotent(cli, GetParameters.Request(names=[name]),
                                  'get_parameters reply')
    probe.node.destroy_client(cli)
    return reply.values[0].double_value


def test_a_node_under_a_namespace_takes_the_file(procs, probe, tmp_path):
    data = yaml.safe_load((ROOT / 'config' / 'controller.yaml').read_text())
    data['/**']['ros__parameters']['kp'] = 7.25
    path = tmp_path / 'controller.yaml'
    path.write_text(yaml.safe_dump(data))
    procs.start('controller', '--namespace', 'cell_7', '--ros-args', '--params-file', path,
                name='controller')
    assert get_parameter(probe, '/cell_7/pneumatic_servo_controller', 'kp') == 7.25
