"""The output gate, exhaustively: it is the one thing between any command and any valve."""
import math

import pytest

from pneumatic_servo.control.gate import ERROR, OK, WARN, OutputGate
from pneumatic_servo.errors import ConfigError


def armed(value=6.0, t=0.0, **kw) -> OutputGate:
    g = OutputGate(**kw)
    assert g.command(value, t) == value
    return g


# ------------------------------------------------------------------------- start-up
def test_starts_safe_and_unarmed_and_the_watchdog_waits_for_the_first_command():
    g = OutputGate()
    for t in (0.0, 0.05, 1.0, 1e6):
        assert g.output(t) == 5.0
    assert not g.faulted and not g.armed
    assert g.status(10.0).level == OK and 'waiting' in g.status(10.0).message


def test_first_command_arms_it():
    g = OutputGate()
    g.command(6.2, 1.0)
    assert g.armed and g.output(1.05) == 6.2


# ------------------------------------------------------------------------ pass/clamp
@pytest.mark.parametrize('value', [0.0, 0.001, 2.5, 4.999, 5.0, 5.001, 7.77, 9.999, 10.0])
def test_in_range_passes_unchanged(value):
    g = armed(value)
    assert g.output(0.01) == value
    assert g.status(0.01).level == OK and g.clamped == 0


@pytest.mark.parametrize('value, out', [(10.0001, 10.0), (12.0, 10.0), (1e300, 10.0),
                                        (-1e-9, 0.0), (-3.0, 0.0), (-1e300, 0.0)])
def test_out_of_range_is_clamped_and_warned_not_faulted(value, out):
    g = OutputGate()
    assert g.command(value, 0.0) == out
    assert g.output(0.01) == out
    st = g.status(0.01)
    assert st.level == WARN and 'clamped' in st.message and g.clamped == 1
    assert not g.faulted
    g.command(6.0, 0.02)  # an in-range command clears the warning
    assert g.status(0.02).level == OK


def test_custom_clamp_range():
    g = OutputGate(min_v=2.0, max_v=8.0)
    assert g.command(9.0, 0.0) == 8.0
    assert g.command(1.0, 0.01) == 2.0


# ----------------------------------------------------------------------- non-finite
@pytest.mark.parametrize('bad', [math.nan, math.inf, -math.inf, float('nan'), 'abc', None,
                                 object()])
def test_non_finite_or_non_numeric_goes_safe_and_latches(bad):
    g = armed(7.0)
    assert g.command(bad, 0.01) == 5.0
    assert g.output(0.011) == 5.0
    assert g.faulted and 'non-finite' in g.faults[0]
    st = g.status(0.02)
    assert st.level == ERROR and st.output_v == 5.0 and g.non_finite == 1
    # latched: good commands do not bring the valve back, they are counted as ignored
    assert g.command(6.0, 0.03) == 5.0 and g.output(0.031) == 5.0
    assert g.ignored == 1


def test_non_finite_before_arming_latches_too():
    g = OutputGate()
    assert g.command(math.nan, 0.0) == 5.0
    assert g.faulted and g.output(0.0) == 5.0


# ------------------------------------------------------------------------- watchdog
def test_watchdog_boundary_default_100_ms():
    g = armed(7.0, 0.0)
    assert g.output(0.1) == 7.0          # exactly at the limit: still fresh
    assert not g.faulted
    assert g.output(0.1000001) == 5.0    # just past it: safe and latched
    assert g.faulted and 'watchdog' in g.faults[0]
    assert g.output(0.05) == 5.0         # stays safe whatever the clock says
    g.command(7.0, 0.2)
    assert g.output(0.2) == 5.0


def test_fresh_commands_keep_it_alive():
    g = armed(6.0, 0.0)
    t = 0.0
    for _ in range(100):
        t += 0.09
        g.command(6.0, t)
        assert g.output(t + 0.09) == 6.0
    assert not g.faulted


