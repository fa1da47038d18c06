"""The pure core must import and run where ROS is absent (the layering of docs/architecture.md)."""
import pkgutil
import subprocess
import sys

import pneumatic_servo

CHECK = r'''
import importlib, sys
class Block:
    def find_spec(self, name, path=None, target=None):
        root = name.split('.')[0]
        if root == 'rclpy' or root.endswith('_msgs') or root.endswith('_interfaces'):
            raise ImportError(f'ROS module {name} imported by the core')
sys.meta_path.insert(0, Block())
for mod in sys.argv[1:]:
    importlib.import_module(mod)
import numpy as np
from pneumatic_servo.model import simulate
r = simulate(None, np.arange(0.0, 0.05, 1e-3), 5.5)
assert np.isfinite(r.states).all()
print('ok')
'''


def core_modules():
    """Every module of the package outside ``pneumatic_servo.ros``."""
    out = []
    for info in pkgutil.walk_packages(pneumatic_servo.__path__, 'pneumatic_servo.'):
        if info.name.startswith(('pneumatic_servo.ros', 'pneumatic_servo.cli.')):
            continue
        out.append(info.name)
    return out


def test_core_imports_without_ros():
    mods = core_modules()
    assert 'pneumatic_servo.model.simulate' in mods
    proc = subprocess.run([sys.executable, '-c', CHECK, *mods], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip().endswith('ok')


def test_core_runs_without_numba():
    """The same model source runs as plain Python when compilation is off."""
    code = ('import numpy as np; from pneumatic_servo.model import simulate; '
            'r = simulate(None, np.arange(0.0, 0.02, 1e-3), 6.0); '
            'assert np.isfinite(r.states).all() and r.p_a_pa[-1] > r.p_a_pa[0]; print("ok")')
    env = {'PNEUMATIC_SERVO_JIT': '0', 'PATH': '/usr/bin:/bin'}
    proc = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr[-2000:]
