"""The balance laws that every model shares: chamber mass and energy, moment balance.

Components add into the totals of the context vector; these kernels set up
the context from state and inputs, then turn the totals into derivatives.
Equations (SI, absolute pressure), per chamber with volume V and net inflow
m_dot, enthalpy inflow H, heat inflow Q:

    m c_v dT/dt = H - c_v T m_dot - p dV/dt + Q                (Eq. 31)
    dp/dt = (R T m_dot + m R dT/dt - p dV/dt) / V, m = pV/(RT) (Eq. 32)

and for the shaft (Eq. 37 with Eqs 34-36):

    J_tot dw/dt = A d_f (p_a - p_b) + tau_ext - tau_friction
"""
import numpy as np

from .._jit import njit
from ..effects.layout import (
    BLOCKED,
    C_CIRCUIT,
    C_CP,
    C_CV,
    C_DVA,
    C_DVB,
    C_FBRK_NEG,
    C_FBRK_POS,
    C_FEDGE_NEG,
    C_FEDGE_POS,
    C_FKIN,
    C_HA,
    C_HB,
    C_INERTIA,
    C_ISOTHERMAL,
    C_KAPPA,
    C_M4,
    C_MA,
    C_MB,
    C_PE,
    C_PS,
    C_PS_REG,
    C_QA,
    C_QB,
    C_R,
    C_T,
    C_TE,
    C_TORQUE,
    C_TS,
    C_U,
    C_VA,
    C_VB,
    C_XV,
    FLOW,
    K_ALPHA,
    K_AREA,
    K_BLOCKED,
    K_DF,
    K_GAIN,
    K_HALF_W,
    K_HOLE_R,
    K_J,
    K_KAPPA,
    K_MP,
    K_NULL,
    K_OUTLET,
    K_PE,
    K_R,
    K_STROKE,
    K_TE,
    K_TS,
    K_VDA,
    K_VDB,
    K_VVALVE,
    OMEGA,
    P_A,
    P_B,
    SERVO,
    T_A,
    T_B,
    THETA,
    add_flow,
)
from ..physics.gas import ideal_critical_ratio, orifice_flow
from ..physics.mechanics import shaft_inertia
from ..physics.valve import spool_displacement

#: [s] time constant with which a stuck shaft's residual velocity inside the
#: stiction band decays to zero, so that sticking stores no drift; also how
#: fast an isothermal chamber's gas returns to the wall temperature.
HOLD_TIME_CONSTANT_S = 1e-3


@njit(cache=True, allocates=False)
def core_begin(t, x, u, ps, P, circuit, c, dx):
    """Fill the context from time, state and inputs; zero all totals and derivatives."""
    c[:] = 0.0
    dx[:] = 0.0
    r, k = P[K_R], P[K_KAPPA]
    c[C_T], c[C_U], c[C_PS], c[C_PS_REG] = t, u, ps, ps
    c[C_TS], c[C_PE], c[C_TE] = P[K_TS], P[K_PE], P[K_TE]
    c[C_R], c[C_KAPPA], c[C_CV], c[C_CP] = r, k, r / (k - 1.0), k * r / (k - 1.0)
    c[C_CIRCUIT] = circuit
    c[C_XV] = spool_displacement(u, P[K_NULL], P[K_GAIN], P[K_HALF_W] + P[K_HOLE_R])
    c[C_INERTIA] = shaft_inertia(P[K_MP], P[K_DF], P[K_J])
    swept = P[K_AREA] * P[K_DF]  # dV_a/dtheta (docs/model.md, settlement 2)
    if circuit == SERVO:
        th = min(max(x[THETA], 0.0), P[K_STROKE])
        c[C_VA] = P[K_VDA] + swept * th
        c[C_VB] = P[K_VDB] + swept * (P[K_STROKE] - th)
        c[C_DVA] = swept * x[OMEGA]
        c[C_DVB] = -swept * x[OMEGA]
    elif circuit == BLOCKED:
        th = P[K_BLOCKED]
        c[C_VA] = P[K_VDA] + swept * th
        c[C_VB] = P[K_VDB] + swept * (P[K_STROKE] - th)
    else:  # closed_port, flow: the valve chamber alone
        c[C_VA] = P[K_VVALVE]
        c[C_VB] = P[K_VVALVE]


