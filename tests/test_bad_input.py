"""Every bad input a careless or hostile user gives: one line naming the problem and the fix,
exit code 2, no traceback, and no partial output file.

One parametrised suite over the classes an adversarial review found (physically impossible
measurements, unclosed recordings, checks with nothing to check, nonsense that identify
would write, YAML as engineers write it, user modules that fail, undecodable and special
files, outputs that cannot be written, huge tables, multi-line messages) and more. Each case
runs the real command line in a process of its own on real files made here: forked from a
server that has imported the package (``forked_cli``), so that the interpreter's start is
paid once; the replay cases and one plain case run it as a fresh interpreter.
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from forked_cli import ForkedCli

from pneumatic_servo.experiment import Experiment
from pneumatic_servo.io import read_experiment, write_experiment

ROOT = Path(__file__).resolve().parents[1]
BAGS = ROOT / 'bags'
CLI = 'import sys; from pneumatic_servo.cli import main; sys.exit(main(sys.argv[1:]))'


def _env() -> dict:
    env = dict(os.environ, PYTHONWARNINGS='ignore')
    env.pop('PNEUMATIC_SERVO_DEBUG', None)
    return env


def run(*argv, cwd):
    """``pneumatic-servo argv`` as a fresh interpreter."""
    return subprocess.run([sys.executable, '-c', CLI, *map(str, argv)], cwd=cwd, env=_env(),
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope='module')
def forked():
    """``forked.run(*argv, cwd=...)``: the command line, forked from an imported server."""
    cli = ForkedCli(_env())
    yield cli
    cli.close()


# ------------------------------------------------------------------------- the files
#: a user's own effects (README, "Components and effects") whose hooks fail
USER_EFFECTS = """
from pneumatic_servo.effects import Component, Param
from pneumatic_servo.effects.layout import C_TORQUE, THETA


def _table(t, x, s, p, P, c, dx):
    if x[THETA] > 0.5:
        raise ValueError('my torque table ends at 0.5 rad')
    c[C_TORQUE] += p[0]


def _root(t, x, s, p, P, c, dx):
    c[C_TORQUE] += p[0] * (x[THETA] - 4.0) ** 0.5      # NaN below 4 rad: everywhere


class Helper:
    gain = 2.0


def _object(t, x, s, p, P, c, dx):
    c[C_TORQUE] += p[0] * Helper().gain                 # numba cannot compile a class


def _effect(name, hook):
    return type(name, (Component,), dict(
        name=name.lower() + '_effect', summary=name, acts_on='angle', mechanics=hook,
        params=(Param('torque_n_m', 'N.m', 0.05, 0.0, 5.0, 'a torque'),)))


Table, Root, Uncompilable = (_effect('Table', _table), _effect('Root', _root),
                             _effect('Uncompilable', _object))
