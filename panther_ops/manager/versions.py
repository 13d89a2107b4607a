"""Stack versions as the manager and its planners compare them: ``(2, 3, 2)``, and the lookup of
what a release has from a table of the releases each value starts at."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TypeVar

Version = tuple[int, int, int]
T = TypeVar("T")


def by_release(version: Version, since: Sequence[tuple[Version, T]], older: T) -> T:
    """The value of the first entry of ``since`` (the release it starts at, the value; newest
    first) that ``version`` has reached; ``older`` for a version before all of them."""
    return next((value for first, value in since if version >= first), older)
