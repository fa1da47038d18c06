"""One fitting stack: a problem, one solver, one account of the uncertainty.

* :mod:`.problem`: normalised residuals of parameter vectors over data parts,
  bounds and scales from each :class:`~pneumatic_servo.effects.Param`, a
  penalty for failed simulations; many vectors simulated in one batch;
* :mod:`.solver`: scipy's ``least_squares`` (trf, real bounds, ``x_scale``) fed
  by the batched simulations as its Jacobian, with an optional bracket search
  for rough costs;
* :mod:`.uncertainty`: standard errors, correlation, parameters at a bound,
  and the one estimator of the effective sample count.

``identification.output_error`` and ``analysis.diagnosis`` are thin uses of it.
"""
from .identifiability import Combination, Identifiability
from .problem import FAILED_RESIDUAL, Part, Problem, channel_scales, residual_rows, stack
from .solver import Fit, fit
from .uncertainty import Uncertainty, effective_samples, uncertainty

__all__ = ['Part', 'Problem', 'residual_rows', 'channel_scales', 'stack', 'FAILED_RESIDUAL',
           'Fit', 'fit', 'Uncertainty', 'uncertainty', 'effective_samples', 'Identifiability',
           'Combination']
