"""Residual tests (analysis.residuals): whiteness, cross-correlation with the command,
correlation with regressors, and the summary of which equation the residual lives in."""
import numpy as np
import pytest

from pneumatic_servo.analysis.diagnosis import DiagnoseOptions, predictions
from pneumatic_servo.analysis.diagnosis.data import Data
from pneumatic_servo.analysis.residuals import (
    channel_tests,
    effective_samples,
    regressors,
    residual_tests,
    summary,
)
from pneumatic_servo.model import ModelConfig
from pneumatic_servo.synth.hidden import make_hidden_set


@pytest.fixture(scope='module')
def loop():
    """A clean closed-loop record (1 kHz, 4 s)."""
    return make_hidden_set([], seed=21, designs=('closed_loop',),
                           durations={'closed_loop': 4.0})[0]


def test_white_residual_passes(loop):
    rng = np.random.default_rng(0)
    pred = {'angle_rad': loop['angle_rad'] + rng.normal(0, 1e-3, len(loop.t))}
    t = channel_tests([loop], [pred], 'angle')
    assert t.whiteness < 0.15
    assert not t.significant
    lag, peak = t.xcorr_peak
    assert abs(peak) < 3 * t.xcorr_band


def test_residual_moving_with_velocity_is_named(loop):
    vel = regressors(loop)['velocity']
    rng = np.random.default_rng(1)
    pred = {'angle_rad': loop['angle_rad'] + 2e-3 * vel + rng.normal(0, 1e-3, len(loop.t))}
    t = channel_tests([loop], [pred], 'angle')
    top = next(iter(t.significant))
    assert top in ('velocity', 'sign(velocity)')
    assert t.correlations['velocity'] > t.bands['velocity']
    assert t.whiteness > 0.5  # a smooth error is not white


def test_cross_correlation_finds_a_command_lag(loop):
    u = loop['command_v']
    lag = 15
    du = np.concatenate([np.full(lag, u[0]), u[:-lag]]) - u.mean()
    pred = {'p_a_pa': loop['p_a_pa'] + 2e3 * du}
    t = channel_tests([loop], [pred], 'p_a', max_lag_s=0.05)
    peak_lag, peak = t.xcorr_peak
    assert peak_lag == pytest.approx(lag * loop.dt, abs=1.5 * loop.dt)
    assert peak > t.xcorr_band


def test_bands_account_for_autocorrelation():
    rng = np.random.default_rng(2)
    white = rng.normal(size=20000)
    smooth = np.convolve(white, np.ones(50) / 50, 'same')
    assert effective_samples(white) > 0.5 * len(white)
    assert effective_samples(smooth) < 0.05 * len(smooth)


def _base_residuals(effect):
    """The paper model's k-step predictions of a rig with ``effect`` hidden."""
    exps = make_hidden_set([effect], seed=22, designs=('closed_loop', 'blocked'),
                           durations={'closed_loop': 4.0, 'blocked': 3.0})
    data = Data.of(exps, DiagnoseOptions(horizon_s=0.25))
    return data.experiments, predictions(ModelConfig.paper(), data)


def test_summary_places_a_load_torque_in_the_moment_balance():
    exps, preds = _base_residuals('external_load_torque')
    s = summary(exps, preds)
    assert s['channel'] == 'angle'
    assert s['equation'].startswith('moment balance')
    # the pressures follow the shaft: the angle error explains most of their error
    assert min(s['volume_explained'].values()) > 0.5
    assert not s['white']


def test_summary_names_what_asymmetric_friction_moves_with():
    exps, preds = _base_residuals('asymmetric_friction')
    s = summary(exps, preds)
    assert s['equation'].startswith('moment balance')
    assert next(iter(s['moves_with'])) == 'sign(velocity)'


def test_summary_places_leaks_in_a_mass_balance():
    exps, preds = _base_residuals('external_leakage')
    tests = residual_tests(exps, preds)
    s = summary(exps, preds, tests)
    assert 'mass balance' in s['equation']
    assert set(tests) == {'angle', 'p_a', 'p_b'}
    exps, preds = _base_residuals('piston_seal_leakage')
    s = summary(exps, preds)
    assert s['equation'].startswith('mass balance of both chambers')
    assert 'p_a - p_b' in s['moves_with']


def test_residuals_are_smoothed_within_each_segment():
    """The one-pass moving average equals each segment averaged on its own (a segment's
    residual never borrows from the next one's start)."""
    from pneumatic_servo.fitting.problem import smooth
    rng = np.random.default_rng(3)
    x, breaks = rng.normal(size=1000), np.array([100, 340, 352, 800])
    for width in (3, 5, 9):
        kernel = np.ones(width)
        alone = np.concatenate([np.convolve(p, kernel, 'same')
                                / np.convolve(np.ones(len(p)), kernel, 'same')
                                for p in np.split(x, breaks)])
        np.testing.assert_allclose(smooth(x, width, breaks), alone, rtol=0, atol=1e-12)


def test_the_screen_ranks_on_the_held_out_segments_at_the_fitted_rate(loop):
    """Discovery's linear screen simulates some 150 terms: it uses the held-out segments
    decimated like the fitted part; everything judged keeps the record's rate."""
    data = Data.of([loop], DiagnoseOptions())
    fit, val, screen = data.fit[0], data.val[0], data.screen_val[0]
    assert screen.exp.dt == pytest.approx(fit.exp.dt) and fit.exp.dt > 2 * val.exp.dt
    spans = [(val.exp.t[a], val.exp.t[b - 1]) for a, b in val.plan.segments]
    coarse = [(screen.exp.t[a], screen.exp.t[b - 1]) for a, b in screen.plan.segments]
    assert len(coarse) == len(spans)
    np.testing.assert_allclose(np.array(coarse), np.array(spans), atol=fit.exp.dt)
