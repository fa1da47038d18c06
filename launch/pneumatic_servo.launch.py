"""Plant and controller on a ROS 2 install: ``ros2 launch pneumatic_servo
pneumatic_servo.launch.py backend:=sim|rig|replay [clock_mode:=lockstep] [controller:=smc]
[bag:=PATH] [daq:=virtual] [namespace:=NS]``.

Without ``ros2 launch`` (a pip install), ``pneumatic-servo up`` does the same.

The plant is a lifecycle node driven by the standard launch_ros transition events: launch
configures it, activates it once it is inactive, and logs a failed transition (the valve
then stays at its safe voltage). Parameter files: ``config/plant_sim.yaml`` and
``config/controller.yaml`` are generated from the node declarations
(``python -m pneumatic_servo.ros.params_file config``); the launch arguments' defaults are
read from the same declarations, so nothing here restates a default.
"""
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, LogInfo, RegisterEventHandler
from launch.events import matches_action
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import LifecycleNode, Node
from launch_ros.event_handlers import OnStateTransition
from launch_ros.events.lifecycle import ChangeState
from lifecycle_msgs.msg import Transition

from pneumatic_servo.ros.controller_node import CONTROLLER_SPECS
from pneumatic_servo.ros.plant_node import PLANT_SPECS

#: the plant and controller parameters set by launch arguments
PLANT_ARGS = ('backend', 'clock_mode', 'model_config', 'rig_config', 'daq', 'bag')
CONTROLLER_ARGS = ('controller',)


def _arguments():
    out = [DeclareLaunchArgument(name, default_value=str(PLANT_SPECS[name].default),
                                 description=PLANT_SPECS[name].describe())
           for name in PLANT_ARGS]
    out += [DeclareLaunchArgument(name, default_value=str(CONTROLLER_SPECS[name].default),
                                  description=CONTROLLER_SPECS[name].describe())
            for name in CONTROLLER_ARGS]
    out.append(DeclareLaunchArgument('namespace', default_value='',
                                     description='namespace for both nodes'))
    return out


def _transition(node, transition_id):
    return EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(node),
                                       transition_id=transition_id))


def generate_launch_description():
    share = get_package_share_directory('pneumatic_servo')
    arg = {name: LaunchConfiguration(name)
           for name in PLANT_ARGS + CONTROLLER_ARGS + ('namespace',)}
    lockstep = PythonExpression(["'", arg['clock_mode'], "' == 'lockstep'"])
    plant = LifecycleNode(
        package='pneumatic_servo', executable='pneumatic-servo', arguments=['plant'],
        name='pneumatic_servo_plant', namespace=arg['namespace'], output='screen',
        parameters=[os.path.join(share, 'config', 'plant_sim.yaml'),
                    {name: arg[name] for name in PLANT_ARGS}, {'autostart': False}])
    controller = Node(
        package='pneumatic_servo', executable='pneumatic-servo', arguments=['controller'],
        name='pneumatic_servo_controller', namespace=arg['namespace'], output='screen',
        parameters=[os.path.join(share, 'config', 'controller.yaml'),
                    {'controller': arg['controller'], 'model_config': arg['model_config'],
                     'use_sim_time': lockstep}])
    activate_when_inactive = RegisterEventHandler(OnStateTransition(
        target_lifecycle_node=plant, start_state='configuring', goal_state='inactive',
        entities=[LogInfo(msg='plant configured; activating'),
                  _transition(plant, Transition.TRANSITION_ACTIVATE)]))
    failed = [RegisterEventHandler(OnStateTransition(
        target_lifecycle_node=plant, start_state=start, goal_state=goal,
        entities=[LogInfo(msg=f'plant: {what} failed; the valve stays at its safe voltage '
                              '(see the node log for the reason)')]))
        for start, goal, what in (('configuring', 'unconfigured', 'configure'),
                                  ('activating', 'inactive', 'activate'),
                                  ('errorprocessing', 'unconfigured', 'a transition'))]
    return LaunchDescription(_arguments() + [
        plant, controller, activate_when_inactive, *failed,
        _transition(plant, Transition.TRANSITION_CONFIGURE)])
