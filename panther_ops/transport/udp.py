"""UDP: receive datagrams on an address of this machine (NMEA forwarded by a router)."""

from __future__ import annotations

import socket
import time
from collections.abc import Iterator

from panther_ops.errors import OpsError, UsageError

MAX_DATAGRAM = 65535


def bind_udp(host: str, port: int) -> socket.socket:
    """A UDP socket bound to ``host:port`` (IPv4 or IPv6). Bad address: UsageError."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_DGRAM, flags=socket.AI_PASSIVE)
    except socket.gaierror as exc:
        raise UsageError(f"--udp {host}:{port}: cannot resolve {host!r}: {exc.strerror}") from exc
    family, kind, proto, _canon, addr = infos[0]
    sock = socket.socket(family, kind, proto)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(addr)
    except OSError as exc:
        sock.close()
        hint = "another listener (gpsd, nmea-gps) may hold the port, or the address is not on this machine"
        raise OpsError(f"cannot listen on udp {host}:{port}: {exc.strerror or exc}", hint=hint) from exc
    return sock


def datagrams(sock: socket.socket, *, timeout_s: float | None) -> Iterator[tuple[bytes, float]]:
    """Datagrams and their arrival time (epoch seconds) until ``timeout_s`` has passed
    (None: until the caller stops)."""
    deadline = None if timeout_s is None else time.monotonic() + timeout_s
    while True:
        if deadline is not None:
            left = deadline - time.monotonic()
            if left <= 0:
                return
            sock.settimeout(left)
        else:
            sock.settimeout(None)
        try:
            data, _peer = sock.recvfrom(MAX_DATAGRAM)
        except TimeoutError:
            return
        yield data, time.time()
