"""Findings: what the validators report, one distinct message per rule."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class Severity(str, Enum):
    """How bad a finding is: an error makes the file unusable, a warning does not."""

    ERROR = "error"
    WARNING = "warning"


@dataclass(frozen=True)
class Finding:
    """One problem found in a file.

    Attributes:
        severity: error or warning.
        code: a stable rule identifier (e.g. ``anim-id-reserved``), for tests and filters.
        message: one line for an operator: what is wrong and what is allowed.
        where: the file, and the element or key inside it, when known.
    """

    severity: Severity
    code: str
    message: str
    where: str = ""

    def __str__(self) -> str:
        prefix = f"{self.where}: " if self.where else ""
        return f"{prefix}{self.severity.value}: {self.message} [{self.code}]"


def error(code: str, message: str, where: str = "") -> Finding:
    """An error finding."""
    return Finding(Severity.ERROR, code, message, where)


def warning(code: str, message: str, where: str = "") -> Finding:
    """A warning finding."""
    return Finding(Severity.WARNING, code, message, where)


def has_errors(findings: list[Finding]) -> bool:
    """True when at least one finding is an error."""
    return any(f.severity is Severity.ERROR for f in findings)
