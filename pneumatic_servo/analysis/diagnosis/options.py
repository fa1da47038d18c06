"""How diagnosis fits and scores candidate effects, and the error rate of its statements."""
from __future__ import annotations

from dataclasses import dataclass, fields

from ...prediction import DIAGNOSIS_HORIZON_S

#: probability that a record of a correct model gets any status but ``consistent``
FALSE_ALARM_RATE = 0.01
#: an effect is of practical size when the held-out error it explains is at least this share
#: of the prediction floor (both as RMS): less is within what the model cannot predict anyway
PRACTICAL_SIZE = 0.5
#: replicas of the record simulated to measure its prediction floor (:mod:`.floor`)
REPLICAS = 16
#: [Hz] the fitted parts are decimated to about this rate: a fit simulates them many times,
#: and 250 Hz resolves the actuator's dynamics (the committed test records are at 250 Hz)
FIT_RATE_HZ = 250.0
#: two candidates whose held-out residuals differ by less than this fraction explain
#: the data about equally
AMBIGUITY = 0.05


@dataclass(frozen=True)
class DiagnoseOptions:
    """How candidates are fitted and scored, and how sure a statement must be.

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
    fit_rate_hz : float [Hz]
        The fitted parts are decimated to about this rate (0: not at all); the held-out
        parts, the floor and every statement keep the record's own rate.
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
    false_alarm_rate : float
        Probability that a record of a correct model is given any status but
        ``consistent``; shared between the tests of the record against its floor
        and the tests of the candidates (:mod:`.criteria`).
    practical_size : float
        Share of the prediction floor (RMS) that the error an effect explains must
        reach for the effect to earn its place; a significant effect below it is
        reported as small.
    replicas : int
        Replicas simulated to measure the prediction floor.
    seed : int
        Seed of the replicas' noise and jitter (a diagnosis is reproducible).
    ambiguity : float
        Relative difference of held-out residuals below which two effects tie.
    discover : bool
        Also look for generic correction terms (:mod:`.discovery`) where the missing
        physics may live outside the named effects.
    test_dependence : bool
        Test, variable by variable, what the best discovered correction depends on
        (:mod:`.dependence`): one fit through the simulator per variable tried, where no
        name fits.
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
    fit_rate_hz: float = FIT_RATE_HZ
    max_iter: int = 6
    full_fits: int = 4
    refit_present: bool = True
    false_alarm_rate: float = FALSE_ALARM_RATE
    practical_size: float = PRACTICAL_SIZE
    replicas: int = REPLICAS
    seed: int = 0
    ambiguity: float = AMBIGUITY
    discover: bool = True
    test_dependence: bool = True
    max_terms: int = 3
    discovery_fits: int = 3

    def to_json(self) -> dict:
        """The options that shape the scores and decisions (for the JSON result)."""
        skip = {'max_iter', 'full_fits', 'refit_present', 'discovery_fits'}
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
