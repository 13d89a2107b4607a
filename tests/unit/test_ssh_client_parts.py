"""The parts under each SSH connection: the TCP socket, the private-key cache, ssh_config lookups."""

from __future__ import annotations

import getpass
import os
import socket
import threading
from pathlib import Path

import paramiko
import pytest

from panther_ops.transport import ssh_config
from panther_ops.transport.ssh import _client_type
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


# -- private keys: parsed once per version of the file ----------------------------------
def _write_key(path: Path) -> paramiko.PKey:
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

    raw = Ed25519PrivateKey.generate().private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.OpenSSH, serialization.NoEncryption()
    )
    path.write_bytes(raw)
    return paramiko.Ed25519Key.from_private_key_file(str(path))


def test_a_key_file_is_parsed_once_and_again_when_it_changes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    key_path = tmp_path / "id_ed25519"
    first = _write_key(key_path)
    calls: list[str] = []
    real = paramiko.Ed25519Key.from_private_key_file.__func__  # type: ignore[attr-defined]

    def counting(cls: type, filename: str, password: object = None) -> paramiko.PKey:
        calls.append(filename)
        return real(cls, filename, password)  # type: ignore[no-any-return]

    monkeypatch.setattr(paramiko.Ed25519Key, "from_private_key_file", classmethod(counting))
    a, b = _client_type()(), _client_type()()
    for c in (a, b):
        c._log = lambda *args: None  # no transport here to log through
    got1 = a._key_from_filepath(str(key_path), paramiko.Ed25519Key, None)
    got2 = b._key_from_filepath(str(key_path), paramiko.Ed25519Key, None)
    assert got1 is got2 and got1.get_fingerprint() == first.get_fingerprint()
    assert calls == [str(key_path)]

    second = _write_key(key_path)  # a new key in the same file: a new mtime
    os.utime(key_path, ns=(1, 1))
    calls.clear()
    got3 = a._key_from_filepath(str(key_path), paramiko.Ed25519Key, None)
    assert got3.get_fingerprint() == second.get_fingerprint() != first.get_fingerprint()
    assert calls == [str(key_path)]


def test_a_format_that_does_not_fit_fails_every_time_with_a_fresh_error(tmp_path: Path) -> None:
    key_path = tmp_path / "id_ed25519"
    _write_key(key_path)
    client = _client_type()()
    errors = []
    for _ in range(2):
        with pytest.raises(paramiko.SSHException) as info:
            client._key_from_filepath(str(key_path), paramiko.RSAKey, None)
        errors.append(info.value)
    assert errors[0] is not errors[1]
    assert type(errors[0]) is type(errors[1]) and errors[0].args == errors[1].args


def test_a_missing_key_file_is_reported_as_paramiko_does(tmp_path: Path) -> None:
    with pytest.raises(OSError):
        _client_type()()._key_from_filepath(str(tmp_path / "nope"), paramiko.Ed25519Key, None)


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
