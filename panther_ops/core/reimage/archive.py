"""One backup archive per robot: ``<robot>-<UTC time>.tar.gz``, mode 0600, written atomically,
and read back for a restore only when every member is what its manifest says.

Members: ``manifest.json`` first, then ``files/<path on the robot>`` with the robot's modes,
owners and times: regular files and symbolic links, each listed in the manifest, nothing else.
Reading never extracts to disk: members are read into memory, one at a time, after their
name, type, size and mode were checked against the manifest.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import re
import tarfile
import tempfile
import time
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from panther_ops.core.reimage.backup import Carried
from panther_ops.core.reimage.manifest import CONTROL, MANIFEST, Entry, ManifestError, ManifestVersionError, entries
from panther_ops.errors import UsageError

_SAFE = re.compile(r"[^A-Za-z0-9._-]")


def out_dir(path: str) -> Path:
    """The directory archives go to (created 0700 when missing); UsageError if it cannot be."""
    d = Path(path)
    if d.exists() and not d.is_dir():
        raise UsageError(f"--out {path}: not a directory")
    try:
        d.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"--out {path}: cannot create it: {exc.strerror}") from exc
    return d


def write_archive(carried: Carried, directory: Path, robot: str) -> Path:
    """Write the robot's archive (0600 from the start; renamed into place when complete)."""
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    final = directory / f"{_SAFE.sub('_', robot)}-{stamp}.tar.gz"
    fd, tmp = tempfile.mkstemp(prefix=".backup-", suffix=".part", dir=directory)  # mode 0600
    try:
        with os.fdopen(fd, "wb") as raw:
            with tarfile.open(fileobj=raw, mode="w:gz") as tar:
                _add(tar, carried)
            raw.flush()
            os.fsync(raw.fileno())
        os.replace(tmp, final)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return final


def _add(tar: tarfile.TarFile, carried: Carried) -> None:
    manifest = json.dumps(carried.manifest(), indent=2).encode() + b"\n"
    info = tarfile.TarInfo(MANIFEST)
    info.size, info.mode, info.mtime = len(manifest), 0o600, int(time.time())
    tar.addfile(info, io.BytesIO(manifest))
    for f in carried.files:
        assert f.info is not None
        member = tarfile.TarInfo("files" + f.path)
        for attr in ("mode", "uid", "gid", "uname", "gname", "mtime", "type", "linkname"):
            setattr(member, attr, getattr(f.info, attr))
        member.size = len(f.data) if f.kind == "file" else 0
        tar.addfile(member, io.BytesIO(f.data) if f.kind == "file" else None)


# --- reading an archive back --------------------------------------------------------------------

_FILE_TYPES = (tarfile.REGTYPE, tarfile.AREGTYPE)
_OTHER_TYPES = {
    tarfile.LNKTYPE: "a hard link", tarfile.CHRTYPE: "a character device", tarfile.BLKTYPE: "a block device",
    tarfile.FIFOTYPE: "a fifo", tarfile.DIRTYPE: "a directory", tarfile.CONTTYPE: "a contiguous file",
    tarfile.GNUTYPE_SPARSE: "a sparse file",
}


@dataclass(frozen=True)
class Contents:
    """A backup archive whose every member was found as its manifest lists it."""

    manifest: dict[str, Any]
    entries: list[Entry]
    data: dict[str, bytes]
    """Each file entry's content, by path on the robot."""


class _Refused(Exception):
    """A member that is not as the manifest says: its name and what is wrong."""

    def __init__(self, member: str, what: str) -> None:
        super().__init__(what)
        self.member, self.what = member, what


def read_archive(path: str) -> Contents:
    """The archive's manifest, read first, and every member checked against it (name, type,
    size, mode, sha256 or link target; no path outside the archive, no hard link, device, fifo
    or directory, no member twice, none missing). UsageError naming the member and what is wrong:
    the archive is refused whole, before anything is written anywhere."""
    where = f"--from {path}"
    if not Path(path).is_file():
        raise UsageError(f"{where}: no such file")
    refused = "the archive is refused, nothing was written"
    hint = "the archive was changed or damaged since `reimage backup` wrote it: restore from another backup"
    try:
        with tarfile.open(path, "r:gz") as tar:
            return _read(tar, where)
    except _Refused as exc:
        raise UsageError(f"{where}: member {exc.member!r}: {exc.what}; {refused}", hint=hint) from None
    except ManifestVersionError as exc:
        raise UsageError(f"{where}: {MANIFEST}: {exc}; {refused}",
                         hint="another panther-ops wrote it: restore with that version") from None
    except ManifestError as exc:
        raise UsageError(f"{where}: {MANIFEST}: {exc}; {refused}", hint=hint) from None
    except (tarfile.TarError, OSError, EOFError, zlib.error) as exc:
        raise UsageError(f"{where}: not a readable backup archive ({exc})") from exc


