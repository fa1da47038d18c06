"""Synthetic experiments: the paper's experiments run on a model through realistic sensors.

``make_experiment(config, design_name, seed)`` runs one design of
:data:`DESIGNS` (flow tests, closed-port test, heat-transfer discharge,
charge/discharge, friction runs, the 2 Hz sine, closed-loop steps and sine)
on any model configuration, including catalogue effects. The ground truth
of the bundled library is :func:`synthetic_rig`; :func:`generate_library`
regenerates ``bags/`` (``pneumatic-servo generate OUTDIR``).
"""
from .designs import DESIGNS, LIBRARY, Design, make_experiment
from .sensors import SensorModel, measure, measure_static
from .truth import TRUTH_VALUES, synthetic_rig

__all__ = ['DESIGNS', 'LIBRARY', 'Design', 'SensorModel', 'TRUTH_VALUES', 'make_experiment',
           'measure', 'measure_static', 'synthetic_rig']
