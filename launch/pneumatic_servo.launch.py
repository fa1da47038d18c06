"""Plant, controller and monitor on a ROS 2 install: ``ros2 launch pneumatic_servo
pneumatic_servo.launch.py backend:=sim|rig|replay [clock_mode:=lockstep] [controller:=smc]
[bag:=PATH] [daq:=virtual] [namespace:=NS] [monitor:=false] [monitor_config:=CFG]
[floor_file:=FILE] [track:=piston_seal_leakage]``.

The monitor (the identified model beside the running rig, ``docs/ros.md``) runs by default;
it reads the plant's topics and publishes nothing the plant or the controller reads. Its
model is ``monitor_config``, by default the plant's ``model_config``.

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
from launch.conditions import IfCondition
from launch.events import matches_action
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import LifecycleNode, Node
from launch_ros.event_handlers import OnStateTransition
from launch_ros.events.lifecycle import ChangeState
from lifecycle_msgs.msg import Transition

from pneumatic_servo.ros.controller_node import CONTROLLER_SPECS
from pneumatic_servo.ros.monitor_node import MONITOR_SPECS
from pneumatic_servo.ros.plant_specs import PLANT_SPECS

#: the plant, controller and monitor parameters set by launch arguments
PLANT_ARGS = ('backend', 'clock_mode', 'model_config', 'rig_config', 'daq', 'bag')
CONTROLLER_ARGS = ('controller',)
MONITOR_ARGS = ('floor_file', 'track')


def _arguments():
    out = [DeclareLaunchArgument(name, default_value=str(PLANT_SPECS[name].default),
                                 description=PLANT_SPECS[name].describe())
           for name in PLANT_ARGS]
    out += [DeclareLaunchArgument(name, default_value=str(CONTROLLER_SPECS[name].default),
                                  description=CONTROLLER_SPECS[name].describe())
            for name in CONTROLLER_ARGS]
    out += [DeclareLaunchArgument(name, default_value=str(MONITOR_SPECS[name].default),
                                  description=MONITOR_SPECS[name].describe())
            for name in MONITOR_ARGS]
    out.append(DeclareLaunchArgument('monitor', default_value='true',
                                     description='run the monitor beside the plant'))
    out.append(DeclareLaunchArgument('monitor_config',
                                     default_value=LaunchConfiguration('model_config'),
                                     description="the monitor's model (default: the plant's "
                                                 'model_config)'))
    out.append(DeclareLaunchArgument('namespace', default_value='',
                                     description='namespace for the nodes'))
    return out


def _transition(node, transition_id):
    return EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(node),
                                       transition_id=transition_id))


def generate_launch_description():
    share = get_package_share_directory('pneumatic_servo')
    arg = {name: LaunchConfiguration(name)
           for name in PLANT_ARGS + CONTROLLER_ARGS + MONITOR_ARGS
           + ('namespace', 'monitor', 'monitor_config')}
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
    # the monitor configures and activates itself (autostart): nothing waits on it
    monitor = LifecycleNode(
        package='pneumatic_servo', executable='pneumatic-servo', arguments=['monitor'],
        name='pneumatic_servo_monitor', namespace=arg['namespace'], output='screen',
        condition=IfCondition(arg['monitor']),
        parameters=[os.path.join(share, 'config', 'monitor.yaml'),
                    {'model_config': arg['monitor_config'],
                     **{name: arg[name] for name in MONITOR_ARGS}}])
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
        plant, controller, monitor, activate_when_inactive, *failed,
        _transition(plant, Transition.TRANSITION_CONFIGURE)])
