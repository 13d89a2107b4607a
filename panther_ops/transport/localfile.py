"""Files of this machine (the operator's own simulation files): atomic write with a backup."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path


def write_with_backup(path: Path, data: bytes) -> Path:
    """Copy ``path`` to ``path.panther-ops.bak`` (mode kept), then replace it atomically
    (a temporary file beside it, fsynced, renamed). Returns the backup's path."""
    backup = path.with_name(path.name + ".panther-ops.bak")
    shutil.copy2(path, backup)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=str(path.parent))
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, path.stat().st_mode & 0o7777)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return backup
