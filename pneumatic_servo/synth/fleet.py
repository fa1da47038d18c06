"""A synthetic fleet: N rigs x M days of closed-loop recordings, two of them degrading.

Every rig is the paper's model with a small seal leak and its own friction (a few per cent
off the paper's). One rig's piston seal leak grows day by day from a given day on; another
rig's Coulomb friction grows. One bag is written and then cut short, as a recorder killed
mid-write leaves it. Each bag carries its rig (``pneumatic_servo.rig``), its day and
``synthetic: true`` in its custom data, and is stamped one day after the last.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from ..model.config import ModelConfig
from .hidden import closed_loop_experiment, hidden_config

#: healthy seal leak area of every rig [m^2] (below what a per-recording fit resolves)
HEALTHY_SEAL_LEAK_M2 = 2e-9
FRICTION_KEY = 'stribeck_friction.coulomb_friction_n'
SEAL_KEY = 'piston_seal_leakage.seal_leak_area_m2'
FIRST_DAY = datetime(2026, 11, 2, 8, 0, tzinfo=timezone.utc)


@dataclass
class FleetDesign:
    """Which rigs degrade, how, and from which day (0-based)."""

    rigs: int = 4
    days: int = 6
    duration_s: float = 3.0
    rate_hz: float = 250.0
    leaking_rig: str = 'cell-2'
    leak_from_day: int = 2
    leak_per_day_m2: float = 1.2e-8
    rubbing_rig: str = 'cell-3'
    friction_from_day: int = 2
    friction_per_day_n: float = 2.5
    broken: tuple[str, int] = ('cell-1', 3)  # (rig, day) of the bag cut short
    seed: int = 0
    truth: dict = field(default_factory=dict)

    def rig_names(self) -> list[str]:
        return [f'cell-{i + 1}' for i in range(self.rigs)]

    def values(self, rig: str, day: int) -> dict[str, float]:
        """True seal leak [m^2] and Coulomb friction [N] of ``rig`` on ``day``."""
        base = ModelConfig.paper().get(FRICTION_KEY)
        friction = base * (1.0 + 0.04 * (self.rig_names().index(rig) - 1))
        leak = HEALTHY_SEAL_LEAK_M2
        if rig == self.leaking_rig and day >= self.leak_from_day:
            leak += self.leak_per_day_m2 * (day - self.leak_from_day + 1)
        if rig == self.rubbing_rig and day >= self.friction_from_day:
            friction += self.friction_per_day_n * (day - self.friction_from_day + 1)
        return {SEAL_KEY: leak, FRICTION_KEY: friction}


def _config(values: dict[str, float]) -> ModelConfig:
    base = ModelConfig.paper()
    base.set(FRICTION_KEY, values[FRICTION_KEY])
    return hidden_config({'piston_seal_leakage': {'seal_leak_area_m2': values[SEAL_KEY]}},
                         base)


def _cut_short(bag: Path) -> None:
    """Truncate the bag's storage file to a third, as a killed recorder leaves it."""
    data = next(p for p in bag.iterdir() if p.suffix in ('.mcap', '.db3'))
    size = data.stat().st_size
    with data.open('r+b') as f:
        f.truncate(size // 3)


def write_fleet(out_dir, design: FleetDesign | None = None) -> Path:
    """Write ``out_dir/<rig>/day_<dd>`` bags and ``truth.json``; returns ``out_dir``."""
    from ..io import write_experiment
    design = design or FleetDesign()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=False)
    rng = np.random.default_rng(design.seed)
    truth = {}
    for rig in design.rig_names():
        for day in range(design.days):
            values = design.values(rig, day)
            exp = closed_loop_experiment(_config(values), rng, design.duration_s,
                                         design.rate_hz)
            stamp = FIRST_DAY.timestamp() + 86400 * day
            bag = out_dir / rig / f'day_{day:02d}'
            write_experiment(exp, bag, 'mcap', {
                'synthetic': 'true', 'generator': 'pneumatic_servo.synth.fleet', 'rig': rig,
                'day': day, 'hidden_values': values}, start_time_ns=int(stamp * 1e9),
                compress=True)
            if (rig, day) == tuple(design.broken):
                _cut_short(bag)
            truth[f'{rig}/day_{day:02d}'] = values
    (out_dir / 'truth.json').write_text(json.dumps({
        'synthetic': True, 'generator': 'pneumatic_servo.synth.fleet',
        'leaking_rig': design.leaking_rig, 'rubbing_rig': design.rubbing_rig,
        'broken': f'{design.broken[0]}/day_{design.broken[1]:02d}',
        'tracked': [SEAL_KEY, FRICTION_KEY], 'values': truth}, indent=1))
    return out_dir


#: the bundled fleet: 4 rigs x 6 days of 3 s records at 250 Hz (about 2 MB)
DEMO_DESIGN = FleetDesign()


def main(argv=None) -> int:
    """``python -m pneumatic_servo.synth.fleet OUT_DIR``: write the demo fleet."""
    import sys
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print('usage: python -m pneumatic_servo.synth.fleet OUT_DIR', file=sys.stderr)
        return 2
    print(write_fleet(args[0], DEMO_DESIGN))
    return 0


if __name__ == '__main__':
    raise SystemExit(main())
