"""The paper's qualitative results checked on simulations, and its static curves.

What is reproduced (Zhang et al., Energies 2019; the runs and the figures are made by
:func:`pneumatic_servo.synth.paper_figures.run_paper_figures`):

* charge/discharge with the pistons held, 0.6 MPa gauge, 5 V -> 5.5 V
  (Figs 22-23): p_a rises but stays below supply, p_b falls but stays above
  atmosphere, T_a jumps and recovers, T_b dips and recovers. Each claim is a
  boolean computed from the simulation;
* the open-loop servo response to a 2 Hz, 5 +/- 0.35 V sine (Figs 24-26);
* the static tests: closed-port p_a (Table 5), M4 and M5 (Figs 19-20);
* the flow coefficient C1 as printed and as settled (Eq. 40, docs/model.md);
* what each switchable part contributes: with and without clearance flow,
  heat transfer versus adiabatic versus isothermal, Stribeck versus
  Coulomb + viscous friction.

The figures themselves are drawn by :mod:`.paper_plots`.
"""
from __future__ import annotations

import numpy as np

from ..model import Model, ModelConfig, circuits
from ..model.simulate import SimResult
from .paper_plots import MPA

#: a temperature excursion smaller than this is not a 'jump' or 'dip' [K]
MIN_EXCURSION_K = 1.0
#: 'does not reach' supply or atmosphere = stays this far from it [Pa]; the paper's
#: transmitters resolve 0.6 kPa (0.1 % of 0.6 MPa)
PRESSURE_MARGIN_PA = 1e3
#: 'recovers' = the final deviation from room temperature is below this share of the peak one
RECOVERY_FRACTION = 0.1


# ------------------------------------------------------------------------- summaries
def check_charge_discharge(res: SimResult, config: ModelConfig, step_time_s: float
                           ) -> dict:
    """The paper's charge/discharge claims, each evaluated on the simulation.

    Parameters
    ----------
    res : SimResult
        Output of :func:`pneumatic_servo.synth.runs.charge_discharge`.
    config : ModelConfig
        The model's configuration (atmospheric pressure, room temperature).
    step_time_s : float [s]
        Time of the valve step.

    Returns
    -------
    dict
        Booleans ``p_a_rises``, ``p_a_stays_below_supply``, ``p_b_falls``,
        ``p_b_stays_above_atmosphere``, ``t_a_jumps``, ``t_a_recovers``,
        ``t_b_dips``, ``t_b_recovers``, ``all_hold``, and the values they rest
        on (SI: Pa, K).
    """
    core = config.core
    pe, te = core['atmospheric_pressure_pa'], core['room_temperature_k']
    ps = float(np.max(res.inputs['supply_pa']))
    k = int(np.searchsorted(res.t, step_time_s))
    pa, pb, ta, tb = res.p_a_pa, res.p_b_pa, res.t_a_k, res.t_b_k
    ta_peak, tb_low = float(np.max(ta[k:])), float(np.min(tb[k:]))
    out = {
        'supply_pa': ps, 'atmospheric_pa': pe, 'room_temperature_k': te,
        'p_a_at_step_pa': float(pa[k]), 'p_a_final_pa': float(pa[-1]),
        'p_a_max_pa': float(np.max(pa)),
        'p_b_at_step_pa': float(pb[k]), 'p_b_final_pa': float(pb[-1]),
        'p_b_min_pa': float(np.min(pb)),
        't_a_peak_k': ta_peak, 't_a_final_k': float(ta[-1]),
        't_b_lowest_k': tb_low, 't_b_final_k': float(tb[-1]),
    }
    out['p_a_rises'] = bool(pa[-1] > pa[k] + PRESSURE_MARGIN_PA)
    out['p_a_stays_below_supply'] = bool(np.max(pa) < ps - PRESSURE_MARGIN_PA)
    out['p_b_falls'] = bool(pb[-1] < pb[k] - PRESSURE_MARGIN_PA)
    out['p_b_stays_above_atmosphere'] = bool(np.min(pb) > pe + PRESSURE_MARGIN_PA)
    out['t_a_jumps'] = bool(ta_peak - te > MIN_EXCURSION_K and ta_peak > ta[k])
    out['t_a_recovers'] = bool(abs(ta[-1] - te) < RECOVERY_FRACTION * (ta_peak - te))
    out['t_b_dips'] = bool(te - tb_low > MIN_EXCURSION_K and tb_low < tb[k])
    out['t_b_recovers'] = bool(abs(tb[-1] - te) < RECOVERY_FRACTION * (te - tb_low))
    claims = [key for key, v in out.items() if isinstance(v, bool)]
    out['all_hold'] = all(out[key] for key in claims)
    return out


def sine_summary(res: SimResult, settle_s: float = 5.0) -> dict:
    """Ranges of angle [rad], p_a and p_b [Pa] after ``settle_s`` [s] of the sine response."""
    keep = res.t >= min(settle_s, res.t[-1] / 2)
    ang = res.angle_rad[keep]
    out = {'window_start_s': float(res.t[keep][0])}
    for name, sig in (('angle_rad', ang), ('p_a_pa', res.p_a_pa[keep]),
                      ('p_b_pa', res.p_b_pa[keep])):
        out[f'{name}_min'] = float(np.min(sig))
        out[f'{name}_max'] = float(np.max(sig))
    out['angle_peak_to_peak_deg'] = float(np.degrees(np.ptp(ang)))
    out['finite'] = bool(np.all(np.isfinite(res.states)))
    return out


# ----------------------------------------------------------------------- static curves
def static_curves(model: Model, config: ModelConfig,
                  voltages_v=None) -> dict[str, dict[str, list[float]]]:
    """Closed-port p_a and M5, flow-test M4, at the paper's three verification supplies."""
    volts = np.linspace(5.0, 10.0, 26) if voltages_v is None else np.asarray(voltages_v)
    out = {}
    for gauge in circuits.PAPER_FLOW_SUPPLIES_GAUGE_PA:
        ps = circuits.gauge_supply_pa(gauge, config)
        closed = [circuits.steady_outputs(model, 'closed_port', v, ps, config) for v in volts]
        flow = [circuits.steady_outputs(model, 'flow', v, ps, config) for v in volts]
        out[f'{gauge * MPA:g} MPa'] = {
            'voltage_v': [float(v) for v in volts],
            'closed_port_p_a_pa': [c['p_a_pa'] for c in closed],
            'closed_port_m5_kg_s': [c['m5_kg_s'] for c in closed],
            'flow_m4_kg_s': [f['m4_kg_s'] for f in flow],
            'flow_m5_kg_s': [f['m5_kg_s'] for f in flow],
        }
    return out
