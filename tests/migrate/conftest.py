"""The demo fleet fixture of the unit tests (a fresh demo fleet per test)."""
from __future__ import annotations

from tests.unit.conftest import demo

__all__ = ["demo"]
