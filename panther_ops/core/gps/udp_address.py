"""A UDP address given on the command line: a port, or ``HOST:PORT`` (pure checks, exit 2 on bad input)."""

from __future__ import annotations

from panther_ops.errors import UsageError


def check_port(port: int, what: str = "port") -> int:
    if not 1 <= port <= 65535:
        raise UsageError(f"{what} {port}: a UDP port is 1-65535")
    return port


def parse_address(text: str, option: str = "--udp") -> tuple[str, int]:
    """``HOST:PORT`` or ``[IPv6]:PORT`` -> (host, port). Bad input: UsageError."""
    host, sep, port_text = text.rpartition(":")
    if not sep or not host or not port_text.isdigit():
        raise UsageError(f"{option} {text!r}: expected HOST:PORT, e.g. 0.0.0.0:5000 or [::1]:5000")
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    if not host or any(c.isspace() for c in host):
        raise UsageError(f"{option} {text!r}: the host may not be empty or contain spaces")
    return host, check_port(int(port_text), f"{option} port")
