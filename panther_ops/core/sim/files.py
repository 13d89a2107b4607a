"""The simulation files on this machine (a robot description's components, a world SDF, the
battery plugin): read, and written atomically with a backup beside the file
(``transport.localfile``); the CLI only shows the diff and asks."""

from __future__ import annotations

from pathlib import Path

from panther_ops.errors import InputError
from panther_ops.transport.localfile import write_with_backup


def read_text(path: Path) -> str:
    """The file's text (UTF-8); a file that cannot be read is an input error naming it."""
    try:
        return path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", path=str(path)) from None
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text ({exc.reason} at byte {exc.start})", path=str(path)) from None


def write_text(path: Path, text: str) -> Path:
    """Replace the file atomically, its old content kept as ``<file>.panther-ops.bak``; the backup's path."""
    return write_with_backup(path, text.encode())
