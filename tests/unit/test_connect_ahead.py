"""Connections opened ahead: the one the SSH connection takes, or none; never a stray one.

A real TCP listener on loopback stands for a robot's sshd (only the TCP connection matters
here; the lab tests check the same with real sshd)."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.fleet.connect_ahead import connect_ahead
from panther_ops.core.fleet.inventory import load_inventory
from panther_ops.core.fleet.runner import Connections
from panther_ops.transport import ahead
from panther_ops.transport.base import Endpoint


@pytest.fixture(autouse=True)
def _clean() -> Iterator[None]:
    ahead.discard()
    yield
    ahead.discard()


@pytest.fixture
def listener() -> Iterator[socket.socket]:
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(16)
    srv.settimeout(5)
    yield srv
    srv.close()


def _wait_pending(n: int) -> None:
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        with ahead._lock:
            if sum(len(v) for v in ahead._pending.values()) >= n:
                return
        time.sleep(0.005)
    raise AssertionError("the connections were not started")


def _endpoint(name: str, port: int, config: Path) -> Endpoint:
    return Endpoint(name=name, host=name, ssh_config=str(config), port=port)


def test_the_connection_opened_ahead_is_the_one_taken(tmp_path: Path, listener: socket.socket) -> None:
    port = listener.getsockname()[1]
    conf = tmp_path / "ssh_config"
    conf.write_text("Host r1\n  HostName 127.0.0.1\n")
    ahead.open_ahead([_endpoint("r1", port, conf)])
    _wait_pending(1)
    peer, _ = listener.accept()  # the robot side sees it before anything is sent
    sock = ahead.take("127.0.0.1", port, 5.0)
    assert sock is not None
    assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) == 1 and sock.gettimeout() == 5.0
    sock.sendall(b"SSH-2.0-test\r\n")
    assert peer.recv(100) == b"SSH-2.0-test\r\n"
    assert ahead.take("127.0.0.1", port, 5.0) is None  # one per connection
    sock.close()
    peer.close()


def test_nothing_opened_where_the_address_is_not_sure(tmp_path: Path, listener: socket.socket) -> None:
    port = listener.getsockname()[1]
    conf = tmp_path / "ssh_config"
    conf.write_text("Match host r1\n  HostName 127.0.0.1\n")
    jumped = Endpoint(name="r2", host="127.0.0.1", port=port, jump=Endpoint(name="j", host="127.0.0.1", port=port))
    assert ahead.guess_address(_endpoint("r1", port, conf)) is None  # only paramiko reads Match
    assert ahead.guess_address(jumped) is None  # reached through its jump host
    ahead.open_ahead([_endpoint("r1", port, conf), jumped])
    time.sleep(0.2)
    assert ahead._pending == {}
    listener.settimeout(0.2)
    with pytest.raises(TimeoutError):
        listener.accept()


def test_a_refused_connection_is_left_to_the_real_one(tmp_path: Path) -> None:
    free = socket.socket()
    free.bind(("127.0.0.1", 0))
    port = free.getsockname()[1]
    free.close()  # nobody listens there
    ahead.open_ahead([Endpoint(name="r", host="127.0.0.1", port=port, ssh_config=str(tmp_path / "none"))])
    _wait_pending(1)
    assert ahead.take("127.0.0.1", port, 2.0) is None


def _gated(monkeypatch: pytest.MonkeyPatch) -> threading.Event:
    """Hold the opener before each connect until the event is set."""
    gate = threading.Event()
    connect = ahead._connect

    def held(address: tuple[str, int]) -> Any:
        gate.wait(5)
        return connect(address)

    monkeypatch.setattr(ahead, "_connect", held)
    return gate


def test_an_address_asked_for_before_it_started_is_waited_for(tmp_path: Path, listener: socket.socket,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    port = listener.getsockname()[1]
    gate = _gated(monkeypatch)
    ahead.open_ahead([Endpoint(name="r", host="127.0.0.1", port=port, ssh_config=str(tmp_path / "none"))])
    threading.Timer(0.2, gate.set).start()
    sock = ahead.take("127.0.0.1", port, 2.0)  # the opener is 0.2 s late: taken all the same
    assert sock is not None
    sock.close()


def test_a_name_asked_for_before_it_started_is_not(tmp_path: Path, listener: socket.socket,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    port = listener.getsockname()[1]
    gate = _gated(monkeypatch)
    ahead.open_ahead([Endpoint(name="r", host="localhost", port=port, ssh_config=str(tmp_path / "none"))])
    assert ahead.take("localhost", port, 1.0) is None  # the connection resolves it itself
    gate.set()
    time.sleep(0.2)
    assert ahead._pending == {}  # and the opener, coming late, keeps nothing


def test_discarded_while_opening_nothing_is_left(tmp_path: Path, listener: socket.socket,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    port = listener.getsockname()[1]
    gate = _gated(monkeypatch)
    ahead.open_ahead([Endpoint(name="r", host="127.0.0.1", port=port, ssh_config=str(tmp_path / "none"))])
    ahead.discard()  # the command ended before the opener got this far
    gate.set()
    time.sleep(0.2)
    assert ahead._pending == {}
    assert ahead.take("127.0.0.1", port, 1.0) is None


def test_a_later_command_opens_ahead_again(tmp_path: Path, listener: socket.socket) -> None:
    port = listener.getsockname()[1]
    endpoint = Endpoint(name="r", host="127.0.0.1", port=port, ssh_config=str(tmp_path / "none"))
    assert ahead.take("127.0.0.1", port, 1.0) is None  # a command that did not open ahead
    for _ in range(2):  # two commands in one process (tests, a long-lived caller)
        ahead.open_ahead([endpoint])
        _wait_pending(1)
        sock = ahead.take("127.0.0.1", port, 2.0)
        assert sock is not None
        sock.close()
        ahead.discard()


def test_connections_close_discards_what_was_not_taken(tmp_path: Path, listener: socket.socket) -> None:
    port = listener.getsockname()[1]
    inv_file = tmp_path / "inventory.yaml"
    (tmp_path / "ssh_config").write_text("")
    inv_file.write_text(
        "version: 1\nsettings:\n  ssh_config: ssh_config\nrobots:\n"
        f"  a:\n    host: 127.0.0.1\n    port: {port}\n"
        "  b:\n    host: 127.0.0.1\n    port: 1\n    jump: a\n"
    )
    inv = load_inventory(str(inv_file))
    connect_ahead(inv, list(inv.robots.values()))
    _wait_pending(1)
    peer, _ = listener.accept()
    with Connections(inv):
        pass
    assert ahead._pending == {}
    peer.settimeout(2)
    assert peer.recv(10) == b""  # closed without a byte sent
    peer.close()


def test_an_address_opened_ahead_is_not_opened_twice(tmp_path: Path, listener: socket.socket) -> None:
    port = listener.getsockname()[1]
    endpoint = Endpoint(name="r", host="127.0.0.1", port=port, ssh_config=str(tmp_path / "none"))
    ahead.open_ahead([endpoint])
    _wait_pending(1)
    ahead.open_ahead([endpoint])  # a second opening for the same robot
    time.sleep(0.2)
    assert sum(len(v) for v in ahead._pending.values()) == 1
    listener.settimeout(0.2)
    first, _ = listener.accept()
    with pytest.raises(TimeoutError):
        listener.accept()
    first.close()
