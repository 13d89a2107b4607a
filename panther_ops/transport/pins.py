"""Pinned TLS certificates (the RUTX11's self-signed one): a file of ``KEY SHA256:hex`` lines.

Recorded on first use like an SSH host key; a different certificate later is refused. The
file is created with mode 0600.
"""

from __future__ import annotations

import os
from pathlib import Path

DEFAULT_PATH = "~/.config/panther-ops/router_pins"
ENV = "PANTHER_OPS_ROUTER_PINS"


def pin_path() -> Path:
    return Path(os.path.expanduser(os.environ.get(ENV) or DEFAULT_PATH))


def pinned(key: str, path: Path | None = None) -> str | None:
    file = path or pin_path()
    if not file.exists():
        return None
    for line in file.read_text(encoding="utf-8").splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0] == key:
            return parts[1]
    return None


def pin(key: str, fp: str, path: Path | None = None) -> None:
    file = path or pin_path()
    file.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    fd = os.open(file, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
    with os.fdopen(fd, "a", encoding="utf-8") as fh:
        fh.write(f"{key} {fp}\n")
