"""The DAQ driver interface: raw electrical signals in and out, nothing more. Pure.

A driver reads the analog inputs [V] and the encoder counter [counts, raw,
wrapping at 2**bits] and writes the valve's analog output [V]. Scaling,
counter unwrapping, limits and fault checks live in :mod:`.rigio`, so that
every driver (the NI card, the virtual DAQ, a user's own) shares them.
"""
from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

from ..errors import PneumaticServoError


class DaqError(PneumaticServoError):
    """The DAQ failed (device missing, read or write error); the plant goes safe."""


@dataclass
class RawSample:
    """One read: analog inputs by name [V], and the raw encoder count."""

    volts: dict
    count: int


class DaqDriver(ABC):
    """Raw access to one rig's DAQ. Implementations: :class:`~.nidaq.NiDaqDriver`,
    :class:`~.virtual.VirtualDaq`."""

    #: a short description for diagnostics (device, driver)
    description = 'DAQ'

    @abstractmethod
    def read(self) -> RawSample:
        """Sample all inputs once (raises :class:`DaqError`)."""

    @abstractmethod
    def write(self, volts: float) -> None:
        """Set the valve output [V] (raises :class:`DaqError`)."""

    def close(self) -> None:
        """Release the device (after the caller has written the safe output)."""
