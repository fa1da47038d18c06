"""One row of the fleet table: what the check of one recording found, typed. Its JSON form
(:meth:`Row.to_json`) is what the row store and ``fleet --json`` hold."""
from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields


@dataclass(frozen=True)
class Row:
    """The result of one recording (SI units).

    Attributes
    ----------
    path : str
        The recording (a bag directory or a CSV table).
    rig : str or None
        The rig it came from (see ``discover.rig_of``).
    start_time : str or None
        Its start, ISO 8601 (from the bag).
    key : str
        Content key of the recording, the model config and the options: what a rerun skips.
    status : {'ok', 'error'}
        'error': the recording could not be checked (``error`` says why, on one line).
    error : str or None
    channels : dict
        Channel -> ``rmse``, ``max_abs``, ``fit_percent`` [SI] of the verification's view.
    verify : dict
        ``passed``, ``mode`` and ``checks`` (one row per channel); empty if not verified.
    params : dict
        Tracked ``'owner.name'`` -> ``value`` and ``stderr`` [SI], fitted to this recording.
    verdict : str or None
        The diagnosis's verdict (with ``--diagnose``).
    diagnosis : dict or None
        ``status``, ``verdict`` and ``reason`` of the diagnosis.
    synthetic : bool or None
        The recording says it is synthetic (None: it was not read).
    units : dict
        Channel -> SI unit.
    seconds : float or None
        Time the check took [s].
    """

    path: str
    rig: str | None = None
    start_time: str | None = None
    key: str = ''
    status: str = 'ok'
    error: str | None = None
    channels: dict = field(default_factory=dict)
    verify: dict = field(default_factory=dict)
    params: dict = field(default_factory=dict)
    verdict: str | None = None
    diagnosis: dict | None = None
    synthetic: bool | None = None
    units: dict = field(default_factory=dict)
    seconds: float | None = None

    @property
    def passed(self) -> bool | None:
        """The verification's result (None: not verified)."""
        return self.verify.get('passed')

    @property
    def failed(self) -> bool:
        """An error, or a verification that failed."""
        return self.status == 'error' or self.passed is False

    def to_json(self) -> dict:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> 'Row':
        """The row of a JSON object (a line of the row store); keys it does not know are
        left out, keys it lacks take their defaults."""
        known = {f.name for f in fields(cls)}
        values = {k: v for k, v in data.items() if k in known}
        for name in _MAPPINGS:
            if values.get(name) is None:
                values.pop(name, None)
        return cls(**values)


_MAPPINGS = ('channels', 'verify', 'params', 'units')
