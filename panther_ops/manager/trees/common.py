"""Helpers to write conditions and scripts of the Python-built trees."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from panther_ops.manager.bt.expression import Env
from panther_ops.manager.nodes.base import PyProgram


class Values:
    """Attribute access to blackboard entries: ``v.battery_status``."""

    def __init__(self, env: Env) -> None:
        self._env = env

    def __getattr__(self, name: str) -> Any:
        return self._env.get(name)


def check(text: str, reads: str, fn: Callable[[Values], bool]) -> PyProgram:
    """A condition: `reads` is the space-separated list of entries `fn` reads."""
    return PyProgram(text, lambda env: fn(Values(env)), reads=reads.split())


def assign(**targets: str) -> PyProgram:
    """A script copying entries: ``assign(current_anim_id="ERROR_ANIM_ID")``."""

    def run(env: Env) -> None:
        for target, source in targets.items():
            env.set(target, env.get(source))

    text = "; ".join(f"{t} = {s}" for t, s in targets.items())
    return PyProgram(text, run, reads=targets.values(), writes=targets.keys())
