"""The deployed manager's files on the robot, its state file, and how a deploy plan is shown."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import posixpath
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.fleet.plan import FileEdit, RobotPlan
from panther_ops.core.manager_ops.bundle import ARCHIVE_NAME
from panther_ops.core.manager_ops.settings import CONTAINER_DIR, ROBOT_DIR, STATE_FILE
from panther_ops.results import Diff


# ---------------------------------------------------------------------------------------
# layout on the robot
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Layout:
    """Paths of one deployment, on the robot and inside the container."""

    home: str
    version: str

    @property
    def root(self) -> str:
        return f"{self.home}/{ROBOT_DIR}"

    @property
    def state(self) -> str:
        return state_path(self.home)

    @property
    def archive(self) -> str:
        return f"{self.root}/{self.version}/{ARCHIVE_NAME}"

    @property
    def container_archive(self) -> str:
        return f"{CONTAINER_DIR}/{self.version}/{ARCHIVE_NAME}"

    def config(self, *parts: str) -> str:
        return posixpath.join(self.root, "config", *parts)

    def container_config(self, *parts: str) -> str:
        return posixpath.join(CONTAINER_DIR, "config", *parts)


def state_path(home: str) -> str:
    """``deployed.json`` on the robot."""
    return f"{home}/{ROBOT_DIR}/{STATE_FILE}"


def parse_state(data: bytes | None) -> dict[str, Any] | None:
    """``deployed.json`` as read (None: nothing deployed, or unreadable)."""
    if data is None:
        return None
    try:
        doc = json.loads(data)
    except ValueError:
        return None
    return doc if isinstance(doc, dict) else None


def _state_bytes(doc: Mapping[str, Any]) -> bytes:
    return (json.dumps(doc, indent=2, sort_keys=True) + "\n").encode()


@dataclass
class ManagerPlan(RobotPlan):
    """A plan whose uploaded copies show as one line each instead of a full diff.

    The archive is binary and the BT projects are the shipped templates: the operator reads
    compose.yaml, manager.yaml and deployed.json in full, the rest as what and how big.
    """

    briefs: dict[str, str] = field(default_factory=dict)

    @property
    def diffs(self) -> list[Diff]:
        return [Diff(e.path, self.briefs[e.path]) if e.path in self.briefs else e.diff() for e in self.edits]


def _size(n: int) -> str:
    return f"{n} B" if n < 1024 else (f"{n / 1024:.1f} KiB" if n < 1024 * 1024 else f"{n / 1048576:.1f} MiB")


def brief(edit: FileEdit, what: str) -> str:
    """A one-line stand-in for the diff of a file written as a whole (or removed)."""
    if edit.after is None:
        return f"--- a{edit.path}\n+++ /dev/null\n@@ removed: {_size(len(edit.before or b''))} @@\n"
    old = "/dev/null" if edit.before is None else f"a{edit.path}"
    sha = hashlib.sha256(edit.after).hexdigest()[:12]
    verb = "new file" if edit.before is None else "replaced"
    return f"--- {old}\n+++ b{edit.path}\n@@ {verb}: {_size(len(edit.after))}, sha256 {sha} @@\n+{what}\n"


def as_manager_plan(plan: RobotPlan, briefs: Mapping[str, str]) -> ManagerPlan:
    values = {f.name: getattr(plan, f.name) for f in dataclasses.fields(RobotPlan)}
    return ManagerPlan(**values, briefs=dict(briefs))
