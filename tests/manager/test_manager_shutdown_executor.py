"""The shutdown executor: HTTP signing against a local server, SSH over loopback, and that a
tick never waits for the network (every tick under 5 ms with a host whose sshd is down)."""

from __future__ import annotations

import hashlib
import hmac
import shutil
import subprocess
import threading
import time
from collections.abc import Iterator
from concurrent.futures import Future
from pathlib import Path
from typing import Any, ClassVar
from urllib.parse import parse_qs, urlparse

import pytest
import yaml
from py_trees.common import Status

from panther_ops.manager.blackboard import TreeBlackboard
from panther_ops.manager.clock import ManualClock, MonotonicClock
from panther_ops.manager.nodes.base import NodeContext
from panther_ops.manager.nodes.shutdown import ShutdownHostsFromFile, ShutdownSingleHost
from panther_ops.manager.shutdown_executor import (
    HostState,
    HttpShutdown,
    OpenSshShutdown,
    ParamikoShutdown,
    ShutdownBackends,
    ShutdownExecutor,
    ShutdownHost,
    SubprocessPinger,
    SubprocessRunner,
    ThreadDispatcher,
    load_shutdown_hosts,
    parse_shutdown_hosts,
    run_all,
    sign_shutdown_request,
)
from panther_ops.manager.trees.safety import build_shutdown_tree
from tests.loopback_http import QuietHandler, serving
from tests.manager.doubles import FakeLocalRunner, FakeRobotIO, fake_backends, tick
from tests.ports import free_port

SECRET = "husarion"


class ShutdownServer(QuietHandler):
    """A husarion-shutdown stand-in: checks the signature, never shuts anything down."""

    received: ClassVar[list[str]] = []
    secret = SECRET

    def do_GET(self) -> None:
        self.received.append(self.path)
        url = urlparse(self.path)
        query = parse_qs(url.query)
        ts = query.get("ts", [""])[0]
        expected = hmac.new(self.secret.encode(), f"/shutdown|{ts}".encode(),
                            hashlib.sha256).hexdigest()
        ok = url.path == "/shutdown" and query.get("sig", [""])[0] == expected
        self.reply(200 if ok else 403, b"shutting down" if ok else b"bad signature")


@pytest.fixture
def http_port() -> Iterator[int]:
    ShutdownServer.received = []
    with serving(ShutdownServer) as port:
        yield port


def test_signature_is_hmac_sha256_of_path_and_timestamp() -> None:
    expected = hmac.new(b"husarion", b"/shutdown|1700000000", hashlib.sha256).hexdigest()
    assert sign_shutdown_request("husarion", 1700000000) == expected


def test_http_request_is_signed_and_checked_by_the_server(http_port: int) -> None:
    host = ShutdownHost(ip="127.0.0.1", port=http_port, secret=SECRET, ping_for_success=False)
    outcome = HttpShutdown(wall_time=lambda: 1700000000.5).request(host)
    assert outcome.ok and outcome.output == "shutting down"
    assert ShutdownServer.received == [
        f"/shutdown?ts=1700000000&sig={sign_shutdown_request(SECRET, 1700000000)}"]
    wrong = ShutdownHost(ip="127.0.0.1", port=http_port, secret="not-the-secret")
    refused = HttpShutdown().request(wrong)
    assert not refused.ok and "HTTP 403" in refused.error


def test_run_all_over_http_with_the_real_backends(http_port: int) -> None:
    hosts = [ShutdownHost(ip="127.0.0.1", port=http_port, secret=SECRET, ping_for_success=False)]
    started = time.monotonic()
    results = run_all(hosts, MonotonicClock())
    assert [r.state for r in results] == [HostState.SUCCESS]
    assert time.monotonic() - started < 5
    assert len(ShutdownServer.received) == 1


