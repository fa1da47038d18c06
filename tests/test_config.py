"""Configuration: the paper's parameters from YAML in SI, units at the edges, and bad input
that ends in one line naming the fix (in the library and at the command line)."""
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from pneumatic_servo.effects.layout import CORE_PARAMS
from pneumatic_servo.errors import ConfigError
from pneumatic_servo.model import ModelConfig

ROOT = Path(__file__).resolve().parents[1]
PAPER_YAML = ROOT / 'config' / 'paper_rig.yaml'


def test_paper_rig_yaml_is_the_papers_model():
    cfg = ModelConfig.load(PAPER_YAML)
    paper = ModelConfig.paper()
    assert cfg.to_dict() == paper.to_dict()
    # Table 2, Table 4, C0, h, Eq. 40 (settled), docs/model.md settlement 4, supply 0.6 MPa gauge
    expected = {
        'core.piston_area_m2': 3.4636e-4, 'core.pinion_pitch_diameter_m': 0.014,
        'core.piston_mass_kg': 0.210, 'core.gear_inertia_kg_m2': 1.678e-4,
        'core.spool_shoulder_half_width_m': 1.010e-3, 'core.hole_radius_m': 1.000e-3,
        'core.spool_diameter_m': 6.000e-3, 'core.sleeve_bore_diameter_m': 6.023e-3,
        'core.gas_viscosity_pa_s': 1.83e-5, 'core.dead_volume_a_m3': 5e-6,
        'core.dead_volume_b_m3': 5e-6, 'core.stroke_rad': 3.31613,
        'core.atmospheric_pressure_pa': 101325.0, 'core.supply_pressure_pa': 701325.0,
        'core.supply_temperature_k': 293.15, 'core.room_temperature_k': 293.15,
        'core.gas_constant_j_per_kg_k': 287.0, 'core.heat_capacity_ratio': 1.4,
        'core.stiction_velocity_band_rad_s': 1e-3, 'core.spool_gain_m_per_v': 2e-4,
        'orifice_flow.critical_pressure_ratio': 0.5382,
        'orifice_flow.area_conversion_coefficient': 0.43,
        'orifice_flow.flow_coefficient_p0': 0.4517,
        'orifice_flow.flow_coefficient_p1_per_m': 1713.94,
        'orifice_flow.flow_coefficient_p2_per_m2': -3.133e6,
        'orifice_flow.flow_coefficient_p3_per_m3': 1.8641e9,
        'orifice_flow.flow_coefficient_p4_per_m4': -3.5227e11,
        'clearance_flow.clearance_initial_length_m': 2.0e-3,
        'wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k': 15.797,
        'wall_heat_transfer.wall_area_a_m2': 1.5106348e-2,
        'stribeck_friction.static_friction_n': 10.60,
        'stribeck_friction.coulomb_friction_n': 6.03,
        'stribeck_friction.stribeck_velocity_rad_s': 0.14,
        'stribeck_friction.viscous_friction_n_s_per_rad': 0.85,
    }
    for key, value in expected.items():
        assert cfg.get(key) == pytest.approx(value, rel=1e-12), key
    assert abs(cfg.core['stroke_rad'] - 190 * 3.141592653589793 / 180) < 1e-5


def test_units_convert_to_si_at_the_edge():
    cfg = ModelConfig.from_dict({'core': {
        'supply_pressure_pa': '0.6 MPa gauge', 'dead_volume_a_m3': '5 cm^3',
        'stroke_rad': '190 deg', 'room_temperature_k': '20 degC',
        'hole_radius_m': '1 mm'}})
    assert cfg.core['supply_pressure_pa'] == pytest.approx(701325.0)
    assert cfg.core['dead_volume_a_m3'] == pytest.approx(5e-6)
    assert cfg.core['stroke_rad'] == pytest.approx(3.316125578789226)
    assert cfg.core['room_temperature_k'] == pytest.approx(293.15)
    assert cfg.core['hole_radius_m'] == pytest.approx(1e-3)


def test_save_and_load_round_trip(tmp_path):
    cfg = ModelConfig.paper().with_slot('adiabatic').with_effect('external_leakage',
                                                                 {'leak_area_a_m2': 1e-8})
    path = tmp_path / 'rig.yaml'
    cfg.save(path, header='round trip')
    again = ModelConfig.load(path)
    assert again.to_dict() == cfg.to_dict()
    assert [c.name for c in again.component_classes()] == [c.name for c in
                                                           cfg.component_classes()]


def _one_line_error(data) -> str:
    with pytest.raises(ConfigError) as info:
        ModelConfig.from_dict(data)
    msg = str(info.value)
    assert '\n' not in msg and msg.strip() == msg and len(msg) < 500
    return msg


