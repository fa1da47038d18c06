"""Open-world diagnosis from the command line, as the README walks it: a discovered term
emitted as an effect, renamed, and taking part like a built-in while the error falls; a
memory effect whose shape has no closed form. (Split from ``test_open_world.py`` so the
two run on different pytest-xdist workers.)"""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pneumatic_servo.analysis.diagnosis.interpret import leading
from pneumatic_servo.synth.plan import GAIN

ROOT = Path(__file__).resolve().parents[1]


def _cli(*args, cwd):
    cmd = [sys.executable, '-c', 'import sys; from pneumatic_servo.cli import main; '
           'sys.exit(main())', *map(str, args)]
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=900,
                          env=dict(os.environ, PYTHONWARNINGS='ignore'))


@pytest.mark.study
def test_walkthrough_emit_rename_and_watch_the_error_fall(tmp_path):
    """The README path on the bundled bag: unexplained -> the discovered term -> the emitted
    effect, renamed by the user -> it takes part like a built-in and the error falls."""
    bag = ROOT / 'bags' / 'unlisted_effect_demo'
    out = tmp_path / 'd1.json'
    proc = _cli('diagnose', bag, '--json', out, '--emit-effect', tmp_path / 'arm.py',
                '--report', tmp_path / 'report', cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert 'status: unexplained' in proc.stdout
    data = json.loads(out.read_text())
    assert data['status'] == 'unexplained' and data['verdict'] == 'none'
    first = data['discovered'][0]
    assert first['equation'] == 'moment_balance' and 'angle' in first['terms']
    assert {'equation', 'terms', 'stderr', 'error_reduction', 'interpretation'} <= set(first)
    html = (tmp_path / 'report' / 'index.html').read_text()
    assert html.index('unexplained') < html.index('Ranking') if 'Ranking' in html else True
    # the user renames the emitted class to the physics they recognise
    source = (tmp_path / 'arm.py').read_text()
    source = source.replace('class DiscoveredMomentBalance', 'class ReturnSpring')
    source = source.replace("name = 'discovered_moment_balance'", "name = 'return_spring'")
    (tmp_path / 'return_spring.py').write_text(source)
    before = _cli('compare', bag, '--json', tmp_path / 'before.json', cwd=tmp_path)
    after = _cli('compare', bag, '--effects', f'{tmp_path / "return_spring.py"}:ReturnSpring',
                 '--json', tmp_path / 'after.json', cwd=tmp_path)
    assert before.returncode == 0 and after.returncode == 0, after.stderr
    fit = {name: json.loads((tmp_path / f'{name}.json').read_text())['k_step']['channels']
           for name in ('before', 'after')}
    for ch in ('angle', 'p_a', 'p_b'):
        assert fit['after'][ch]['rmse'] < 0.5 * fit['before'][ch]['rmse'], ch


@pytest.mark.study
def test_memory_walkthrough_unexplained_shape_closed_form_emitted_error_falls(tmp_path):
    """The README's memory walkthrough on bags/hysteresis_demo: a solenoid's hysteresis is
    unexplained, located in the valve input as the direction the command last moved, shown
    as a shape with its band, written as an effect with a state, and it halves the error."""
    bag = ROOT / 'bags' / 'hysteresis_demo'
    proc = _cli('diagnose', bag, '--json', tmp_path / 'd.json', '--emit-effect',
                tmp_path / 'hysteresis.py', '--report', tmp_path / 'report', cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    data = json.loads((tmp_path / 'd.json').read_text())
    assert data['status'] == 'unexplained' and data['verdict'] == 'none'
    first = data['discovered'][0]
    assert first['equation'] == 'valve_input'
    assert leading(first['terms'], first['term_shares']) == 'command_direction', first
    # the spool lags the command: a negative effective command in the direction it moved,
    # near the truth (0.06 V)
    assert -0.09 < first['terms']['command_direction'] < -0.03
    assert data['ladder'][-1]['overall'] <= 0.5 * data['ladder'][0]['overall']
    assert (tmp_path / 'report' / 'equation_residual.png').stat().st_size > 5000
    # the designs that would test its dependence further, in the JSON, printed and on the page
    plans = data['next_designs']
    assert plans and all(d['now'] + GAIN <= d['share'] <= 1.0 for d in plans), plans
    assert 'records that would test further what the first correction' in proc.stdout
    words = f"{plans[0]['design']} would move {plans[0]['variable']}"
    assert words in proc.stdout
    assert words in (tmp_path / 'report' / 'index.html').read_text()
    source = (tmp_path / 'hysteresis.py').read_text()
    assert 'states = (State(' in source  # the command's memory is the effect's own state
    runs = {}
    for name, extra in (('before', ()), ('after', ('--effects', f'{tmp_path / "hysteresis.py"}'
                                                                ':DiscoveredValveInput'))):
        out = _cli('compare', bag, *extra, '--json', tmp_path / f'{name}.json', cwd=tmp_path)
        assert out.returncode == 0, out.stderr
        runs[name] = json.loads((tmp_path / f'{name}.json').read_text())['k_step']['channels']
    for ch in ('angle', 'p_a', 'p_b'):
        assert runs['after'][ch]['rmse'] < runs['before'][ch]['rmse'], ch
    assert runs['after']['angle']['rmse'] < 0.5 * runs['before']['angle']['rmse']


# ------------------------------------------------------------------ a lagging transmitter