def test_hosts_file_formats_of_both_eras(tmp_path: Path) -> None:
    path = tmp_path / "hosts.yaml"
    path.write_text(yaml.safe_dump({"hosts": [
        {"ip": "192.0.2.3", "username": "husarion"},
        {"ip": "192.0.2.12", "username": "pi", "timeout": 40, "command": "/home/pi/seq.sh"},
        {"ip": "192.0.2.5", "port": 3003, "timeout": 10.0},
        {"username": "nobody"},
        {"ip": "192.0.2.6", "username": "x", "colour": "red"},
        {"ip": "192.0.2.3", "username": "husarion"},
    ]}))
    parsed = load_shutdown_hosts(path)
    ssh, long_one, web = parsed.hosts
    assert (ssh.method.value, ssh.port, ssh.command, ssh.timeout) == ("ssh", 22, "sudo shutdown now", 5.0)
    assert (long_one.timeout, long_one.command) == (40.0, "/home/pi/seq.sh")
    assert (web.method.value, web.port, web.secret, web.timeout) == ("http", 3003, "husarion", 10.0)
    assert [p.split(": ", 1)[1] for p in parsed.problems] == [
        "hosts[3]: no ip, skipped", "hosts[4]: unknown keys: colour, skipped",
        "hosts[5]: duplicate of husarion@192.0.2.3:22, skipped"]
    assert parse_shutdown_hosts(None).hosts == ()


def test_executor_steps_never_block_on_slow_pings() -> None:
    clock = ManualClock()
    backends = fake_backends(clock, up={"192.0.2.3": True}, down_after=0.2)

    class SlowPinger:
        """Test double: a ping that takes a second to say 'no answer'."""

        def is_reachable(self, ip: str) -> bool:
            time.sleep(1.0)
            return False

    backends.pinger = SlowPinger()
    backends.dispatcher = ThreadDispatcher()
    executor = ShutdownExecutor([ShutdownHost(ip="192.0.2.3", username="u")], backends, clock)
    try:
        durations = []
        while not executor.done:
            started = time.perf_counter()
            executor.step()
            durations.append(time.perf_counter() - started)
            time.sleep(0.01)
        # a step that waited for the ping would take its whole second; a loaded machine may
        # delay a step by a few milliseconds, which says nothing about blocking
        assert max(durations) < 0.25
        assert executor.results()[0].state is HostState.SKIPPED
    finally:
        backends.close()


class HeldDispatcher:
    """Test double of a dispatcher whose jobs finish only when the test lets them (`finish`)."""

    def __init__(self) -> None:
        self.held: list[tuple[Any, Future[Any]]] = []

    def submit(self, fn: Any) -> Future[Any]:
        future: Future[Any] = Future()
        self.held.append((fn, future))
        return future

    def finish(self) -> None:
        held, self.held = self.held, []
        for fn, future in held:
            future.set_result(fn())

    def close(self) -> None:
        return None


@pytest.mark.parametrize(("answer", "state"), [(False, HostState.SUCCESS), (True, HostState.FAILURE)])
def test_a_ping_on_its_way_at_the_time_limit_decides(answer: bool, state: HostState) -> None:
    """As the stock ShutdownHost (ping, then look at the clock): a ping sent before the host's
    time limit and answered after it is waited for, and its answer says whether the host went
    down. A loaded robot whose pings take long does not fail a host that did go down."""
    clock = ManualClock()
    backends = fake_backends(clock, up={"192.0.2.3": True}, down_after=None)
    dispatcher = HeldDispatcher()
    backends.dispatcher = dispatcher
    executor = ShutdownExecutor([ShutdownHost(ip="192.0.2.3", username="u", timeout=5.0)], backends, clock)
    for _ in range(4):  # the first ping, the request, its answer: now pinging, one ping on its way
        executor.step()
        dispatcher.finish()
    executor.step()
    assert executor.results()[0].state is HostState.PINGING and len(dispatcher.held) == 1
    clock.advance(6.0)  # past the limit while that ping is on its way
    executor.step()
    assert executor.results()[0].state is HostState.PINGING
    backends.pinger.up["192.0.2.3"] = answer  # type: ignore[attr-defined]
    dispatcher.finish()
    executor.step()
    assert executor.results()[0].state is state


