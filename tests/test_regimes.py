"""Operating-regime segmentation and the error share per regime (analysis.regimes)."""
import numpy as np
import pytest

from pneumatic_servo.analysis.regimes import FAMILIES, Thresholds, error_shares, hot_spots, segment
from pneumatic_servo.experiment import Experiment
from pneumatic_servo.model import ModelConfig
from pneumatic_servo.synth.hidden import make_hidden_set


@pytest.fixture(scope='module')
def clean():
    """A clean rig: open-loop sine, closed-loop run and blocked charge/discharge (1 kHz)."""
    return make_hidden_set([], seed=11, durations={'sine': 2.0, 'closed_loop': 4.0,
                                                   'blocked': 2.0})


def _series(exps, name):
    return next(e for e in exps if e.name == name)


def test_every_applicable_family_labels_every_sample(clean):
    servo = segment(_series(clean, 'closed_loop'))
    assert set(servo) == set(FAMILIES)
    blocked = segment(_series(clean, 'blocked'))
    # the pistons are held: no motion families, but both chambers and the flow
    assert set(blocked) == {'valve', 'chamber_a', 'chamber_b', 'flow'}
    for labels in list(servo.values()) + list(blocked.values()):
        assert np.all(labels != '')


def test_valve_regime_follows_the_command(clean):
    exp = _series(clean, 'closed_loop')
    labels = segment(exp, thresholds=Thresholds(null_band_v=0.2))['valve']
    near = np.abs(exp['command_v'] - 5.0) < 0.2
    assert np.array_equal(labels == 'near_null', near)


def test_chamber_regimes_follow_the_pressure_steps(clean):
    exp = _series(clean, 'blocked')
    labels = segment(exp)['chamber_a']
    # 5 V -> 5.6 V at 1/14 of the record charges chamber a, 5.6 -> 4.4 V discharges it
    t_step = exp.duration / 14
    k_up = int(round((t_step + 0.005) / exp.dt))
    k_down = int(round((4 * t_step + 0.005) / exp.dt))
    assert labels[k_up] == 'charging'
    assert labels[k_down] == 'discharging'


def test_choked_flow_when_filling_from_low_pressure(clean):
    exp = _series(clean, 'blocked')
    labels = segment(exp)['flow']
    # the 1 V phase empties chamber a into the atmosphere and fills b from the supply
    p_b, ps = exp['p_b_pa'], exp['supply_pa']
    choked_b = (p_b / ps < 0.5382) & (exp['command_v'] < 5.0)
    assert choked_b.sum() > 10
    assert np.all(labels[choked_b] == 'choked')
    assert {'choked', 'subsonic'} <= set(labels)


def test_motion_regimes(clean):
    exp = _series(clean, 'closed_loop')
    fam = segment(exp)
    assert {'stuck', 'sliding'} <= set(fam['motion'])
    assert {'increasing', 'decreasing', 'still'} <= set(fam['direction'])
    assert np.array_equal(fam['motion'] == 'stuck', fam['direction'] == 'still')
    assert {'accelerating', 'steady'} <= set(fam['acceleration'])


def test_end_stop_regime():
    t = np.arange(0.0, 1.0, 1e-3)
    stroke = ModelConfig.paper().core['stroke_rad']
    angle = np.where(t < 0.5, 0.01, 0.5 * stroke)
    exp = Experiment(t, {'command_v': np.full_like(t, 5.0), 'angle_rad': angle}, 'servo')
    labels = segment(exp)['end_stop']
    assert np.all(labels[t < 0.45] == 'near_stop')
    assert np.all(labels[t > 0.55] == 'mid_stroke')


def test_error_share_lands_where_the_error_is(clean):
    exp = _series(clean, 'closed_loop')
    open_ = np.abs(exp['command_v'] - 5.0) >= 0.1
    pred = {'angle_rad': exp['angle_rad'] + np.where(open_, 0.01, 0.0),
            'p_a_pa': exp['p_a_pa'] + np.where(open_, 0.0, 500.0),
            'p_b_pa': exp['p_b_pa'].copy()}
    shares = {(s.family, s.regime): s for s in error_shares([exp], [pred])}
    assert shares[('valve', 'open')].error_share['angle'] == pytest.approx(1.0)
    assert shares[('valve', 'near_null')].error_share['p_a'] == pytest.approx(1.0)
    assert shares[('valve', 'open')].time_share == pytest.approx(open_.mean())
    # the classes of a family share out all of the time and all of the error
    for fam in FAMILIES:
        rows = [s for s in shares.values() if s.family == fam]
        assert sum(s.time_share for s in rows) == pytest.approx(1.0)
        assert sum(s.error_share['angle'] for s in rows) == pytest.approx(1.0)
    spots = hot_spots(list(shares.values()))
    assert any(s['channel'] == 'p_a' and s['regime'] == 'near_null' for s in spots)


def test_pooled_over_experiments_and_static_tables():
    exps = make_hidden_set([], seed=12, designs=('blocked', 'closed_port'),
                           durations={'blocked': 1.5})
    preds = [{k: v * 1.001 for k, v in e.signals.items() if k.endswith('_pa')} for e in exps]
    shares = error_shares(exps, preds)
    fams = {s.family for s in shares}
    assert {'valve', 'chamber_a', 'chamber_b', 'flow'} <= fams
    valve = [s for s in shares if s.family == 'valve']
    assert sum(s.time_share for s in valve) == pytest.approx(1.0)
