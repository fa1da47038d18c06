"""Open-world diagnosis of what the sensors read and the energy balance: a lagging pressure
transmitter or temperature sensor, a heat flow, a reading said beside the chosen one, a
gauge transmitter's gain error. Each unlisted effect is registered only while its data
are made. (Split from ``test_open_world.py`` so they run on another pytest-xdist worker.)"""
import math
from dataclasses import dataclass

import numpy as np
import pytest

from pneumatic_servo import effects as registry
from pneumatic_servo.analysis.diagnosis import DiagnoseOptions, diagnose
from pneumatic_servo.effects import Component, Param
from pneumatic_servo.effects.layout import C_QA, C_TORQUE, OMEGA, P_A, P_B, T_A


def _first_order_lag(signal: str):
    """A sensor error: ``signal``, sampled at 1 kHz, read through a first-order lag of the
    component's ``lag_s`` (scipy's filter, not the package's operator)."""
    def sensor_error(values, signals, core):
        from scipy.signal import lfilter
        v = np.asarray(signals[signal], dtype=float)
        a = np.exp(-1e-3 / values['lag_s'])
        return {signal: lfilter([1 - a], [1, -a], v, zi=[a * v[0]])[0] - v}
    return staticmethod(sensor_error)


class LaggingTransmitterB(Component):
    """Chamber b's transmitter sits at the end of a long thin line: it reads 10 ms late."""

    name = 'test_lagging_transmitter_b'
    params = (Param('lag_s', 's', 0.01, 1e-4, 1.0, 'time constant'),)
    sensor_error = _first_order_lag('p_b_pa')


@pytest.mark.study
def test_a_lagging_pressure_transmitter_is_read_as_a_lag_of_its_reading():
    """A lag as fast as the closed loop's steps is far from its first-order rate there; the
    lag operator on the reading writes it (``terms.lag``): located in chamber b's reading,
    its lag terms are, over the record, about the transmitter's 10 ms."""
    from pneumatic_servo.analysis.diagnosis.readings import equivalent_lag_ms
    from pneumatic_servo.synth.varied import Record, make_record
    with registry.registered(LaggingTransmitterB):
        exp = make_record(Record('closed_steps', 1000.0, 10.0, seed=5, effects={
            LaggingTransmitterB.name: {'lag_s': 0.01}}))
    result = diagnose([exp])
    assert result.status == 'unexplained' and result.verdict == 'none', result.reason
    best = result.discovered[0]
    assert best.equation == 'measurement_p_b', result.reason
    assert best.leading.startswith('lag_') and best.leading.endswith('_p_b'), best.terms
    lag_ms = equivalent_lag_ms(best.equation, best.terms, result.trial.data,
                               result.trial.base.config.core)
    assert lag_ms == pytest.approx(10.0, rel=0.3), best.terms
    assert f'reads through a lag of about {lag_ms:.2g} ms' in best.interpretation
    assert best.error_reduction > 0.5


# ----------------------------------------------- the energy balances and temperature readings
def _cold_plate_hook(t, x, s, p, P, c, dx):
    c[C_QA] += p[0] * (p[1] - x[T_A])


class ColdPlate(Component):
    """Chamber a is bolted to a cooled plate: heat leaves it through the plate."""

    name = 'test_cold_plate'
    params = (Param('conductance_w_per_k', 'W/K', 0.3, 0.0, 100.0, 'plate conductance'),
              Param('plate_temperature_k', 'K', 278.15, 200.0, 400.0, 'plate temperature'))
    heat = _cold_plate_hook


class SlowThermocouple(Component):
    """Chamber a's thermocouple reads the gas temperature through a 60 ms lag."""

    name = 'test_slow_thermocouple'
    params = (Param('lag_s', 's', 0.06, 1e-4, 10.0, 'time constant'),)
    sensor_error = _first_order_lag('t_a_k')