def real_backends(tmp_path: Path) -> ShutdownBackends:
    known_hosts = tmp_path / "known_hosts"
    known_hosts.write_text("")
    return ShutdownBackends(SubprocessPinger(), ParamikoShutdown(known_hosts), HttpShutdown(),
                            FakeLocalRunner(), ThreadDispatcher())


def test_every_tick_under_5ms_with_a_host_whose_sshd_is_stopped(tmp_path: Path) -> None:
    """127.0.0.1 answers ping but nothing listens on the SSH port: connection refused.

    A tick that waited on the ping, the connection or the command would be over 5 ms in every
    run; a tick that only took long because the machine's scheduler ran something else is not
    in the next run. So each node gets up to three runs, and one of them must have every tick
    under 5 ms (the statuses and the messages are checked in every run)."""
    port = free_port()
    hosts = tmp_path / "hosts.yaml"
    hosts.write_text(yaml.safe_dump({"hosts": [
        {"ip": "127.0.0.1", "username": "husarion", "port": port, "timeout": 3.0}]}))
    slowest: dict[str, list[float]] = {}
    for _run in range(3):
        backends = real_backends(tmp_path)
        blackboard = TreeBlackboard("Shutdown")
        blackboard.update({"SHUTDOWN_HOSTS_PATH": str(hosts), "SHUTDOWN_LOCALHOST_COMMAND": "poweroff"})
        ctx = NodeContext(FakeRobotIO(), MonotonicClock(), blackboard, backends)
        tree = build_shutdown_tree(ctx)
        single = ShutdownSingleHost("single", ctx, ip="127.0.0.1", username="husarion", port=port)
        from_file = ShutdownHostsFromFile("file", ctx, shutdown_hosts_file=str(hosts))
        try:
            for node in (single, from_file, tree):
                if any(t < 0.005 for t in slowest.get(node.name, [])):
                    continue  # this node already had a run with every tick under 5 ms
                durations: list[float] = []
                status = Status.RUNNING
                deadline = time.monotonic() + 10
                while status == Status.RUNNING and time.monotonic() < deadline:
                    started = time.perf_counter()
                    status = tick(node) or Status.SUCCESS
                    durations.append(time.perf_counter() - started)
                    time.sleep(1 / 30)
                assert len(durations) >= 3  # ping, request, outcome: one step per tick
                slowest.setdefault(node.name, []).append(max(durations))
                if node is tree:
                    assert status == Status.SUCCESS  # hosts failed, the robot's own step still ran
                    assert backends.local.commands == ["poweroff"]  # type: ignore[attr-defined]
                else:
                    assert status == Status.FAILURE
                    assert "unable to connect" in node.feedback_message.lower()
        finally:
            backends.close()
    for name, runs in slowest.items():
        assert min(runs) < 0.005, f"{name}: slowest tick of each run {[f'{t * 1000:.1f} ms' for t in runs]}"
    assert len(slowest) == 3


def _sshd_unavailable(msg: str) -> None:
    """Skip, or fail under CI=true (the SSH backends must be tested against a real sshd in CI)."""
    import os

    if os.environ.get("CI", "").strip().lower() == "true":
        pytest.fail(f"{msg} (CI=true: the real-sshd tests must run)", pytrace=False)
    pytest.skip(msg)


