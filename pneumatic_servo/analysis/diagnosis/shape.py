"""Shape before formula: does a closed form fit what discovery found, or only a free shape?

Discovery writes a correction as a few terms of its vocabulary (:mod:`.discovery`). Where
the correction depends on the angle alone, a free shape over the stroke (the
piecewise-linear knots ``angle_shape_*`` of :mod:`pneumatic_servo.effects.terms`) is fitted
in the same equation through the simulator, from a linear start, with the same split,
residuals and free base parameters, and scored held out like every candidate. Then:

* the shape explains the held-out data **clearly better** than the closed form (the
  candidate-level test of :func:`.status.clearly_better`): no closed form in the vocabulary
  fits; the shape becomes the first discovered correction, so the ladder, ``--apply`` and
  ``--emit-effect`` use it;
* otherwise the closed form stands: a free shape over the stroke explains no more.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...effects.corrections import BY_EQUATION
from ...effects.terms import BY_NAME as TERMS
from ...model.assembly import Model
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
from .interpret import describe_shape, leading
from .status import clearly_better
from .trial import Trial
from .verdict import rank

#: the variable a free shape runs over
SHAPE_VARIABLE = 'angle'


@dataclass(frozen=True)
class ShapeCheck:
    """The free shape fitted beside a closed form, and whether it fits clearly better."""

    shape: Discovered
    closed_form: Discovered
    no_closed_form: bool

    def words(self) -> str:
        """The statement the finding adds."""
        if self.no_closed_form:
            return (f'no closed form in the vocabulary fits: a free shape over the stroke '
                    f'cuts the held-out error by {100 * self.shape.error_reduction:.0f} % '
                    f'against {100 * self.closed_form.error_reduction:.0f} %, clearly more '
                    f'({self.shape.interpretation})')
        return (f'a free shape over the stroke explains no more '
                f'({100 * self.shape.error_reduction:.0f} % against '
                f'{100 * self.closed_form.error_reduction:.0f} %): the closed form stands')


def shape_terms(equation: str) -> list[str]:
    """The knots of a free shape offered in ``equation`` (none: it has no shape stage)."""
    return [t.name for t in BY_EQUATION[equation].equation.terms if not t.screened]


def depends_on_angle_only(found: Discovered) -> bool:
    """Whether the leading term of ``found`` is a function of the angle alone."""
    used = set(TERMS[leading(found.terms)].variables) - {'stroke'}
    return used == {SHAPE_VARIABLE}


def fit_shape(trial: Trial, found: Discovered) -> ShapeCheck | None:
    """The free shape in the equation of ``found`` fitted, scored and compared with it; None
    where the equation has no shape or ``found`` does not depend on the angle alone."""
    knots = shape_terms(found.equation)
    if not knots or not depends_on_angle_only(found):
        return None
    data, base = trial.data, trial.base
    host = correction_host(base.config)
    model = Model(host)
    keys = [_key(found.equation, k) for k in knots]
    start = _linear_start(model, host, keys, found.equation, data)
    screened = ScreenedEquation(found.equation, keys, dict(zip(keys, start)), 0.0)
    shape = confirm(screened, host, model, base, data, list(trial.free), trial.options)
    undetermined = {r for r, se in terms_of(shape.stderr).items() if se is None}
    shape = replace(shape, interpretation=describe_shape(found.equation, shape.terms,
                                                         base.config, undetermined))
    shape = rank([shape], trial)[0]
    return ShapeCheck(shape, found, clearly_better(trial, shape, found))


def _linear_start(model, host, keys, equation: str, data: Data) -> list[float]:
    """Knot values from the linearised fit (one batch of sensitivities on the fitted part)."""
    size = BY_EQUATION[equation].equation.size
    steps = [SCREEN_STEP * size] * len(keys)
    r0, S = _sensitivities(model, host, keys, steps, data.fit)
    coef = np.linalg.lstsq(S, -r0, rcond=None)[0]
    return [float(np.clip(c, host.param(k).lower, host.param(k).upper))
            for c, k in zip(coef, keys)]
