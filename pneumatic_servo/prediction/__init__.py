"""One way to predict a recorded experiment with the model.

* :mod:`.inputs`: what drives the model (the valve command and supply shifted by
  the model's delays, the held angle of a blocked record, a smoothed supply) and
  the measured signals a prediction starts from;
* :mod:`.start`: the state vector at a segment start, measured where the record
  measures it, with an optional lead-in simulation for the rest;
* :mod:`.plans`: which samples are predicted from where (open loop, fixed
  k-step windows for ``compare``, quiet starts for ``diagnose``);
* :mod:`.predict`: :func:`predict`, many parameter sets in one parallel batch.

``compare``, ``identification`` and ``analysis.diagnosis`` all predict through
:func:`predict`.
"""
from .inputs import config_for
from .plans import COMPARE_HORIZON_S, DIAGNOSIS_HORIZON_S, Plan, open_loop, quiet_starts, windows
from .predict import STATE_SIGNALS, predict, predict_checked

__all__ = ['Plan', 'open_loop', 'windows', 'quiet_starts', 'predict', 'predict_checked',
           'config_for', 'STATE_SIGNALS', 'COMPARE_HORIZON_S', 'DIAGNOSIS_HORIZON_S']