def _blocked_record(cls, seed=3):
    """4 s at 1 kHz with the pistons held at mid-stroke and the valve stepped every 0.4 s,
    pressures and gas temperatures read with noise, ``cls`` registered only meanwhile."""
    from pneumatic_servo.experiment import Experiment
    from pneumatic_servo.model import Model, ModelConfig
    from pneumatic_servo.model.circuits import gauge_supply_pa
    from pneumatic_servo.synth.runs import blocked_run
    with registry.registered(cls):
        cfg = ModelConfig.paper().with_effect(cls.name)
        t = np.arange(4001) * 1e-3
        levels = np.array([5.0, 6.0, 4.3, 5.7, 4.6, 6.2, 4.0, 5.4, 5.0, 5.9])
        u = levels[np.minimum((t / 0.4).astype(int), len(levels) - 1)]
        angle, supply = 0.5 * cfg.core['stroke_rad'], gauge_supply_pa(0.6e6)
        res = blocked_run(Model(cfg), cfg, t, u, supply, angle)
        true = {k: np.asarray(res[k]) for k in ('p_a_pa', 'p_b_pa', 't_a_k', 't_b_k')}
        if cls.sensor_error is not None:
            error = cls.sensor_error(cls.defaults(), true, cfg.core)
            true = {k: v + error.get(k, 0.0) for k, v in true.items()}
    rng = np.random.default_rng(seed)
    noise = {'p_a_pa': 300.0, 'p_b_pa': 300.0, 't_a_k': 0.05, 't_b_k': 0.05}
    signals = {k: v + rng.normal(0.0, noise[k], len(v)) for k, v in true.items()}
    signals.update(command_v=u, supply_pa=np.full(len(t), supply))
    return Experiment(t, signals, 'blocked', cls.name, False, {'blocked_angle_rad': angle})


@pytest.mark.study
def test_a_lagging_temperature_sensor_is_found_in_its_reading():
    """Where a record holds the gas temperatures, each has its measurement equation: a
    thermocouple's lag is read as one, with its time constant."""
    result = diagnose([_blocked_record(SlowThermocouple)])
    assert result.status == 'unexplained' and result.verdict == 'none', result.reason
    best = result.discovered[0]
    assert best.equation == 'measurement_t_a' and best.leading == 'rate_t_a', best.terms
    assert -best.terms['rate_t_a'] == pytest.approx(0.06, rel=0.2)
    assert 'temperature reads' in best.interpretation and 'ms late' in best.interpretation


@pytest.mark.study
def test_a_heat_flow_is_found_in_the_energy_balance_and_only_where_temperatures_are_read():
    """A heat sink on chamber a moves its pressure as a leak would; with the gas
    temperature read, the energy balance tells them apart and takes it, with the plate's
    law: heat through the wall, 0.3 W/K to a plate 15 K below the room. That law is a level
    and a slope that fit only together, reached from another start than the term that
    fits best alone (``ScreenedEquation.other``). A record without temperatures is never
    offered the energy balances (``Equation.needs``)."""
    from pneumatic_servo.analysis.diagnosis.data import Data
    from pneumatic_servo.analysis.diagnosis.discovery import seen_equations
    exp = _blocked_record(ColdPlate)
    result = diagnose([exp])
    assert result.verdict == 'none', result.reason
    best = result.discovered[0]
    assert best.equation == 'energy_balance_a', result.reason
    assert best.leading == 'wall_minus_t_a', best.terms
    assert best.terms['wall_minus_t_a'] == pytest.approx(0.3, rel=0.25)
    assert best.error_reduction > 0.8 and 'through the wall' in best.interpretation
    names = [eq.name for eq in seen_equations(Data.of([exp], DiagnoseOptions()))]
    assert {'energy_balance_a', 'energy_balance_b'} <= set(names)
    blind = exp.__class__(exp.t, {k: v for k, v in exp.signals.items()
                                  if k not in ('t_a_k', 't_b_k')}, 'blocked', exp.name,
                          False, exp.metadata)
    names = [eq.name for eq in seen_equations(Data.of([blind], DiagnoseOptions()))]
    assert not {'energy_balance_a', 'energy_balance_b'} & set(names)


# ------------------------------------------------------- two readings the records cannot tell
def _gear_friction_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] -= p[0] * abs(x[P_A] - x[P_B]) * math.tanh(x[OMEGA] / 0.005)


class LoadedGearFriction(Component):
    """Gear friction that grows with the transmitted load |p_a - p_b|."""

    name = 'test_loaded_gear_friction'
    params = (Param('torque_per_pa', 'N.m/Pa', 5e-7, 0.0, 1e-4, 'friction per Pa of load'),)
    mechanics = _gear_friction_hook


@pytest.mark.study
def test_a_reading_the_records_cannot_tell_from_the_chosen_one_is_said_beside_it():
    """On an open-loop chirp the load drives the motion nearly all the time, so a friction
    that grows with |p_a - p_b| reads as a piston torque a few per cent smaller: the
    simpler reading leads, and the one that fits as well or better is said beside it, in
    its own words and under ``fits_as_well``, with the record that would tell them apart."""
    from pneumatic_servo.effects.terms import BY_NAME
    from pneumatic_servo.synth.varied import Record, make_record
    with registry.registered(LoadedGearFriction):
        exp = make_record(Record('chirp', 500.0, 10.0, integrator='rk4', seed=8, effects={
            LoadedGearFriction.name: {'torque_per_pa': 5e-7}}))
    result = diagnose([exp])
    assert result.verdict == 'none', result.reason
    best = result.discovered[0]
    assert best.equation == 'moment_balance', result.reason
    readings = [best.leading, *best.fits_as_well]
    assert best.fits_as_well and 'sign_velocity_times_abs_pressure_difference' in readings, \
        best.interpretation
    for term in best.fits_as_well:
        assert set(BY_NAME[term].depends_on) != set(BY_NAME[best.leading].depends_on)
        assert best.fits_as_well[term] in best.interpretation
    # and which record would tell them apart: one where the direction of motion varies
    # independently of the load (the shaft braked, or driven by an outside load)
    assert ('a record in which velocity varies independently of p_a and p_b would tell them '
            'apart') in best.interpretation
    assert best.to_json()['fits_as_well'] == best.fits_as_well


