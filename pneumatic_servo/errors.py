"""The package's exceptions. Each message is one line that names the fix."""


class PneumaticServoError(Exception):
    """Base class: a problem with user input that the user can fix."""


class ConfigError(PneumaticServoError):
    """A bad parameter, unit, component name or config file."""


class ExperimentError(PneumaticServoError):
    """A bad, incomplete or unreadable recorded experiment (bag or CSV)."""


class SimulationError(PneumaticServoError):
    """The simulation could not produce a finite, physical result."""


class EffectError(SimulationError):
    """A component's own code failed in a simulation (its hook raised, could not be compiled,
    or gave NaN): the message names the component and its error."""
