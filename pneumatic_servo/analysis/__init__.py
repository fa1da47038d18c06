"""Analysis: metrics, comparison, regimes, residual tests, diagnosis, plots and reports."""
