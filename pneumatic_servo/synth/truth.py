"""The synthetic rig: the ground truth the bundled experiments were generated from.

Its identified parameters (flow coefficient C1, heat transfer coefficient h,
Stribeck friction) deliberately differ from the paper's published values,
so an identification that returned the defaults would fail its tests.
Everything the paper measured directly (geometry, Table 2) is the paper's.
"""
from __future__ import annotations

from ..model.config import ModelConfig

#: the identified parameters of the synthetic rig ('owner.name' -> SI value)
TRUTH_VALUES = {
    # C1(|x_v|) polynomial, Eq. 40 with the sign settled (docs/model.md): 5-13 % above the paper's
    'orifice_flow.flow_coefficient_p0': 0.4852,
    'orifice_flow.flow_coefficient_p1_per_m': 1850.0,
    'orifice_flow.flow_coefficient_p2_per_m2': -3.30e6,
    'orifice_flow.flow_coefficient_p3_per_m3': 1.95e9,
    'orifice_flow.flow_coefficient_p4_per_m4': -3.70e11,
    # h: the paper's 15.797 W/(K.m^2) + 36 %
    'wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k': 21.5,
    # Stribeck friction (paper Table 4: 10.60 N, 6.03 N, 0.14 rad/s, 0.85 N.s/rad)
    'stribeck_friction.static_friction_n': 9.3,
    'stribeck_friction.coulomb_friction_n': 6.9,
    'stribeck_friction.stribeck_velocity_rad_s': 0.22,
    'stribeck_friction.viscous_friction_n_s_per_rad': 1.25,
}


def synthetic_rig(base: ModelConfig | None = None) -> ModelConfig:
    """The synthetic rig's model: ``base`` (default the paper's) with :data:`TRUTH_VALUES`.

    Catalogue effects already in ``base`` are kept, so a hidden-effect
    generator can start from ``synthetic_rig().with_effect(...)`` or pass
    its own base.
    """
    cfg = (base or ModelConfig.paper()).copy()
    for key, value in TRUTH_VALUES.items():
        cfg.set(key, value)
    cfg.validate()
    return cfg
