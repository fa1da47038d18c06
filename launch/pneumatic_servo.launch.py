"""Plant and controller on a ROS 2 install: ``ros2 launch pneumatic_servo
pneumatic_servo.launch.py backend:=sim|rig|replay [clock_mode:=lockstep] [controller:=smc]
[bag:=PATH] [daq:=virtual]``.

Without ``ros2 launch`` (a pip install), ``pneumatic-servo up`` does the same.
Parameter files: ``config/plant_sim.yaml`` and ``config/controller.yaml`` hold every
parameter with its default; launch arguments override them.
"""
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import Node

ARGS = (
    ('backend', 'sim', 'what is behind the plant: sim, rig or replay'),
    ('clock_mode', 'free', 'sim: free (real time) or lockstep (plant owns /clock)'),
    ('controller', 'pid', 'control law: pid or smc (model-based)'),
    ('model_config', '', "model config YAML ('' = the paper's rig)"),
    ('rig_config', '', "rig wiring and scaling YAML ('' = config/rig_pci6229.yaml)"),
    ('daq', 'nidaqmx', 'rig: nidaqmx (the NI card) or virtual (simulated card)'),
    ('bag', '', 'replay: rosbag2 directory'),
    ('namespace', '', 'namespace for both nodes'),
)


def generate_launch_description():
    share = get_package_share_directory('pneumatic_servo')
    plant_params = os.path.join(share, 'config', 'plant_sim.yaml')
    controller_params = os.path.join(share, 'config', 'controller.yaml')
    arg = {name: LaunchConfiguration(name) for name, _, _ in ARGS}
    lockstep = PythonExpression(["'", arg['clock_mode'], "' == 'lockstep'"])
    plant = Node(
        package='pneumatic_servo', executable='pneumatic-servo', arguments=['plant'],
        name='pneumatic_servo_plant', namespace=arg['namespace'], output='screen',
        parameters=[plant_params, {
            'backend': arg['backend'], 'clock_mode': arg['clock_mode'],
            'model_config': arg['model_config'], 'rig_config': arg['rig_config'],
            'daq': arg['daq'], 'bag': arg['bag']}])
    controller = Node(
        package='pneumatic_servo', executable='pneumatic-servo', arguments=['controller'],
        name='pneumatic_servo_controller', namespace=arg['namespace'], output='screen',
        parameters=[controller_params, {
            'controller': arg['controller'], 'model_config': arg['model_config'],
            'use_sim_time': lockstep}])
    return LaunchDescription(
        [DeclareLaunchArgument(name, default_value=default, description=text)
         for name, default, text in ARGS] + [plant, controller])
