"""Plain JSON values of numpy and Python data: the one conversion the package's JSON (and
YAML) outputs go through.

JSON has no NaN or infinity (strict readers reject the ``NaN`` that ``json.dumps`` writes),
so a value that is not finite becomes ``null``.
"""
from __future__ import annotations

import json
import math

import numpy as np


def plain(value):
    """``value`` with numpy scalars and arrays as Python numbers and lists, tuples as lists,
    mapping keys as strings, and NaN and infinities as None; anything else as it is."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def dumps(value, **options) -> str:
    """Strict JSON of :func:`plain` ``value``; an object JSON has no form for (a path, a
    date) is written as its ``str``. ``options`` go to ``json.dumps`` (``indent``, ...)."""
    return json.dumps(plain(value), allow_nan=False, default=str, **options)
