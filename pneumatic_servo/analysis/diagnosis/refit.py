"""The fit's own scatter in the floor of a named effect.

The floor's replicas (:mod:`.floor`) score the fitted values as they are. But a named
effect's values were fitted to this very record, and where stick-slip makes the fit cost
rough (its jumps are as large as the fall towards the minimum) they land 10-20 % from the
truth, far beyond their standard errors, and the held-out angle feels it. Judged against a
floor without that scatter, a whole answer reads as a departure: a leak of 0.4 x the example
size, fitted 8 % and 16 % off, left the angle 1.9 x its floor, while the true values left
1.2 x.

So where what an effect leaves departs, or a generic correction fits clearly better than
the effect (:func:`.status.clearly_better` then asks for more than the fit's scatter), a
parametric bootstrap with refit decides: whole replicas of the record (fitted and held-out
parts) are simulated with the fitted model, the effect is screened and fitted on each
exactly as on the record, and the held-out mean square of the refitted values is compared
with that of the values the replica came from. The mean log ratio raises the floor and
their variance widens it (:meth:`.floor.Floor.with_refits`).

The bootstrap starts from the fitted values, and so cannot show a fit that stopped near its
own start far from the truth: such a record stays ``unexplained``, with the effect listed
as a partial fit (``docs/diagnosis.md``, the 0.7 x leak of the power study).
"""
from __future__ import annotations

import math

import numpy as np

from ...errors import SimulationError
from ...model.assembly import Model
from .candidates import Candidate, screen_effect, try_effect
from .criteria import Departures
from .floor import replica_data
from .hosts import fitted_on
from .scoring import score_many
from .status import best_generic, clearly_better

#: whole replicas refitted: each costs one candidate fit
REFITS = 3


def refit_log_ratios(trial, cand: Candidate, count: int = REFITS) -> dict[str, np.ndarray]:
    """Channel (and ``'overall'``) -> log ratios of the held-out mean square of ``cand``
    refitted on each of ``count`` whole replicas to that of ``cand`` itself there."""
    host = fitted_on(trial.base.config, cand.config)
    model = Model(host)
    rng = np.random.default_rng(trial.options.seed + 1)
    out: dict[str, list[float]] = {}
    for _ in range(count):
        data = replica_data(model, host, trial.data, rng)
        screen = screen_effect(cand.effect, trial.base, data)
        try:
            refitted = try_effect(screen, trial.base, data, list(trial.free),
                                  trial.options).score
        except SimulationError:
            continue  # a replica the effect cannot be simulated on adds no scatter
        truth = score_many(model, data, [host])[0]
        for ch in (*truth.channels, None):
            ratio = refitted.mean_square(ch) / max(truth.mean_square(ch), 1e-300)
            out.setdefault(ch or 'overall', []).append(math.log(max(ratio, 1e-300)))
    return {k: np.array(v) for k, v in out.items()}


def remainder(trial, cand: Candidate, discovered=()) -> Departures:
    """What named effect ``cand`` leaves, against its own model's floor; where it departs, or
    where a generic correction of ``discovered`` fits clearly better, against that floor
    with the fit's scatter added (:data:`REFITS` refits): a whole answer does not depart
    from it, and a generic correction must beat the named effect by more than that scatter
    (:func:`.status.clearly_better`)."""
    floor = trial.floor_of(cand.config)
    left = trial.departures(cand.score, floor)
    found = best_generic(trial, list(discovered))
    if left.departs or (found is not None and clearly_better(trial, found, cand)):
        floor = floor.with_refits(refit_log_ratios(trial, cand))
        left = trial.departures(cand.score, floor)
    return left