"""


def bag_with(tmp: Path, name: str, change, source: Path = BAGS / 'sine_2hz') -> Path:
    """A copy of ``source`` with its signals changed by ``change(signals, metadata)``."""
    exp = read_experiment(source)
    sig = {k: v.copy() for k, v in exp.signals.items()}
    meta = {}
    change(sig, meta)
    out = tmp / name
    write_experiment(Experiment(exp.t, sig, exp.circuit, name, False, {}), out, 'sqlite3',
                     meta)
    return out


def csv_with(tmp: Path, name: str, rows: list[str], header='circuit,voltage_v,supply_pa,'
             'm4_kg_s,m5_kg_s') -> Path:
    path = tmp / name
    path.write_text('\n'.join([header] + rows) + '\n')
    return path


def flow_rows(m4='0.002', t_s=None) -> list[str]:
    rows = []
    for i, v in enumerate(np.linspace(5.5, 10.0, 10)):
        extra = f',{t_s}' if t_s is not None else ''
        rows.append(f'flow,{v:.2f},701325,{m4 if i == 3 else 0.001 * (1 + i)},0.0005{extra}')
    return rows


def bag_copy(tmp: Path, name: str) -> Path:
    out = tmp / name
    shutil.copytree(BAGS / 'sine_2hz', out)
    return out


def fifo(tmp: Path, name: str) -> Path:
    path = tmp / name
    os.mkfifo(path)
    return path


@pytest.fixture(scope='module')
def files(tmp_path_factory):
    """Every bad file of the suite, made once."""
    t = tmp_path_factory.mktemp('bad')
    f = {}
    f['kpa_bag'] = bag_with(t, 'kpa', lambda s, m: s.update(p_a_pa=s['p_a_pa'] / 1e3))
    # chamber b discharges towards atmosphere: as gauge it reads about 0
    f['gauge_bag'] = bag_with(t, 'gauge', lambda s, m: s.update(p_b_pa=s['p_b_pa'] - 101325.0),
                              BAGS / 'heat_transfer')
    f['supply0_bag'] = bag_with(t, 'supply0', lambda s, m: s.update(
        supply_pa=np.full_like(s['p_a_pa'], 5e4)))
    f['degrees_bag'] = bag_with(t, 'degrees', lambda s, m: s.update(
        angle_rad=np.degrees(s['angle_rad'])))
    f['huge_angle_bag'] = bag_with(t, 'huge_angle', lambda s, m: s.update(
        angle_rad=np.full_like(s['angle_rad'], 1e300)))
    # item 7: impossible only for the whole record, so no range check decides them
    f['gauge_whole_bag'] = bag_with(t, 'gauge_whole', lambda s, m: s.update(
        p_a_pa=s['p_a_pa'] - 5.2e5, p_b_pa=s['p_b_pa'] - 5.2e5))  # 63 to 84 kPa throughout
    f['supply_below_bag'] = bag_with(t, 'supply_below', lambda s, m: s.update(
        supply_pa=np.full_like(s['p_a_pa'], 5.5e5)))  # both chambers above it throughout
    f['negative_bag'] = bag_with(t, 'negative', lambda s, m: s.update(
        p_a_pa=s['p_a_pa'] - 7e5))
    f['held_bag'] = bag_with(t, 'held', lambda s, m: m.update(blocked_angle_rad=1e300))
    custom_list = bag_copy(t, 'custom_list')
    meta = (custom_list / 'metadata.yaml').read_text()
    (custom_list / 'metadata.yaml').write_text(meta.replace(
        'custom_data:', 'custom_data:\n  - a\n  - b\n  old_custom_data:', 1))
    f['custom_list_bag'] = custom_list
    broken_yaml = bag_copy(t, 'broken_yaml')
    (broken_yaml / 'metadata.yaml').write_text('rosbag2_bagfile_information:\n  version: [9\n'
                                               '  storage_identifier: mcap\n')
    f['broken_yaml_bag'] = broken_yaml
    fifo_meta = t / 'fifo_meta'
    fifo_meta.mkdir()
    fifo(fifo_meta, 'metadata.yaml')
    f['fifo_meta_bag'] = fifo_meta
    wal = bag_with(t, 'unclosed', lambda s, m: None)
    db3 = next(wal.glob('*.db3'))
    Path(str(db3) + '-wal').write_bytes(b'\x37\x7f\x06\x82' + b'\x00' * 4000)
    f['wal_bag'] = wal
    f['fifo_csv'] = fifo(t, 'table.csv')
    f['text_csv'] = csv_with(t, 'text.csv', flow_rows()[:3] + ['flow,7.0,701325,abc,0.0005'])
    f['negative_m4_csv'] = csv_with(t, 'neg_m4.csv', flow_rows(m4='-0.0005'))
    f['ts0_csv'] = csv_with(t, 'ts0.csv', flow_rows(t_s='0'),
                            header='circuit,voltage_v,supply_pa,m4_kg_s,m5_kg_s,t_s_k')
    f['kpa_csv'] = csv_with(t, 'kpa.csv', [f'closed_port,{v:.2f},701.3,{400 + 10 * i:.1f}'
                                           for i, v in enumerate(np.linspace(4, 6, 11))],
                            header='circuit,voltage_v,supply_pa,p_a_pa')
    f['above_supply_csv'] = csv_with(t, 'above_supply.csv', [
        f'closed_port,{v:.2f},601325,{651325 + 1000 * i}'
        for i, v in enumerate(np.linspace(4, 6, 11))], header='circuit,voltage_v,supply_pa,p_a_pa')
    big = t / 'big.csv'
    with big.open('w') as out:
        out.write('circuit,voltage_v,supply_pa,p_a_pa\n')
        out.writelines(f'closed_port,{5 + (i % 100) / 100:.2f},701325,400000\n'
                       for i in range(200_000))
    f['big_csv'] = big
    f['binary_csv'] = t / 'binary.csv'
    f['binary_csv'].write_bytes(b'\x00\x01\x02\xff' * 100)
    f['latin1_csv'] = t / 'latin1.csv'
    f['latin1_csv'].write_bytes('circuit,voltage_v,supply_pa,p_a_pa\n# d\xe9j\xe0\n'.encode(
        'latin-1'))
    f['utf16_yaml'] = t / 'utf16.yaml'
    f['utf16_yaml'].write_bytes('effects: {}\n'.encode('utf-16'))
    f['binary_yaml'] = t / 'binary.yaml'
    f['binary_yaml'].write_bytes(b'\x00\x01core: 1')
    f['int_key_yaml'] = t / 'int_key.yaml'
    f['int_key_yaml'].write_text('effects:\n  1: {}\n')
    for key, setting, value in (('dash_bar', 'supply_pressure_pa', "'- bar'"),
                                ('two_dots', 'supply_pressure_pa', "'1..2 MPa'"),
                                ('e_mpa', 'supply_pressure_pa', "'e MPa'"),
                                ('minus_degc', 'room_temperature_k', "'-degC'")):
        f[f'{key}_yaml'] = t / f'{key}.yaml'
        f[f'{key}_yaml'].write_text(f'core:\n  {setting}: {value}\n')
    f['list_key_yaml'] = t / 'list_key.yaml'
    f['list_key_yaml'].write_text('effects: {[a, b]: {}}\n')
    f['list_item_yaml'] = t / 'list_item.yaml'
    f['list_item_yaml'].write_text('effects:\n  - [a, b]\n')
    f['mapping_item_yaml'] = t / 'mapping_item.yaml'
    f['mapping_item_yaml'].write_text('effects:\n  - {external_leakage: {}}\n')
    f['held_yaml'] = t / 'held.yaml'
    f['held_yaml'].write_text('core:\n  blocked_angle_rad: 1e300\n')
    f['multiline_yaml'] = t / 'multiline.yaml'
    f['multiline_yaml'].write_text('core:\n  piston_area_m2: [1\n  other: 2\n')
    f['badmod_yaml'] = t / 'badmod.yaml'
    f['badmod_yaml'].write_text("effects:\n  'no_such_module_xyz:Thing': {}\n")
    broken_module = t / 'broken_effect.py'
    broken_module.write_text('import no_such_dependency_xyz\n')
    f['broken_module'] = broken_module
    user_effects = t / 'user_effects.py'
    user_effects.write_text(USER_EFFECTS)
    f['user_effects'] = user_effects
    f['user_effect_yaml'] = t / 'user_effect.yaml'
    f['user_effect_yaml'].write_text(f"effects:\n  '{user_effects}:Uncompilable': {{}}\n")
    f['fifo_yaml'] = fifo(t, 'cfg.yaml')
    f['a_file'] = t / 'a_file.txt'
    f['a_file'].write_text('x')
    f['a_dir'] = t / 'a_dir'
    f['a_dir'].mkdir()
    return f


class F(str):
    """A file of the ``files`` fixture, by key (``suffix`` appended: a class name)."""

    def __new__(cls, key, suffix=''):
        obj = super().__new__(cls, key)
        obj.suffix = suffix
        return obj


class Out(str):
    """A path in the test's own output directory."""


