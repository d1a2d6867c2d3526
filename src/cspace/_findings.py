"""Findings: what a robot file can still be analysed with, each with a stable code.

The record (`Diagnostic`), its severity, and the one table of codes
(`CODES`), used by every layer that finds something: the format readers, the
analysis (`diagnostics` lists every code and its meaning) and the
report.
"""

from __future__ import annotations

from enum import Enum
from typing import Any, NamedTuple

from cspace.errors import printable


class Severity(str, Enum):
    """How serious a finding is. Errors make ``cspace inspect`` exit 1."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


class Diagnostic(NamedTuple):
    """One finding about a file that could still be analysed.

    Attributes:
        severity: error, warning or info.
        code: Stable identifier, e.g. ``"joint-locked"``; usable with ``--ignore``.
        joint: The joint it is about, or None for the whole robot.
        message: One sentence a person understands.
        line: The line of the element it is about in the file (the ``<limit>`` or the
            ``<axis>`` when it is about one, else the joint's), or None.
    """

    severity: Severity
    code: str
    joint: str | None
    message: str
    line: int | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this finding."""
        return {
            "severity": self.severity.value,
            "code": self.code,
            "joint": self.joint,
            "message": self.message,
            "line": self.line,
        }


CODES: dict[str, Severity] = {
    "limits-empty": Severity.ERROR,
    "limits-not-finite": Severity.ERROR,
    "axis-invalid": Severity.ERROR,
    "number-invalid": Severity.ERROR,
    "joint-locked": Severity.WARNING,
    "continuous-has-limits": Severity.WARNING,
    "mimic-limits-contradict": Severity.WARNING,
    "mimic-not-periodic": Severity.WARNING,
    "mimic-ignored": Severity.WARNING,
    "revolute-ambiguous-range": Severity.WARNING,
    "axis-normalized": Severity.WARNING,
    "multi-turn": Severity.INFO,
    "euler-coordinates": Severity.INFO,
    "axis-default": Severity.INFO,
    "root-joint-added": Severity.INFO,
    "mimic-kept-free": Severity.INFO,
    "ball-range-whole": Severity.INFO,
    "parser-message": Severity.INFO,
    "findings-truncated": Severity.INFO,
    "equality-joint": Severity.INFO,
    "equality-mimic": Severity.INFO,
    "equality-weld": Severity.INFO,
    "equality-connect": Severity.INFO,
    "equality-tendon": Severity.INFO,
    "name-made-up": Severity.INFO,
    "xml-version": Severity.INFO,
    "limits-in-degrees": Severity.WARNING,
    "limit-bound-missing": Severity.WARNING,
    "root-joint-suggested": Severity.INFO,
    "sdf-link-floats": Severity.INFO,
    "read-beyond-folder": Severity.INFO,
    "xml-lenient": Severity.INFO,
}
"""Every diagnostic code and its severity."""


def finding(code: str, joint: str | None, message: str, line: int | None = None) -> Diagnostic:
    """A diagnostic with the severity its code carries; its message is one printable line."""
    return Diagnostic(CODES[code], code, joint, printable(message), line)
