"""A secret value: passed to the robot, never shown (in a log, a table, a diff)."""

from __future__ import annotations


class Secret:
    """A value that must reach the robot but never a log, a table or a diff."""

    __slots__ = ("_value",)

    def __init__(self, value: str) -> None:
        self._value = value

    def reveal(self) -> str:
        return self._value

    def __repr__(self) -> str:
        return "Secret('****')"

    def __str__(self) -> str:
        return "****"