SINE = BAGS / 'sine_2hz'
#: (case id, argv (text, F file keys, Out output paths), words the one line must hold, Out outputs
#: that must not exist afterwards)
CASES = [
    # 6: physically impossible measurements, named with the likely cause
    ('pressure_in_kpa', ['compare', F('kpa_bag')], 'looks like kPa', []),
    ('gauge_pressure', ['compare', F('gauge_bag')], 'gauge', []),  # charges from atmosphere
    ('supply_50kpa_abs', ['compare', F('supply0_bag')], 'supply/pressure', []),
    ('angle_in_degrees', ['compare', F('degrees_bag')], 'degrees', []),
    ('angle_1e300', ['compare', F('huge_angle_bag')], 'joint_states position', []),
    ('held_angle_1e300', ['compare', F('held_bag')], 'blocked_angle_rad', []),
    ('csv_pressure_in_kpa', ['compare', F('kpa_csv')], 'absolute Pa', []),
    ('config_held_angle', ['compare', SINE, '--config', F('held_yaml')], 'blocked_angle_rad', []),
    # item 7: impossible for the whole record, each signal within its range; every verb
    ('gauge_whole_record', ['compare', F('gauge_whole_bag')], 'gauge readings?', []),
    ('gauge_whole_record_verify', ['verify', F('gauge_whole_bag')],
     'below the atmosphere (101325 Pa) in every sample', []),
    ('gauge_whole_record_simulate', ['simulate', F('gauge_whole_bag'), '--out', Out('OUT/sim')],
     'add the atmospheric pressure', [Out('OUT/sim')]),
    ('gauge_whole_record_diagnose', ['diagnose', F('gauge_whole_bag')], 'gauge readings?', []),
    ('chambers_above_supply', ['compare', F('supply_below_bag')],
     'chamber_a/pressure is above supply/pressure in every sample', []),
    ('closed_port_above_supply', ['compare', F('above_supply_csv')],
     'supply recorded as gauge?', []),
    ('closed_port_above_supply_identify', ['identify', F('above_supply_csv'), '--out',
                                           Out('OUT/id.yaml')], 'above supply/pressure',
     [Out('OUT/id.yaml')]),
    ('negative_pressure', ['simulate', F('negative_bag'), '--out', Out('OUT/sim')],
     'never negative: gauge readings', [Out('OUT/sim')]),
    # 7: an unclosed writer's WAL
    ('unmerged_wal', ['compare', F('wal_bag')], 'write-ahead log', []),
    # 8: checks with nothing to check
    ('horizon_0', ['compare', SINE, '--horizon', '0'], '--horizon', []),
    ('horizon_negative', ['verify', SINE, '--mode', 'k_step', '--horizon', '-1'], '--horizon',
     []),
    ('horizon_nan', ['compare', SINE, '--horizon', 'nan'], 'finite', []),
    ('skip_everything', ['compare', SINE, '--skip', '1e9'], 'nothing to compare', []),
    ('verify_skip_everything', ['verify', SINE, '--skip', '1e9'], 'nothing to compare', []),
    # 9: identify refuses nonsense
    ('negative_m4', ['identify', F('negative_m4_csv'), '--out', Out('OUT/id.yaml')], 'm4',
     [Out('OUT/id.yaml')]),
    ('negative_tau', ['identify', SINE, '--out', Out('OUT/id.yaml'), '--thermocouple-tau', '-1'],
     '--thermocouple-tau', [Out('OUT/id.yaml')]),
    ('zero_supply_temperature', ['identify', F('ts0_csv'), '--out', Out('OUT/id.yaml')],
     'temperature', [Out('OUT/id.yaml')]),
    ('max_nfev_0', ['identify', SINE, '--out', Out('OUT/id.yaml'), '--max-nfev', '0'],
     '--max-nfev', [Out('OUT/id.yaml')]),
    # 10 and 15: YAML as engineers write it; one line even for a YAML error
    ('yaml_error_in_config', ['compare', SINE, '--config', F('multiline_yaml')], 'line', []),
    ('yaml_error_in_metadata', ['compare', F('broken_yaml_bag')], 'metadata.yaml', []),
    # 11: user modules that fail
    ('unknown_module', ['compare', SINE, '--effects', 'no_such_module_xyz:Thing'],
     'no_such_module_xyz', []),
    ('module_fails_on_import', ['compare', SINE, '--effects', F('broken_module', ':Thing')],
     'no_such_dependency_xyz', []),
    ('config_names_unknown_module', ['compare', SINE, '--config', F('badmod_yaml')],
     'no_such_module_xyz', []),
    # item 7: a user's effect whose hook raises, yields NaN or cannot be compiled is named
    ('user_hook_raises', ['compare', SINE, '--effects', F('user_effects', ':Table')],
     "effect 'table_effect' (", []),
    ('user_hook_raises_own_error', ['compare', SINE, '--effects', F('user_effects', ':Table')],
     'raised ValueError in its mechanics hook at t = 0 s', []),
    ('user_hook_raises_own_message', ['diagnose', SINE, '--effects',
                                      F('user_effects', ':Table')],
     'my torque table ends at 0.5 rad', []),
    ('user_hook_nan', ['simulate', SINE, '--effects', F('user_effects', ':Root'), '--out',
                       Out('OUT/sim')], "effect 'root_effect' (", [Out('OUT/sim')]),
    ('user_hook_nan_in_stage', ['compare', SINE, '--effects', F('user_effects', ':Root')],
     'gave NaN or inf in its mechanics hook', []),
    ('user_hook_nan_in_diagnose', ['diagnose', SINE, '--effects', F('user_effects', ':Root')],
     "candidate 'root_effect' could not be simulated over any held-out window", []),
    ('user_hook_uncompilable', ['compare', SINE, '--config', F('user_effect_yaml')],
     "effect 'uncompilable_effect' (", []),
    # 12: tracebacks that became one line
    ('non_string_effect_key', ['compare', SINE, '--config', F('int_key_yaml')], 'name', []),
    # item 7: unit values that are the pattern's characters but no number; non-text keys
    ('unit_value_dash', ['compare', SINE, '--config', F('dash_bar_yaml')],
     "core.supply_pressure_pa: cannot read '- bar'", []),
    ('unit_value_two_dots', ['compare', SINE, '--config', F('two_dots_yaml')],
     "two_dots.yaml: core.supply_pressure_pa: cannot read '1..2 MPa'", []),
    ('unit_value_e', ['simulate', SINE, '--config', F('e_mpa_yaml'), '--out', Out('OUT/sim')],
     "cannot read 'e MPa'", [Out('OUT/sim')]),
    ('unit_value_minus_degc', ['compare', SINE, '--config', F('minus_degc_yaml')],
     "core.room_temperature_k: cannot read '-degC'", []),
    ('verify_limit_two_dots', ['verify', SINE, '--max-pressure-error', '1..2 kPa'],
     '--max-pressure-error', []),
    ('list_as_effect_key', ['compare', SINE, '--config', F('list_key_yaml')],
     'write the key as text', []),
    ('list_in_effect_list', ['compare', SINE, '--config', F('list_item_yaml')],
     "effects: ['a', 'b'] is not a component name", []),
    ('mapping_in_effect_list', ['diagnose', SINE, '--config', F('mapping_item_yaml')],
     'is not a component name', []),
    (F('binary_csv'), ['compare', F('binary_csv')], 'binary', []),
    (F('latin1_csv'), ['compare', F('latin1_csv')], 'UTF-8', []),
    ('utf16_config', ['compare', SINE, '--config', F('utf16_yaml')], 'UTF-16', []),
    ('binary_config', ['compare', SINE, '--config', F('binary_yaml')], 'binary', []),
    ('custom_data_list', ['compare', F('custom_list_bag')], 'custom_data', []),
    ('simulate_dev_null', ['simulate', '/dev/null', '--out', Out('OUT/sim')], 'device',
     [Out('OUT/sim')]),
    ('text_in_number_column', ['compare', F('text_csv')], 'not a number', []),
    ('json_into_missing_dir', ['diagnose', SINE, '--json', Out('OUT/missing/d.json')],
     'does not exist', []),
    ('json_into_proc', ['compare', SINE, '--json', '/proc/c.json'], 'cannot be written', []),
    ('report_onto_a_file', ['diagnose', SINE, '--report', F('a_file')], 'is a file', []),
    ('apply_onto_a_directory', ['diagnose', SINE, '--apply', F('a_dir')], 'directory',
     []),
    ('simulate_onto_existing', ['simulate', SINE, '--out', F('a_file')], 'exists', []),
    ('false_alarm_rate_above_1', ['diagnose', SINE, '--false-alarm-rate', '2'],
     '--false-alarm-rate', []),
    ('too_few_replicas', ['diagnose', SINE, '--replicas', '2'], '--replicas', []),
    # 13: hangs that became one line
    (F('fifo_csv'), ['compare', F('fifo_csv')], 'named pipe', []),
    ('fifo_metadata', ['compare', F('fifo_meta_bag')], 'named pipe', []),
    ('fifo_config', ['compare', SINE, '--config', F('fifo_yaml')], 'named pipe', []),
    ('csv_of_200k_rows', ['compare', F('big_csv')], 'too large', []),
    # 5: ROS verbs refuse non-finite numbers before anything starts
    ('up_duration_nan', ['up', '--duration', 'nan'], '--duration', []),
    ('plant_rate_inf', ['plant', '--rate', 'inf'], '--rate', []),
    ('record_duration_negative', ['record', Out('OUT/rec'), '--duration', '-5'], '--duration',
     [Out('OUT/rec')]),
    ('record_unknown_topic', ['record', Out('OUT/rec'), '--duration', '1', '--topics', 'foo'],
     'foo', [Out('OUT/rec')]),
    # more of the same classes
    ('no_such_bag', ['compare', Out('OUT/nothing_here')], 'no such', []),
    ('unknown_verb_option', ['compare', SINE, '--frobnicate'], 'unrecognized', []),
    ('diagnose_unknown_effect', ['diagnose', SINE, '--effects', 'no_such_effect'],
     'no_such_effect', []),
]


