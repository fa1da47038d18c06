"""Bag-replay regression tests for your own rig, in a few lines of pytest.

Example (``tests/test_my_rig.py``)::

    import pytest
    from pneumatic_servo.testing import assert_bag_matches_model, bag_cases

    @pytest.mark.parametrize('bag', bag_cases('recordings/'), ids=lambda p: p.name)
    def test_rig_matches_model(bag):
        assert_bag_matches_model(bag, 'config/my_rig.yaml',
                                 max_angle_error_deg=1.25, max_pressure_error_pa=4000)

Each recorded experiment is replayed through the model (open loop by
default, as the paper's Section 6.3 verification) and the largest error of
every measured channel is checked; a failure names the channels and prints
the table that ``pneumatic-servo verify`` prints.
"""
from __future__ import annotations

from pathlib import Path

from .analysis.compare import (
    PAPER_MAX_ANGLE_ERROR_DEG,
    PAPER_MAX_PRESSURE_ERROR_PA,
    format_table,
    limits_for,
    verify,
)
from .experiment import Experiment
from .io import read_experiment

__all__ = ['assert_bag_matches_model', 'bag_cases']


def assert_bag_matches_model(bag, config=None, *,
                             max_angle_error_deg: float = PAPER_MAX_ANGLE_ERROR_DEG,
                             max_pressure_error_pa: float = PAPER_MAX_PRESSURE_ERROR_PA,
                             max_flow_error_kg_s: float | None = None,
                             effects=None, mode: str = 'open_loop', horizon_s: float = 0.2,
                             skip_s: float = 0.0, **read_options) -> dict:
    """Assert that the model reproduces a recorded experiment within the given errors.

    Parameters
    ----------
    bag : str, Path or Experiment
        A rosbag2 directory (sqlite3 or MCAP), a static CSV, or an Experiment.
    config : ModelConfig, str or Path, optional
        The model (default: the paper's); ``effects`` adds catalogue effects.
    max_angle_error_deg : float [deg]
    max_pressure_error_pa : float [Pa]
    max_flow_error_kg_s : float, optional [kg/s]
        Limits on the largest absolute error (None: channel not checked).
    mode : {'open_loop', 'k_step'}
        Prediction view checked; ``horizon_s`` [s] for k-step.
    skip_s : float [s]
        Leave the first ``skip_s`` out.
    read_options
        Passed to :func:`pneumatic_servo.io.read_experiment` (e.g. ``namespace``).

    Returns
    -------
    dict
        The comparison (as ``compare --json``), for further checks.

    Raises
    ------
    AssertionError
        Naming the failing channels, with the table of errors and limits.
    """
    exp = bag if isinstance(bag, Experiment) else read_experiment(bag, **read_options)
    limits = limits_for(max_angle_error_deg, max_pressure_error_pa, max_flow_error_kg_s)
    ok, rows, result = verify(exp, config, effects=effects, limits=limits, mode=mode,
                              horizon_s=horizon_s, skip_s=skip_s)
    if not ok:
        failing = ', '.join(r['channel'] for r in rows if r['passed'] is False)
        raise AssertionError(f'{exp.name}: the model misses the {mode.replace("_", "-")} '
                             f'limits on {failing}\n{format_table(rows)}')
    return result


def bag_cases(directory, pattern: str = '*') -> list[Path]:
    """Bag directories and CSV tables in ``directory`` matching ``pattern``, sorted.

    Use it to parametrize a test over every recording of a rig.
    """
    directory = Path(directory)
    found = [p for p in directory.glob(pattern)
             if (p.is_dir() and (p / 'metadata.yaml').exists()) or p.suffix == '.csv']
    return sorted(found)