@pytest.fixture
def loopback_sshd(tmp_path: Path) -> Iterator[dict[str, Any]]:
    """An sshd on 127.0.0.1 for this test only (public-key login as the current user).

    sshd needs its privilege separation directory /run/sshd; where this machine has none (its own
    sshd is never started), it runs in a private mount namespace with a fresh /run (root only),
    so nothing of the host is changed.
    """
    import os

    sshd, keygen = shutil.which("sshd") or "/usr/sbin/sshd", shutil.which("ssh-keygen")
    if not Path(sshd).exists() or keygen is None:
        _sshd_unavailable("sshd / ssh-keygen not installed (scripts/install-test-deps.sh)")
    prefix: list[str] = []
    if not Path("/run/sshd").is_dir():
        unshare = shutil.which("unshare")
        if os.geteuid() != 0 or unshare is None:
            _sshd_unavailable("no /run/sshd and no root to give sshd a private /run")
        prefix = [str(unshare), "--mount", "--propagation", "private", "sh", "-c",
                  'mount -t tmpfs -o mode=0755 tmpfs /run && mkdir -m 0755 /run/sshd && exec "$@"', "sshd"]
    for name in ("host_key", "client_key"):
        subprocess.run([str(keygen), "-q", "-t", "ed25519", "-N", "", "-f", str(tmp_path / name)],
                       check=True)
    (tmp_path / "authorized_keys").write_text((tmp_path / "client_key.pub").read_text())
    port = free_port()
    config = tmp_path / "sshd_config"
    config.write_text(
        f"Port {port}\nListenAddress 127.0.0.1\nHostKey {tmp_path / 'host_key'}\n"
        f"AuthorizedKeysFile {tmp_path / 'authorized_keys'}\nPasswordAuthentication no\n"
        "KbdInteractiveAuthentication no\nUsePAM no\nStrictModes no\n"
        f"PidFile {tmp_path / 'sshd.pid'}\n")
    process = subprocess.Popen([*prefix, sshd, "-D", "-e", "-f", str(config)], stderr=subprocess.PIPE, text=True)
    assert process.stderr is not None
    said = []
    for line in process.stderr:  # wait for sshd to say it listens (or to exit)
        said.append(line)
        if line.startswith("Server listening on"):
            break
    else:
        process.wait(timeout=5)
        _sshd_unavailable(f"sshd did not start: {''.join(said)[-300:]}")
    threading.Thread(target=process.stderr.read, daemon=True).start()  # keep its log flowing
    host_key = (tmp_path / "host_key.pub").read_text().split()
    yield {"port": port, "client_key": tmp_path / "client_key",
           "known_line": f"[127.0.0.1]:{port} {host_key[0]} {host_key[1]}\n"}
    process.terminate()
    process.wait(timeout=5)


def loopback_host(loopback_sshd: dict[str, Any], command: str) -> ShutdownHost:
    """The loopback sshd as a host to shut down, by this user, running `command`."""
    import getpass

    return ShutdownHost(ip="127.0.0.1", username=getpass.getuser(), port=loopback_sshd["port"],
                        command=command, timeout=5.0)


def empty_known_hosts(tmp_path: Path) -> Path:
    known_hosts = tmp_path / "known_hosts"
    known_hosts.write_text("")
    return known_hosts


@pytest.mark.parametrize(("backend", "command", "output", "refusal"), [
    (ParamikoShutdown, "echo harmless-test-command", "harmless-test-command", ("known_hosts",)),
    # the backend the deployed manager uses where paramiko is missing: the real ssh client
    (OpenSshShutdown, "echo harmless-test-command 'two words'", "harmless-test-command two words",
     ("SSH error", "verification failed")),
])
def test_ssh_refuses_an_unknown_host_key_and_runs_with_a_known_one(
        loopback_sshd: dict[str, Any], tmp_path: Path, backend: type[ParamikoShutdown | OpenSshShutdown],
        command: str, output: str, refusal: tuple[str, ...]) -> None:
    host = loopback_host(loopback_sshd, command)
    known_hosts = empty_known_hosts(tmp_path)
    strict = backend(known_hosts, key_filename=loopback_sshd["client_key"])
    refused = strict.request(host)
    assert not refused.ok and all(word in refused.error for word in refusal), refused.error
    assert known_hosts.read_text() == ""  # nothing was added
    known_hosts.write_text(loopback_sshd["known_line"])
    accepted = strict.request(host)
    assert accepted.ok, accepted.error
    assert accepted.output.strip() == output


def test_local_commands_run_without_a_shell() -> None:
    runner = SubprocessRunner()
    assert runner.run("echo 'one two'", 5).output == "one two\n"
    assert not runner.run("false", 5).ok
    assert "No such file" in runner.run("/nonexistent/binary", 5).error


