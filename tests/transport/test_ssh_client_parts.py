"""The parts under each SSH connection: the TCP socket, the private-key cache, ssh_config lookups."""

from __future__ import annotations

import getpass
import socket
import threading
from pathlib import Path

import paramiko
import pytest

from panther_ops.transport import ssh_config
from panther_ops.transport.tcp import QuickSocket, connect_tcp


# -- TCP --------------------------------------------------------------------------------
def test_connect_tcp_turns_nagle_off_and_reads_with_quick_acks() -> None:
    server = socket.create_server(("127.0.0.1", 0))
    port = server.getsockname()[1]

    def serve() -> None:
        conn, _ = server.accept()
        with conn:
            conn.sendall(b"SSH-2.0-test\r\n")
            conn.recv(16)

    t = threading.Thread(target=serve)
    t.start()
    try:
        sock = connect_tcp("127.0.0.1", port, 5.0)
        with sock:
            assert isinstance(sock, QuickSocket)
            assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) != 0
            assert sock.gettimeout() == 5.0
            assert sock.recv(64) == b"SSH-2.0-test\r\n"
            if hasattr(socket, "TCP_QUICKACK"):  # Linux: set again after the read
                assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_QUICKACK) != 0
            sock.sendall(b"bye")
    finally:
        t.join(5)
        server.close()


def test_connect_tcp_refused_is_an_oserror() -> None:
    probe = socket.create_server(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()  # nothing listens there now
    with pytest.raises(OSError):
        connect_tcp("127.0.0.1", port, 2.0)


# -- ssh_config: no user-database lookup per block that has no Match ----------------------
CONFIG = """\
{many}
Host r01
    HostName 10.200.9.11
    User husarion
Host r02
    HostName 10.200.9.12
    Port 2222
Match user {me} host r0*
    IdentityFile ~/.ssh/lab_key
Match originalhost r02
    User operator
Host *
    ConnectTimeout 7
"""


def test_lookups_answer_as_paramiko_does_without_asking_for_the_user_per_block(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    many = "".join(f"Host other{i}\n    HostName 10.200.9.{100 + i}\n" for i in range(20))
    text = CONFIG.format(me=getpass.getuser(), many=many)
    path = tmp_path / "ssh_config"
    path.write_text(text)
    plain = paramiko.SSHConfig.from_text(text)
    asked: list[int] = []
    real_getuser = getpass.getuser
    monkeypatch.setattr(getpass, "getuser", lambda: asked.append(1) or real_getuser())
    for alias in ("r01", "r02", "r03"):
        want = dict(plain.lookup(alias))
        asked.clear()
        got = ssh_config._lookup(str(path), alias)
        assert got == want, alias
        # the 2 Match blocks in both passes and the tokens: not once per Host block (24 here)
        assert 0 < len(asked) <= 6, (alias, len(asked))
    assert ssh_config._lookup(str(path), "r02")["user"] == "operator"
