"""A UDP address given on the command line: a port, or ``HOST:PORT`` (pure checks, exit 2 on bad input)."""

from __future__ import annotations

from panther_ops.core.parse.numbers import NumberError
from panther_ops.core.parse.numbers import port as parse_port
from panther_ops.errors import UsageError


def check_port(port: object, what: str = "port") -> int:
    """A UDP port (`core.parse.numbers.port`: 1-65535, an int or its ASCII digits); UsageError naming ``what``."""
    try:
        return parse_port(port)
    except NumberError:
        raise UsageError(f"{what} {port!r}: a UDP port is 1-65535 (ASCII digits)") from None


def parse_address(text: str, option: str = "--udp") -> tuple[str, int]:
    """``HOST:PORT`` or ``[IPv6]:PORT`` -> (host, port). Bad input: UsageError."""
    host, sep, port_text = text.rpartition(":")
    if not sep or not host or not port_text:
        raise UsageError(f"{option} {text!r}: expected HOST:PORT, e.g. 0.0.0.0:5000 or [::1]:5000")
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    if not host or any(c.isspace() for c in host):
        raise UsageError(f"{option} {text!r}: the host may not be empty or contain spaces")
    return host, check_port(port_text, f"{option} port")
