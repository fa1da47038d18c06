"""The paper's model parts and their simpler alternatives, one component each.

Slots: ``orifice`` (orifice_flow), ``clearance`` (clearance_flow or
no_clearance_flow), ``thermal`` (wall_heat_transfer, adiabatic or
isothermal), ``friction`` (stribeck_friction or coulomb_viscous_friction).
"""
from .._jit import njit
from ..errors import ConfigError
from ..physics.friction import coulomb_viscous_force, stribeck_force
from ..physics.gas import clearance_flow, orifice_flow
from ..physics.valve import annulus_area, effective_area, flow_coefficient
from .base import Component, Param
from .layout import (
    C_FBRK_NEG,
    C_FBRK_POS,
    C_FEDGE_NEG,
    C_FEDGE_POS,
    C_FKIN,
    C_ISOTHERMAL,
    C_KAPPA,
    C_M5,
    C_MSUP,
    C_PE,
    C_PS,
    C_QA,
    C_QB,
    C_R,
    C_TE,
    C_TS,
    C_XV,
    K_ALPHA,
    K_DF,
    K_DH,
    K_DS,
    K_HALF_W,
    K_HOLE_R,
    K_MU,
    OMEGA,
    P_A,
    P_B,
    T_A,
    T_B,
    add_flow,
)

PAPER = 'Zhang et al., Energies 2019, 12, 2470'


@njit(cache=True, allocates=False)
def _orifice_hook(t, x, s, p, P, c, dx):
    xv = c[C_XV]
    xa = abs(xv)
    c1 = flow_coefficient(xa, p[0], p[1], p[2], p[3], p[4])
    area = effective_area(xa, c1, p[5], P[K_HALF_W], P[K_HOLE_R], annulus_area(P[K_DH], P[K_DS]))
    b, band, r, k = p[6], p[7], c[C_R], c[C_KAPPA]
    ps, ts, pe, te = c[C_PS], c[C_TS], c[C_PE], c[C_TE]
    if xv >= 0.0:  # port 1 -> a and b -> port 3 are metered (Eqs 8, 9)
        m1a = orifice_flow(area, ps, ts, x[P_A], x[T_A], b, r, k, band)
        m3 = orifice_flow(area, x[P_B], x[T_B], pe, te, b, r, k, band)
        add_flow(c, 0, m1a, ts, x[T_A])
        add_flow(c, 1, -m3, te, x[T_B])
        c[C_MSUP] += m1a
    else:  # port 1 -> b and a -> port 5 are metered (Eqs 22, 23)
        m1b = orifice_flow(area, ps, ts, x[P_B], x[T_B], b, r, k, band)
        m5 = orifice_flow(area, x[P_A], x[T_A], pe, te, b, r, k, band)
        add_flow(c, 1, m1b, ts, x[T_B])
        add_flow(c, 0, -m5, te, x[T_A])
        c[C_MSUP] += m1b
        c[C_M5] += m5


class OrificeFlow(Component):
    """Compressible flow through the metering edges (Eqs 3-9, 21-23).

    Effective area S_e = C1(x_v) (2 S_V + C0 S_H); isentropic nozzle law with
    the measured critical pressure ratio b; C1 is the sign-settled symmetric
    polynomial of Eq. 40 (docs/model.md, settlement 1).
    """

    name = 'orifice_flow'
    slot = 'orifice'
    summary = 'valve metering-edge flow, nozzle law with measured b (paper Eqs 3-9, 21-23)'
    reference = PAPER + ', Eqs 3-9, 21-23, 40'
    acts_on = 'pressure'
    params = (
        Param('flow_coefficient_p0', '1', 0.4517, 0.05, 1.0, 'C1 at the null'),
        Param('flow_coefficient_p1_per_m', '1/m', 1713.94, -1e5, 1e5, 'C1 polynomial, x term'),
        Param('flow_coefficient_p2_per_m2', '1/m^2', -3.133e6, -1e9, 1e9, 'C1, x^2 term'),
        Param('flow_coefficient_p3_per_m3', '1/m^3', 1.8641e9, -1e13, 1e13, 'C1, x^3 term'),
        Param('flow_coefficient_p4_per_m4', '1/m^4', -3.5227e11, -1e16, 1e16, 'C1, x^4 term'),
        Param('area_conversion_coefficient', '1', 0.43, 0.0, 1.0, 'C0 of Eq. 3'),
        Param('critical_pressure_ratio', '1', 0.5382, 0.1, 0.95, 'critical pressure ratio b'),
        Param('laminar_ratio_band', '1', 0.005, 1e-4, 0.05,
              'width of the linear region next to pressure ratio 1', fit=False),
    )
    flows = _orifice_hook


