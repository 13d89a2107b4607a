"""One backup archive per robot: ``<robot>-<UTC time>.tar.gz``, mode 0600, written atomically.

Members: ``manifest.json`` first, then ``files/<path on the robot>`` with the robot's modes,
owners and times.
"""

from __future__ import annotations

import io
import json
import os
import re
import tarfile
import tempfile
import time
from pathlib import Path

from panther_ops.core.reimage.backup import Carried
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
    info = tarfile.TarInfo("manifest.json")
    info.size, info.mode, info.mtime = len(manifest), 0o600, int(time.time())
    tar.addfile(info, io.BytesIO(manifest))
    for f in carried.files:
        assert f.info is not None
        member = tarfile.TarInfo("files" + f.path)
        for attr in ("mode", "uid", "gid", "uname", "gname", "mtime", "type", "linkname"):
            setattr(member, attr, getattr(f.info, attr))
        member.size = len(f.data) if f.kind == "file" else 0
        tar.addfile(member, io.BytesIO(f.data) if f.kind == "file" else None)
