"""Hand-written CDR for the few message types on the ROS nodes' hot path.

The codec lives in :mod:`pneumatic_servo.io.cdr` (the bag reader and writer share its
layout rules); this module is the nodes' import path. Why hand-written: rclpy converts
every message between Python objects and C structs; at 1 kHz with seven messages per
period that is the largest cost of the loop (tens of microseconds per message). These
types are fixed, so the plant publishes bytes packed there and the controller reads the
two or three numbers it needs straight from the bytes. tests/ros/test_cdr.py checks every
function against rclpy's own (de)serialisation.
"""
from __future__ import annotations

from ..io.cdr import (
    HEADER,
    F64x2,
    header_block,
    joint_state_after_header,
    pack_clock,
    pack_float64,
    pack_joint_state,
    pack_scalar,
    unpack_float64,
    unpack_joint_state,
    unpack_scalar,
)

__all__ = ['F64x2', 'HEADER', 'header_block', 'joint_state_after_header', 'pack_clock',
           'pack_float64', 'pack_joint_state', 'pack_scalar', 'unpack_float64',
           'unpack_joint_state', 'unpack_scalar']
