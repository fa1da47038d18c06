"""Which fitted parameters, and which combinations of them, the data do not determine.

From the Jacobian of the normalised residual at the solution, each column
scaled by its parameter's scale and then to unit length (so that only
directions count, not units):

* a column of (near) zero: the residual does not depend on that parameter at all
  (the part it belongs to is not in these records);
* a singular value far below the largest: moving the parameters along its
  singular vector leaves the residual unchanged, so only the orthogonal
  combination is determined. Two parameters that enter only as a sum or only as
  a product are named as such.

Undetermined parameters get no standard error and do not count as fitted.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: a column whose norm is below this share of the largest is not seen by the data
ZERO_COLUMN = 1e-9
#: a singular value below this share of the largest marks a direction the data do not see
#: (two unit columns at 0.6 deg from each other; a correlation above 0.99995)
NULL_DIRECTION = 1e-2
#: components of a null direction larger than this take part in the combination
PART_OF = 0.1


@dataclass
class Combination:
    """Parameters of which only one combination is determined: ``kind`` 'sum' (their sum),
    'product' (their product) or 'linear' (the combination ``weights`` [SI] of
    ``keys`` is determined only up to the null direction)."""

    keys: list[str]
    kind: str
    null_direction: list[float]

    def text(self) -> str:
        names = [k.partition('.')[2] or k for k in self.keys]
        if self.kind == 'sum':
            return f'only {" + ".join(names)} is determined'
        if self.kind == 'product':
            return f'only {" x ".join(names)} is determined'
        return f'only a combination of {", ".join(names)} is determined'


@dataclass
class Identifiability:
    """What the data determine: the rank (determined directions), the parameters the
    residual does not depend on, and the combinations of which only one is determined."""

    rank: int
    unused: list[str] = field(default_factory=list)
    combinations: list[Combination] = field(default_factory=list)

    @property
    def undetermined(self) -> list[str]:
        return self.unused + [k for c in self.combinations for k in c.keys]

    def reason(self, key: str) -> str | None:
        """Why ``key`` is not determined (None if it is)."""
        if key in self.unused:
            return 'the data do not depend on it'
        for c in self.combinations:
            if key in c.keys:
                return c.text()
        return None


def _kind(keys_x: np.ndarray, direction: np.ndarray) -> str:
    """'sum', 'product' or 'linear' for a two-parameter null direction in raw units."""
    if len(direction) != 2:
        return 'linear'
    a, b = direction
    if abs(a + b) <= 0.05 * max(abs(a), abs(b)):
        return 'sum'
    xa, xb = keys_x
    if xa and xb and abs(a / xa + b / xb) <= 0.05 * max(abs(a / xa), abs(b / xb)):
        return 'product'
    return 'linear'


def identifiability(keys: list[str], x: np.ndarray, jac: np.ndarray, scale: np.ndarray
                    ) -> Identifiability:
    """The identifiability of ``keys`` at values ``x`` [SI] from the Jacobian ``jac``
    (residuals x parameters) and the parameters' ``scale`` [SI]."""
    js = jac * scale
    norms = np.linalg.norm(js, axis=0)
    top = norms.max() if norms.size else 0.0
    seen = norms > ZERO_COLUMN * top if top > 0 else np.zeros(len(keys), bool)
    unused = [k for k, ok in zip(keys, seen) if not ok]
    idx = np.flatnonzero(seen)
    out = Identifiability(rank=0, unused=unused)
    if not len(idx):
        return out
    _, sv, vt = np.linalg.svd(js[:, idx] / norms[idx], full_matrices=False)
    null = sv < NULL_DIRECTION * sv[0]
    out.rank = int(np.sum(~null))
    for v in vt[null]:
        part = np.flatnonzero(np.abs(v) > PART_OF)
        if len(part) < 2:
            continue
        cols = idx[part]
        raw = v[part] / norms[cols] * scale[cols]  # the null direction in SI units
        out.combinations.append(Combination([keys[i] for i in cols],
                                            _kind(x[cols], raw), [float(r) for r in raw]))
    return out
