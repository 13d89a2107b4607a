"""Files of this machine (the operator's own files): atomic writes, with a backup or not."""

from __future__ import annotations

import os
import secrets
import shutil
from pathlib import Path


def write_atomic(path: Path, data: bytes) -> None:
    """Create or replace ``path`` atomically: a temporary file beside it (created as ``open``
    creates a file: mode 0666 less the umask; the mode of the file it replaces, if any),
    written, fsynced, renamed over it. The directory is created first when it is missing."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        if path.exists():
            os.chmod(tmp, path.stat().st_mode & 0o7777)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_with_backup(path: Path, data: bytes) -> Path:
    """Copy ``path`` to ``path.panther-ops.bak`` (mode kept), then replace it atomically
    (:func:`write_atomic`). Returns the backup's path."""
    backup = path.with_name(path.name + ".panther-ops.bak")
    shutil.copy2(path, backup)
    write_atomic(path, data)
    return backup
