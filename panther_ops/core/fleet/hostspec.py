"""What an inventory may give as a robot's address and jump host (docs/inventory.md).

A host is an IPv4 or IPv6 address, or a name: an RFC 1123 hostname, a Husarnet peer name
or an alias of ``~/.ssh/config`` (letters, digits, '-' and '_' in dot-separated labels, no
label starting or ending with '-'). A jump host is ``[user@]host[:port]`` (IPv6 in
brackets: ``user@[fd00::1]:22``). Nothing else passes: no whitespace, no leading '-' (it
would read as an option of ``ssh``, e.g. ``-oProxyCommand=...``), no shell metacharacter,
no slash, no control character.
"""

from __future__ import annotations

import ipaddress
import re
from dataclasses import dataclass

HOST_FORMS = ("an IPv4/IPv6 address or a hostname (RFC 1123 / Husarnet name / ~/.ssh/config alias: "
              "letters, digits, '-' and '_' in dot-separated labels)")
JUMP_FORMS = "a robot of the inventory, or [user@]host[:port] (IPv6 as user@[addr]:port)"
_LABEL = re.compile(r"^[A-Za-z0-9_](?:[A-Za-z0-9_-]{0,61}[A-Za-z0-9_])?$")
_USER = re.compile(r"^[a-z_][a-z0-9_.-]{0,31}$")
_MAX_NAME = 253


class HostSpecError(ValueError):
    """A host or jump spec that is not allowed; the message says why."""


def check_host(value: str) -> str:
    """``value`` if it is an IP address or hostname, else HostSpecError saying why."""
    if not value:
        raise HostSpecError("empty host")
    bad = _forbidden(value)
    if bad:
        raise HostSpecError(f"host {value!r} {bad}")
    try:
        ipaddress.ip_address(value)
        return value
    except ValueError:
        pass
    if len(value) > _MAX_NAME:
        raise HostSpecError(f"host {value[:40]!r}... is longer than {_MAX_NAME} characters")
    name = value[:-1] if value.endswith(".") else value
    if not all(_LABEL.match(label) for label in name.split(".")):
        raise HostSpecError(f"host {value!r} is not an IP address or hostname")
    if re.fullmatch(r"[0-9.]+", name):
        raise HostSpecError(f"host {value!r} is not a valid IPv4 address")
    return value


@dataclass(frozen=True)
class JumpSpec:
    """A jump host given as ``[user@]host[:port]``."""

    user: str | None
    host: str
    port: int | None


def parse_jump(value: str) -> JumpSpec:
    """``[user@]host[:port]`` checked and split, else HostSpecError saying why."""
    bad = _forbidden(value)
    if bad:
        raise HostSpecError(f"jump {value!r} {bad}")
    user: str | None = None
    rest = value
    if "@" in value:
        user, rest = value.split("@", 1)
        if not _USER.match(user):
            raise HostSpecError(f"jump {value!r}: user {user!r} is not a user name")
    port: int | None = None
    if rest.startswith("["):
        host, sep, tail = rest[1:].partition("]")
        if not sep:
            raise HostSpecError(f"jump {value!r}: '[' without ']'")
        try:
            ipaddress.IPv6Address(host)
        except ValueError:
            raise HostSpecError(f"jump {value!r}: {host!r} in brackets is not an IPv6 address") from None
        if tail and not tail.startswith(":"):
            raise HostSpecError(f"jump {value!r}: unexpected {tail!r} after ']'")
        port_text = tail[1:] if tail else None
    elif rest.count(":") == 1:
        host, _, port_text = rest.partition(":")
    else:
        host, port_text = rest, None
    if port_text is not None:
        from panther_ops.core.parse.numbers import NumberError
        from panther_ops.core.parse.numbers import port as parse_port

        try:
            port = parse_port(port_text)
        except NumberError:
            raise HostSpecError(f"jump {value!r}: port {port_text!r} is not 1-65535 (ASCII digits)") from None
    try:
        check_host(host)
    except HostSpecError as exc:
        raise HostSpecError(f"jump {value!r}: {exc}") from None
    return JumpSpec(user, host, port)


def _forbidden(value: str) -> str | None:
    """Why ``value`` can never be a host, or None."""
    if value.startswith("-"):
        return "starts with '-' (it would be read as an option)"
    if any(c.isspace() for c in value):
        return "holds whitespace"
    if any(ord(c) < 32 or ord(c) == 127 for c in value):
        return "holds a control character"
    shell = sorted({c for c in value if c in ";&|`$<>()*?!\"'\\{}~#%^="})
    if shell:
        return f"holds {' '.join(shell)} (shell metacharacters are not allowed)"
    if "/" in value:
        return "holds '/' (a host is not a path)"
    return None