def _read(tar: tarfile.TarFile, where: str) -> Contents:
    first = tar.next()
    if first is None or first.name != MANIFEST or first.type not in _FILE_TYPES:
        shown = "it is empty" if first is None else f"its first member is {first.name!r}"
        raise UsageError(f"{where}: not a panther-ops backup ({shown}, not the file {MANIFEST})")
    manifest = _manifest(_content(tar, first))
    listed = entries(manifest)
    by_member = {e.member: e for e in listed}
    seen = {first.name}
    data: dict[str, bytes] = {}
    name = first.name
    for member in tar:
        if member is first:
            continue
        name = member.name
        if name in seen:
            raise _Refused(name, "is in the archive twice")
        seen.add(name)
        entry = _judge(member, by_member.get(name))
        if entry.kind == "file":
            content = _content(tar, member)
            if hashlib.sha256(content).hexdigest() != entry.sha256:
                raise _Refused(name, f"{entry.path} does not match its sha256 in the manifest (damaged)")
            data[entry.path] = content
    _end(tar, name)
    for e in listed:
        if e.member not in seen:
            raise _Refused(e.member, f"missing: {e.path} is in the manifest but not in the archive")
    return Contents(manifest, listed, data)


def _end(tar: tarfile.TarFile, last: str) -> None:
    """After the last member only the end-of-archive zeros, to the end of the compressed stream
    (read whole, so that gzip checks its CRC): tarfile stops quietly at a header it cannot read,
    which would hide whatever follows (a damaged block, a second archive appended)."""
    stream = tar.fileobj
    assert stream is not None
    stream.seek(tar.offset)
    while chunk := stream.read(1 << 16):
        if chunk.strip(b"\0"):
            raise _Refused(last, "is followed by data that is not a member of the archive (damaged, or "
                                 "something appended)")


def _manifest(raw: bytes) -> dict[str, Any]:
    def no_twice(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        keys = [k for k, _ in pairs]
        twice = sorted({k for k in keys if keys.count(k) > 1})
        if twice:
            raise ManifestError(f"key {twice[0]!r} appears twice in one object")
        return dict(pairs)

    try:
        doc = json.loads(raw.decode("utf-8"), object_pairs_hook=no_twice)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ManifestError(f"not JSON ({exc})") from None
    if not isinstance(doc, dict):
        raise ManifestError("not a JSON object")
    return doc


def _judge(member: tarfile.TarInfo, entry: Entry | None) -> Entry:
    """The manifest's entry for ``member``, when the member is as that entry says; else _Refused."""
    name = member.name
    if CONTROL.search(name):
        raise _Refused(name, "holds a control character in its name")
    if name.startswith("/"):
        raise _Refused(name, "is an absolute path, outside the archive's root")
    if ".." in name.split("/"):
        raise _Refused(name, "climbs out of the archive's root ('..')")
    if member.issym():
        what = f"is a symbolic link to {member.linkname!r}"
        if entry is None:
            raise _Refused(name, f"{what} that the manifest does not list")
        if entry.kind != "symlink":
            raise _Refused(name, f"{what}, but the manifest lists a file")
        if member.linkname != entry.link:
            raise _Refused(name, f"{what}, but the manifest says it links to {entry.link!r}")
    elif member.type not in _FILE_TYPES:
        kind = _OTHER_TYPES.get(member.type, f"an entry of tar type {member.type!r}")
        target = f" to {member.linkname!r}" if member.islnk() else ""
        raise _Refused(name, f"is {kind}{target}: a backup archive holds only files and the symbolic links "
                             "its manifest lists")
    elif entry is None:
        raise _Refused(name, "is not in the manifest")
    elif entry.kind != "file":
        raise _Refused(name, f"is a file, but the manifest lists a symbolic link to {entry.link!r}")
    if member.size != entry.size:
        raise _Refused(name, f"holds {member.size} bytes, but the manifest says {entry.size}")
    if member.mode & 0o7777 != entry.mode:
        raise _Refused(name, f"has mode {member.mode & 0o7777:04o}, but the manifest says {entry.mode:04o}")
    return entry


def _content(tar: tarfile.TarFile, member: tarfile.TarInfo) -> bytes:
    fh = tar.extractfile(member)
    data = fh.read() if fh is not None else b""
    if len(data) != member.size:
        raise _Refused(member.name, f"ends after {len(data)} of its {member.size} bytes (truncated)")
    return data
