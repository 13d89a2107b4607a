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


def test_a_quick_socket_reads_what_arrived_in_one_call(monkeypatch: pytest.MonkeyPatch) -> None:
    a, b = socket.socketpair()
    quick = QuickSocket(a.family, a.type, a.proto, fileno=a.detach())
    calls: list[int] = []
    real = socket.socket.recv

    def counted(self: socket.socket, n: int, flags: int = 0) -> bytes:
        calls.append(n)
        return real(self, n, flags)

    monkeypatch.setattr(socket.socket, "recv", counted)
    b.sendall(b"HEADER" + b"body of the packet")
    assert quick.recv(6) == b"HEADER"  # one system call read the whole packet...
    assert quick.recv(100) == b"body of the packet"  # ...the rest comes from it
    assert len(calls) == 1
    b.sendall(b"next")
    assert quick.recv(2) == b"ne" and quick.recv(2) == b"xt" and len(calls) == 2
    b.close()
    assert quick.recv(10) == b""  # the end is still the end
    quick.close()


def test_the_c_helpers_answer_as_paramikos_own() -> None:
    import random

    from panther_ops.transport.paramiko_import import REPLACED, import_paramiko

    util = import_paramiko().util
    assert set(REPLACED) == {"constant_time_bytes_eq", "safe_string", "start_handshake", "handshake_timed_out"}
    rnd = random.Random(7)
    for _ in range(300):
        a = bytes(rnd.randrange(256) for _ in range(rnd.randrange(40)))
        b = a if rnd.random() < 0.5 else bytes(rnd.randrange(256) for _ in range(rnd.randrange(40)))
        assert util.constant_time_bytes_eq(a, b) == REPLACED["constant_time_bytes_eq"](a, b)
        assert util.safe_string(a) == REPLACED["safe_string"](a)
    for a, b in [("|1|abc=", "|1|abc="), ("|1|abc=", "|1|abd="), ("é", "é"), ("é", "e")]:
        assert util.constant_time_bytes_eq(a, b) == REPLACED["constant_time_bytes_eq"](a, b)
    assert util.safe_string("text é") == REPLACED["safe_string"]("text é")


def test_paramiko_is_only_imported_through_import_paramiko() -> None:
    """A task importing paramiko itself while the preload thread imports it through
    import_paramiko (stand-ins in sys.modules) broke both imports: every run-time import
    of paramiko in the operator side goes through the serialized function first."""
    import re
    from pathlib import Path

    import panther_ops

    root = Path(panther_ops.__file__).parent
    offenders = []
    for path in root.rglob("*.py"):
        if "manager" in path.parts or path.name == "paramiko_import.py":
            continue  # the runtime manager runs on robots, in its own process
        lines = path.read_text().splitlines()
        for i, line in enumerate(lines):
            if re.fullmatch(r"\s*(import paramiko|from paramiko\b.*)", line):
                j = i - 1
                while j > 0 and re.fullmatch(r"\s*(import paramiko|from paramiko\b.*)", lines[j]):
                    j -= 1  # a run of paramiko imports: what comes before the first counts
                before = lines[j].strip()
                if not (before.startswith("if TYPE_CHECKING") or before.startswith("import_paramiko()")):
                    offenders.append(f"{path.relative_to(root)}:{i + 1}")
    assert offenders == []


def test_import_paramiko_beside_other_threads_importing() -> None:
    """Fresh interpreters: import_paramiko in one thread while others ask importlib.metadata
    and import paramiko through it too; every thread gets what it asked for."""
    import subprocess
    import sys

    code = """
import importlib, sys, threading
from panther_ops.transport.paramiko_import import import_paramiko
errors, got = [], []
def via():
    try: got.append(import_paramiko().Transport.__name__)
    except BaseException as e: errors.append(repr(e))
def meta():
    try: got.append(importlib.import_module("importlib.metadata").version("pip"))
    except BaseException as e: errors.append(repr(e))
ts = [threading.Thread(target=via)] + [threading.Thread(target=f) for f in (meta, via, meta, via)]
for t in ts: t.start()
for t in ts: t.join()
assert not errors, errors
assert got.count("Transport") == 3 and len(got) == 5, got
import importlib.metadata as m
assert not type(m).__name__.startswith("_Quick"), "the stand-in is gone"
print("ok")
"""
    for _ in range(5):
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
        assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr


def test_a_key_exchange_deadline_instead_of_a_timer_thread() -> None:
    import time

    from panther_ops.transport.paramiko_import import import_paramiko

    paramiko = import_paramiko()
    a, b = socket.socketpair()
    packetizer = paramiko.packet.Packetizer(a)
    threads = threading.active_count()
    assert not packetizer.handshake_timed_out()  # not started: never
    packetizer.start_handshake(0.05)
    assert threading.active_count() == threads, "no timer thread"
    assert not packetizer.handshake_timed_out()
    time.sleep(0.06)
    assert packetizer.handshake_timed_out()
    packetizer.complete_handshake()
    assert not packetizer.handshake_timed_out()  # completed: no longer
    a.close()
    b.close()
