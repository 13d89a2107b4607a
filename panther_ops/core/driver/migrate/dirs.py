"""The directories a migration creates in the config tree, and that its way back removes.

2.3.2 reads the gamepad file from ``husarion_ugv_teleop/config/``, a package directory a 2.2
tree does not have: the migration writes a file there (the write creates the directories), the
way back (and the rollback of a migration whose driver fails) removes the file and, with
:data:`RMDIR_EMPTY`, each such directory left empty, deepest first. ``rmdir`` removes only empty
directories: one that holds anything else stays.
"""

from __future__ import annotations

import posixpath
from collections.abc import Iterable

DIRS_KEY = "remove_if_empty"
"""The plan data key: the directories to remove once empty (the way back: after it is applied;
a migration: after its rollback)."""
RMDIR_EMPTY = 'r="${PANTHER_OPS_ROOT:-}"; for d; do rmdir -- "$r$d" 2>/dev/null; done; exit 0'
"""$@ = directories, deepest first: each removed if empty (else kept, silently)."""


def dirs_of(removed: Iterable[str], kept: Iterable[str], tree: str | None) -> list[str]:
    """The directories under ``tree`` (not itself) that hold only files in ``removed``: each file's
    parents below the tree, without the parents of a file in ``kept``, deepest first."""
    if not tree:
        return []
    root = tree.rstrip("/")
    busy = {d for path in kept for d in _parents(path, root)}
    out = {d for path in removed for d in _parents(path, root) if d not in busy}
    return sorted(out, key=lambda d: (-d.count("/"), d))


def _parents(path: str, root: str) -> list[str]:
    out: list[str] = []
    d = posixpath.dirname(path)
    while d.startswith(root + "/"):
        out.append(d)
        d = posixpath.dirname(d)
    return out
