"""Fixed indices shared by the core and the components: states, context, core parameters.

Units: SI throughout, pressures absolute.
"""
from .._jit import njit
from .base import Param

# --- core states -----------------------------------------------------------
THETA, OMEGA, P_A, P_B, T_A, T_B = range(6)
CORE_STATE_NAMES = ('angle_rad', 'velocity_rad_s', 'p_a_pa', 'p_b_pa', 't_a_k', 't_b_k')
CORE_STATE_ABS_TOL = (1e-6, 1e-4, 5.0, 5.0, 1e-3, 1e-3)
N_CORE_STATES = 6

# --- circuits (paper's test rigs) -------------------------------------------
SERVO, BLOCKED, CLOSED_PORT, FLOW = range(4)
CIRCUITS = {'servo': SERVO, 'blocked': BLOCKED, 'closed_port': CLOSED_PORT, 'flow': FLOW}

# --- context vector: inputs, named totals and outputs -------------------------
(C_T, C_U, C_XV, C_PS, C_TS, C_PE, C_TE, C_R, C_KAPPA, C_CV, C_CP,
 C_VA, C_VB, C_DVA, C_DVB,
 C_MA, C_MB, C_HA, C_HB, C_QA, C_QB, C_MSUP,
 C_TORQUE, C_INERTIA, C_FKIN, C_FBRK_POS, C_FBRK_NEG, C_ISOTHERMAL,
 C_M4, C_M5, C_CIRCUIT, C_PS_REG, C_FEDGE_POS, C_FEDGE_NEG, N_CONTEXT) = range(35)
#: context entries recorded as simulation outputs, with names and units
OUTPUTS = (C_XV, C_PS, C_M4, C_M5, C_MSUP)
OUTPUT_NAMES = ('spool_position_m', 'valve_supply_pressure_pa', 'm4_kg_s', 'm5_kg_s',
                'supply_mass_flow_kg_s')


@njit(cache=True, allocates=False)
def add_flow(c, chamber, mdot, t_source, t_chamber):
    """Add signed mass flow ``mdot`` [kg/s] into ``chamber`` (0 = a, 1 = b) with its enthalpy.

    Inflow brings c_p * ``t_source``; outflow takes c_p * ``t_chamber``.
    """
    t = t_source if mdot > 0.0 else t_chamber
    c[C_MA + chamber] += mdot
    c[C_HA + chamber] += c[C_CP] * t * mdot


# --- core parameters: geometry, environment, valve geometry, circuits --------
CORE_PARAMS = (
    Param('piston_area_m2', 'm^2', 3.4636e-4, 1e-6, 1e-1, 'effective area A of one piston'),
    Param('pinion_pitch_diameter_m', 'm', 0.014, 1e-3, 1.0, 'pitch diameter d_f of the pinion'),
    Param('piston_mass_kg', 'kg', 0.210, 0.0, 100.0, 'mass m_p of one piston'),
    Param('gear_inertia_kg_m2', 'kg.m^2', 1.678e-4, 0.0, 10.0, 'moment of inertia J of the gear'),
    Param('dead_volume_a_m3', 'm^3', 5.0e-6, 1e-8, 1e-2,
          'volume of chamber a (with valve chamber and tubing) at theta = 0'),
    Param('dead_volume_b_m3', 'm^3', 5.0e-6, 1e-8, 1e-2,
          'volume of chamber b (with valve chamber and tubing) at theta = theta_max'),
    Param('stroke_rad', 'rad', 3.31613, 0.1, 6.5,
          'stroke theta_max; theta = 0 where a is smallest'),
    Param('atmospheric_pressure_pa', 'Pa', 101325.0, 5e4, 1.2e5, 'atmospheric pressure p_e'),
    Param('supply_pressure_pa', 'Pa', 701325.0, 1.1e5, 2.0e6,
          'supply pressure p_s (absolute) used when no measured supply is given'),
    Param('supply_temperature_k', 'K', 293.15, 200.0, 400.0, 'supply gas temperature T_s'),
    Param('room_temperature_k', 'K', 293.15, 200.0, 400.0, 'room and wall temperature T_e'),
    Param('gas_constant_j_per_kg_k', 'J/(kg.K)', 287.0, 200.0, 400.0, 'specific gas constant R'),
    Param('heat_capacity_ratio', '1', 1.4, 1.01, 1.7, 'isentropic index kappa'),
    Param('stiction_velocity_band_rad_s', 'rad/s', 1e-3, 1e-6, 0.1,
          'velocity band alpha within which the shaft can stick (Eq. 34)'),
    Param('spool_gain_m_per_v', 'm/V', 2e-4, 1e-6, 1e-2, 'spool travel per volt (Eq. 39)'),
    Param('valve_null_voltage_v', 'V', 5.0, 0.0, 10.0, 'nominal valve centre voltage'),
    Param('spool_shoulder_half_width_m', 'm', 1.010e-3, 1e-5, 1e-2,
          'half width a of the shoulder'),
    Param('hole_radius_m', 'm', 1.000e-3, 1e-5, 1e-2, 'radius r of a sleeve hole'),
    Param('spool_diameter_m', 'm', 6.000e-3, 1e-4, 0.1, 'diameter d_s of the spool shoulder'),
    Param('sleeve_bore_diameter_m', 'm', 6.023e-3, 1e-4, 0.1, 'inner diameter d_h of the sleeve'),
    Param('gas_viscosity_pa_s', 'Pa.s', 1.83e-5, 1e-6, 1e-4, 'dynamic viscosity mu of air'),
    Param('valve_chamber_volume_m3', 'm^3', 1.0e-6, 1e-9, 1e-3,
          'volume of the valve chamber alone (closed_port and flow circuits)'),
    Param('flow_outlet_area_m2', 'm^2', 2.0e-6, 1e-9, 1e-3,
          'effective area of port 4 and the flow meter to atmosphere (flow circuit)'),
    Param('blocked_angle_rad', 'rad', 0.0, 0.0, 6.5,
          'angle at which the pistons are held (blocked circuit)'),
)
CORE_INDEX = {p.name: i for i, p in enumerate(CORE_PARAMS)}
(K_AREA, K_DF, K_MP, K_J, K_VDA, K_VDB, K_STROKE, K_PE, K_PS, K_TS, K_TE, K_R, K_KAPPA,
 K_ALPHA, K_GAIN, K_NULL, K_HALF_W, K_HOLE_R, K_DS, K_DH, K_MU, K_VVALVE, K_OUTLET,
 K_BLOCKED) = range(len(CORE_PARAMS))
N_CORE_PARAMS = len(CORE_PARAMS)