@pytest.mark.parametrize('data, fix', [
    ({'core': {'dead_volume_a_m3': -1e-6}}, 'outside [1e-08'),
    ({'core': {'valve_chamber_volume_m3': 0.0}}, 'outside'),
    ({'effects': {'external_leakge': {}}}, "did you mean 'external_leakage'"),
    ({'effects': {'no_such_effect': {}}}, 'known:'),
    ({'components': {'adiabatc': {}}}, "did you mean 'adiabatic'"),
    ({'core': {'supply_pressure_pa': '0.6 kg'}}, 'give a value in Pa'),
    ({'core': {'supply_pressure_mpa': 0.6}}, "did you mean 'supply_pressure_pa' (in Pa)"),
    ({'core': {'supply_pressure_pa': 0.6}}, "e.g. '0.6 MPa gauge'"),
    ({'core': {'stroke_rad': '190 furlongs'}}, "unknown unit 'furlongs'"),
    ({'stribeck_friction': {}}, 'use core, components, effects'),
    ({'components': {'stribeck_friction': {'static_friction_n': 5.0}}}, 'raise F_s or lower F_c'),
    ({'core': {'sleeve_bore_diameter_m': 5e-3}}, 'must exceed core.spool_diameter_m'),
    ({'effects': {'external_leakage': {'leak_area_a_m2': '1 mm'}}}, 'give a value in m^2'),
    ({'effects': {'adiabatic': {}}}, 'list it under components'),
    ({'core': {'supply_pressure_pa': '- bar'}}, "core.supply_pressure_pa: cannot read '- bar'"),
    ({'core': {'supply_pressure_pa': '1..2 MPa'}}, "cannot read '1..2 MPa'"),
    ({'core': {'supply_pressure_pa': 'e MPa'}}, "cannot read 'e MPa'"),
    ({'core': {'room_temperature_k': '..degC'}}, "core.room_temperature_k: cannot read"),
    ({'effects': [['a', 'b']]}, "effects: ['a', 'b'] is not a component name"),
    ({'effects': [{'external_leakage': {}}]}, 'is not a component name'),
])
def test_bad_parameters_give_one_line_naming_the_fix(data, fix):
    assert fix in _one_line_error(data)


def test_bad_file_names_the_file(tmp_path):
    bad = tmp_path / 'bad.yaml'
    bad.write_text('core:\n  dead_volume_a_m3: -1.0e-6\n')
    with pytest.raises(ConfigError, match='bad.yaml: core.dead_volume_a_m3'):
        ModelConfig.load(bad)
    broken = tmp_path / 'broken.yaml'
    broken.write_text('core: [unclosed\n')
    with pytest.raises(ConfigError, match='broken.yaml line'):
        ModelConfig.load(broken)


def test_every_core_parameter_has_si_unit_and_default_in_bounds():
    for p in CORE_PARAMS:
        assert p.lower <= p.default <= p.upper, p.name
        assert p.unit and p.description


# --- the command line ------------------------------------------------------------------------
def _cli(*args, cwd):
    """Run the installed ``pneumatic-servo`` command (or its entry point) in a subprocess."""
    script = Path(sys.executable).with_name('pneumatic-servo')
    cmd = [str(script)] if script.exists() else [
        sys.executable, '-c', 'import sys; from pneumatic_servo.cli import main; sys.exit(main())']
    env = dict(os.environ, PYTHONWARNINGS='ignore')
    return subprocess.run(cmd + list(args), cwd=cwd, capture_output=True, text=True,
                          timeout=120, env=env)


@pytest.mark.parametrize('content', [
    'core:\n  supply_pressure_pa: 0.6 kg\n',
    'core:\n  supply_pressure_mpa: 0.6\n',
    'core:\n  dead_volume_b_m3: -5.0e-6\n',
    'effects:\n  flux_capacitor: {}\n',
    'core: [unclosed\n',
])
def test_demo_with_bad_config_exits_nonzero_with_one_line(tmp_path, content):
    (tmp_path / 'bad.yaml').write_text(content)
    proc = _cli('demo', '--config', 'bad.yaml', '--out', 'out', cwd=tmp_path)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and 'Traceback' not in proc.stderr, proc.stderr
    assert lines[0].startswith('pneumatic-servo demo: error: ') and 'bad.yaml' in lines[0]
    assert not (tmp_path / 'out').exists()  # fails before doing any work


def test_demo_with_missing_config_exits_nonzero(tmp_path):
    proc = _cli('demo', '--config', 'nope.yaml', cwd=tmp_path)
    assert proc.returncode == 2 and 'nope.yaml' in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_demo_help_lists_its_options(tmp_path):
    proc = _cli('demo', '--help', cwd=tmp_path)
    assert proc.returncode == 0
    for opt in ('--out', '--config', '--skip-ros', '--skip-diagnosis'):
        assert opt in proc.stdout


def test_yaml_written_by_hand_in_gauge_units_loads(tmp_path):
    path = tmp_path / 'rig.yaml'
    path.write_text(yaml.safe_dump({'core': {'supply_pressure_pa': '0.5 MPa gauge'},
                                    'effects': ['sensor_delay']}))
    cfg = ModelConfig.load(path)
    assert cfg.core['supply_pressure_pa'] == pytest.approx(601325.0)
    assert 'sensor_delay' in cfg.effects
