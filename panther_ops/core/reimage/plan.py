"""The planner of `reimage restore` (pure): a backup archive back onto the reinstalled robot, through the pipeline.

The archive is read and checked first (its manifest, then every member against it: name, type,
size, mode, sha256; anything else refuses the whole archive); the plan then
reads the robot's files as a backup would and writes back every file of the robot user's home
that differs (content or mode) as one plan with exact diffs: the key pair, known_hosts and
authorized_keys, the config tree, mounted files, the deployed manager and the compose file,
then recreates the driver, and the services the compose file gets back (the manager, an
nmea-gps service: defined in the backup's compose file, not in the reinstalled one), and
verifies them. Onto a newer release of the same line the new
compose file is kept and the backup's customisations are re-applied onto it (``reapply``);
across release lines restore is refused with exit 2. The archive and the robot are read by
`read.py`.
"""

from __future__ import annotations

import hashlib
import posixpath
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.reimage.reapply import reapply, same_line
from panther_ops.core.stack import parse_version
from panther_ops.core.yaml.diff import unified_diff
from panther_ops.errors import UsageError
from panther_ops.results import Diff


@dataclass(frozen=True)
class BackupFile:
    path: str
    mode: int
    data: bytes
    secret: bool = False


@dataclass(frozen=True)
class SecretFileEdit(FileEdit):
    """A FileEdit whose diff names the secret's size and hash, never its content."""

    def diff(self) -> Diff:
        def shown(data: bytes | None) -> str | None:
            if data is None:
                return None
            return f"(secret: {len(data)} bytes, sha256 {hashlib.sha256(data).hexdigest()[:16]}...)\n"

        return Diff(self.path, unified_diff(shown(self.before), shown(self.after), self.path))


@dataclass
class Backup:
    """A backup archive, read and checked."""

    path: str
    manifest: dict[str, Any]
    files: list[BackupFile]
    links: list[str]

    @property
    def robot(self) -> dict[str, Any]:
        robot: dict[str, Any] = self.manifest.get("robot") or {}
        return robot


def plan_restore(backup: Backup, robot: str, home: str, compose: str, identity: Mapping[str, Any],
                 current: Mapping[str, tuple[bytes, str]]) -> RobotPlan:
    """The plan writing the backup's files back where they differ from the robot's: ``identity``
    and ``current`` (path -> content and octal mode) are what a backup of it reads now
    (`read.py`), ``compose`` its compose file's path under ``home``."""
    was, cur = backup.robot.get("stack_version"), identity.get("stack_version")
    reapplied: list[str] = []
    if was != cur and not (was and cur and same_line(parse_version(was), parse_version(cur))):
        raise UsageError(
            f"the robot now runs stack {cur or 'unknown'}, the backup {backup.path} was taken on {was}: "
            "restoring across release lines (e.g. 2.1 -> 2.2, where files move) is not supported; "
            "nothing was changed",
            hint="restore onto an image of the backup's release line, then update with `driver update`",
        )
    edits, warnings = [], [f"not restored: {p} (a symbolic link)" for p in backup.links]
    brought_back: list[str] = []
    for f in backup.files:
        if not f.path.startswith(home + "/"):
            warnings.append(f"not restored: {f.path} (outside {home}; restore it by hand)")
            continue
        old = current.get(f.path)
        data = f.data
        if f.path == compose and was != cur and old is not None:
            text, reapplied = reapply(f.data.decode(), old[0].decode(), compose)
            data = text.encode()
        if f.path == compose:
            brought_back = [n for n in _services(data) if n not in _services(old[0] if old else None)]
        if old is not None and old[0] == data and int(old[1], 8) == f.mode:
            continue
        edits.append(_edit(BackupFile(f.path, f.mode, data, f.secret), old[0] if old is not None else None))
    if reapplied:
        warnings.append(f"stack {was} -> {cur}: the new image's compose file kept, re-applied: "
                        + ", ".join(reapplied))
    service = str(identity.get("driver_service") or backup.robot.get("driver_service") or "")
    # the driver, and the services the reinstall lost (the manager, nmea-gps, ...) started again
    recreate = tuple(dict.fromkeys([*([service] if service else []), *brought_back]))
    return RobotPlan(
        robot, f"restore {len(edits)} file(s) from {Path(backup.path).name}", edits,
        recreate=recreate, compose_file=compose,
        verify=[Verify(s) for s in recreate], noop="every file is as in the backup",
        warnings=warnings, home=home,
    )


def _services(data: bytes | None) -> list[str]:
    """The service names of a compose file's text (none when it does not parse)."""
    if data is None:
        return []
    from ruamel.yaml import YAML

    try:
        doc = YAML(typ="safe", pure=True).load(data)
    except Exception:  # a compose file that does not parse defines no service to start
        return []
    services = doc.get("services") if isinstance(doc, dict) else None
    return [str(n) for n in services] if isinstance(services, dict) else []


def _edit(f: BackupFile, before: bytes | None) -> FileEdit:
    """The write of one file; a secret's diff is masked (a private key: wholly; a shutdown
    hosts file: its ``secret:`` values)."""
    if f.secret and posixpath.basename(f.path).startswith("shutdown_hosts"):
        from panther_ops.core.fleet.plan import MaskedFileEdit

        return MaskedFileEdit(f.path, before, f.data, f.mode)
    if f.secret:
        return SecretFileEdit(f.path, before, f.data, f.mode)
    return FileEdit(f.path, before, f.data, f.mode)