#: the case also run as a fresh interpreter, as a user runs it (the others are forked)
FRESH_CASE = 'pressure_in_kpa'


@pytest.mark.parametrize('case, argv, words, outputs', CASES, ids=[c[0] for c in CASES])
def test_bad_input_is_one_line_exit_2_and_leaves_nothing(case, argv, words, outputs, files,
                                                         forked, tmp_path):
    (tmp_path / 'OUT').mkdir()
    args = [f'{files[a]}{a.suffix}' if isinstance(a, F) else
            tmp_path / a if isinstance(a, Out) else a for a in argv]
    proc = (run if case == FRESH_CASE else forked.run)(*args, cwd=tmp_path)
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-2000:])
    assert 'Traceback' not in proc.stderr
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f'pneumatic-servo {argv[0]}: error:'), lines[0]
    assert words in lines[0], lines[0]
    for out in outputs:
        assert not (tmp_path / out).exists(), out


def test_a_fast_calls_two_replies_are_both_read(files, forked, tmp_path):
    """The harness itself: a call that fails in milliseconds has both of its replies (pid,
    exit code) in the pipe by the time the first is read. They are both read at once; a
    buffered ``readline`` under a ``select`` once left the second waiting 300 s for a line
    it already held (a flaky ``fifo_csv`` case, whose child had long exited)."""
    proc = forked.run('compare', files['fifo_csv'], cwd=tmp_path, timeout=20,
                      settle=3.0)
    assert proc.returncode == 2 and 'named pipe' in proc.stderr, proc.stderr


