"""rclpy's private interfaces that ``ros/private.py`` uses, exercised one by one: a change in
an rclpy release fails here, naming the piece, instead of somewhere in the 1 kHz loop."""
import rclpy
from rclpy.parameter import Parameter
from std_msgs.msg import Float64

from pneumatic_servo.ros import private


def test_wait_set_take_and_clock_subscription(domain):
    ctx = rclpy.Context()
    rclpy.init(context=ctx, domain_id=domain)
    try:
        node = rclpy.create_node('private_probe', context=ctx)
        pub = node.create_publisher(Float64, 'private_probe_topic', 10)
        sub = node.create_subscription(Float64, 'private_probe_topic', lambda m: None, 10)
        raw = node.create_subscription(Float64, 'private_probe_topic', lambda m: None, 10,
                                       raw=True)
        ws = private.wait_set(ctx, 2)  # _rclpy.WaitSet(subscriptions, ..., context.handle)
        pub.publish(Float64(data=4.5))
        ready = set()
        for _ in range(200):  # discovery on loopback can take a moment
            ready = private.wait(ws, [sub, raw], 50_000_000)
            if private.is_ready(sub, ready) and private.is_ready(raw, ready):
                break
            pub.publish(Float64(data=4.5))
        assert private.is_ready(sub, ready), 'WaitSet.get_ready_entities or handle.pointer'
        msg = private.take(sub)  # subscription.handle.take_message(type, raw)
        assert isinstance(msg, Float64) and msg.data == 4.5
        data = private.take(raw)
        assert isinstance(data, bytes) and len(data) >= 12  # CDR: header + one float64
        import time
        before = time.time_ns()
        pub.publish(Float64(data=5.5))
        got = None
        for _ in range(200):
            got = private.take_with_source(raw)  # take_message's info['source_timestamp']
            if got is not None:
                break
            private.wait(ws, [raw], 50_000_000)
        assert got is not None and isinstance(got[0], bytes)
        assert before - 1_000_000_000 < got[1] <= got[2] + 1_000_000, 'source/receive stamps'
        assert private.clock_subscription(node) is None  # no sim time, no /clock
        sim = rclpy.create_node('private_probe_sim', context=ctx, parameter_overrides=[
            Parameter('use_sim_time', Parameter.Type.BOOL, True)])
        clock_sub = private.clock_subscription(sim)  # node._time_source._clock_sub
        assert clock_sub is not None and clock_sub.topic_name == '/clock'
        sim.destroy_node()
        node.destroy_node()
    finally:
        rclpy.shutdown(context=ctx)
