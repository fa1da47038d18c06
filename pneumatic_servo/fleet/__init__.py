"""Fleet scale: verify, track and diagnose many recordings on Dask; alert when a rig degrades.

``discover`` finds the recordings, ``task`` checks one (a pure function a Dask worker
runs), ``store`` streams the rows to disk and lets a rerun resume, ``alerts`` finds
parameters that trend or step beyond their uncertainty, ``table`` and ``report`` write
what pandas users and maintenance engineers read, and ``run`` puts it together.
"""
from .alerts import Alert, detect_alerts
from .discover import Recording, find_recordings
from .run import FleetOptions, run_fleet
from .task import TaskOptions, check_recording

__all__ = ['Alert', 'FleetOptions', 'Recording', 'TaskOptions', 'check_recording',
           'detect_alerts', 'find_recordings', 'run_fleet']
