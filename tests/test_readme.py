"""The README's Python, run as printed: the extension path a user copies must work."""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_readme_python_runs_as_printed(tmp_path):
    blocks = re.findall(r'```python\n(.*?)```', (ROOT / 'README.md').read_text(), re.S)
    assert len(blocks) >= 3
    script = tmp_path / 'readme.py'
    script.write_text('\n'.join(blocks) + '\nassert res.angle_rad.shape == t.shape\n'
                      'assert 0.0 <= res.angle_rad.min() and res.p_a_pa.min() > 1e5\n'
                      'test_my_rig()\n')
    proc = subprocess.run([sys.executable, str(script)], cwd=ROOT, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
