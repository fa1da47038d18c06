"""Shared test set-up: keep DDS traffic on this machine, and render plots off-screen."""
import os

os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
os.environ.setdefault('MPLBACKEND', 'Agg')

#: the files that take longest (minutes each on a loaded 2-core CI machine, 2026-11-26),
#: run first: run.sh gives two pytest-xdist workers whole files in collection order
#: (--no-loadscope-reorder), and a long file started last keeps one worker going alone
LONG_FIRST = ('ros/test_ros_monitor.py', 'test_open_world.py', 'test_diagnose.py',
              'test_open_world_readings.py', 'test_open_world_cli.py', 'test_fleet.py',
              'test_effects.py', 'ros/test_safety_matrix.py', 'test_bad_input.py')


def pytest_collection_modifyitems(items):
    def rank(item):
        path = item.nodeid.split('::')[0].removeprefix('tests/')
        return LONG_FIRST.index(path) if path in LONG_FIRST else len(LONG_FIRST)
    items.sort(key=rank)  # stable: the order within and among the rest is kept
