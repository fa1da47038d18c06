"""Which physical effect is the model missing? One module per concern:

* :mod:`.options`: how candidates are fitted and scored;
* :mod:`.data`: the experiments prepared and split into fitted and held-out parts;
* :mod:`.scoring`: held-out scores and the information criterion;
* :mod:`.hosts`: compiled models shared by candidates;
* :mod:`.candidates`: which effects to try, their screen, fit and score;
* :mod:`.verdict`: the ranking, the verdict and ties;
* :mod:`.ladder`: the held-out error as effects are added;
* :mod:`.result`: the :class:`Diagnosis` and :func:`apply`;
* :mod:`.run`: :func:`diagnose`, the orchestration;
* :mod:`.text`: the result as lines of text.
"""
from .options import DiagnoseOptions
from .result import Diagnosis, apply
from .pipeline import diagnose, predictions, where_it_fails

__all__ = ['diagnose', 'apply', 'predictions', 'where_it_fails', 'Diagnosis',
           'DiagnoseOptions']
