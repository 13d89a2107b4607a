"""`gps listen`: decode NMEA arriving at a UDP address of this machine."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from panther_ops.core.gps.nmea import Fix, NmeaDecoder
from panther_ops.core.gps.udp_address import parse_address


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
