"""rosbag2 (sqlite3 and MCAP) <-> :class:`~pneumatic_servo.experiment.Experiment`, in the
layout of rosbags' own ``rosbag2`` package:

- :mod:`.reader`: :func:`read_bag` (validated, resampled Experiment) and
  :func:`read_series` (each measurement on its own stamps), with :class:`ReadOptions`,
  and :func:`read_messages` (any topic's messages, for topics outside the interface);
  the messages of a topic are decoded a batch at a time by the topic's codec
  (:mod:`pneumatic_servo.io.codecs`);
- :mod:`.writer`: :func:`write_experiment_bag` and :func:`write_raw_bag`;
- :mod:`.metadata`: the bag's custom data and its topics matched to docs/interfaces.md;
- :mod:`.storage`: the directory and storage files checked, rosbags' reader and writer
  opened as ROS 2 Jazzy's recorder writes;
- :mod:`.errors`: what a storage or decoding failure means, in one line.
"""
from __future__ import annotations

from ..codecs import typestore
from .reader import ReadOptions, read_bag, read_messages, read_series
from .storage import BAG_VERSION, STORAGES, add_topic, offered_qos
from .writer import (
    DEFAULT_LATENCY_S,
    DEFAULT_START_NS,
    MAX_STAMP_NS,
    write_experiment_bag,
    write_raw_bag,
)

__all__ = ['BAG_VERSION', 'DEFAULT_LATENCY_S', 'DEFAULT_START_NS', 'MAX_STAMP_NS',
           'ReadOptions', 'STORAGES', 'add_topic', 'offered_qos', 'read_bag', 'read_messages',
           'read_series',
           'typestore', 'write_experiment_bag', 'write_raw_bag']
