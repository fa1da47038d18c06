"""Pure physics functions in SI units: no state, no ROS, numba-compatible."""
