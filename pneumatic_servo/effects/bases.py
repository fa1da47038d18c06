"""The functions of the state the vocabulary's expressions call (:mod:`.terms`): each
works on a scalar in a compiled hook and on a record's arrays in numpy, so that one
expression serves both. Emitted effect files import them from :mod:`.terms`.
"""
from __future__ import annotations

import numpy as np

from .._jit import njit

#: [s] time constant with which the command's memory follows outside its play band (fast
#: against the loop, slow enough not to stiffen the integration)
COMMAND_MEMORY_S = 0.002
#: windows over the stroke: Gaussian bumps centred at (k + 1/2) / N_WINDOWS of the stroke
N_WINDOWS = 4
#: knots of a free shape over the stroke (the shape stage, :mod:`..analysis.diagnosis.shape`):
#: piecewise linear between equally spaced knots from one end stop to the other
N_KNOTS = 8
#: knots of the free function of one variable fitted beside a correction to test whether it
#: depends on that variable (:attr:`Term.probes`, :mod:`..analysis.diagnosis.dependence`):
#: coarse, as the test asks only whether the variable matters, not its shape
N_PROBE_KNOTS = 5


@njit(cache=True)
def signed_sqrt(v):
    """sign(v) sqrt(|v|): an orifice's flow against its pressure drop."""
    return np.sign(v) * np.sqrt(np.abs(v))


@njit(cache=True)
def window(angle, stroke, k):
    """Smooth window ``k`` of :data:`N_WINDOWS` over the stroke [1]."""
    centre = (k + 0.5) / N_WINDOWS * stroke
    width = stroke / (2.0 * N_WINDOWS)
    return np.exp(-0.5 * ((angle - centre) / width) ** 2)


@njit(cache=True)
def _tent(share, n, k):
    """Basis function ``k`` of ``n`` piecewise-linear hats equally spaced over ``share`` from
    0 to 1 [1]: 1 at knot k, falling linearly to 0 at its neighbours; beyond the ends the end
    knots hold."""
    u = np.minimum(np.maximum(share, 0.0), 1.0) * (n - 1)
    return np.maximum(1.0 - np.abs(u - k), 0.0)


@njit(cache=True)
def hat(angle, stroke, k):
    """Basis function ``k`` of a piecewise-linear shape over the stroke [1]: knot k of
    :data:`N_KNOTS`, equally spaced from 0 to ``stroke`` (:func:`_tent`)."""
    return _tent(angle / stroke, N_KNOTS, k)


@njit(cache=True)
def knot(value, low, high, k):
    """Basis function ``k`` of a free function of one variable [1]: knot k of
    :data:`N_PROBE_KNOTS`, equally spaced from ``low`` to ``high`` (:func:`_tent`; a span
    that is not positive holds the first)."""
    return _tent((value - low) / np.maximum(high - low, 1e-30), N_PROBE_KNOTS, k)


@njit(cache=True)
def memory_direction(offset, width):
    """The command's direction from its distance to the memory state [1] (compiled)."""
    return min(max(offset / (0.5 * width), -1.0), 1.0)


@njit(cache=True)
def memory_rate(offset, width):
    """d(memory)/dt [V/s]: the memory follows the command outside its play band."""
    half = 0.5 * width
    return (offset - min(max(offset, -half), half)) / COMMAND_MEMORY_S
