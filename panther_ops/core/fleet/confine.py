"""Paths from user input, resolved and kept inside the directory they belong to.

A robot's ``compose_file`` (inventory) names a file on the robot: no ``..`` component (it
would name another directory than the one written), no control character; on a local
(demo) robot it must also stay inside the robot's directory once links are resolved. A
backup id (``config rollback --to``) names a directory under ``~/.panther-ops/backups``.
A local file's backup (``config rollback --file FILE``) restores that one file and nothing
else, whatever its manifest names. Anything else is refused with exit 2 naming the path.
(The compose file's check, which needs the robot's transport for the demo case, is
`core/fleet/reading.py`'s ``compose_file``.)
"""

from __future__ import annotations

import posixpath
import re
from collections.abc import Mapping
from typing import Any

from panther_ops.errors import UsageError

BACKUP_ID = re.compile(r"^[0-9]{8}T[0-9]{6}Z-[0-9a-f]{4}$")
BACKUP_PREFIX = re.compile(r"^[0-9A-Za-z-]{1,40}$")
BACKUP_FILE = re.compile(r"^files/[0-9]+$")


SERVICE_NAME = re.compile(r"^[a-zA-Z0-9][a-zA-Z0-9_.-]*$")
"""A compose service's name (Docker Compose's own rule)."""


def compose_path_problem(path: str) -> tuple[str, str] | None:
    """Why ``path`` cannot name a robot's compose file (message, hint), or None when it can:
    absolute or ``~/``, no control character, no ``..`` component. The inventory's
    ``compose_file`` (`robot/read.py`) and a backup's manifest (`plan_rollback.py`) both
    go through it."""
    if not path or any(ord(c) < 32 or c == "\x7f" for c in path):
        return (f"compose_file {path!r} is empty or holds a control character",
                "compose_file: the path of the compose file on the robot, e.g. ~/compose.yaml")
    if not (path.startswith("/") or path.startswith("~/")):
        return (f"compose_file {path} must be absolute or start with ~/",
                "e.g. ~/compose.yaml or /home/husarion/compose.yaml")
    if ".." in path.split("/"):
        return (f"compose_file {path} holds '..': it would leave its directory",
                "name the file directly, e.g. ~/compose.yaml")
    return None


def backup_ref(to: str | None) -> str | None:
    """A backup id or unique prefix given by the operator (``--to``)."""
    if to is not None and not BACKUP_PREFIX.match(to):
        raise UsageError(f"backup id {to!r} is not a backup id (e.g. 20261122T101500Z-1a2b or a prefix of one)",
                         hint="panther-ops config history lists them")
    return to


def backup_entry_ok(entry_id: object, files: object) -> bool:
    """A backup manifest read from the robot names its own directory and files only."""
    if not isinstance(entry_id, str) or not BACKUP_ID.match(entry_id):
        return False
    if not isinstance(files, list):
        return False
    for f in files:
        if not isinstance(f, dict) or not isinstance(f.get("path"), str):
            return False
        backup = f.get("backup")
        if backup is not None and not (isinstance(backup, str) and BACKUP_FILE.match(backup)):
            return False
        p = f["path"]
        if not (p.startswith("/") or p.startswith("~/")) or ".." in p.split("/") or posixpath.normpath(p) in ("/", "~"):
            return False
    return True


def backup_of_file(entry: Mapping[str, Any], path: str) -> bool:
    """A backup of the local file ``path``, read from the file's own directory: a well-formed
    manifest of one file of that name, kept as ``files/0`` (or none: the change created the
    file). The name, not the directory, counts (a directory moved or copied keeps its
    history); a rollback writes ``path`` itself, never the path the manifest names."""
    files = entry.get("files")
    if not backup_entry_ok(entry.get("id"), files) or not isinstance(files, list) or len(files) != 1:
        return False
    named = posixpath.basename(files[0]["path"])
    return bool(named == posixpath.basename(path) and files[0].get("backup") in (None, "files/0"))


def local_file(file: str, option: str = "--file") -> str:
    """A local file named by the operator (``--file``): a file path (it may be gone) in an
    existing directory, no control character. UsageError otherwise, naming what is allowed."""
    import os

    allowed = "the path of a local hosts file (the FILE of `shutdown hosts add|remove FILE`)"
    if not file or any(ord(c) < 32 or c == "\x7f" for c in file):
        raise UsageError(f"{option} {file!r} is empty or holds a control character", hint=allowed)
    if os.path.isdir(file):
        raise UsageError(f"{option} {file} is a directory", hint=allowed)
    parent = os.path.dirname(os.path.abspath(file))
    if not os.path.isdir(parent):
        raise UsageError(f"{option} {file}: directory {parent} does not exist", hint=allowed)
    if os.path.exists(file) and not os.path.isfile(file):
        raise UsageError(f"{option} {file} is not a regular file", hint=allowed)
    return os.path.realpath(file)
