"""Synthetic experiments: the paper's experiments run on a model through realistic sensors.

``make_experiment(config, design_name, seed)`` runs one design of
:data:`DESIGNS`, the one registry of experiments (flow tests, closed-port test,
heat-transfer discharge, charge/discharge, friction runs, the 2 Hz sine, closed-loop
steps and sine, and the designs of the hidden-effect sets), on any model configuration,
including catalogue effects; :mod:`.runs` holds the runs they are built on. The ground
truth of the bundled library is :func:`synthetic_rig`; :func:`generate_library`
regenerates ``bags/`` from the designs of :data:`LIBRARY` (``pneumatic-servo generate
OUTDIR``).
"""
from .designs import DESIGNS, LIBRARY, Design, make_experiment
from .sensors import SensorModel, measure, measure_static
from .truth import TRUTH_VALUES, synthetic_rig

__all__ = ['DESIGNS', 'LIBRARY', 'Design', 'SensorModel', 'TRUTH_VALUES', 'make_experiment',
           'measure', 'measure_static', 'synthetic_rig']
