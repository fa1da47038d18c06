"""The plant's publishers belong to the configured node (as ros2/demos lifecycle_py): none
before configure, the mode's set after it, none after cleanup. Seen from another
participant over real DDS."""
import rclpy
from rclpy.lifecycle import TransitionCallbackReturn

from pneumatic_servo.ros.plant_node import PlantNode

SUCCESS = TransitionCallbackReturn.SUCCESS


def test_publishers_exist_only_while_configured(domain, probe):
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain)
    try:
        plant = PlantNode(overrides={'autostart': False, 'clock_mode': 'lockstep'},
                          context=context)

        def seen(topic):
            return probe.node.count_publishers(topic)
        probe.spin_until(lambda: seen('/diagnostics') == 1, 10.0, 'the plant on the graph')
        assert seen('/joint_states') == seen('/clock') == seen('/valve/applied') == 0
        assert plant.state == 'unconfigured' and not plant.started

        assert plant.trigger_configure() == SUCCESS
        probe.spin_until(lambda: (seen('/joint_states'), seen('/clock'),
                                  seen('/chamber_a/pressure'), seen('/valve/applied'))
                         == (1, 1, 1, 1), 10.0, 'the configured plant publishes')
        assert seen('/valve/command') == 1, "the probe's own: only a replay publishes it"
        assert plant.trigger_activate() == SUCCESS
        assert plant.state == 'active'
        assert not plant.started, 'lockstep waits for its subscribers before sample 0'

        assert plant.trigger_deactivate() == SUCCESS
        assert plant.trigger_cleanup() == SUCCESS
        probe.spin_until(lambda: seen('/joint_states') == seen('/clock') == 0, 10.0,
                         'publishers gone after cleanup')
        assert seen('/diagnostics') == 1, 'diagnostics go on in every state'
        assert plant.state == 'unconfigured' and plant.pubs == {}
        plant.destroy_node()
    finally:
        rclpy.try_shutdown(context=context)
