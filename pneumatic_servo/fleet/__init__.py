"""Fleet scale: verify, track and diagnose many recordings on Dask; alert when a rig degrades.

``discover`` finds the recordings, ``task`` checks one (a pure function a Dask worker
runs) into a :class:`~.row.Row`, ``store`` streams the rows to disk and lets a rerun
resume, ``alerts`` finds parameters that trend or step beyond their uncertainty, ``table``
and ``report`` write what pandas users and maintenance engineers read, ``cluster`` puts it
together on Dask, and ``bundled`` runs it on the bundled fleet.
"""
from .alerts import Alert, detect_alerts
from .cluster import FleetOptions, run_fleet
from .discover import Recording, find_recordings
from .row import Row
from .task import TaskOptions, check_recording

__all__ = ['Alert', 'FleetOptions', 'Recording', 'Row', 'TaskOptions', 'check_recording',
           'detect_alerts', 'find_recordings', 'run_fleet']