@njit(cache=True, allocates=False)
def _clearance_hook(t, x, s, p, P, c, dx):
    xv = c[C_XV]
    ds = P[K_DS]
    gap = 0.5 * (P[K_DH] - ds)
    length = p[0] + abs(xv)
    mu, r = P[K_MU], c[C_R]
    ps, ts, pe, te = c[C_PS], c[C_TS], c[C_PE], c[C_TE]
    if xv >= 0.0:  # port 1 -> b and a -> port 5 through the clearance (Eqs 17, 18)
        m1b = clearance_flow(ds, gap, length, ps, ts, x[P_B], x[T_B], mu, r)
        m5 = clearance_flow(ds, gap, length, x[P_A], x[T_A], pe, te, mu, r)
        add_flow(c, 1, m1b, ts, x[T_B])
        add_flow(c, 0, -m5, te, x[T_A])
        c[C_MSUP] += m1b
        c[C_M5] += m5
    else:  # port 1 -> a and b -> port 3 (Eqs 24, 25)
        m1a = clearance_flow(ds, gap, length, ps, ts, x[P_A], x[T_A], mu, r)
        m3 = clearance_flow(ds, gap, length, x[P_B], x[T_B], pe, te, mu, r)
        add_flow(c, 0, m1a, ts, x[T_A])
        add_flow(c, 1, -m3, te, x[T_B])
        c[C_MSUP] += m1a


class ClearanceFlow(Component):
    """Laminar flow through the spool-sleeve clearance on the closed edges (Eqs 10-18, 24-25)."""

    name = 'clearance_flow'
    slot = 'clearance'
    summary = 'laminar leakage through the spool clearance (paper Eqs 17-18, 24-25)'
    reference = PAPER + ', Eqs 10-18, 24-25'
    acts_on = 'pressure'
    params = (
        Param('clearance_initial_length_m', 'm', 2.0e-3, 1e-5, 0.05,
              'initial overlap length L0 of the clearance'),
    )
    flows = _clearance_hook


class NoClearanceFlow(Component):
    """No clearance flow: closed metering edges are taken as perfectly sealed."""

    name = 'no_clearance_flow'
    slot = 'clearance'
    summary = 'closed edges seal perfectly (simpler alternative to clearance_flow)'
    reference = 'textbook simplification'


@njit(cache=True, allocates=False)
def _wall_heat_hook(t, x, s, p, P, c, dx):
    te = c[C_TE]
    c[C_QA] += p[0] * p[1] * (te - x[T_A])
    c[C_QB] += p[0] * p[2] * (te - x[T_B])


class WallHeatTransfer(Component):
    """Convective heat exchange with walls at room temperature (Eqs 30-31)."""

    name = 'wall_heat_transfer'
    slot = 'thermal'
    summary = 'heat exchange between gas and walls, constant h (paper Eqs 30-31)'
    reference = PAPER + ', Eqs 26-31, h = 15.797 W/(K.m^2)'
    acts_on = 'pressure'
    params = (
        Param('heat_transfer_coefficient_w_per_m2_k', 'W/(m^2.K)', 15.797, 0.0, 1000.0,
              'heat transfer coefficient h', plausible=(1.0, 200.0)),
        Param('wall_area_a_m2', 'm^2', 1.5106348e-2, 0.0, 10.0, 'inner wall area S_ha', fit=False),
        Param('wall_area_b_m2', 'm^2', 1.5106348e-2, 0.0, 10.0, 'inner wall area S_hb', fit=False),
    )
    heat = _wall_heat_hook


class Adiabatic(Component):
    """No heat exchange with the walls (h = 0)."""

    name = 'adiabatic'
    slot = 'thermal'
    summary = 'no heat exchange (simpler alternative to wall_heat_transfer)'
    reference = 'textbook simplification'


