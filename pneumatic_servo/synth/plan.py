"""The record to make next: the experiment designs (:mod:`.designs`) that would test further
what a discovered correction depends on, each simulated on the fitted model.

The dependence test names the variable tried beside a correction that the records moved
least, apart from the variables the correction already depends on
(:func:`~pneumatic_servo.analysis.diagnosis.coverage.least_moved`). Which record would move
it more is not plain: a four-way valve moves p_a and p_b together through a sine, and a held
piston moves them apart but shows no torque. So each time-series design of a circuit in which
the correction's equation acts is run on the fitted model (the correction in it), through
the design's own sensors, and its record is read as the test reads the user's: the share of
the rig's range over which it moves the variable apart from the others
(:func:`~pneumatic_servo.effects.variables.apart_span`).

The share is a simulation's, of the model as fitted: how far such a record would move the
variable, not that the test will then say the correction depends on it.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..analysis.diagnosis.coverage import coverage, least_moved, moved_share, records_of
from ..analysis.diagnosis.discovered import Discovered
from ..effects.corrections import BY_EQUATION
from ..effects.variables import apart_span
from ..errors import SimulationError
from ..model.assembly import Model
from .designs import DESIGNS, make_experiment

#: designs shown, best first
SHOWN = 3
#: [1] the share of the rig's range by which a design must move the variable further than
#: the records did to be shown: one that moves it a little further tests it little better
#: (on held-out set 11 a mixed closed-loop run was the best for p_b, at 36 % of the range
#: where the records had 35)
GAIN = 0.1


@dataclass(frozen=True)
class NextDesign:
    """A design and the share [1] of the rig's range of ``variable`` over which, simulated on
    the fitted model, it moves the variable apart from ``apart_from``; ``now``: the share the
    diagnosed records moved it over."""

    design: str
    summary: str
    variable: str
    apart_from: tuple[str, ...]
    share: float
    now: float

    def words(self) -> str:
        apart = f' apart from {" and ".join(self.apart_from)}' if self.apart_from else ''
        return (f'{self.design} would move {self.variable}{apart} over {100 * self.share:.0f} '
                f'% of the rig\'s range on the fitted model (these records: '
                f'{100 * self.now:.0f} %): {self.summary}')

    def to_json(self) -> dict:
        return {'design': self.design, 'summary': self.summary, 'variable': self.variable,
                'apart_from': list(self.apart_from), 'share': self.share, 'now': self.now}


def next_designs(found: Discovered, seed: int = 0) -> list[NextDesign]:
    """The designs that would move the variable :func:`least_moved` names for ``found``
    over at least :data:`GAIN` more of the rig's range than the diagnosed records did, best
    first (at most :data:`SHOWN`; none where no variable with a range was tried). A design
    the fitted model cannot run is left out."""
    test = least_moved(found)
    if test is None:
        return []
    core = found.config.core
    now = moved_share(test, core)
    model = Model(found.config)
    circuits = BY_EQUATION[found.equation].equation.circuits
    out = []
    for name, design in DESIGNS.items():
        if design.static or design.circuit not in circuits:
            continue
        try:
            record = make_experiment(found.config, name, seed, model=model)
        except SimulationError:  # a fitted model outside what a design can drive
            continue
        span = apart_span(records_of([record]), core, test.variable, list(test.apart_from))
        share = None if span is None else coverage(test.variable, span, core)
        if share is not None and share >= now + GAIN:
            out.append(NextDesign(name, design.summary, test.variable, test.apart_from,
                                  share, now))
    return sorted(out, key=lambda d: -d.share)[:SHOWN]
