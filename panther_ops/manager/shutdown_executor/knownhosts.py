"""Is a host's key recorded in a known_hosts file? (plain and hashed names, no paramiko needed)

SSH shutdowns refuse unknown host keys (both backends), while the stock C++ node (libssh)
never checked them: a host missing from the robot's known_hosts would silently stop being shut
down. The manager warns at start and `manager deploy` refuses for such hosts; both ask here.

Names as OpenSSH writes them: ``ip`` for port 22, ``[ip]:port`` otherwise; comma-separated
lists; hashed names ``|1|<base64 salt>|<base64 HMAC-SHA1(salt, name)>``. Marker lines
(``@cert-authority``, ``@revoked``), comments and wildcard patterns are not matched.
"""

from __future__ import annotations

import base64
import binascii
import hashlib
import hmac


def known_hosts_name(host: str, port: int) -> str:
    """The name a host is stored under in known_hosts."""
    return host if port == 22 else f"[{host}]:{port}"


def _hashed_match(entry: str, name: str) -> bool:
    parts = entry.split("|")
    if len(parts) != 4 or parts[1] != "1":
        return False
    try:
        salt, digest = base64.b64decode(parts[2]), base64.b64decode(parts[3])
    except (binascii.Error, ValueError):
        return False
    return hmac.compare_digest(hmac.new(salt, name.encode(), hashlib.sha1).digest(), digest)


def is_known(known_hosts_text: str, host: str, port: int = 22) -> bool:
    """True when the text has a key line for ``host`` on ``port``."""
    name = known_hosts_name(host, port)
    for raw in known_hosts_text.splitlines():
        line = raw.strip()
        if not line or line.startswith(("#", "@")):
            continue
        fields = line.split()
        if len(fields) < 3:
            continue
        for entry in fields[0].split(","):
            if entry == name or (entry.startswith("|1|") and _hashed_match(entry, name)):
                return True
    return False
