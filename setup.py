"""ament_python package that also installs with plain pip (see README, 'Installing')."""
from glob import glob

from setuptools import find_packages, setup

package_name = 'pneumatic_servo'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['tests', 'tests.*']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', glob('config/*.yaml')),
        ('share/' + package_name + '/launch', glob('launch/*.py')),
    ],
    python_requires='>=3.10',
    install_requires=['numpy>=1.24', 'scipy>=1.10', 'pyyaml>=6', 'rosbags>=0.10',
                      'matplotlib>=3.7'],
    extras_require={
        # ROS 2 Jazzy from PyPI for machines without a ROS install; on a ROS
        # install these come from the distribution (package.xml exec_depends).
        'ros': ['ros-jazzy-rclpy', 'ros-jazzy-common-interfaces', 'ros-jazzy-rmw-fastrtps-cpp'],
        # compiled kernels; the model runs as plain Python without it
        'fast': ['numba>=0.59'],
        # the paper rig's NI PCI-6229 through NI-DAQmx (only for backend rig, driver nidaqmx)
        'rig': ['nidaqmx'],
        # many recordings on Dask (pneumatic-servo fleet): scheduler, progress bar, Parquet
        'fleet': ['dask[distributed]>=2024.1', 'tqdm', 'pyarrow'],
        'test': ['pytest>=7', 'pytest-timeout', 'pytest-xdist', 'hypothesis'],
    },
    zip_safe=True,
    maintainer='pneumatic_servo developers',
    maintainer_email='pneumatic-servo@example.org',
    description='Nonlinear model, identification and model-discrepancy diagnosis for '
                'pneumatic rotary position servos, with ROS 2 nodes',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'pneumatic-servo = pneumatic_servo.cli:main',
        ],
    },
)
