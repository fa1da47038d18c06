"""The frozen context of one diagnosis: the data split, the model as given, what is refitted,
the options, the sensor noise and the record's prediction floor."""
from __future__ import annotations

from dataclasses import dataclass

from ...model.assembly import Model
from ...model.config import ModelConfig
from .candidates import Baseline
from .criteria import Departures, Levels, departures
from .data import Data
from .floor import Floor, measure_floor
from .hosts import fitted_on
from .options import DiagnoseOptions
from .scoring import Score


def floor_for(host: ModelConfig, data: Data, options: DiagnoseOptions) -> Floor:
    """The prediction floor of ``host`` (a model on the composition it is simulated on) on
    ``data`` (:func:`.floor.measure_floor`)."""
    return measure_floor(Model(host), host, data, options.replicas, options.seed)


@dataclass(frozen=True)
class Trial:
    """Everything the candidates are fitted on and judged against, built once.

    Attributes
    ----------
    data : Data
        The experiments, decimated and split into fitted and held-out parts.
    base : Baseline
        The model as given (its free keys fitted) and its held-out score.
    free : tuple of str
        Keys refitted with every candidate.
    options : DiagnoseOptions
        Fit, scoring and decision settings.
    noise : float
        Sensor noise as left in the smoothed residual [normalised] (for reference).
    floor : Floor
        What the fitted model itself leaves on replicas of these records.
    levels : Levels
        Significance levels of the departure and candidate tests.
    """

    data: Data
    base: Baseline
    free: tuple[str, ...]
    options: DiagnoseOptions
    noise: float
    floor: Floor
    levels: Levels

    def departures(self, score: Score, floor: Floor | None = None) -> Departures:
        """``score`` against ``floor`` (default the model as given's), per channel and
        pooled."""
        return departures(score, floor or self.floor, self.levels.departure)

    def floor_of(self, config: ModelConfig) -> Floor:
        """The prediction floor of another model (a candidate's) on these records: what a
        model leaves depends on the model, so what a named effect leaves is judged against
        its own floor, not the floor of the model it corrects. Simulated on the composition
        the candidate was fitted on (:func:`.hosts.fitted_on`)."""
        return floor_for(fitted_on(self.base.config, config), self.data, self.options)
