"""`gps listen`: decode NMEA arriving at a UDP address of this machine."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from panther_ops.core.gps.nmea import Fix, NmeaDecoder
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


@dataclass
class ListenResult:
    address: str
    fixes: list[Fix] = field(default_factory=list)
    decoder: NmeaDecoder = field(default_factory=NmeaDecoder)
    timed_out: bool = False


def listen(address: str, *, count: int | None, timeout_s: float | None,
           on_fix: Callable[[Fix], None] | None = None) -> ListenResult:
    """Receive until ``count`` fixes were decoded or ``timeout_s`` passed (None: until
    interrupted; a KeyboardInterrupt ends the wait and the result so far is returned)."""
    from panther_ops.transport.udp import bind_udp, datagrams

    host, port = parse_address(address)
    result = ListenResult(address=f"{host}:{port}")
    sock = bind_udp(host, port)
    try:
        for data, when in datagrams(sock, timeout_s=timeout_s):
            for fix in result.decoder.feed(data, received_at=when):
                result.fixes.append(fix)
                if on_fix is not None:
                    on_fix(fix)
                if count is not None and len(result.fixes) >= count:
                    return result
        result.timed_out = True
    except KeyboardInterrupt:
        pass
    finally:
        sock.close()
    return result
