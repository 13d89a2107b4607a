"""A TCP connection to a host on the robot's LAN, through the robot's SSH connection.

The robot's SSH transport opens a ``direct-tcpip`` channel (what ``ssh -W`` does: no second
login, no process on the robot). The standard library's TLS and HTTP need a real socket, so
the channel is joined to one end of a local socket pair by two pump threads; the caller gets
the other end.
"""

from __future__ import annotations

import contextlib
import logging
import socket
import threading
from typing import Any

from panther_ops.errors import TransportError

CHUNK = 32768
log = logging.getLogger(__name__)


def _pump(read: Any, write: Any, done: Any) -> None:
    try:
        while True:
            data = read(CHUNK)
            if not data:
                break
            write(data)
    except Exception as exc:  # any error of either side ends this direction; the other side sees EOF
        log.debug("tunnel pump ended: %r", exc)
    finally:
        with contextlib.suppress(Exception):  # a pump never raises out of its thread
            done()


def open_tcp(ssh_client: Any, robot: str, host: str, port: int, *, timeout: float = 10.0) -> socket.socket:
    """A socket connected to ``host:port`` as seen from the robot (``ssh_client``: its paramiko client)."""
    import paramiko

    transport = ssh_client.get_transport()
    if transport is None or not transport.is_active():
        raise TransportError(robot, "the SSH connection is closed")
    try:
        chan = transport.open_channel("direct-tcpip", (host, port), ("127.0.0.1", 0), timeout=timeout)
    except paramiko.ChannelException as exc:
        raise TransportError(robot, f"the robot cannot reach {host}:{port} ({exc.text or exc.code})") from None
    except (paramiko.SSHException, OSError) as exc:
        raise TransportError(robot, f"no channel to {host}:{port} through the robot: {exc}") from None
    ours, theirs = socket.socketpair()
    ended = [0]
    lock = threading.Lock()

    def finish() -> None:  # the second pump to end closes both ends it used
        with lock:
            ended[0] += 1
            last = ended[0] == 2
        if last:
            for end in (chan, theirs):
                with contextlib.suppress(Exception):  # already closed by the other side
                    end.close()

    def close_theirs() -> None:
        with contextlib.suppress(OSError):
            theirs.shutdown(socket.SHUT_RDWR)
        finish()

    def close_chan() -> None:
        chan.shutdown_write()
        finish()

    threading.Thread(target=_pump, args=(chan.recv, theirs.sendall, close_theirs), daemon=True).start()
    threading.Thread(target=_pump, args=(theirs.recv, chan.sendall, close_chan), daemon=True).start()
    ours.settimeout(timeout)
    return ours


def forward_local(ssh_client: Any, robot: str, host: str, port: int, *, timeout: float = 10.0
                  ) -> tuple[int, Any]:
    """``ssh -L`` for one connection: a port on 127.0.0.1 of this machine whose first client
    is joined to ``host:port`` as seen from the robot (for libraries that open their own
    socket). The channel is opened at once, so an unreachable target raises here. Returns
    the local port and a function that closes everything."""
    remote = open_tcp(ssh_client, robot, host, port, timeout=timeout)
    listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    listener.bind(("127.0.0.1", 0))
    listener.listen(1)
    listener.settimeout(timeout)

    def serve() -> None:
        try:
            conn, _ = listener.accept()
        except OSError:
            remote.close()
            return
        finally:
            listener.close()
        remote.settimeout(None)
        back = threading.Thread(target=_pump, args=(remote.recv, conn.sendall, lambda: _shut(conn)), daemon=True)
        back.start()
        _pump(conn.recv, remote.sendall, lambda: _shut(remote))
        back.join(timeout)
        for end in (conn, remote):
            with contextlib.suppress(OSError):
                end.close()

    threading.Thread(target=serve, daemon=True).start()

    def close() -> None:
        for s in (listener, remote):
            with contextlib.suppress(OSError):
                s.close()

    return int(listener.getsockname()[1]), close


def _shut(sock: socket.socket) -> None:
    with contextlib.suppress(OSError):
        sock.shutdown(socket.SHUT_RDWR)
