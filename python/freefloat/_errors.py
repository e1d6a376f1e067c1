"""The exceptions of freefloat. Each carries the library's message (``str(e)``, ``e.message``),
the name of the library's error (``e.kind``, e.g. ``"invalid_parameter"``) and its numbers
(``e.numbers``, a dict; radians, seconds: the ``numbers`` of the command line's JSON error
object; ``e.details`` is the same dict, its earlier name)."""

from __future__ import annotations

from typing import Any, Mapping, Optional


class FreefloatError(Exception):
    """Base class of every error raised by freefloat."""

    message: str
    kind: str
    numbers: dict[str, Any]
    details: dict[str, Any]

    def __init__(self, message: str, *, kind: str = "", details: Optional[Mapping[str, Any]] = None) -> None:
        super().__init__(message)
        self.message = message
        self.kind = kind
        self.numbers = dict(details or {})
        self.details = self.numbers


class BadInput(FreefloatError, ValueError):
    """The input is at fault (the CLI's exit code 2): a parameter out of range, an unknown
    option, an unreadable robot file, a transformation that does not apply to this robot, a
    keyword that does not apply to this robot (``transform`` for an :class:`freefloat.Arm`). A
    ``ValueError``, so ``except ValueError`` catches it too.

    ``name``, ``value`` and ``expected`` are set for a rejected parameter, else None."""

    name: Optional[str]
    value: Any
    expected: Optional[str]

    def __init__(self, message: str, *, kind: str = "", details: Optional[Mapping[str, Any]] = None) -> None:
        super().__init__(message, kind=kind, details=details)
        self.name = self.details.get("name")
        self.value = self.details.get("value")
        self.expected = self.details.get("expected")


class NoPlan(FreefloatError):
    """The method has no plan for this problem (the CLI's exit code 3): start or goal outside
    the domain of the transformation, in different components, a path leaving the domain,
    Newton's method or the ECSA iteration not converging, ... ``details`` holds the numbers."""


class NotCertified(FreefloatError):
    """A plan was computed, but its verification exceeds the tolerance.

    ``final_error`` and ``tolerance`` are in rad; ``level`` is ``"velocity"`` (system (7)
    integrated with the planned controls) or ``"torque"`` (the full dynamics with the planned
    torques); ``plan`` is the uncertified :class:`freefloat.Plan`."""

    final_error: float
    tolerance: float
    level: str
    plan: Any

    def __init__(
        self,
        message: str,
        *,
        kind: str = "not_certified",
        details: Optional[Mapping[str, Any]] = None,
        plan: Any = None,
    ) -> None:
        super().__init__(message, kind=kind, details=details)
        self.final_error = float(self.details.get("final_error", float("nan")))
        self.tolerance = float(self.details.get("tolerance", float("nan")))
        self.level = str(self.details.get("level", ""))
        self.plan = plan
