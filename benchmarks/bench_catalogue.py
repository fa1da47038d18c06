"""Every catalogue effect hidden alone, diagnosed with the full catalogue: named, recovered
and the error cut (the acceptance test ``tests/test_diagnose.py::
test_hidden_effect_is_named_recovered_and_cuts_the_error``, which the suite runs on four of
the twelve: one of each kind; all twelve took 40 minutes on a loaded 2-core CI machine).

Runs that test on every effect in a subprocess and prints each one's outcome and time.
Run: ``.venv/bin/python benchmarks/bench_catalogue.py``.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    env = dict(os.environ, PNEUMATIC_SERVO_ALL_EFFECTS='1')
    proc = subprocess.run(
        [sys.executable, '-m', 'pytest', '-q', '-rA', '--durations=0', '-p',
         'no:cacheprovider', 'tests/test_diagnose.py::'
         'test_hidden_effect_is_named_recovered_and_cuts_the_error'],
        cwd=ROOT, env=env, capture_output=True, text=True)
    lines = proc.stdout.splitlines()
    for line in lines:  # the per-effect outcome and the time of each
        if line.startswith(('PASSED', 'FAILED', 'ERROR')) or ' call ' in line:
            print(line)
    print(lines[-1] if lines else proc.stderr[-2000:])
    print(f'load average at the end: {os.getloadavg()[0]:.1f}')
    return proc.returncode


if __name__ == '__main__':
    sys.exit(main())
