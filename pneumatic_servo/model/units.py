"""Unit strings in config files: '0.6 MPa gauge', '5 cm^3', '2 mm' -> SI.

Only the edges convert; inside, everything is SI with absolute pressure.
"""
import math
import re

from ..errors import ConfigError

#: symbol -> (SI unit it converts to, factor)
_UNITS = {
    'Pa': ('Pa', 1.0), 'kPa': ('Pa', 1e3), 'MPa': ('Pa', 1e6), 'bar': ('Pa', 1e5),
    'mbar': ('Pa', 1e2), 'psi': ('Pa', 6894.757),
    'm': ('m', 1.0), 'cm': ('m', 1e-2), 'mm': ('m', 1e-3), 'um': ('m', 1e-6),
    'm^2': ('m^2', 1.0), 'cm^2': ('m^2', 1e-4), 'mm^2': ('m^2', 1e-6),
    'm^3': ('m^3', 1.0), 'L': ('m^3', 1e-3), 'l': ('m^3', 1e-3), 'ml': ('m^3', 1e-6),
    'cm^3': ('m^3', 1e-6), 'mm^3': ('m^3', 1e-9),
    's': ('s', 1.0), 'ms': ('s', 1e-3), 'us': ('s', 1e-6),
    'rad': ('rad', 1.0), 'deg': ('rad', math.pi / 180.0),
    'rad/s': ('rad/s', 1.0), 'deg/s': ('rad/s', math.pi / 180.0),
    'K': ('K', 1.0), 'N': ('N', 1.0), 'N.m': ('N.m', 1.0), 'Nm': ('N.m', 1.0),
    'kg': ('kg', 1.0), 'g': ('kg', 1e-3), 'kg.m^2': ('kg.m^2', 1.0),
    'g.cm^2': ('kg.m^2', 1e-7), 'V': ('V', 1.0), 'mV': ('V', 1e-3),
}
_PATTERN = re.compile(r'^\s*([-+0-9.eE]+)\s*([A-Za-z^/.0-9]+)\s*(gauge|abs)?\s*$')


def to_si(value, unit: str, where: str, atmospheric_pa: float = 101325.0) -> float:
    """Convert a config ``value`` (number, or string with a unit) to the SI ``unit``.

    Numbers are taken as already in SI. Strings like ``'0.6 MPa gauge'`` or
    ``'45 deg'`` are converted; ``degC`` converts to K. ``where`` names the
    setting in error messages.
    """
    if isinstance(value, bool):
        raise ConfigError(f'{where}: expected a number in {unit}, got {value!r}')
    if isinstance(value, (int, float)):
        return float(value)
    if not isinstance(value, str):
        raise ConfigError(f'{where}: expected a number in {unit}, got {value!r}')
    text = value.strip()

    def unreadable():
        return ConfigError(f"{where}: cannot read {value!r}; write a number in {unit} "
                           f"or a value with a unit such as '1.5 {unit}'")

    def number_of(digits: str) -> float:
        try:
            return float(digits)
        except ValueError:                      # '-', '1..2', 'e': the pattern's characters
            raise unreadable() from None

    m_c = re.match(r'^\s*([-+0-9.eE]+)\s*degC\s*$', text)
    if m_c and unit == 'K':
        return number_of(m_c.group(1)) + 273.15
    m = _PATTERN.match(text)
    if not m:
        try:
            return float(text)
        except ValueError:
            raise unreadable() from None
    number, symbol, ref = number_of(m.group(1)), m.group(2), m.group(3)
    if symbol not in _UNITS:
        raise ConfigError(f"{where}: unknown unit {symbol!r} in {value!r}; "
                          f"{where.rsplit('.', 1)[-1]} is in {unit}")
    si_unit, factor = _UNITS[symbol]
    if si_unit != unit:
        raise ConfigError(f'{where}: {value!r} is in {si_unit} but this setting is in {unit}; '
                          f'give a value in {unit}')
    result = number * factor
    if ref == 'gauge':
        if unit != 'Pa':
            raise ConfigError(f"{where}: 'gauge' only applies to pressures")
        result += atmospheric_pa
    return result


_EXAMPLES = {'Pa': "'0.6 MPa gauge' or 701325", 'm^3': "'5 cm^3' or 5e-6", 'm': "'2 mm' or 0.002",
             'm^2': "'0.5 mm^2' or 5e-7", 's': "'5 ms' or 0.005", 'rad': "'45 deg' or 0.785",
             'K': "'20 degC' or 293.15"}


def unit_hint(unit: str) -> str:
    """How to write a value of ``unit`` correctly, for error messages."""
    example = _EXAMPLES.get(unit)
    text = f'give it in SI ({unit})'
    return text + (f' or with a unit, e.g. {example}' if example else '')
