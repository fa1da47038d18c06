"""Without numba (``PNEUMATIC_SERVO_JIT=0``: the same source as plain Python), diagnosis of a
clean closed-loop record runs to its answer: a wild trial step that takes a square root of
a negative temperature is a failed simulation, as it is compiled, not a traceback.
``.ci/run`` also runs the core tests this way."""
import os
import subprocess
import sys

import numpy as np

from pneumatic_servo.io import write_experiment
from pneumatic_servo.synth.hidden import closed_loop_experiment, hidden_config

CLI = 'import sys; from pneumatic_servo.cli import main; sys.exit(main(sys.argv[1:]))'


def test_diagnose_without_numba_gives_the_answer(tmp_path):
    exp = closed_loop_experiment(hidden_config([]), np.random.default_rng(2), 2.0, 250.0)
    exp.metadata.pop('true_states', None)
    bag = write_experiment(exp, tmp_path / 'clean', 'sqlite3', {'synthetic': 'true'})
    proc = subprocess.run([sys.executable, '-c', CLI, 'diagnose', str(bag), '--effects',
                           'external_load_torque', '--quiet'], capture_output=True, text=True,
                          timeout=600, env={**os.environ, 'PNEUMATIC_SERVO_JIT': '0'})
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert 'Traceback' not in proc.stderr
    assert 'status: consistent' in proc.stdout
