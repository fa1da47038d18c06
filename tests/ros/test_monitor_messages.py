"""What the monitor node says (``ros/monitor_messages.py``): its health words and tables."""
import math

from pneumatic_servo.ros.monitor_messages import (
    EFFECT_FIELDS,
    RESIDUAL_FIELDS,
    effect_table,
    health,
    residual_table,
)


def test_a_quiet_monitor_is_ok():
    assert health('active', {'state': 'judging'}, 0, None, False) == ('ok', ['active: judging'])
    # a measurement a few seconds ago: still live
    assert health('active', {'state': 'judging'}, 0, None, False, 4.0)[0] == 'ok'


def test_every_reason_for_a_warning_is_said():
    report = {'state': 'judging', 'decimating': True, 'last_error': 'NaN in window 3',
              'counts': {'judged': 10, 'skipped': 5, 'lost': 50, 'samples': 1000},
              'channels': {'angle': {'level': 'warn'}, 'p_a': {'level': 'ok'}}}
    level, words = health('active', report, 7, 'gate: watchdog', True, 12.0)
    assert level == 'warn'
    text = '; '.join(words)
    for part in ('active: judging', 'departs in angle', 'DECIMATING: judged 10',
                 'dropped 7 samples', '50 of 1050 samples missing', 'NaN in window 3',
                 'holds its valve safe (gate: watchdog)', 'no valve/command',
                 'no measurement for 12 s'):
        assert part in text, part
    assert 'p_a' not in text


def test_tables_have_their_documented_columns():
    channel = {'ratio': 1.2, 'rms': 0.1, 'floor_rms': 0.08, 'cusum': 0.5, 'threshold': 9.0,
               'p_value': 0.4, 'window_p_value': 0.3, 'z': 0.1, 'level': 'warn', 'windows': 4}
    msg = residual_table({'t_ns': 2_000_000_000, 'channels': {'angle': channel}})
    assert msg.layout.dim[0].label == 'channel:angle'
    assert msg.layout.dim[1].label == 'field:' + ','.join(RESIDUAL_FIELDS)
    row = dict(zip(RESIDUAL_FIELDS, msg.data))
    assert row['data_time_s'] == 2.0 and row['level'] == 1.0 and row['ratio'] == 1.2
    est = {'seal.area': {'t_s': 3.0, 'value': 1e-8, 'stderr': None, 'alert': {'text': 'up'}}}
    row = dict(zip(EFFECT_FIELDS, effect_table(est).data))
    assert row['alert'] == 1.0 and math.isnan(row['stderr'])