def test_yaml_numbers_without_a_dot_are_numbers(tmp_path):
    """5e-6, 1e-8 and 7e5, as every engineer writes them, are read as numbers."""
    cfg = tmp_path / 'rig.yaml'
    cfg.write_text('core:\n  dead_volume_a_m3: 5e-6\n  supply_pressure_pa: 7e5\n'
                   'effects:\n  external_leakage: {leak_area_a_m2: 1e-8}\n')
    proc = run('compare', SINE, '--config', cfg, '--json', tmp_path / 'c.json', cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    from pneumatic_servo.model import ModelConfig
    loaded = ModelConfig.load(cfg)
    assert loaded.get('external_leakage.leak_area_a_m2') == 1e-8
    assert loaded.core['supply_pressure_pa'] == 7e5


@pytest.mark.parametrize('key, words', [('negative_bag', 'never negative'),
                                        ('gauge_whole_bag', 'gauge readings?')])
def test_a_replay_refuses_what_simulate_refuses(key, words, files, tmp_path):
    """The plant's replay backend reads through ``io.read_series`` (each signal on its own
    stamps): it refuses an impossible bag with the same reason, before anything is
    published."""
    pytest.importorskip('rclpy')
    proc = run('plant', '--backend', 'replay', '--bag', files[key], '--duration', '5',
               cwd=tmp_path)
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-2000:])
    assert 'Traceback' not in proc.stderr
    line = proc.stderr.strip().splitlines()[-1]  # after the node's own log line
    assert line.startswith('pneumatic-servo plant: error:') and words in line, proc.stderr


def test_physical_moments_are_not_refused(tmp_path):
    """What a whole record cannot be, a moment can: a chamber pulled below the atmosphere in
    a fast move, a chamber above the supply while the supply drops; and a rig at altitude
    with a chamber vented all along (the other is charged)."""
    def change(s, m):
        s['p_b_pa'][100:150] = 0.6e5                      # a vacuum pull, 50 ms
        s['supply_pa'][200:400] = s['p_a_pa'][200:400] - 2e4   # a supply dip under chamber a
    read_experiment(bag_with(tmp_path, 'moments', change))
    read_experiment(bag_with(tmp_path, 'altitude', lambda s, m: s.update(
        p_b_pa=np.full_like(s['p_b_pa'], 0.795e5))))      # 2000 m: b vented throughout
    from pneumatic_servo.io import read_series
    from pneumatic_servo.io.validate import check_series
    path = tmp_path / 'moments'
    series, meta = read_series(path)
    check_series(str(path), series, meta)
