"""Shared test set-up: keep DDS traffic on this machine, render plots off-screen, and the
two tiers of the suite.

**Tiers.** ``./run.sh test`` (CI) runs every test not marked ``study``; ``./run.sh study``
runs those. A study is an acceptance test at full size: a whole diagnosis with the catalogue
(2-11 min each on a loaded 2-core machine, the most with an empty kernel cache), a fleet on
a local cluster, minutes of a monitor beside a running loop. Each feature keeps a cheaper
test of its behaviour in the first tier, but for the two gaps the README names; the studies
hold the claims the docs make of its size.
"""
import os

os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
os.environ.setdefault('MPLBACKEND', 'Agg')

#: the files that take longest (minutes each on a loaded 2-core machine, 2026-11-26), run
#: first: run.sh gives two pytest-xdist workers whole files in collection order
#: (--no-loadscope-reorder), and a long file started last keeps one worker going alone
LONG_FIRST = ('ros/test_ros_monitor.py', 'test_open_world.py', 'test_diagnose.py',
              'test_open_world_readings.py', 'test_open_world_cli.py', 'test_judgement.py',
              'test_dependence.py',
              'test_effects.py', 'test_fleet.py', 'test_bad_input.py',
              'ros/test_ros_backends.py', 'test_kernel_cache.py', 'ros/test_safety_matrix.py',
              'test_identifiability.py', 'test_monitor.py', 'ros/test_ros_closed_loop.py')


def pytest_configure(config):
    config.addinivalue_line('markers', 'study: an acceptance test at full size, minutes '
                            'long (./run.sh study; not in ./run.sh test)')
    # pytest resets the warning filters for each test: the one pneumatic_servo._jit sets
    # (numba's first-class functions, which the integrators take, are 'experimental')
    config.addinivalue_line('filterwarnings',
                            'ignore:First-class function type feature is experimental')


def pytest_collection_modifyitems(items):
    def rank(item):
        path = item.nodeid.split('::')[0].removeprefix('tests/')
        return LONG_FIRST.index(path) if path in LONG_FIRST else len(LONG_FIRST)
    items.sort(key=rank)  # stable: the order within and among the rest is kept
