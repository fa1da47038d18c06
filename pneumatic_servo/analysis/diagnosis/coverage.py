"""How far the records moved each variable a correction's dependence was tested on
(:mod:`.dependence`), and the record that would test it further: a variable the records
barely moved, or moved only with those the correction depends on, cannot be said, whatever
the correction depends on (closed-loop holds keep the chamber pressures within a few per
cent). ``synth.plan`` names the designs that would move it.
"""
from __future__ import annotations

import math

from ...effects.terms import PROBE_SPANS, PROBED
from ...effects.variables import RIG_RANGES
from ...prediction.inputs import smoothed_signals
from .discovered import Discovered

#: how a span in each SI unit of :data:`PROBED` is shown: (unit shown, factor from SI)
#: (the command, the one variable in volts, is read about the valve's null)
_SHOWN = {'rad': ('deg', 180.0 / math.pi), 'Pa': ('kPa abs', 1e-3),
          'V': ("V about the valve's null", 1.0)}


def span_words(variable: str, span: tuple[float, float]) -> str:
    """``span`` of ``variable`` in the units an engineer reads it in ('583 to 606 kPa abs')."""
    unit = next(u for v, _, u, _ in PROBED if v == variable)
    shown, factor = _SHOWN.get(unit, (unit, 1.0))
    return f'{span[0] * factor:.3g} to {span[1] * factor:.3g} {shown}'


def coverage(variable: str, width: float, core: dict) -> float | None:
    """The share [1] of the range a rig with ``core`` can move ``variable`` over
    (:data:`~pneumatic_servo.effects.variables.RIG_RANGES`) that a span ``width`` wide [SI]
    covers, at most 1; None for a variable without one."""
    if variable not in RIG_RANGES:
        return None
    low, high = RIG_RANGES[variable](core)
    return min(1.0, width / (high - low))


def moved_share(test, core: dict) -> float | None:
    """The share [1] of the rig's range over which the records moved the variable of
    ``test`` (a :class:`.dependence.DependenceTest`) apart from the variables the correction
    depends on (its span's share where that was not measured: ``apart`` is never wider than
    the span); None for a variable without a range."""
    width = test.span[1] - test.span[0] if test.apart is None else test.apart
    return coverage(test.variable, width, core)


def least_moved(found: Discovered):
    """Of the variables tried beside ``found`` and not said, the test (a
    :class:`.dependence.DependenceTest`) of the one the records moved over
    the smallest share of the rig's range apart from those it depends on (None where there
    is none): a record that moves it more would test it."""
    core = found.config.core
    shares = {t: moved_share(t, core) for t in found.dependence
              if not t.depends and t.span is not None}
    left = [t for t, share in shares.items() if share is not None]
    return min(left, key=shares.get) if left else None


def next_record(found: Discovered) -> str:
    """The record that would test further what ``found`` depends on, in a sentence ('' where
    no variable with a range was tried)."""
    test = least_moved(found)
    if test is None:
        return ''
    core = found.config.core
    share = coverage(test.variable, test.span[1] - test.span[0], core)
    apart = moved_share(test, core)
    reach = span_words(test.variable, RIG_RANGES[test.variable](core))
    moved = (f'These records moved {test.variable} over '
             f'{span_words(test.variable, test.span)}, {100 * share:.0f} % of the {reach} '
             'the rig can reach')
    if apart < share / 2:  # it moved, but with what the correction already depends on
        others = ' and '.join(test.apart_from)
        return (f'{moved}, and {100 * apart:.0f} % of it apart from {others}: a record '
                f'that moves {test.variable} apart from {others} would test whether the '
                f'correction depends on it (here p = {test.p_value:.2g}).')
    return (f'{moved}: a record that moves it over more of that range would test whether '
            f'the correction depends on it (here p = {test.p_value:.2g}).')


def records_of(experiments) -> list[dict]:
    """The time series among ``experiments``, smoothed, as the probed variables are read from
    them (:func:`~pneumatic_servo.effects.variables.array_namespace`)."""
    return [{**smoothed_signals(e), 't_s': e.t} for e in experiments if not e.static]


def variable_spans(spans: dict[str, float]) -> dict[str, tuple[float, float]]:
    """Per probed variable in the span parameters ``spans`` (:func:`.probe_spans`), its
    (least, largest) value over the records [SI]."""
    return {v: (spans[low.name], spans[high.name]) for v, (low, high) in PROBE_SPANS.items()
            if low.name in spans}
