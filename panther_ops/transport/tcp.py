"""The TCP connection under an SSH session: no Nagle delay, no delayed acknowledgement.

SSH is a conversation of small packets. With the kernel's defaults, two of them sent back
to back by one side wait for the other side's acknowledgement of the first (Nagle), which
the other side delays by up to 40 ms hoping to piggyback it on data (delayed ACK). sshd
leaves Nagle on for sessions without a terminal, and after authentication it sends two
packets in a row (the success and its host-key announcement), so every connection's first
session used to wait ~40 ms for nothing, and each step of the key exchange could as well.

panther-ops sends its own packets at once (``TCP_NODELAY``) and acknowledges the robot's at
once (``TCP_QUICKACK``, Linux: the kernel drops back to delayed acknowledgements by itself,
so it is set again after every read). Measured on a lab robot: connect, authenticate and
run the first command in 32 ms instead of 120 ms (docs/performance.md).
"""

from __future__ import annotations

import socket

_QUICKACK = getattr(socket, "TCP_QUICKACK", None)


class QuickSocket(socket.socket):
    """A TCP socket that acknowledges what it receives at once, where the OS can."""

    def quickack(self) -> None:
        if _QUICKACK is not None:
            try:
                self.setsockopt(socket.IPPROTO_TCP, _QUICKACK, 1)
            except OSError:  # closed meanwhile: the read itself reports it
                return

    def recv(self, bufsize: int, flags: int = 0) -> bytes:
        data = super().recv(bufsize, flags)
        self.quickack()
        return data


def lookup_name(host: str) -> str | bytes:
    """``host`` as ``getaddrinfo`` takes it most cheaply: an ASCII name as bytes.

    Given a str, Python encodes it with the ``idna`` codec, whose first use imports
    ``encodings.idna``, ``stringprep`` and ``unicodedata`` (~9 ms); an ASCII name (every IP
    address, most host names) is the same in bytes. Other names keep the IDNA encoding.
    """
    return host.encode("ascii") if host.isascii() else host


def connect_tcp(host: str, port: int, timeout: float | None) -> QuickSocket:
    """Connect to ``host:port`` (each address it resolves to in turn), Nagle off, quick ACKs.

    Raises OSError like :func:`socket.create_connection`.
    """
    plain = socket.create_connection((lookup_name(host), port), timeout=timeout)  # type: ignore[arg-type]  # bytes are taken
    return connect_quick(plain, timeout)


def connect_quick(plain: socket.socket, timeout: float | None) -> QuickSocket:
    """A connected TCP socket as a :class:`QuickSocket` (blocking, ``timeout``), Nagle off."""
    sock = QuickSocket(plain.family, plain.type, plain.proto, fileno=plain.detach())
    sock.settimeout(timeout)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    sock.quickack()
    return sock
