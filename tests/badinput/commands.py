"""Every command and subcommand of panther-ops, discovered from the typer application.

Tests walk this list rather than a hard-coded one, so a new command is covered the day it
is registered.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from panther_ops.cli.app import full_command


@dataclass(frozen=True)
class Command:
    """One runnable command: its words and its parameters (click's objects)."""

    words: tuple[str, ...]
    params: tuple[Any, ...]

    def __str__(self) -> str:
        return " ".join(self.words)

    @property
    def arguments(self) -> list[Any]:
        return [p for p in self.params if p.param_type_name == "argument"]

    @property
    def options(self) -> list[Any]:
        return [p for p in self.params if p.param_type_name == "option" and "--help" not in p.opts]

    def option(self, name: str) -> Any | None:
        return next((p for p in self.options if name in p.opts), None)

    @property
    def value_options(self) -> list[Any]:
        """Options that take a value (not flags, not counters)."""
        return [p for p in self.options if not p.is_flag and not getattr(p, "count", False)]


def _walk(cmd: Any, words: tuple[str, ...]) -> Iterator[Command]:
    own = [p for p in cmd.params if "--help" not in getattr(p, "opts", ())]
    subs = getattr(cmd, "commands", None)
    if subs is None or (words and own):  # a leaf, or a group that runs by itself (shutdown --hosts)
        yield Command(words, tuple(cmd.params))
    for name, sub in (subs or {}).items():
        yield from _walk(sub, (*words, name))


def every_command() -> list[Command]:
    """Every command and subcommand (groups with options of their own included)."""
    return list(_walk(full_command(), ()))
