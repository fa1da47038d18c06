"""The paper's experiments simulated without sensors, drawn as PNG figures and checked: the
first stage of ``pneumatic-servo demo``.

What is reproduced (Zhang et al., Energies 2019): the charge/discharge with the pistons held
(Figs 22-23) and the 2 Hz open-loop sine (Figs 24-26), both runs of :mod:`.runs`; the static
tests (Table 5, Figs 19-20); the flow coefficient C1 (Eq. 40); and what each switchable part
contributes. The claims are checked by :mod:`pneumatic_servo.analysis.paper_figures`, the
figures drawn by :mod:`pneumatic_servo.analysis.paper_plots`.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ..analysis.paper_figures import check_charge_discharge, sine_summary, static_curves
from ..analysis.paper_plots import (
    plot_charge_discharge,
    plot_flow_coefficient,
    plot_friction_variants,
    plot_pressure_variants,
    plot_sine,
    plot_static,
    plot_thermal_variants,
)
from ..model import Model, ModelConfig
from .runs import charge_discharge, sine_response


def run_paper_figures(out_dir, config: ModelConfig | None = None,
                      log: Callable[[str], None] = print, sine_duration_s: float = 10.0,
                      charge_duration_s: float = 6.0) -> dict:
    """Simulate the paper's experiments, write the figures to ``out_dir`` and summarise.

    Parameters
    ----------
    out_dir : path
        Directory for the PNG files (created).
    config : ModelConfig, optional
        Base model (default: the paper's). Variants swap one slot of it.
    log : callable
        Receives one progress line per stage.
    sine_duration_s, charge_duration_s : float [s]
        Lengths of the sine and charge/discharge records.

    Returns
    -------
    dict
        JSON-serialisable: ``charge_discharge`` (claims and values),
        ``sine`` (ranges), ``variants`` (per slot and variant), ``static``
        (curves) and ``figures`` (name -> path).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cfg = config or ModelConfig.paper()
    model = Model(cfg)
    step_s = 0.1
    figures = {}

    def cd(c):
        return charge_discharge(Model(c), step_time_s=step_s, duration_s=charge_duration_s,
                                config=c)

    def sine(c, duration=sine_duration_s):
        return sine_response(Model(c), duration_s=duration, config=c)

    log('charge/discharge at 0.6 MPa gauge, 5 V -> 5.5 V (blocked circuit)')
    base_cd = cd(cfg)
    checks = check_charge_discharge(base_cd, cfg, step_s)
    figures['charge_discharge'] = plot_charge_discharge(base_cd, cfg, step_s,
                                                        out / 'charge_discharge.png')
    log('2 Hz sine response at 5 +/- 0.35 V (servo circuit)')
    base_sine = sine(cfg)
    figures['sine_response'] = plot_sine(base_sine, out / 'sine_response.png')

    log('switchable parts: clearance, thermal, friction')
    slots = {n: cfg.with_slot(n) for n in ('no_clearance_flow', 'adiabatic', 'isothermal',
                                           'coulomb_viscous_friction')}
    clear = {'with clearance flow (paper)': base_cd, 'no clearance flow':
             cd(slots['no_clearance_flow'])}
    figures['variant_clearance'] = plot_pressure_variants(
        clear, cfg, step_s, 'Clearance part: with vs without clearance flow, charge/discharge',
        out / 'variant_clearance.png')
    thermal = {'heat transfer (paper)': base_cd, 'adiabatic': cd(slots['adiabatic']),
               'isothermal': cd(slots['isothermal'])}
    figures['variant_thermal'] = plot_thermal_variants(thermal, cfg, step_s,
                                                       out / 'variant_thermal.png')
    fric = {'Stribeck (paper)': base_sine,
            'Coulomb + viscous': sine(slots['coulomb_viscous_friction'])}
    figures['variant_friction'] = plot_friction_variants(fric, cfg, out / 'variant_friction.png')

    log('static tests: closed port (Table 5) and flow rates (Figs 19-20)')
    curves = static_curves(model, cfg)
    figures['static_tests'] = plot_static(curves, out / 'static_tests.png')
    figures['flow_coefficient'] = plot_flow_coefficient(cfg, out / 'flow_coefficient.png')

    variants = {
        'clearance': {k: check_charge_discharge(r, cfg, step_s) for k, r in clear.items()},
        'thermal': {k: check_charge_discharge(r, cfg, step_s) for k, r in thermal.items()},
        'friction': {k: sine_summary(r) for k, r in fric.items()},
    }
    return {'charge_discharge': checks, 'sine': sine_summary(base_sine), 'variants': variants,
            'static': curves, 'figures': figures,
            'finite': bool(all(np.all(np.isfinite(r.states)) for r in
                               list(clear.values()) + list(thermal.values())
                               + list(fric.values())))}

