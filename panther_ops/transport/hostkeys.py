"""Strict host-key handling: known_hosts names and fingerprints.

A robot whose key is unknown is refused with its fingerprint shown (``panther-ops trust``
records it, a change through the pipeline: core/fleet/trust.py); a robot whose key changed is
refused with both fingerprints. Nothing is ever added silently.
"""

from __future__ import annotations

import base64
import hashlib
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
