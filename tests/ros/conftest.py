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
def probe(domain):
    p = Probe(domain)
    yield p
    p.close()
