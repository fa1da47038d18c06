"""The forward selection of discovery's screen (:mod:`.discovery`), linear in the screening
sensitivities: no simulation. Each route starts from a term refined through the simulator
and adds, on the fitted part alone, the column that best fits what is left; the held-out
sensitivities only pick where along a route to stop, so that only the columns some route
adds are simulated held out."""
from __future__ import annotations

import math

import numpy as np

from .scoring import BIC_TIE, information_criteria


def distinct(gram: np.ndarray, order: list[int], limit: float = 0.999) -> list[int]:
    """``order`` without the columns that are (nearly) parallel to an earlier one: over
    these data the two terms are the same (a constant supply is a constant), and the
    simpler one, first in the equation's terms, is kept. ``gram``: the sensitivities'
    Gram matrix ``S.T @ S``, formed once for every call (one product per call took seconds
    on a loaded machine)."""
    cols = sorted(order)
    gram = gram[np.ix_(cols, cols)]
    norms = np.sqrt(np.diag(gram))
    kept: list[int] = []
    for a in range(len(cols)):
        if norms[a] > 0 and np.all(np.abs(gram[a, kept]) < limit * norms[kept] * norms[a]):
            kept.append(a)
    chosen = {cols[a] for a in kept}
    return [j for j in order if j in chosen]


def first_term(lead, block, costs, base_val: float, n_eff: float) -> int | None:
    """The leading refined term of ``block``, or None: the simplest (first in the vocabulary)
    whose held-out BIC is within :data:`BIC_TIE` of the best (closer than that, the data do
    not tell them apart)."""
    bic = {j: information_criteria(base_val, float(lead[j][2] @ lead[j][2]), costs[j],
                                   n_eff)[1] for j in lead if j in block}
    if not bic:
        return None
    tie = min(bic.values()) + BIC_TIE
    return min(j for j, b in bic.items() if b <= tie)


def route(first: int, lead, S_fit, gram, block, costs, n_eff: float, max_terms: int
          ) -> tuple[list[int], list[float]]:
    """Forward selection from the refined term ``first``: each step adds the column of
    ``block`` (and its least-squares coefficient, linear in the screening slopes) that best
    fits the fitted part's residual, each column counting as ``costs[column]`` parameters
    (:attr:`Term.cost`), so a window or a product is added only where it fits clearly
    better than a plain term. (columns, coefficients): chosen on the fitted part alone, so
    that only the columns some route adds are simulated held out (:func:`best_prefix`).
    ``gram``: ``S_fit.T @ S_fit``."""
    c0, r_fit, _ = lead[first]
    cols, coef = [first], [c0]
    for _ in range(max_terms - 1):
        # each candidate's least-squares step on the fit residual, all at once
        cand = distinct(gram, [j for j in block if j not in cols])
        if not cand:
            break
        S = S_fit[:, cand]
        steps = -(S.T @ r_fit) / np.einsum('ij,ij->j', S, S)  # no zero column is distinct
        crit = (n_eff * np.log(np.maximum(np.sum((r_fit[:, None] + S * steps) ** 2, axis=0),
                                          1e-300))
                + np.array([costs[j] for j in cand]) * math.log(n_eff))
        best_k = int(np.argmin(crit))  # the first of a tie: the simplest
        j, d = cand[best_k], float(steps[best_k])
        cols, coef = cols + [j], coef + [d]
        r_fit = r_fit + S_fit[:, j] * d
    return cols, coef


def best_prefix(path, lead, S_val: dict, costs, base_val: float, n_eff: float):
    """The prefix of ``path`` (a :func:`route`) with the best held-out BIC: (columns,
    coefficients, held-out RSS, BIC). ``S_val``: held-out sensitivity of each added column."""
    cols, coef = path
    r_val = lead[cols[0]][2]
    best = None
    for k, (j, d) in enumerate(zip(cols, coef)):
        if k:
            r_val = r_val + S_val[j] * d
        rss = float(r_val @ r_val)
        bic = information_criteria(base_val, rss, sum(costs[i] for i in cols[:k + 1]),
                                   n_eff)[1]
        if best is None or bic < best[3]:
            best = (cols[:k + 1], np.array(coef[:k + 1]), rss, bic)
    return best


def routes(lead, S_fit, blocks, owns, costs, base_val: float, n_eff: float, max_terms: int
           ) -> dict:
    """Every route the selection of :func:`.discovery.screen_terms` may judge, by (first
    column, columns): from each equation's leading term over all its columns, over its plain
    ones (cost 1) and over a sensor's own (``owns``), and from each of its other refined
    terms."""
    out, gram = {}, S_fit.T @ S_fit
    for block, own in zip(blocks, owns):
        plain = [j for j in block if costs[j] == 1]
        starts = [(j, block) for j in sorted(lead) if j in block]
        starts += [(first_term(lead, cols, costs, base_val, n_eff), cols)
                   for cols in (plain, own) if cols]
        for j, columns in starts:
            if j is not None:
                out[j, tuple(columns)] = route(j, lead, S_fit, gram, columns, costs, n_eff,
                                               max_terms)
    return out