def _gauge_gain_a(values, signals, core):
    return {'p_a_pa': values['gain_error'] * (signals['p_a_pa']
                                               - core['atmospheric_pressure_pa'])}


class GaugeGainA(Component):
    """Chamber a's gauge transmitter reads 3 % high over its span."""

    name = 'test_gauge_gain_a'
    params = (Param('gain_error', '1', 0.03, -0.5, 0.5, 'relative gain error'),)
    sensor_error = staticmethod(_gauge_gain_a)


@pytest.mark.study
def test_a_gauge_transmitters_gain_error_is_read_over_its_span():
    """A transmitter's gain error scales the pressure above atmosphere. Read as a gain of
    the absolute pressure it comes out a fifth smaller, and on an open-loop chirp, where the
    chamber pressure follows the command, as a level plus a crosstalk of the command that
    fits a little closer held out but not clearly: the gauge reading leads, at its size."""
    from pneumatic_servo.synth.varied import Record, make_record
    with registry.registered(GaugeGainA):
        exp = make_record(Record('chirp', 500.0, 10.0, seed=5,
                                 effects={GaugeGainA.name: {'gain_error': 0.03}}))
    result = diagnose([exp])
    best = result.discovered[0]
    assert (result.verdict, best.equation, best.leading) == \
        ('none', 'measurement_p_a', 'gauge_p_a'), result.reason
    assert best.terms['gauge_p_a'] == pytest.approx(0.03, rel=0.05)
    assert "chamber a transmitter's gain over its gauge span is off by +" in best.interpretation


@dataclass(frozen=True)
class _Found:
    """A fitted correction as the ordering sees it: its equation, terms and words."""

    equation: str
    terms: dict
    interpretation: str = 'its words'
    summary: str = 'what it adds'
    alike_equations: tuple = ()

    @property
    def leading(self) -> str:
        return next(iter(self.terms))


def _found(equation: str, *terms: str) -> _Found:
    return _Found(equation, dict.fromkeys(terms, 1.0))


@pytest.mark.parametrize('best, other, first', [
    # a crosstalk of the command into the supply reading, beside a chamber's flow
    (('measurement_supply', 'abs_command'), ('mass_balance_a', 'p_a'), 'mass_balance_a'),
    # a valve error following the command, beside p_b's transmitter lagging
    (('valve_input', 'command'), ('measurement_p_b', 'lag_20ms_p_b', 'constant'),
     'measurement_p_b'),
    # a torque over the stroke, beside a crosstalk of the angle into p_b's reading: kept
    (('moment_balance', 'angle'), ('measurement_p_b', 'cos_angle'), 'moment_balance'),
])
def test_of_equations_the_records_do_not_tell_apart_the_likeliest_kind_leads(best, other,
                                                                              first):
    """Where a correction of another equation earns its place and the best does not explain
    the held-out data clearly better, the likelier kind leads: a sensor's own reading, then
    a balance equation, then a crosstalk into a sensor (``readings.likeliest_first``); and
    the one that leads says the other (``readings.equations_alike``)."""
    from pneumatic_servo.analysis.diagnosis.readings import equations_alike, likeliest_first
    found = [_found(*best), _found(*other)]
    ordered = likeliest_first(found, claims=lambda d: True, beats_clearly=lambda d, c: False)
    assert ordered[0].equation == first and len(ordered) == 2
    said = equations_alike(ordered, lambda d: True, lambda d, c: False)
    assert said[0].alike_equations == (ordered[1].equation,)
    assert f'these records do not tell it from what it adds ({ordered[1].equation})' \
        in said[0].interpretation and 'would tell them apart' in said[0].interpretation
    # beaten clearly, or not earning its place, the other neither leads nor is said
    for claims, beats in ((lambda d: True, lambda d, c: True),
                          (lambda d: d is found[0], lambda d, c: False)):
        assert likeliest_first(found, claims, beats)[0] is found[0]
        assert equations_alike(found, claims, beats)[0] is found[0]
