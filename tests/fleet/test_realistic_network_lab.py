"""A realistic network in the lab: each robot's sshd behind a delay relay (tests/lab/relay.py).

The relay alone is checked on loopback (order kept under jitter, round trips as asked);
then a lab with a 100 ms round trip: the client sees the same address and host key, each
round trip takes ~100 ms, and a configuration change with the driver recreated and
verified works through it.
"""

from __future__ import annotations

import json
import socket
import statistics
import subprocess
import sys
import threading
import time
from typing import Any

import pytest

from panther_ops.cli.app import main
from tests.lab.lab import RELAY
from tests.ports import free_port

COMPOSE = "/home/husarion/compose.yaml"
RTT = 0.1
JITTER = 0.02  # of each one-way delay, in the relay of the first test


def _echo_server() -> tuple[socket.socket, int]:
    server = socket.create_server(("127.0.0.1", 0))

    def serve() -> None:
        while True:
            try:
                conn, _ = server.accept()
            except OSError:
                return

            def echo(c: socket.socket) -> None:
                with c:
                    while data := c.recv(65536):
                        c.sendall(data)

            threading.Thread(target=echo, args=(conn,), daemon=True).start()

    threading.Thread(target=serve, daemon=True).start()
    return server, server.getsockname()[1]


@pytest.fixture
def relay() -> Any:
    """A relay with a 100 ms round trip and ± 20 ms jitter in front of a local echo server."""
    server, port = _echo_server()
    listen = free_port()
    p = subprocess.Popen([sys.executable, "-I", str(RELAY), "--listen", f"127.0.0.1:{listen}",
                          "--to", f"127.0.0.1:{port}", "--delay-ms", "50", "--jitter-ms", "20"],
                         stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout is not None and p.stdout.readline().strip() == "ready"
        yield listen
    finally:
        p.kill()
        p.wait()
        server.close()


def test_the_relay_keeps_order_under_jitter_and_delays_each_round_trip(relay: int) -> None:
    with socket.create_connection(("127.0.0.1", relay), timeout=10) as s:
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sent = b"".join(b"%05d;" % i for i in range(400))
        t0 = time.monotonic()
        for i in range(400):  # 400 small writes, each delayed by its own draw of the jitter
            s.sendall(b"%05d;" % i)
        got = b""
        while len(got) < len(sent):
            got += s.recv(65536)
        assert got == sent, "chunks overtook each other"
        # the first byte comes back once the relay charged the TCP handshake's round trip and
        # the data's: ~2 round trips (each one-way delay 50 ± 20 ms); then each echo is one
        assert time.monotonic() - t0 >= 2 * RTT - 2 * JITTER
        rtts = []
        for _ in range(9):
            t = time.monotonic()
            s.sendall(b"x")
            assert s.recv(1) == b"x"
            rtts.append(time.monotonic() - t)
        assert RTT - JITTER <= statistics.median(rtts) <= RTT + 3 * JITTER, rtts


def test_a_lab_behind_relays(lab_factory: Any, capsys: pytest.CaptureFixture[str]) -> None:
    lab = lab_factory(2, docker=True, images=("2.1.1",), rtt_ms=RTT * 1000)
    r = lab.robots[0]
    # same address, same host key: OpenSSH with strict host keys, as before
    times = []
    for _ in range(3):
        t = time.monotonic()
        out = subprocess.run(["ssh", "-F", str(lab.ssh_config_path), r.name, "echo", "hello"],
                             capture_output=True, text=True, timeout=30, check=False)
        times.append(time.monotonic() - t)
        assert out.returncode == 0 and out.stdout == "hello\n", out.stderr
    # TCP, key exchange (2), new keys, authentication (2-3), channel, exec, close: >= 7 round trips
    assert 7 * RTT <= statistics.median(times) <= 30 * RTT, times  # the rest: CPU of a shared machine
    # the SSH banner: the TCP handshake's round trip, then sshd's first line: 2 round trips
    banners = []
    for _ in range(3):
        t = time.monotonic()
        with socket.create_connection((r.host, 22), timeout=10) as s:
            assert s.recv(64).startswith(b"SSH-2.0-OpenSSH")
        banners.append(time.monotonic() - t)
    assert 1.8 * RTT <= statistics.median(banners) <= 4 * RTT, banners

    # the default path (write, recreate, verify) and --no-restart, through the relays
    inv = str(lab.inventory_path)
    before = {x.name: lab.read(x.name, COMPOSE) for x in lab.robots}
    try:
        capsys.readouterr()
        code = main(["-i", inv, "config", "set", "wheel_type", "WH02", "--all", "--yes", "--json",
                     "--settle", "1"])
        doc = json.loads(capsys.readouterr().out)
        assert code == 0, doc
        assert {x["outcome"] for x in doc["robots"]} == {"changed"}
        for x in lab.robots:
            assert "wheel_type:=WH02" in lab.read(x.name, COMPOSE)
            cmd = lab.docker(x.name, "inspect", "-f", "{{json .Config.Cmd}}", x.driver_container, check=True).stdout
            assert "wheel_type:=WH02" in cmd
        code = main(["-i", inv, "config", "set", "wheel_type", "WH04", "--all", "--yes", "--json", "--no-restart"])
        doc = json.loads(capsys.readouterr().out)
        assert code == 0 and {x["outcome"] for x in doc["robots"]} == {"changed"}, doc
        for x in lab.robots:
            assert "wheel_type:=WH04" in lab.read(x.name, COMPOSE)
    finally:
        for x in lab.robots:
            lab.write(x.name, COMPOSE, before[x.name])
            lab.sh(x.name, "rm -rf /home/husarion/.panther-ops")
