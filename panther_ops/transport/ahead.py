"""TCP connections to the robots opened ahead, while panther-ops itself still loads.

A robot's sshd spends ~6 ms of CPU between accepting a connection and sending its banner
(it forks and re-executes itself, then reads its configuration and host keys); a fleet's
robots do that in parallel with each other, and with nothing of ours, as soon as they see
the connection. paramiko and the SSH configuration lookup take a while to load, so the
connections are started (non-blocking) right after the inventory names the robots, and
each SSH connection later takes its socket from here instead of connecting itself.

The address is the one the connection itself will use: ``ssh_config.resolve_quick``,
which answers only where the quick ssh_config reader knows the file (no ``Match``, no
``Include``, no tokens...), so nothing is opened ahead where paramiko would have to read
it, nor for robots behind a jump host. :func:`take` hands a socket out only for exactly
the address and port the connection resolved, and :func:`discard` closes those not taken.
Connecting ahead never sends anything: the robot's sshd sees a TCP connection, nothing else.
"""

from __future__ import annotations

import errno
import select
import socket
import sys
import threading
import time
from dataclasses import dataclass
from typing import Any

from panther_ops.transport.base import Endpoint
from panther_ops.transport.ssh_config import resolve_quick
from panther_ops.transport.tcp import QuickSocket, connect_quick, lookup_name


def guess_address(endpoint: Endpoint) -> tuple[str, int] | None:
    """Where ``endpoint``'s SSH connection will go when it is direct; None: unsure, or a jump."""
    hop = resolve_quick(endpoint)
    if hop is None or hop.jump is not None:
        return None
    return hop.hostname, hop.port


@dataclass
class _Pending:
    sock: socket.socket
    started: float
    alternatives: bool
    """The name resolved to more than one address (only the first was tried here)."""


_lock = threading.Condition()
_pending: dict[tuple[str, int], list[_Pending]] = {}
_expected: dict[tuple[str, int], int] = {}
"""Connects of the current opening not started yet, per address."""
_round = [0]
"""Bumped by :func:`discard`: a connect started before it that completes afterwards is
closed at once."""


def _literal(host: str) -> int | None:
    """The address family of an IP address literal; None for a name."""
    for family in (socket.AF_INET, socket.AF_INET6):
        try:
            socket.inet_pton(family, host)
        except (OSError, ValueError):
            continue
        return family
    return None


def _connect(address: tuple[str, int]) -> _Pending | None:
    """Start one non-blocking connect (to the first address of a name); None: it failed."""
    host, port = address
    family = _literal(host)
    target: Any
    if family is not None:
        target = (host, port) if family == socket.AF_INET else (host, port, 0, 0)
        alternatives = False
    else:
        try:
            infos = socket.getaddrinfo(lookup_name(host), port, type=socket.SOCK_STREAM)
        except OSError:
            return None  # the connection itself will say why
        family, _, _, _, target = infos[0]
        alternatives = len(infos) > 1
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setblocking(False)
    if sock.connect_ex(target) not in (0, errno.EINPROGRESS):
        sock.close()
        return None
    return _Pending(sock, time.monotonic(), alternatives)


def _start(address: tuple[str, int], round_: int) -> None:
    try:
        started = _connect(address)
    except OSError:  # no socket to be had (e.g. out of file descriptors): the connection says so
        started = None
    with _lock:
        current = round_ == _round[0] and _expected.get(address, 0) > 0
        if current:
            _expected[address] -= 1
            if started is not None:
                _pending.setdefault(address, []).append(started)
            _lock.notify_all()
    if started is not None and not current:
        started.sock.close()


QUICK_SWITCH = 5e-5
"""The interpreter's thread switch interval (s) while the connects to IP addresses start.

Each connect gives up the interpreter lock twice (socket, connect); with the default 5 ms
switch interval and the other threads busy importing, taking it back cost up to 5 ms each
time (measured: 30 connects spread over ~110 ms). For those few milliseconds the lock
changes hands at once; names that need resolving come after, at the default interval."""


def open_ahead(endpoints: list[Endpoint]) -> None:
    """Start connecting to every endpoint whose address is sure (in the background); an
    address already connected or being connected ahead is not connected twice.

    The addresses are worked out here (the quick ssh_config reader: ~1 ms for 30 robots),
    so a connection that wants its socket before the opener reached it waits for it.
    """
    addresses = [a for a in map(guess_address, endpoints) if a is not None]
    with _lock:
        round_ = _round[0]
        fresh = [a for a in addresses if not _pending.get(a) and not _expected.get(a)]
        for address in fresh:
            _expected[address] = _expected.get(address, 0) + 1
    literal = [a for a in fresh if _literal(a[0]) is not None]
    ordered = literal + [a for a in fresh if a not in literal]  # IP addresses first, names after

    def run() -> None:
        done = 0
        default = sys.getswitchinterval()
        sys.setswitchinterval(min(default, QUICK_SWITCH))
        try:
            for address in ordered:
                if done == len(literal):
                    sys.setswitchinterval(default)  # names resolve at the default interval
                _start(address, round_)
                done += 1
        finally:
            sys.setswitchinterval(default)
            with _lock:  # whatever did not start never will: nobody waits for it
                if round_ == _round[0]:
                    for address in ordered[done:]:
                        if _expected.get(address):
                            _expected[address] -= 1
                _lock.notify_all()

    if ordered:
        threading.Thread(target=run, name="connect-ahead", daemon=True).start()


def take(host: str, port: int, timeout: float | None) -> QuickSocket | None:
    """The connection opened ahead to ``host:port``, once established; None: connect anew.

    An IP address whose connect has not started yet is waited for (the opener starts them
    all within milliseconds); a name that still needs resolving is not, and is then not
    connected ahead at all. Raises TimeoutError when the connection did not complete within
    ``timeout`` (counted from its start) and the name has no other address to try.
    """
    address = (host, port)
    with _lock:
        if _literal(host) is not None:
            _lock.wait_for(lambda: _pending.get(address) or not _expected.get(address), timeout=5.0)
        waiting = _pending.get(address)
        if not waiting:
            _expected.pop(address, None)  # not started: it will not be any more
            return None
        entry = waiting.pop(0)
    sock = entry.sock
    left = None if timeout is None else max(0.0, timeout - (time.monotonic() - entry.started))
    poller = select.poll()
    poller.register(sock, select.POLLOUT)
    if not poller.poll(None if left is None else int(left * 1000)):
        sock.close()
        if entry.alternatives:
            return None
        raise TimeoutError(f"timed out connecting to {host}:{port}")
    if sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR):
        sock.close()
        return None  # refused or unreachable: a fresh connection reports it as usual
    return connect_quick(sock, timeout)


def discard() -> None:
    """Close every connection opened ahead and not taken."""
    with _lock:
        left = [p.sock for entries in _pending.values() for p in entries]
        _pending.clear()
        _expected.clear()
        _round[0] += 1
        _lock.notify_all()
    for sock in left:
        sock.close()
