"""Fixtures of the ROS tests (see rostest_helpers)."""
import pytest
from rostest_helpers import Probe, Procs, next_domain


@pytest.fixture
def domain():
    return next_domain()


@pytest.fixture
def procs(domain, tmp_path):
    p = Procs(domain, tmp_path)
    yield p
    p.cleanup()


@pytest.fixture
def probe(domain, request):
    p = Probe(domain)
    yield p
    # The test's processes end before the probe does: the probe's participant is then not
    # torn down while peers are still leaving the domain (or were SIGKILLed mid-message).
    if 'procs' in request.fixturenames:
        request.getfixturevalue('procs').cleanup()
        p.spin(0.2)
    p.close()
