"""When no named effect fits: find the equation, and the terms in it, where the missing
physics lives.

Every generic correction of :mod:`pneumatic_servo.effects.corrections` (one per
balance equation, input and measurement, each a linear combination of the terms
of :mod:`pneumatic_servo.effects.terms` offered there) is tried through the real
simulator, with the same split,
residuals and criteria as the named effects:

1. **Screen** (one batch): each (equation, term) coefficient is stepped
   once from zero; the change of the fitted and held-out residuals is its
   sensitivity. Per equation, a forward selection of at most ``max_terms``
   regressors fits the fit-part residual with these sensitivities (linear
   least squares) and keeps the subset with the best held-out information
   criterion. This is output-error sparse regression: it needs no derivative
   of noisy, quantised signals and no unmeasured gas temperature, which an
   equation-error regression would. A second batch screens, in the equations
   the first ranks best, the modulations of their leading term (that term
   times the angle, a pressure, the command, a window over the stroke ...:
   :func:`.terms.modulations`), so that what the correction depends on is
   more than the plainest term that carries an effect's mean.
2. **Confirm**: the best few equations are fitted in full (nonlinear, through
   the simulator, with the bases and effects that the named candidates refit)
   and scored on the held-out data; the result is a :class:`Discovered`
   candidate that the ranking treats like a named one. In a sensor's equation
   the set of its own reading's terms is confirmed too, and a set of another
   signal leads only where it explains clearly more.

The forward selection itself, linear in the sensitivities, is :mod:`.selection`.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ...effects.corrections import BY_EQUATION, EQUATIONS, coefficient_name
from ...effects.terms import BY_NAME as TERMS
from ...fitting import residual_rows, stack
from ...fitting.problem import with_values
from ...model.assembly import Model
from ...model.config import ModelConfig
from .candidates import Baseline, fit_parameters
from .data import Data
from .discovered import Discovered, terms_of  # noqa: F401 - where callers import it
from .hosts import shared_host
from .interpret import interpret
from .options import DiagnoseOptions
from .readings import alike, angle_span_deg, equivalent_lag_ms, simplest_best, term_spread
from .scoring import information_criteria, relative_fall, score_many
from .selection import best_prefix, distinct, first_term, routes

#: sensitivity step of a coefficient, as a share of its plausible size: large enough to step
#: over the roughness of stick-slip
SCREEN_STEP = 0.05
#: single terms of each equation refined through the simulator before the selection
LEADING_PER_EQUATION = 4
#: secant steps of each such term's coefficient at most (the second settles a friction's,
#: whose response bends sharply, to within a few per cent) ...
SECANT_STEPS = 2
#: ... while a step moves it by more than this share
SETTLED = 0.1


def correction_host(config: ModelConfig) -> ModelConfig:
    """``config`` on its shared host plus every generic correction at zero (one compiled
    composition for the whole discovery)."""
    host = shared_host(config)
    for cls_ in BY_EQUATION.values():
        if cls_.name not in host.effects:
            host = host.with_effect(cls_.name, cls_.neutral)
    return host


def _key(equation: str, regressor: str) -> str:
    return f'{BY_EQUATION[equation].name}.{coefficient_name(regressor)}'


@dataclass(frozen=True)
class ScreenedEquation:
    """One equation after the linear screen: its best regressors and their coefficients [SI],
    and the held-out error reduction the linearisation predicts."""

    equation: str
    keys: list[str]
    start: dict[str, float]
    reduction: float
    bic: float = field(default=0.0)
    #: the best set of plain terms (cost 1 each), where the best set holds a window, a
    #: product or a memory: the linear screen's small steps can favour those, so both are
    #: fitted through the simulator and the better kept
    plain: ScreenedEquation | None = None
    #: the best set reached from another leading term, where it differs: two terms that fit
    #: only together (a level and a slope that cancel over the record) are not reached from
    #: the term that fits best alone; fitted through the simulator, it replaces the set
    #: above only where it explains clearly more (a marginal gain picks spurious sets)
    other: ScreenedEquation | None = None
    #: the elaboration of a plain leading term (a product of its variables with others,
    #: :func:`_elaborations`) that the screen found closer held out, before its extra cost:
    #: a friction that grows with the load |p_a - p_b| reads, where the load drives the
    #: motion, as a smaller piston torque; both are fitted through the simulator, and where
    #: they are not told apart both are said (:func:`alike`)
    richer: ScreenedEquation | None = None
    #: the best set of a sensor's own terms (:attr:`.corrections.Equation.own`), where the
    #: best set holds another variable: fitted through the simulator, the other leads only
    #: where it explains clearly more
    own: ScreenedEquation | None = None


def _residuals(model, host, keys, values, parts) -> list[np.ndarray]:
    """Residual vectors over ``parts`` of ``host`` with each key set to its value (one batch,
    one configuration per key), each from its own start states: started from ``host``'s
    instead (one lead-in per window, not per column, a quarter of the screen's simulation),
    the screen ranked differently and six studies failed (``docs/diagnosis.md``)."""
    if not keys:
        return []
    configs = [with_values(host, [k], [v]) for k, v in zip(keys, values)]
    return [stack(r) for r in residual_rows(model, parts, configs)]


def _sensitivities(model, host, keys, steps, parts) -> tuple[np.ndarray, np.ndarray]:
    """(residual at zero, sensitivity matrix) over ``parts``: one batch."""
    r0 = stack(residual_rows(model, parts, [host])[0])
    return r0, _slopes(model, host, keys, steps, r0, parts)


def _slopes(model, host, keys, steps, r0, parts) -> np.ndarray:
    """(rows, len(keys)) sensitivities over ``parts`` of the residual ``r0`` at zero: one
    batch."""
    rows = _residuals(model, host, keys, steps, parts)
    return np.column_stack([(r - r0) / h for r, h in zip(rows, steps)] or
                           [np.zeros((len(r0), 0))])


def _slope_fit(r: np.ndarray, s: np.ndarray) -> float:
    """Least-squares coefficient c of r + s c = 0."""
    ss = float(s @ s)
    return -float(s @ r) / ss if ss > 0 else 0.0


def _leading_terms(model, host, keys, terms, r_fit, S_fit, data, blocks, owns,
                   per_equation: int):
    """The best single term of each equation, refined through the simulator.

    The screening slope is taken at a small step; an effect of plausible size
    is well beyond it, where the response bends (friction that switches with the
    direction of motion bends it most). The few best terms of each equation by the
    linear fit, and their elaborations (:func:`_elaborations`), are evaluated
    at their estimate and moved by up to :data:`SECANT_STEPS` secant steps from there,
    while they move by more than :data:`SETTLED`; the last estimate is evaluated on the
    fitted and the held-out parts (one batch per step, one more held out).

    ``owns``: per block, its columns of a sensor's own terms, whose best is refined too.

    Returns, per candidate column: (coefficient, fit residual, held-out residual).
    """
    cols = []
    gram = S_fit.T @ S_fit
    for block, own in zip(blocks, owns):
        rss = {j: float(np.sum((r_fit + S_fit[:, j] * _slope_fit(r_fit, S_fit[:, j])) ** 2))
               for j in block if np.any(S_fit[:, j])}
        best = distinct(gram, sorted(rss, key=rss.get))[:per_equation]
        if own and not set(best) & set(own):
            best += sorted((j for j in own if j in rss), key=rss.get)[:1]
        more = [j for i in best for j in _elaborations(i, block, terms) if j not in best]
        cols += best + list(dict.fromkeys(more))
    bounds = [(host.param(keys[j]).lower, host.param(keys[j]).upper) for j in cols]
    coef = [float(np.clip(_slope_fit(r_fit, S_fit[:, j]), *b)) for j, b in zip(cols, bounds)]
    before = [(0.0, r_fit)] * len(cols)
    at_fit = _residuals(model, host, [keys[j] for j in cols], coef, data.fit)
    moving = list(range(len(cols)))
    for _ in range(SECANT_STEPS):
        step = {i: _secant(coef[i], at_fit[i], *before[i], *bounds[i]) for i in moving}
        for i, r in zip(moving, _residuals(model, host, [keys[cols[i]] for i in moving],
                                           [step[i] for i in moving], data.fit)):
            before[i], coef[i], at_fit[i] = (coef[i], at_fit[i]), step[i], r
        # a coefficient that has settled stays: another step would only move it within
        # the simulation's roughness
        moving = [i for i in moving if abs(coef[i] - before[i][0]) > SETTLED * abs(coef[i])]
    at_val = _residuals(model, host, [keys[j] for j in cols], coef, data.screen_val)
    return {j: (c, rf, rv) for j, c, rf, rv in zip(cols, coef, at_fit, at_val)}


def _elaborations(lead: int, block: list[int], terms) -> list[int]:
    """The columns of ``block`` that elaborate term ``lead``: a product of the variables it
    depends on with others (:attr:`Term.cost` > 1). The small steps of the linear screen
    misjudge these most: a friction that grows with pressure ranks far below plain
    Coulomb friction there, and clearly above it once refined."""
    seed = set(terms[lead].depends_on)
    return [j for j in block if terms[j].cost > 1 and seed and seed < set(terms[j].depends_on)]


def _richer(lead, first: int, block: list[int], terms, costs, base_val: float,
            n_eff: float) -> tuple:
    """The refined elaboration of term ``first`` that leaves less held out than it (as a
    path: columns, coefficients, held-out RSS, BIC), or an empty path."""
    def rss(j):
        return float(lead[j][2] @ lead[j][2])
    closer = [j for j in _elaborations(first, block, terms) if j in lead and rss(j) < rss(first)]
    if not closer:
        return [], np.zeros(0), base_val, 0.0
    j = min(closer, key=rss)
    return ([j], np.array([lead[j][0]]), rss(j),
            information_criteria(base_val, rss(j), costs[j], n_eff)[1])


def _secant(c, r, c0, r0, lower, upper) -> float:
    """The coefficient one secant step on from ``c`` (residual ``r``), through the earlier
    point ``c0`` (``r0``), within its bounds."""
    if c == c0:
        return c
    return float(np.clip(c + _slope_fit(r, (r - r0) / (c - c0)), lower, upper))


def seen_equations(data: Data) -> list:
    """The equations the records can tell apart: those whose needed signals (a chamber's
    temperature for its energy balance) every time series of ``data`` holds."""
    series = [e for e in data.experiments if not e.static]
    return [eq for eq in EQUATIONS if not eq.needs or (bool(series) and all(
        signal in e.signals for e in series for signal in eq.needs))]


def screen_terms(base: Baseline, data: Data, n_eff: float, options: DiagnoseOptions
                 ) -> tuple[list[ScreenedEquation], ModelConfig, Model]:
    """The screen of every equation, best first, with the host it ran on."""
    host = correction_host(base.config)
    model = Model(host)
    keys, terms, steps, costs, blocks = [], [], [], [], []
    equations = seen_equations(data)

    def add(eq, chosen, block):
        """Append the columns of ``chosen`` terms of ``eq`` to ``block``."""
        block += range(len(keys), len(keys) + len(chosen))
        for term in chosen:
            keys.append(_key(eq.name, term.name))
            terms.append(term)
            steps.append(SCREEN_STEP * eq.size / term.typical)
            costs.append(term.cost)
    for eq in equations:
        blocks.append([])
        add(eq, [t for t in eq.terms if t.screened and not t.modulates], blocks[-1])
    own_terms = [{t.name for t in eq.own} for eq in equations]

    def owns():
        """Per block, its columns of a sensor's own terms."""
        return [[j for j in block if terms[j].name in own]
                for block, own in zip(blocks, own_terms)]
    r_fit, S_fit = _sensitivities(model, host, keys, steps, data.fit)
    r_val = stack(residual_rows(model, data.screen_val, [host])[0])
    lead = _leading_terms(model, host, keys, terms, r_fit, S_fit, data, blocks, owns(),
                          LEADING_PER_EQUATION)
    base_val = float(r_val @ r_val)
    # the second batch: the modulations of the leading term of each of the equations the
    # first ranks best (what its size varies with: a flow force on the spool is the
    # command's, growing with the pressure drop), linear in their screening slopes
    firsts = {i: first_term(lead, block, costs, base_val, n_eff)
              for i, block in enumerate(blocks)}
    ranked = sorted((i for i in firsts if firsts[i] is not None), key=lambda i: float(
        lead[firsts[i]][2] @ lead[firsts[i]][2]))[:options.discovery_fits]
    start = len(keys)
    for i in ranked:
        add(equations[i], [t for t in equations[i].terms
                           if t.modulates == terms[firsts[i]].name], blocks[i])
    S_fit = np.column_stack([S_fit, _slopes(model, host, keys[start:], steps[start:], r_fit,
                                            data.fit)])
    owned = owns()  # with the modulations just added
    routed = routes(lead, S_fit, blocks, owned, costs, base_val, n_eff, options.max_terms)
    # held out, only the columns some route adds (about a fifth of them): one batch
    added = sorted({j for cols, _ in routed.values() for j in cols[1:]})
    S_val = dict(zip(added, _slopes(model, host, [keys[j] for j in added],
                                    [steps[j] for j in added], r_val, data.screen_val).T))
    out = []
    for eq, block, own in zip(equations, blocks, owned):
        def screened(path):
            """The path (columns, coefficients, held-out RSS, BIC) as a screened equation."""
            cols, coef, rss, bic = path
            chosen = [keys[j] for j in cols]
            return ScreenedEquation(
                eq.name, chosen, dict(zip(chosen, map(float, coef))),
                relative_fall(math.sqrt(rss), math.sqrt(base_val)), bic) if cols else None

        def select(columns):
            """The best prefix of the route from the leading term of ``columns``, or an
            empty path if they hold none."""
            first = first_term(lead, columns, costs, base_val, n_eff)
            return ([], np.zeros(0), base_val, 0.0) if first is None else best_prefix(
                routed[first, tuple(columns)], lead, S_val, costs, base_val, n_eff)
        path = select(block)
        best = screened(path)
        if best is None:
            continue
        if any(TERMS[t].cost > 1 for t in terms_of(best.start)):
            best = replace(best, plain=screened(select([j for j in block if costs[j] == 1])))
        # a plain first term's refined elaboration, whatever the path added to it (a
        # modulation of it, linear in the screen, can stand where the refined product fits)
        if costs[path[0][0]] == 1:
            best = replace(best, richer=screened(_richer(lead, path[0][0], block, terms,
                                                         costs, base_val, n_eff)))
        # the best route from another leading term, where it differs
        others = [best_prefix(routed[j, tuple(block)], lead, S_val, costs, base_val, n_eff)
                  for j in sorted(lead) if j in block and j != path[0][0]]
        other = min(others, key=lambda p: p[3]) if others else None
        if other is not None and set(other[0]) != set(path[0]):
            best = replace(best, other=screened(other))
        if own and not set(path[0]) <= set(own):
            best = replace(best, own=screened(select(own)))
        out.append(best)
    return sorted(out, key=lambda s: s.bic), host, model


def confirm(screened: ScreenedEquation, host: ModelConfig, model: Model, base: Baseline,
            data: Data,
            free: list[str], options: DiagnoseOptions) -> Discovered:
    """Fit the screened terms in full through the simulator and score them held out."""
    t0 = time.perf_counter()
    name = BY_EQUATION[screened.equation].name
    keys = screened.keys
    start = {k: float(np.clip(v, host.param(k).lower, host.param(k).upper))
             for k, v in screened.start.items()}
    start_cfg = with_values(host, list(start), list(start.values()))
    result = fit_parameters(model, start_cfg, keys + [k for k in free if k not in keys], data,
                            options, bracket=False)
    score = score_many(model, data, [result.config])[0]
    values = {k: result.config.get(k) for k in keys}
    base_values = {k: result.config.get(k) for k in free}
    clean = with_values(base.config, list(base_values), list(base_values.values()))
    clean = clean.with_effect(name, {k.partition('.')[2]: v for k, v in values.items()})
    problems = [f'{k} stopped at a bound of its fit range' for k in result.at_bound
                if k in values]
    sizes, shares = term_spread(terms_of(values), data, base.config.core)
    found = Discovered(
        effect=name, params=values, stderr={k: result.stderr[k] for k in keys}, fixed={},
        base_params=base_values, score=score,
        error_reduction=relative_fall(score.overall, base.score.overall),
        channel_reduction={ch: relative_fall(v, base.score.channels.get(ch, 0.0))
                           for ch, v in score.channels.items()},
        n_params=sum(TERMS[t].cost for t in terms_of(values)), problems=problems,
        config=clean, correlation=result.correlation,
        converged=result.converged, seconds=time.perf_counter() - t0,
        acts_on=BY_EQUATION[screened.equation].acts_on,
        summary=BY_EQUATION[screened.equation].equation.description,
        equation=screened.equation, screened_reduction=screened.reduction, sizes=sizes,
        shares=shares,
        interpretation=interpret(screened.equation, terms_of(values), base.config, shares,
                                 equivalent_lag_ms(screened.equation, terms_of(values), data,
                                                   base.config.core), angle_span_deg(data)))
    return found


def discover(base: Baseline, data: Data, free: list[str], n_eff: float,
             options: DiagnoseOptions, clearly_better=None) -> list[Discovered]:
    """Generic corrections of the baseline, screened and the best ``discovery_fits``
    confirmed; unranked (the ranking fills in the information criteria).
    ``clearly_better(d, c)``: whether correction d explains clearly more than c (the
    candidate-level test), for the set reached from another start."""
    screened, host, model = screen_terms(base, data, n_eff, options)
    out = []
    for s in screened[:options.discovery_fits]:
        found = [confirm(c, host, model, base, data, free, options)
                 for c in (s, s.plain, s.richer) if c is not None]
        best = simplest_best(found, base, n_eff)
        if s.other is not None and clearly_better is not None:
            other = confirm(s.other, host, model, base, data, free, options)
            # the set from another start leads where it explains clearly more, or where it
            # is simpler and the better fit does not beat it clearly (a gauge transmitter's
            # gain error read as a level plus a crosstalk of the command); only then is it
            # weighed against the others (said beside it, it gave spurious readings)
            if clearly_better(other, best) or (other.n_params < best.n_params
                                               and not clearly_better(best, other)):
                best = other
                found.append(other)
        if s.own is not None and clearly_better is not None:
            own = confirm(s.own, host, model, base, data, free, options)
            # a sensor's error is its own reading's unless another explains clearly more
            if not clearly_better(best, own):
                best = own
                found.append(own)
        out.append(alike(found, base, n_eff, best))
    return out