@njit(cache=True, allocates=False)
def _chamber(p, temp, vol, dvol, mdot, hdot, qdot, r, cv, isothermal, t_wall):
    """(dp/dt [Pa/s], dT/dt [K/s]) of one chamber from its totals."""
    mass = p * vol / (r * temp)
    if isothermal:  # the gas is held at the wall temperature (relaxes there within ~ms)
        dtemp = (t_wall - temp) / HOLD_TIME_CONSTANT_S
    else:
        dtemp = (hdot - cv * temp * mdot - p * dvol + qdot) / (mass * cv)
    dp = (r * temp * mdot + mass * r * dtemp - p * dvol) / vol
    return dp, dtemp


@njit(cache=True, allocates=False)
def core_end(t, x, P, circuit, c, dx):
    """Turn the totals into state derivatives: chambers, then the shaft."""
    r, cv = c[C_R], c[C_CV]
    iso = c[C_ISOTHERMAL] > 0.5
    if circuit == FLOW:  # port 4 open to atmosphere through the flow meter
        kappa = c[C_KAPPA]
        m4 = orifice_flow(P[K_OUTLET], x[P_A], x[T_A], c[C_PE], c[C_TE],
                          ideal_critical_ratio(kappa), r, kappa, 0.005)
        add_flow(c, 0, -m4, c[C_TE], x[T_A])
        c[C_M4] = m4
    dx[P_A], dx[T_A] = _chamber(x[P_A], x[T_A], c[C_VA], c[C_DVA], c[C_MA], c[C_HA], c[C_QA],
                                r, cv, iso, c[C_TE])
    if circuit <= BLOCKED:
        dx[P_B], dx[T_B] = _chamber(x[P_B], x[T_B], c[C_VB], c[C_DVB], c[C_MB], c[C_HB],
                                    c[C_QB], r, cv, iso, c[C_TE])
    if circuit != SERVO:
        return
    w = x[OMEGA]
    drive = P[K_AREA] * P[K_DF] * (x[P_A] - x[P_B]) + c[C_TORQUE]
    inertia = c[C_INERTIA]
    if abs(w) <= P[K_ALPHA]:  # stiction band, Eq. 34
        # breaking away takes at least the sliding friction at the band edge: otherwise a
        # drive between the two would chatter along the edge (a Karnopp sliding mode)
        brk_pos = max(c[C_FBRK_POS], c[C_FEDGE_POS])
        brk_neg = max(c[C_FBRK_NEG], c[C_FEDGE_NEG])
        if -brk_neg <= drive <= brk_pos:
            acc = -w / HOLD_TIME_CONSTANT_S
        elif drive > 0.0:
            acc = (drive - brk_pos) / inertia
        else:
            acc = (drive + brk_neg) / inertia
    else:
        acc = (drive - c[C_FKIN]) / inertia
    th = x[THETA]
    # end stops: the stop reacts whatever pushes into it
    if (th <= 0.0 and w <= 0.0 and acc < 0.0) or (th >= P[K_STROKE] and w >= 0.0 and acc > 0.0):
        acc = -w / HOLD_TIME_CONSTANT_S
    dx[THETA] = w
    dx[OMEGA] = acc


def nan_on_math_error(rhs):
    """Plain Python raises where compiled code yields NaN (the square root of a negative
    temperature in a wild trial step): make it NaN too, so the integrator reports a failed
    simulation instead of the process dying. Used when compilation is off."""
    def safe(t, x, u, ps, P, circuit, c, dx):
        try:
            rhs(t, x, u, ps, P, circuit, c, dx)
        except (ValueError, ZeroDivisionError, OverflowError):
            dx[:] = np.nan
    return safe
