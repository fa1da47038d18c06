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

Before a generic correction is compared with a named effect at all, the named effect's own
fit is restarted either side of its values (:func:`restarted`): on the rough cost the
polish stops in a local minimum, and those lie a few per cent apart (a load torque's at
0.1727, 0.1771 and 0.1830 N.m, costs 19.2, 17.0 and 18.5, where the bracket had landed on
the last). A generic correction fitted from another start must not win on a minimum the
named effect simply missed.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import SimulationError
from ...fitting.problem import with_values
from ...model.assembly import Model
from .candidates import Candidate, fit_parameters, placed, screen_effect, try_effect
from .criteria import Departures
from .floor import replica_data
from .hosts import fitted_on
from .scoring import score_many
from .status import best_generic, clearly_better

#: whole replicas refitted: each costs one candidate fit
REFITS = 3
#: relative steps either side of each fitted value a named effect's fit restarts from
#: (the stick-slip cost's local minima lie a few per cent apart)
RESTART_STEPS = (-0.03, 0.03)


def restarted(trial, cand: Candidate) -> Candidate:
    """Named effect ``cand`` with its fit polished again from starts either side of each
    fitted value (:data:`RESTART_STEPS`), where one lands lower on the fit parts' cost than
    its own values polished again; else ``cand`` itself."""
    screen = placed(cand.effect, trial.base, cand.params)
    keys = list(cand.params)
    free = list(trial.free)

    def landing(values: dict) -> tuple[float, dict]:
        host = with_values(screen.host, list(values), list(values.values()))
        fit = fit_parameters(screen.model, host, keys + [k for k in free if k not in keys],
                             trial.data, trial.options, bracket=False)
        return fit.cost, {k: fit.config.get(k) for k in keys}

    own_cost, _ = landing(cand.params)
    starts = [{**cand.params, k: float(np.clip(v * (1.0 + s), screen.host.param(k).lower,
                                                screen.host.param(k).upper))}
              for k, v in cand.params.items() for s in RESTART_STEPS if v != 0.0]
    cost, best = min((landing(start) for start in starts), key=lambda c: c[0],
                     default=(own_cost, None))
    if best is None or cost >= own_cost:
        return cand
    return try_effect(replace(screen, start=best), trial.base, trial.data, free,
                      trial.options, bracket=False)


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
