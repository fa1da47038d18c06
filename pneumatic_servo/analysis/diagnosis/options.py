"""How diagnosis fits and scores candidate effects: the options and their defaults."""
from __future__ import annotations

from dataclasses import dataclass, fields

from ...prediction import DIAGNOSIS_HORIZON_S

#: a fall of the held-out residual below this fraction never names an effect
MIN_REDUCTION = 0.2
#: information-criterion gain (BIC, lower is better) an effect must reach
MIN_DELTA_BIC = -10.0
#: an effect must explain a held-out error this many times the sensor noise (as it is
#: left in the smoothed residual)
MIN_NOISE_RATIO = 3.0
#: two candidates whose held-out residuals differ by less than this fraction explain
#: the data about equally
AMBIGUITY = 0.05


@dataclass
class DiagnoseOptions:
    """How candidates are fitted and scored.

    Attributes
    ----------
    horizon_s : float [s]
        Length of the prediction segments, each started from the measured
        state (k-step-ahead prediction).
    lead_s : float [s]
        Lead-in simulated before each segment to estimate the states that
        are not measured (gas temperatures, effect states).
    smooth_s : float [s]
        Width of the centred moving average applied to time-series residuals.
    blocks : int
        Each time series is cut into this many blocks, alternately used for
        fitting and for validation.
    decimate : int
        Keep every n-th sample (command averaged over the n) when fitting and
        scoring: simulation cost is set by the number of input intervals.
    max_iter : int
        Solver iterations per candidate after the bracket search.
    refit_present : bool
        Refit the effects already in the model with every candidate (and for
        the baseline): an effect found in an earlier round absorbed what it
        could of the effects not yet found.
    full_fits : int
        Candidates fitted in full: those whose best point of the coarse
        parameter grid fits best. The others are scored at that grid point
        (a screen; raise this to fit every candidate).
    min_reduction : float
        Smallest held-out residual fall (fraction) that can name an effect.
    min_delta_bic : float
        BIC change an effect must reach (negative: lower is better).
    min_noise_ratio : float
        The held-out error an effect explains must be this many times the
        sensor noise (both as normalised RMS).
    ambiguity : float
        Relative difference of held-out residuals below which two effects tie.
    discover : bool
        Also look for generic correction terms (:mod:`.discovery`) where the missing
        physics may live outside the named effects.
    max_terms : int
        Most regressors in one discovered correction.
    discovery_fits : int
        Equations whose screened correction is fitted in full.
    """

    horizon_s: float = DIAGNOSIS_HORIZON_S
    lead_s: float = 0.1
    smooth_s: float = 0.01
    blocks: int = 4
    decimate: int = 1
    max_iter: int = 6
    full_fits: int = 4
    refit_present: bool = True
    min_reduction: float = MIN_REDUCTION
    min_delta_bic: float = MIN_DELTA_BIC
    min_noise_ratio: float = MIN_NOISE_RATIO
    ambiguity: float = AMBIGUITY
    discover: bool = True
    max_terms: int = 3
    discovery_fits: int = 3

    def to_json(self) -> dict:
        """The options that shape the scores (for the JSON result)."""
        skip = {'max_iter', 'full_fits', 'refit_present', 'discovery_fits'}
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