@pytest.mark.parametrize('limit', [0.001, 0.02, 0.5, 10.0])
def test_watchdog_limit_is_a_parameter(limit):
    g = armed(6.0, 0.0, watchdog_s=limit)
    assert g.output(limit * 0.999) == 6.0
    assert g.output(limit * 1.001 + 1e-9) == 5.0 and g.faulted


def test_watchdog_changed_at_run_time():
    g = armed(6.0, 0.0)
    g.watchdog_s = 0.01
    assert g.output(0.02) == 5.0 and g.faulted


def test_nan_clock_trips_rather_than_passes():
    g = armed(6.0, 0.0)
    assert g.output(math.nan) == 5.0 and g.faulted


def test_status_does_not_trip_the_watchdog():
    g = armed(6.0, 0.0)
    st = g.status(5.0)
    assert not g.faulted and st.command_age_s == pytest.approx(5.0)


# ----------------------------------------------------------------------- trip/reset
def test_trip_latches_any_reason_and_reset_needs_a_fresh_command():
    g = armed(6.0, 0.0)
    g.trip('SensorFault: chamber_b open wire')
    assert g.output(0.01) == 5.0 and 'open wire' in g.status(0.01).message
    g.reset()
    assert not g.faulted and not g.armed
    assert g.output(0.02) == 5.0         # still safe until a fresh command
    g.command(6.5, 0.03)
    assert g.output(0.04) == 6.5


def test_faults_accumulate_once_each_in_order():
    g = armed(6.0, 0.0)
    g.trip('a')
    g.trip('b')
    g.trip('a')
    assert g.faults == ('a', 'b')


def test_reset_does_not_resurrect_the_old_command():
    g = armed(9.0, 0.0)
    g.trip('x')
    g.reset()
    assert g.output(0.001) == 5.0


# ----------------------------------------------------------------------- hold/release
def test_hold_is_safe_without_a_fault_and_ignores_commands():
    g = armed(6.0, 0.0)
    g.hold('inactive')
    assert g.output(0.01) == 5.0 and not g.faulted
    assert g.command(8.0, 0.02) == 5.0 and g.output(0.02) == 5.0
    st = g.status(0.02)
    assert st.level == OK and 'inactive' in st.message and st.output_v == 5.0
    g.release()
    assert g.output(0.03) == 5.0         # released, but needs a fresh command
    g.command(6.0, 0.04)
    assert g.output(0.05) == 6.0


def test_hold_with_a_latched_fault_reports_the_fault():
    g = armed(6.0, 0.0)
    g.trip('boom')
    g.hold('shutdown')
    assert g.status(0.1).level == ERROR and g.output(0.1) == 5.0


# ----------------------------------------------------------------------- construction
@pytest.mark.parametrize('kw', [dict(watchdog_s=0.0), dict(watchdog_s=-1.0),
                                dict(watchdog_s=math.nan), dict(watchdog_s=math.inf),
                                dict(safe_v=11.0), dict(min_v=-1.0), dict(max_v=10.5),
                                dict(min_v=6.0), dict(max_v=4.0), dict(min_v=7.0, max_v=3.0),
                                dict(safe_v=math.nan), dict(watchdog_s='0.1')])
def test_bad_configuration_is_rejected_with_a_reason(kw):
    with pytest.raises(ConfigError, match='output gate'):
        OutputGate(**kw)


def test_a_long_random_command_stream_never_leaves_the_range():
    import random
    rnd = random.Random(1)
    g = OutputGate()
    t = 0.0
    specials = [math.nan, math.inf, -math.inf, 1e308, -1e308, 0.0, 10.0]
    for i in range(20000):
        t += rnd.choice((0.0005, 0.001, 0.01, 0.2))
        v = rnd.choice(specials) if rnd.random() < 0.01 else rnd.uniform(-20.0, 30.0)
        out = g.command(v, t)
        assert 0.0 <= out <= 10.0 and math.isfinite(out)
        if not math.isfinite(v):
            assert out == 5.0
        o = g.output(t + rnd.uniform(0.0, 0.3))
        assert 0.0 <= o <= 10.0 and math.isfinite(o)
        if g.faulted:
            assert o == 5.0
            if rnd.random() < 0.5:
                g.reset()
