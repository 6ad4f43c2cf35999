"""The measurement type of a row of :class:`satgnc.od.Observations`: the strings ``"range"`` and
``"range_rate"`` as a str enum (issue 17: ``Observations.type`` held the compiled
``MeasurementType`` enums while the docs promised strings).

Compatibility with scripts written against the enums: a member also compares equal to the
``MeasurementType`` member of the same name (with a ``DeprecationWarning``: compare with the string),
has the same ``name``, ``int()`` gives the C++ enumerator, and :attr:`ObservationType.measurement_type`
returns the compiled enum. What changed: ``.value`` is the string (was 0 / 1), ``isinstance(k,
MeasurementType)`` is False, ``MeasurementType.range == k`` (the enum on the left) is False, and
``np.array(obs.type)`` is an array of strings (compare it with ``"range"``).
"""

from __future__ import annotations

import enum
import warnings
from typing import Any

from . import _satgnc as _c


class ObservationType(str, enum.Enum):
    """Measurement type of an observation row: ``"range"`` (km) or ``"range_rate"`` (km/s).

    A ``str``: ``k == "range"``, ``str(k) == "range"``, f-strings and CSV print the name. Comparing
    with the deprecated ``satgnc.od.MeasurementType`` members still works and warns."""

    range = "range"
    range_rate = "range_rate"

    def __str__(self) -> str:
        return str(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, _c.MeasurementType):
            warnings.warn(
                "Observations.type holds strings now (ObservationType): compare with 'range' / "
                "'range_rate' instead of satgnc.od.MeasurementType",
                DeprecationWarning,
                stacklevel=2,
            )
            return self.name == other.name
        return str.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self.__eq__(other)

    __hash__ = str.__hash__  # equal to its string, so it hashes like it (dict and set lookups by "range")

    def __int__(self) -> int:
        return int(self.measurement_type)

    @property
    def measurement_type(self) -> Any:
        """The compiled ``MeasurementType`` member of the same name (what the C++ solvers take)."""
        return _c.MeasurementType.__members__[self.name]

    @classmethod
    def of(cls, kind: Any) -> ObservationType:
        """``kind`` (a str, a ``MeasurementType`` or an ObservationType) as an ObservationType."""
        if isinstance(kind, cls):
            return kind
        if isinstance(kind, _c.MeasurementType):
            return cls[kind.name]
        return cls(str(kind))
