"""The demo's fleet stage: the bundled synthetic fleet (``bags/fleet_demo``) checked on a
local Dask cluster, with the seal leak and the Coulomb friction tracked; prints the alerts
and checks them against the fleet's ``truth.json``."""
from __future__ import annotations

import json
from pathlib import Path

from ..errors import ExperimentError
from ..files import bundled
from ..jsonable import dumps
from ..model.config import ModelConfig
from .discover import find_recordings
from .report import write_report
from .cluster import FleetOptions, parameter_names, run_fleet
from .task import TaskOptions

FLEET_DEMO = 'fleet_demo'
TRACK = ('piston_seal_leakage',)
FREE = ('stribeck_friction.coulomb_friction_n',)
#: error limits of the demo [deg, Pa]: the paper's are for its own rig and sensors; these
#: fit the synthetic sensors' noise, so that a healthy rig passes and a worn one fails
MAX_ANGLE_ERROR_DEG, MAX_PRESSURE_ERROR_PA = 2.0, 8e3


def fleet_demo_dir() -> Path:
    return bundled(FLEET_DEMO, 'truth.json',
                   'python -m pneumatic_servo.synth.fleet bags/fleet_demo', ExperimentError)


def run_fleet_demo(out_dir, log=print, fleet_dir=None) -> dict:
    """Check the bundled fleet into ``out_dir`` (row store, JSON, page); a summary dict."""
    from ..analysis.compare import limits_for
    fleet_dir = Path(fleet_dir) if fleet_dir else fleet_demo_dir()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    truth = json.loads((fleet_dir / 'truth.json').read_text())
    config = ModelConfig.paper()
    task = TaskOptions(track=TRACK, free=FREE,
                       limits=limits_for(MAX_ANGLE_ERROR_DEG, MAX_PRESSURE_ERROR_PA))
    result = run_fleet(find_recordings([fleet_dir]), config,
                       FleetOptions(out_dir / 'rows.jsonl', progress=False, task=task))
    (out_dir / 'fleet.json').write_text(dumps(result.to_json(), indent=1))
    page = write_report(out_dir, result.rows, result.alerts, parameter_names(config, TRACK))
    for alert in result.alerts:
        log(f'ALERT {alert.text}')
    errors = [r for r in result.rows if r.status == 'error']
    for row in errors:
        log(f'error {Path(row.path).parent.name}/{Path(row.path).name}: {row.error}')
    expected = {truth['leaking_rig'], truth['rubbing_rig']}
    found = {a.rig for a in result.alerts}
    return {'status': 'ok' if found == expected and len(errors) == 1 else 'failed',
            'recordings': len(result.rows), 'errors': len(errors),
            'alerts': len(result.alerts), 'alerted_rigs': ', '.join(sorted(found)),
            'degrading_rigs': ', '.join(sorted(expected)), 'report': str(page)}
