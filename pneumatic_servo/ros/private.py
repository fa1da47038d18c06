"""The one module that touches rclpy's private interfaces.

Each use is here because the public API does not meet the 1 kHz figures on this
machine (``benchmarks/bench_ros.py`` measures ``rclpy.experimental.EventsExecutor``
and the stock executors against it), and each is exercised by
``tests/ros/test_rclpy_private.py``, which fails loudly, naming the piece, when an
rclpy release changes it:

* a small wait set of our own on the hot subscriptions (``_rclpy.WaitSet``), and
  ``take_message`` on a subscription's handle: the stock executors rebuild their
  wait set from every entity of every node on each turn;
* a message's source timestamp, which ``take_message`` returns beside it (the monitor
  orders commands against measurements by it);
* the ``/clock`` subscription rclpy creates for ``use_sim_time``
  (``node._time_source._clock_sub``): with sim time it changes every period and must be
  waited on with the measurements, or a message is stamped with a clock some periods
  late.
"""
from __future__ import annotations

from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy


def wait_set(context, n_subscriptions: int):
    """A wait set for ``n_subscriptions`` subscriptions (and nothing else)."""
    return _rclpy.WaitSet(max(n_subscriptions, 1), 0, 0, 0, 0, 0, context.handle)


def wait(ws, subscriptions, timeout_ns: int) -> set:
    """Wait on ``subscriptions`` up to ``timeout_ns``; the handles' pointers that are ready."""
    ws.clear_entities()
    for s in subscriptions:
        ws.add_subscription(s.handle)
    ws.wait(max(int(timeout_ns), 0))
    return set(ws.get_ready_entities('subscription'))


def is_ready(subscription, ready: set) -> bool:
    return subscription.handle.pointer in ready


def take(subscription):
    """One message of ``subscription`` (raw bytes if it was created raw), or None."""
    got = subscription.handle.take_message(subscription.msg_type, subscription.raw)
    return None if got is None else got[0]


def take_with_source(subscription):
    """One message of ``subscription`` and its source timestamp [ns, the publisher's system
    clock] and receive timestamp [ns], or None: ``(message, source_ns, received_ns)``.
    The monitor orders stampless commands against measurements by when they were published."""
    got = subscription.handle.take_message(subscription.msg_type, subscription.raw)
    if got is None:
        return None
    msg, info = got
    return msg, int(info['source_timestamp']), int(info['received_timestamp'])


def clock_subscription(node):
    """The ``/clock`` subscription rclpy made for ``use_sim_time``, or None without sim time."""
    return getattr(getattr(node, '_time_source', None), '_clock_sub', None)