def test_openssh_backend_strict_batch_argv_failing_command_and_wrong_key(
        loopback_sshd: dict[str, Any], tmp_path: Path) -> None:
    """The real ssh client against a real sshd: its options, a failing command, a key sshd does not know."""
    host = loopback_host(loopback_sshd, "echo harmless-test-command 'two words'")
    known_hosts = tmp_path / "known_hosts"
    known_hosts.write_text(loopback_sshd["known_line"])
    strict = OpenSshShutdown(known_hosts, key_filename=loopback_sshd["client_key"])
    argv = strict.argv(host)
    assert argv[-3:] == ["--", "127.0.0.1", host.command]  # the command is one argument, no local shell
    assert {"BatchMode=yes", "StrictHostKeyChecking=yes", f"UserKnownHostsFile={known_hosts}",
            "GlobalKnownHostsFile=/dev/null"} <= set(argv)
    failing = strict.request(loopback_host(loopback_sshd, "exit 3"))
    assert not failing.ok and failing.error.startswith("command exited with 3")
    other_key = tmp_path / "other_key"
    subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-f", str(other_key)], check=True)
    denied = OpenSshShutdown(known_hosts, key_filename=other_key).request(host)
    assert not denied.ok and "Permission denied" in denied.error  # batch mode: no password prompt


def test_openssh_backend_refuses_option_like_hosts(tmp_path: Path) -> None:
    from panther_ops.manager.shutdown_executor import OpenSshShutdown

    known_hosts = tmp_path / "known_hosts"
    known_hosts.write_text("")
    backend = OpenSshShutdown(known_hosts)
    for ip, user in (("-oProxyCommand=touch x", "husarion"), ("127.0.0.1", "-oProxyCommand=x"),
                     ("127.0.0.1 x", "husarion")):
        out = backend.request(ShutdownHost(ip=ip, username=user))
        assert not out.ok and "is not a plain host or user name" in out.error


def test_real_backends_choose_paramiko_here_and_openssh_without_it(tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    from panther_ops.manager.shutdown_executor import OpenSshShutdown, ssh_backend, ssh_method

    assert ssh_method() == "paramiko" and isinstance(ssh_backend(tmp_path / "kh"), ParamikoShutdown)
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "paramiko" else real(name, *a))
    assert ssh_method() == "openssh"
    chosen = ShutdownBackends.real(tmp_path / "kh").ssh
    assert isinstance(chosen, OpenSshShutdown) and chosen.known_hosts == tmp_path / "kh"
    monkeypatch.setenv("PATH", str(tmp_path))
    assert ssh_method() is None


def test_known_hosts_lookup_matches_openssh(loopback_sshd: dict[str, Any], tmp_path: Path) -> None:
    """`is_known` agrees with the real ssh-keygen on plain, hashed and non-default-port names."""
    from panther_ops.manager.shutdown_executor.knownhosts import is_known

    port = loopback_sshd["port"]
    path = tmp_path / "known_hosts"
    path.write_text(loopback_sshd["known_line"] + "192.0.2.9,192.0.2.10 " + " ".join(
        loopback_sshd["known_line"].split()[1:]) + "\n")
    subprocess.run(["ssh-keygen", "-q", "-H", "-f", str(path)], check=True, capture_output=True)  # hash all names
    hashed = path.read_text()
    assert "192.0.2.9" not in hashed and "[127.0.0.1]" not in hashed
    for text in (loopback_sshd["known_line"], hashed):
        assert is_known(text, "127.0.0.1", port)
        assert not is_known(text, "127.0.0.1", 22) and not is_known(text, "127.0.0.2", port)
    assert is_known(hashed, "192.0.2.10") and not is_known(hashed, "192.0.2.11")
    for name, expected in (("127.0.0.1", True), ("192.0.2.10", True), ("192.0.2.11", False)):
        found = subprocess.run(["ssh-keygen", "-F", f"[{name}]:{port}" if name == "127.0.0.1" else name,
                                "-f", str(path)], capture_output=True, check=False).returncode == 0
        assert found is expected  # the real tool says the same
