"""Shape before formula: does a closed form fit what discovery found, or only a free shape?

Discovery writes a correction as a few terms of its vocabulary (:mod:`.discovery`). Where
the correction depends on the angle alone, a free shape over the stroke (the
piecewise-linear knots ``angle_shape_*`` of :mod:`pneumatic_servo.effects.terms`) is fitted
in the same equation through the simulator, from a linear start, with the same split,
residuals and free base parameters, and scored held out like every candidate. Then:

* the shape does not explain the held-out data clearly better than the closed form found
  (the candidate-level test of :func:`.status.clearly_better`): the closed form stands;
* it does: the shape proposes a formula. The best sets of one, two and three closed-form
  functions of the angle (the equation's screened terms in the angle alone: constant,
  angle, sine, cosine, windows) are fitted to the shape at the record's own angles (linear
  least squares, no simulation), each confirmed through the simulator, and the best by
  held-out BIC is kept. If the shape is not clearly better than that formula, the formula
  is the answer; else no closed form the search found fits, and the shape leads (the
  ladder, ``--apply`` and ``--emit-effect`` use it).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import combinations

import numpy as np

from ...effects.corrections import BY_EQUATION
from ...effects.terms import BY_NAME as TERMS
from ...effects.terms import term_values
from ...model.assembly import Model
from ...prediction.inputs import smoothed_signals
from .data import Data
from .discovery import (
    SCREEN_STEP,
    Discovered,
    ScreenedEquation,
    _key,
    _sensitivities,
    confirm,
    correction_host,
    terms_of,
)
from .interpret import describe_shape
from .scoring import information_criteria
from .status import clearly_better
from .trial import Trial
from .verdict import rank

#: the variable a free shape runs over
SHAPE_VARIABLE = 'angle'


@dataclass(frozen=True)
class ShapeCheck:
    """The free shape fitted beside the closed form found; the formula the shape proposes,
    where it fits clearly better than the closed form found; and whether it fits clearly
    better than each."""

    shape: Discovered
    closed_form: Discovered
    beats_closed_form: bool
    formula: Discovered | None = None
    beats_formula: bool = True

    @property
    def answer(self) -> Discovered:
        """What the diagnosis reports: the closed form found, the formula or the shape."""
        if not self.beats_closed_form:
            return self.closed_form
        return self.shape if self.formula is None or self.beats_formula else self.formula

    def words(self) -> str:
        """The statement the finding adds."""
        ours = f'{100 * self.shape.error_reduction:.0f} %'
        theirs = f'{100 * self.closed_form.error_reduction:.0f} %'
        if self.answer is self.closed_form:
            return (f'a free shape over the stroke explains no more ({ours} against '
                    f'{theirs}): the closed form stands')
        if self.answer is self.formula:
            return (f'a free shape over the stroke explains clearly more ({ours} against '
                    f'{theirs}), and a closed form fitted to that shape about as much '
                    f'({100 * self.formula.error_reduction:.0f} %): '
                    f'{self.formula.interpretation}')
        text = (f'no closed form the search found fits: a free shape over the stroke cuts the '
                f'held-out error by {ours} against {theirs}, clearly more '
                f'({self.shape.interpretation})')
        if self.formula is None:
            return text
        # the closest formula still says what most of the shape is (a gravity arm's cosine,
        # where something else that follows the angle rides on it)
        return (f'{text}; the closest closed form, fitted to that shape, cuts it by '
                f'{100 * self.formula.error_reduction:.0f} %: {self.formula.interpretation}')

    @property
    def corrections(self) -> list[Discovered]:
        """What the stage adds before the corrections found, best first: the answer, and
        the closest formula after a shape that beats it."""
        if self.answer is self.closed_form:
            return []
        if self.answer is self.shape and self.formula is not None:
            return [self.shape, self.formula]
        return [self.answer]


def shape_terms(equation: str) -> list[str]:
    """The knots of a free shape offered in ``equation`` (none: it has no shape stage)."""
    return [t.name for t in BY_EQUATION[equation].equation.terms
            if not t.screened and not t.probes]


def angle_functions(equation: str) -> list[str]:
    """The screened terms of ``equation`` that are functions of the angle alone (and the
    constant): the closed forms a shape over the stroke can propose."""
    return [t.name for t in BY_EQUATION[equation].equation.terms if t.screened
            and set(t.depends_on) <= {SHAPE_VARIABLE}]


def depends_on_angle_only(found: Discovered) -> bool:
    """Whether the leading term of ``found`` is a function of the angle alone."""
    return TERMS[found.leading].depends_on == [SHAPE_VARIABLE]


def fit_shape(trial: Trial, found: Discovered) -> ShapeCheck | None:
    """The free shape in the equation of ``found`` fitted, scored and compared with it, and
    the formula it proposes where it fits clearly better; None where the equation has no
    shape or ``found`` does not depend on the angle alone."""
    knots = shape_terms(found.equation)
    if not knots or not depends_on_angle_only(found):
        return None
    data, base = trial.data, trial.base
    host = correction_host(base.config)
    model = Model(host)
    keys = [_key(found.equation, k) for k in knots]
    start = _linear_start(model, host, keys, found.equation, data)
    shape = _confirmed(trial, host, model, found.equation, dict(zip(keys, start)))
    undetermined = {r for r, se in terms_of(shape.stderr).items() if se is None}
    shape = replace(shape, interpretation=describe_shape(found.equation, shape.terms,
                                                         base.config, undetermined))
    if not clearly_better(trial, shape, found):
        return ShapeCheck(shape, found, False)
    formula = _formula(trial, host, model, shape, undetermined)
    return ShapeCheck(shape, found, True, formula,
                      formula is None or clearly_better(trial, shape, formula))


def _confirmed(trial: Trial, host, model, equation: str, start: dict) -> Discovered:
    """``start`` (key -> value) fitted through the simulator, scored and ranked."""
    screened = ScreenedEquation(equation, list(start), start, 0.0)
    found = confirm(screened, host, model, trial.base, trial.data, list(trial.free),
                    trial.options)
    return rank([found], trial)[0]


def _formula(trial: Trial, host, model, shape: Discovered, undetermined: set
             ) -> Discovered | None:
    """The closed form the shape proposes: the best sets of one to ``max_terms`` functions
    of the angle fitted to the shape at the record's angles, each confirmed through the
    simulator; the best by held-out BIC."""
    names = angle_functions(shape.equation)
    angles = _angles(trial.data)
    known = [r for r in shape.terms if r not in undetermined]
    if not names or not known or not len(angles):
        return None
    core = trial.base.config.core
    target = term_values([TERMS[r] for r in known], {'angle_rad': angles}, core) \
        @ np.array([shape.terms[r] for r in known])
    F = term_values([TERMS[n] for n in names], {'angle_rad': angles}, core)
    out = []
    for size in range(1, trial.options.max_terms + 1):
        best = min(combinations(range(len(names)), size),
                   key=lambda cols: _lstsq(F[:, cols], target)[1])
        coef, _ = _lstsq(F[:, best], target)
        start = {_key(shape.equation, names[j]): float(c) for j, c in zip(best, coef)}
        out.append(_confirmed(trial, host, model, shape.equation, start))
    base_ms = trial.base.score.overall ** 2
    n_eff = float(trial.data.independent)
    return min(out, key=lambda d: information_criteria(base_ms, d.score.overall ** 2,
                                                      d.n_params, n_eff)[1])


def _lstsq(F: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    coef = np.linalg.lstsq(F, y, rcond=None)[0]
    r = y - F @ coef
    return coef, float(r @ r)


def _angles(data: Data) -> np.ndarray:
    """The measured angles [rad] of the fitted records (where the shape was learned)."""
    out = [smoothed_signals(e)['angle_rad'] for e in data.experiments
           if not e.static and 'angle_rad' in e.signals]
    out = np.concatenate(out) if out else np.zeros(0)
    return out[np.isfinite(out)]


def _linear_start(model, host, keys, equation: str, data: Data) -> list[float]:
    """Knot values from the linearised fit (one batch of sensitivities on the fitted part)."""
    size = BY_EQUATION[equation].equation.size
    steps = [SCREEN_STEP * size] * len(keys)
    r0, S = _sensitivities(model, host, keys, steps, data.fit)
    # a knot the record barely reaches has a weak column: it starts at zero, not at the huge
    # value a least-squares solve would give it from noise
    norms = np.linalg.norm(S, axis=0)
    seen = norms > 1e-2 * norms.max() if norms.max() > 0 else np.zeros(len(keys), bool)
    coef = np.zeros(len(keys))
    if seen.any():
        coef[seen] = np.linalg.lstsq(S[:, seen], -r0, rcond=None)[0]
    return [float(c) for c in coef]  # confirm clips them to the bounds
