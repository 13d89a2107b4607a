"""A backup archive's manifest (``manifest.json``, its first member), checked entry by entry.

`reimage backup` writes it (``backup.Carried.manifest``); `reimage restore` reads it before
anything else and judges every other member of the archive against it (``archive.read_archive``).
Every version-1 manifest (every panther-ops that wrote archives) records per file its path, kind,
mode, size and sha256 (a symbolic link: its target), which is all a restore needs to check them.
"""

from __future__ import annotations

import posixpath
import re
from dataclasses import dataclass
from typing import Any

from panther_ops.core.parse.numbers import NumberError, file_mode, whole

MANIFEST_VERSION = 1
MANIFEST = "manifest.json"
FILES = "files"
"""The folder of the archive holding the robot's files, each under its absolute path."""
KINDS = ("file", "symlink")
_SHA256 = re.compile(r"[0-9a-f]{64}", re.ASCII)
CONTROL = re.compile(r"[\x00-\x1f\x7f]")
"""A control character: in no path a manifest lists, nor in a member's name."""


class ManifestError(ValueError):
    """What is wrong with the manifest; ``str()`` names the key (``files[3].sha256``) and what is allowed."""


class ManifestVersionError(ManifestError):
    """A manifest of another version than this panther-ops reads (a newer panther-ops wrote it)."""


@dataclass(frozen=True)
class Entry:
    """One file of the backup as its manifest records it."""

    path: str
    """Absolute path on the robot."""
    kind: str
    """file or symlink."""
    mode: int
    size: int
    sha256: str | None
    """A file's; None for a symbolic link."""
    link: str | None
    """A symbolic link's target; None for a file."""
    secret: bool

    @property
    def member(self) -> str:
        """The archive member that holds it."""
        return FILES + self.path


def clean_path_problem(path: str) -> str | None:
    """Why ``path`` is not a clean absolute path on the robot (None: it is one)."""
    if CONTROL.search(path):
        return "holds a control character"
    if not path.startswith("/"):
        return "is not an absolute path"
    if path == "/":
        return "is the root directory, not a file"
    if path.startswith("//") or posixpath.normpath(path) != path:
        return "is not a clean path (no '.', '..', '//' or trailing '/')"
    return None


def entries(doc: Any) -> list[Entry]:
    """The manifest's file entries, each checked; ManifestError naming the first key at fault."""
    if not isinstance(doc, dict):
        raise ManifestError("not a JSON object")
    if doc.get("version") != MANIFEST_VERSION:
        raise ManifestVersionError(f"version {doc.get('version')!r}: this panther-ops reads version "
                                   f"{MANIFEST_VERSION}")
    if not isinstance(doc.get("robot"), dict):
        raise ManifestError("robot: missing or not an object")
    files = doc.get("files")
    if not isinstance(files, list):
        raise ManifestError("files: missing or not a list")
    out: list[Entry] = []
    seen: dict[str, int] = {}
    for i, raw in enumerate(files):
        entry = _entry(raw, f"files[{i}]")
        if entry.path in seen:
            raise ManifestError(f"files[{i}].path: {entry.path} is listed twice (also files[{seen[entry.path]}])")
        seen[entry.path] = i
        out.append(entry)
    links = [e.path for e in out if e.kind == "symlink"]
    for e in out:
        under = next((p for p in links if e.path.startswith(p + "/")), None)
        if under is not None:
            raise ManifestError(f"files[{seen[e.path]}].path: {e.path} is under {under}, "
                                "which the manifest lists as a symbolic link")
    return out


def _entry(raw: Any, key: str) -> Entry:
    if not isinstance(raw, dict):
        raise ManifestError(f"{key}: not an object")
    path = raw.get("path")
    if not isinstance(path, str):
        raise ManifestError(f"{key}.path: missing or not a text")
    problem = clean_path_problem(path)
    if problem:
        raise ManifestError(f"{key}.path: {path!r} {problem}")
    kind = raw.get("kind")
    if kind not in KINDS:
        raise ManifestError(f"{key}.kind: {kind!r}: allowed are {', '.join(KINDS)}")
    try:
        mode = file_mode(raw.get("mode"))
    except NumberError as exc:
        raise ManifestError(f"{key}.mode: {raw.get('mode')!r}: {exc}") from None
    try:
        size = whole(raw.get("size"), 0, 2**63 - 1)
    except NumberError as exc:
        raise ManifestError(f"{key}.size: {raw.get('size')!r}: {exc}") from None
    sha256, link = raw.get("sha256"), raw.get("link")
    if kind == "file":
        if not isinstance(sha256, str) or not _SHA256.fullmatch(sha256):
            raise ManifestError(f"{key}.sha256: {sha256!r}: 64 lower-case hexadecimal digits")
        link = None
    else:
        if not isinstance(link, str) or not link or "\0" in link:
            raise ManifestError(f"{key}.link: {link!r}: a symbolic link's target (a non-empty text)")
        if size != 0:
            raise ManifestError(f"{key}.size: {size}: a symbolic link's is 0")
        sha256 = None
    secret = raw.get("secret", False)
    if not isinstance(secret, bool):
        raise ManifestError(f"{key}.secret: {secret!r}: true or false")
    return Entry(path, kind, mode, size, sha256, link, secret)