@njit(cache=True, allocates=False)
def _isothermal_hook(t, x, s, p, P, c, dx):
    c[C_ISOTHERMAL] = 1.0


class Isothermal(Component):
    """Gas temperature held at room temperature (infinite heat transfer)."""

    name = 'isothermal'
    slot = 'thermal'
    summary = 'gas stays at room temperature (simpler alternative to wall_heat_transfer)'
    reference = 'textbook simplification'
    heat = _isothermal_hook


@njit(cache=True, allocates=False)
def _stribeck_hook(t, x, s, p, P, c, dx):
    arm = 0.5 * P[K_DF]
    c[C_FKIN] += arm * stribeck_force(x[OMEGA], p[0], p[1], p[2], p[3])
    c[C_FBRK_POS] += arm * p[0]
    c[C_FBRK_NEG] += arm * p[0]
    if abs(x[OMEGA]) <= P[K_ALPHA]:  # the band edge matters only inside the band
        edge = arm * stribeck_force(P[K_ALPHA], p[0], p[1], p[2], p[3])
        c[C_FEDGE_POS] += edge
        c[C_FEDGE_NEG] += edge


class StribeckFriction(Component):
    """Stribeck friction with stiction on the pistons (Eqs 34-36), Table 4 values."""

    name = 'stribeck_friction'
    slot = 'friction'
    summary = 'static, Coulomb, Stribeck and viscous friction (paper Eqs 34-36)'
    reference = PAPER + ', Eqs 34-36, Table 4'
    acts_on = 'angle'
    params = (
        Param('static_friction_n', 'N', 10.60, 0.0, 500.0, 'maximum static friction F_s'),
        Param('coulomb_friction_n', 'N', 6.03, 0.0, 500.0, 'Coulomb friction F_c'),
        Param('stribeck_velocity_rad_s', 'rad/s', 0.14, 1e-3, 10.0, 'Stribeck speed'),
        Param('viscous_friction_n_s_per_rad', 'N.s/rad', 0.85, 0.0, 100.0,
              'viscous friction coefficient B'),
    )
    mechanics = _stribeck_hook

    @classmethod
    def validate(cls, values):
        if values['static_friction_n'] < values['coulomb_friction_n']:
            raise ConfigError('stribeck_friction: static_friction_n must be >= '
                              'coulomb_friction_n (F_s >= F_c); raise F_s or lower F_c')


@njit(cache=True, allocates=False)
def _coulomb_viscous_hook(t, x, s, p, P, c, dx):
    arm = 0.5 * P[K_DF]
    c[C_FKIN] += arm * coulomb_viscous_force(x[OMEGA], p[0], p[1])
    c[C_FBRK_POS] += arm * p[0]
    c[C_FBRK_NEG] += arm * p[0]
    if abs(x[OMEGA]) <= P[K_ALPHA]:
        edge = arm * coulomb_viscous_force(P[K_ALPHA], p[0], p[1])
        c[C_FEDGE_POS] += edge
        c[C_FEDGE_NEG] += edge


class CoulombViscousFriction(Component):
    """Coulomb + viscous friction: breakaway at F_c, no Stribeck dip."""

    name = 'coulomb_viscous_friction'
    slot = 'friction'
    summary = 'Coulomb + viscous friction (simpler alternative to stribeck_friction)'
    reference = 'textbook simplification'
    acts_on = 'angle'
    params = (
        Param('coulomb_friction_n', 'N', 6.03, 0.0, 500.0, 'Coulomb friction F_c'),
        Param('viscous_friction_n_s_per_rad', 'N.s/rad', 0.85, 0.0, 100.0, 'viscous B'),
    )
    mechanics = _coulomb_viscous_hook


PAPER_COMPONENTS = (OrificeFlow, ClearanceFlow, NoClearanceFlow, WallHeatTransfer, Adiabatic,
                    Isothermal, StribeckFriction, CoulombViscousFriction)
#: The paper's choice in each slot.
PAPER_DEFAULTS = {'orifice': 'orifice_flow', 'clearance': 'clearance_flow',
                  'thermal': 'wall_heat_transfer', 'friction': 'stribeck_friction'}
