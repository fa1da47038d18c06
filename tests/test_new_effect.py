"""Adding an effect takes one class: everything the package knows about an effect lives on
the class, so a new one is simulated, generated, fitted and diagnosed with no other edit."""
import numpy as np
import pytest

from pneumatic_servo import effects as registry
from pneumatic_servo._jit import njit
from pneumatic_servo.analysis.diagnosis import DiagnoseOptions, diagnose
from pneumatic_servo.analysis.diagnosis.hosts import shared_host
from pneumatic_servo.analysis.diagnosis.verdict import suggest_experiment
from pneumatic_servo.effects import Component, Param
from pneumatic_servo.effects.layout import C_TORQUE, THETA
from pneumatic_servo.identification.output_error import fit_output_error
from pneumatic_servo.model import Model, ModelConfig, simulate
from pneumatic_servo.synth.hidden import designs_for, hidden_config, make_hidden_set


@njit(cache=False)
def _preload_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] += p[0] * (x[THETA] - p[1])


class PreloadedSpring(Component):
    """A spring on the shaft with a rest angle: torque k (theta - theta_0)."""

    name = 'test_preloaded_spring'
    summary = 'a spring pulls the shaft towards a rest angle'
    reference = 'test suite'
    acts_on = 'angle'
    params = (Param('rate_n_m_per_rad', 'N.m/rad', 0.0, -2.0, 2.0, 'spring rate, signed',
                    plausible=(-1.0, 1.0)),
              Param('rest_angle_rad', 'rad', 1.6, 0.0, 3.4, 'rest angle', fit=False))
    neutral = {'rate_n_m_per_rad': 0.0}
    example = {'rate_n_m_per_rad': -0.15}
    circuits = ('servo',)
    shares_host = True
    excitation = 'slow holds at both ends of the stroke (the held torque grows with angle)'
    mechanics = _preload_hook


@pytest.fixture
def spring():
    with registry.registered(PreloadedSpring):
        yield PreloadedSpring.name


@pytest.mark.study
def test_one_class_is_simulated_generated_fitted_and_diagnosed(spring):
    # simulated: adding it changes the motion
    t = np.arange(0.0, 0.5, 1e-3)
    cfg = hidden_config([spring])
    assert cfg.get(f'{spring}.rate_n_m_per_rad') == -0.15  # the class's example
    moved = simulate(Model(cfg), t, 5.4).angle_rad[-1]
    plain = simulate(None, t, 5.4).angle_rad[-1]
    assert abs(moved - plain) > 1e-3
    # generated: its class says which designs show it
    assert designs_for(spring) == ('sine', 'closed_loop', 'blocked')
    exps = make_hidden_set([spring], seed=3, designs=('closed_loop',),
                           durations={'closed_loop': 4.0}, rate_hz=250.0)
    # fitted by output error from the paper's model plus the effect at its neutral value
    start = ModelConfig.paper().with_effect(spring, PreloadedSpring.neutral)
    fit = fit_output_error(start, exps, [f'{spring}.rate_n_m_per_rad'], mode='k_step',
                           max_nfev=10)
    assert fit.values[f'{spring}.rate_n_m_per_rad'] == pytest.approx(-0.15, rel=0.25)
    # diagnosed among look-alikes, on a host it shares (its class allows it)
    assert spring in shared_host(ModelConfig.paper()).effects
    result = diagnose(exps, effects=[spring, 'external_load_torque', 'payload_inertia'],
                      options=DiagnoseOptions(full_fits=3))
    assert result.verdict == spring, result.reason
    assert 'both ends of the stroke' in suggest_experiment(spring, 'external_load_torque')


def _plain_preload_hook(t, x, s, p, P, c, dx):  # a plain function: register compiles it
    c[C_TORQUE] += p[0] * (x[THETA] - p[1])


class _PlainSpring(PreloadedSpring):
    name = 'test_plain_spring'
    mechanics = _plain_preload_hook


class StifferSpring(_PlainSpring):
    """A user's variant of an effect class: it inherits the hook and changes the name."""

    name = 'test_stiffer_spring'
    example = {'rate_n_m_per_rad': -0.3}


def test_a_subclass_inherits_a_plain_hook_and_runs():
    with registry.registered(StifferSpring):  # its parent was never registered, so never compiled
        t = np.arange(0.0, 0.5, 1e-3)
        moved = simulate(Model(hidden_config([StifferSpring.name])), t, 5.4).angle_rad[-1]
        assert abs(moved - simulate(None, t, 5.4).angle_rad[-1]) > 1e-3
