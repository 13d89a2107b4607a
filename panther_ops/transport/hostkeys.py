"""Strict host-key handling: known_hosts lookup, fingerprints, and recording on request.

A robot whose key is unknown is refused with its fingerprint shown (``panther-ops trust``
records it); a robot whose key changed is refused with both fingerprints. Nothing is ever
added silently.
"""

from __future__ import annotations

import base64
import hashlib
import os
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import paramiko


def fingerprint(key: paramiko.PKey) -> str:
    """OpenSSH-style ``SHA256:...`` fingerprint of a public key."""
    digest = hashlib.sha256(key.asbytes()).digest()
    return "SHA256:" + base64.b64encode(digest).decode().rstrip("=")


def known_hosts_name(host: str, port: int) -> str:
    """The name a host is stored under in known_hosts."""
    return host if port == 22 else f"[{host}]:{port}"


def append_known_host(path: str, host: str, port: int, key: paramiko.PKey) -> None:
    """Record a host key in a known_hosts file (created 0600 when missing)."""
    file = Path(os.path.expanduser(path))
    file.parent.mkdir(parents=True, exist_ok=True)
    line = f"{known_hosts_name(host, port)} {key.get_name()} {key.get_base64()}\n"
    existing = file.read_text() if file.exists() else ""
    if line in existing:
        return
    with open(file, "a", encoding="utf-8") as fh:
        if existing and not existing.endswith("\n"):
            fh.write("\n")
        fh.write(line)
    file.chmod(0o600)


def replace_known_host(path: str, host: str, port: int, key: paramiko.PKey) -> None:
    """Drop the lines of ``host`` (plain, not hashed) and record ``key``; rewritten atomically."""
    file = Path(os.path.expanduser(path))
    name = known_hosts_name(host, port)
    kept: list[str] = []
    if file.exists():
        for line in file.read_text().splitlines(keepends=True):
            fields = line.split()
            hosts = fields[0].split(",") if fields and not line.lstrip().startswith("#") else []
            if name in hosts:
                continue
            kept.append(line if line.endswith("\n") else line + "\n")
    kept.append(f"{name} {key.get_name()} {key.get_base64()}\n")
    tmp = file.with_name(file.name + ".panther-ops.tmp")
    tmp.write_text("".join(kept))
    tmp.chmod(0o600)
    os.replace(tmp, file)
