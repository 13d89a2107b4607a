"""Backup archives for the bad-input corpus: a real `reimage backup` of a demo robot, and
ways to tamper with one (members added, changed, removed, repeated; the manifest edited).

Archives are rebuilt member by member with tarfile, in memory; nothing is extracted.
"""

from __future__ import annotations

import copy
import gzip
import io
import json
import tarfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from panther_ops.cli.app import main

Member = tuple[tarfile.TarInfo, bytes]
Tamper = Callable[[list[Member]], list[Member]]

ROBOT = "panther-03"
COMPOSE = "files/home/husarion/compose.yaml"
ENV = "files/home/husarion/config/common/.env"
LINK = "files/home/husarion/config/husarion_ugv_lights/env-link"
"""A symbolic link the demo robot is given before its backup (to ``../common/.env``)."""
CUSTOMISED = "# customised on this robot\n"
"""Appended to the robot's compose file before its backup: a restore that went ahead would write it."""


def demo_backup(tmp: Path) -> bytes:
    """A `reimage backup` of the demo's panther-03, customised first (its compose file, a
    symbolic link in its config tree), as bytes."""
    demo = tmp / "demo"
    assert main(["demo", "init", "--dest", str(demo)]) == 0
    home = demo / "robots" / ROBOT / "home/husarion"
    with open(home / "compose.yaml", "a") as fh:
        fh.write(CUSTOMISED)
    (home / "config/husarion_ugv_lights/env-link").symlink_to("../common/.env")
    assert main(["-i", str(demo), "reimage", "backup", "-r", ROBOT, "--out", str(tmp / "bk")]) == 0
    (archive,) = (tmp / "bk").iterdir()
    return archive.read_bytes()


def members(archive: bytes) -> list[Member]:
    out: list[Member] = []
    with tarfile.open(fileobj=io.BytesIO(archive), mode="r:gz") as tar:
        for m in tar:
            fh = tar.extractfile(m) if m.isfile() else None
            out.append((m, fh.read() if fh is not None else b""))
    return out


def pack(ms: list[Member]) -> bytes:
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w:gz", format=tarfile.PAX_FORMAT) as tar:
        for original, data in ms:
            info = copy.copy(original)
            if info.type in (tarfile.REGTYPE, tarfile.AREGTYPE):
                info.size = len(data)
                tar.addfile(info, io.BytesIO(data))
            else:
                tar.addfile(info)
    return buf.getvalue()


def tampered(archive: bytes, tamper: Tamper) -> bytes:
    return pack(tamper(members(archive)))


def appended(data: bytes) -> Callable[[bytes], bytes]:
    """The archive's tar stream with ``data`` after its end, compressed again."""
    return lambda archive: gzip.compress(gzip.decompress(archive) + data)


def second_archive(*new: Member) -> bytes:
    """A tar stream of ``new`` alone (to append after an archive's end)."""
    return gzip.decompress(pack(list(new)))


def crc_broken(archive: bytes) -> bytes:
    """The gzip trailer's CRC of the uncompressed data flipped (the data itself intact)."""
    return archive[:-8] + bytes(b ^ 0xFF for b in archive[-8:-4]) + archive[-4:]


def entry(name: str, data: bytes = b"", *, kind: bytes = tarfile.REGTYPE, mode: int = 0o644,
          linkname: str = "") -> Member:
    info = tarfile.TarInfo(name)
    info.type, info.mode, info.linkname, info.size = kind, mode, linkname, len(data)
    if kind in (tarfile.CHRTYPE, tarfile.BLKTYPE):
        info.devmajor, info.devminor = 1, 3
    return info, data


def added(*new: Member) -> Tamper:
    return lambda ms: [*ms, *new]


def replaced(name: str, new: Member) -> Tamper:
    return lambda ms: [new if m[0].name == name else m for m in ms]


def dropped(name: str) -> Tamper:
    return lambda ms: [m for m in ms if m[0].name != name]


def repeated(name: str) -> Tamper:
    return lambda ms: [*ms, *[m for m in ms if m[0].name == name]]


def changed(name: str, edit: Callable[[tarfile.TarInfo, bytes], tuple[tarfile.TarInfo, bytes]]) -> Tamper:
    def tamper(ms: list[Member]) -> list[Member]:
        return [edit(copy.copy(i), d) if i.name == name else (i, d) for i, d in ms]

    return tamper


def manifest_edited(edit: Callable[[dict[str, Any]], Any]) -> Tamper:
    """The manifest's document changed by ``edit`` (which changes it in place or returns raw bytes)."""

    def tamper(ms: list[Member]) -> list[Member]:
        (info, data), *rest = ms
        doc = json.loads(data)
        raw = edit(doc)
        return [(info, raw if isinstance(raw, bytes) else json.dumps(doc).encode()), *rest]

    return tamper


def file_entry(doc: dict[str, Any], member: str) -> dict[str, Any]:
    """The manifest's entry of ``member`` (``files/<path>``)."""
    found: dict[str, Any] = next(f for f in doc["files"] if "files" + f["path"] == member)
    return found
