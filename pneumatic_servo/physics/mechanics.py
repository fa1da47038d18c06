"""The shaft: inertia of the rack-and-pinion drive (Eq. 37). SI units."""
from .._jit import njit


@njit(cache=True)
def shaft_inertia(piston_mass_kg, pitch_diameter_m, gear_inertia_kg_m2):
    """Moment of inertia [kg.m^2] on the shaft: the gear's, plus two pistons of mass m_p
    moving at d_f / 2 times the shaft speed, 2 m_p (d_f / 2)^2 = m_p d_f^2 / 2."""
    return 0.5 * piston_mass_kg * pitch_diameter_m ** 2 + gear_inertia_kg_m2
