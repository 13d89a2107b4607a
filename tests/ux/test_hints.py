"""Hints are the next command, filled in with the robot's values (issue 26, finding 3): a key the
robot refuses, no key at all, a key file missing, a host that never answers, a port nobody
listens on, an unknown host key; and doctor gives a fix for every finding, unreachable robots
included. A real sshd on loopback (tests/sshd.py) and a listener that never answers."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.clirun import run, run_cli
from tests.ports import free_port
from tests.sshd import LoopbackSshd, keygen, missing

from .test_interrupt import Silent

Capsys = pytest.CaptureFixture[str]
ROBOT = "newkey-03"
PLACEHOLDER = re.compile(r"\b(ROBOT|HOST|PORT|KEY|NAME)\b")


@pytest.fixture
def home(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An empty home (no ~/.ssh keys) and no ssh-agent: only what the inventory says is offered."""
    h = tmp_path / "home"
    (h / ".ssh").mkdir(parents=True)
    monkeypatch.setenv("HOME", str(h))
    monkeypatch.delenv("SSH_AUTH_SOCK", raising=False)
    return h


def _inventory(tmp_path: Path, port: int, extra: str = "", known_hosts: Path | None = None) -> str:
    inv = tmp_path / "inv.yaml"
    kh = known_hosts or tmp_path / "known_hosts"
    inv.write_text(f"settings: {{known_hosts: {kh}}}\nrobots:\n  {ROBOT}:\n    host: 127.0.0.1\n"
                   f"    port: {port}\n    user: root\n    connect_timeout: 1\n{extra}")
    return str(inv)


def _unreachable(capsys: Capsys, inv: str) -> tuple[str, str]:
    """The message and the hint of the one robot, `status --json`."""
    code, doc, _, err = run_cli(capsys, "-i", inv, "status", "--json")
    assert code == 4, err
    (robot,) = doc["robots"]
    assert robot["outcome"] == "unreachable"
    hint = robot["data"]["hint"]
    assert not PLACEHOLDER.search(hint), hint
    return robot["message"], hint


def test_a_refused_key_names_the_key_and_the_command_that_installs_it(
        sshd: LoopbackSshd, home: Path, tmp_path: Path, capsys: Capsys) -> None:
    key = keygen(tmp_path / "id_ed25519")  # exists, set as identity_file, not in authorized_keys
    message, hint = _unreachable(capsys, _inventory(tmp_path, sshd.port, f"    identity_file: {key}\n",
                                                    sshd.known_hosts))
    assert f"root@127.0.0.1 refused the key {key}" in message, message
    assert f"ssh-copy-id -i {key}.pub -p {sshd.port} root@127.0.0.1" in hint, hint
    assert "set identity_file" not in hint  # it is set: that was the wrong fix


def test_no_key_at_all_says_so_and_how_to_make_and_install_one(
        sshd: LoopbackSshd, home: Path, tmp_path: Path, capsys: Capsys) -> None:
    message, hint = _unreachable(capsys, _inventory(tmp_path, sshd.port, known_hosts=sshd.known_hosts))
    assert "no key to log in as root@127.0.0.1" in message and "No authentication methods" not in message, message
    assert (f"ssh-keygen -t ed25519 -f ~/.ssh/id_ed25519 && ssh-copy-id -i ~/.ssh/id_ed25519.pub "
            f"-p {sshd.port} root@127.0.0.1") in hint, hint


def test_the_default_key_refused_is_not_called_a_missing_key(
        sshd: LoopbackSshd, home: Path, tmp_path: Path, capsys: Capsys) -> None:
    key = keygen(home / ".ssh" / "id_ed25519")
    message, hint = _unreachable(capsys, _inventory(tmp_path, sshd.port, known_hosts=sshd.known_hosts))
    assert f"refused every key offered ({key})" in message, message
    assert f"ssh-copy-id -i {key}.pub -p {sshd.port} root@127.0.0.1" in hint, hint
    sshd.authorize(key)  # and with the key installed, the same inventory logs in
    _, doc, _, err = run_cli(capsys, "-i", _inventory(tmp_path, sshd.port, known_hosts=sshd.known_hosts),
                             "status", "--json")
    assert doc["robots"][0]["outcome"] != "unreachable", err


def test_a_key_file_named_by_ssh_config_that_is_missing_is_named(
        sshd: LoopbackSshd, home: Path, tmp_path: Path, capsys: Capsys) -> None:
    gone = tmp_path / "keys" / "gone_ed25519"
    (tmp_path / "ssh_config").write_text(f"Host 127.0.0.1\n  IdentityFile {gone}\n")
    inv = _inventory(tmp_path, sshd.port, known_hosts=sshd.known_hosts)
    Path(inv).write_text(Path(inv).read_text().replace("settings: {", f"settings: {{ssh_config: {tmp_path / 'ssh_config'}, "))
    message, hint = _unreachable(capsys, inv)
    assert f"identity file {gone} does not exist" in message, message
    assert f"ssh-copy-id -i {gone}.pub -p {sshd.port} root@127.0.0.1" in hint, hint


def test_an_unknown_host_key_hint_is_trust_with_the_robots_name(
        sshd: LoopbackSshd, home: Path, tmp_path: Path, capsys: Capsys) -> None:
    message, hint = _unreachable(capsys, _inventory(tmp_path, sshd.port))  # an empty known_hosts
    assert message.startswith(f"127.0.0.1:{sshd.port} offers host key ssh-ed25519 SHA256:"), message
    assert message.count(f"127.0.0.1]:{sshd.port}") + message.count(f"127.0.0.1:{sshd.port}") == 1, message
    assert hint.endswith(f"then: panther-ops trust {ROBOT}"), hint


def test_a_login_that_takes_longer_than_the_timeout_is_not_called_a_refused_key(
        home: Path, tmp_path: Path, capsys: Capsys) -> None:
    """sshd checks the key with an AuthorizedKeysCommand that takes 3 s (a robot too busy to
    answer in time, as 300 logins at once on a small machine): paramiko's auth_timeout runs out.
    The key is good: the message says the login did not finish in time, not that it was refused."""
    why = missing()
    if why:
        pytest.skip(why)
    key = keygen(tmp_path / "id_ed25519")
    root = tmp_path / "sshd"
    slow_keys = tmp_path / "slow_keys"  # not the AuthorizedKeysFile: only the command finds the key
    slow_keys.write_text(Path(f"{key}.pub").read_text())
    slow = LoopbackSshd(root, extra=["AuthorizedKeysCommandUser root",
                                     f"AuthorizedKeysCommand /bin/sh -c 'sleep 3; cat {slow_keys}'"])
    try:
        message, hint = _unreachable(capsys, _inventory(tmp_path, slow.port, f"    identity_file: {key}\n",
                                                        slow.known_hosts))
    finally:
        slow.close()
    assert message == "root@127.0.0.1 did not finish logging in within 1 s (the key was not refused)", message
    assert "--forks" in hint and "connect_timeout" in hint, hint
    assert "ssh-copy-id" not in hint  # installing the key again is not the fix


@pytest.fixture
def silent() -> Iterator[Silent]:
    s = Silent()
    yield s
    s.close()


def test_a_host_that_never_answers_is_said_so_with_its_address_and_the_wait(
        silent: Silent, tmp_path: Path, capsys: Capsys) -> None:
    inv = _inventory(tmp_path, silent.port)
    message, hint = _unreachable(capsys, inv)
    assert message == f"127.0.0.1:{silent.port} accepted the connection but did not answer in 1 s (no SSH greeting)"
    assert f"ssh -p {silent.port} root@127.0.0.1" in hint, hint
    code, out, err = run(capsys, "-i", inv, "trust", ROBOT)  # asking for its host key: the same words
    # (trust is a change: the host key's result in the table, its hint on stderr)
    assert code == 4 and "did not answer in 1 s" in out and "No existing session" not in out + err, out + err
    assert f"ssh -p {silent.port} root@127.0.0.1" in err, err


def test_a_port_nobody_listens_on(tmp_path: Path, capsys: Capsys) -> None:
    port = free_port()
    message, hint = _unreachable(capsys, _inventory(tmp_path, port))
    assert message == f"127.0.0.1:{port} refused the connection (no sshd listens on port {port})"
    assert f"ssh -p {port} root@127.0.0.1" in hint, hint


def test_doctor_gives_a_fix_for_an_unreachable_robot(silent: Silent, tmp_path: Path, capsys: Capsys) -> None:
    inv = _inventory(tmp_path, silent.port)
    code, doc, _, err = run_cli(capsys, "-i", inv, "doctor", "--json")
    assert code == 4, err
    (finding,) = doc["robots"][0]["data"]["findings"]
    assert finding["state"] == "fail" and "did not answer in 1 s" in finding["detail"], finding
    assert f"ssh -p {silent.port} root@127.0.0.1" in finding["fix"], finding
    code, out, _ = run(capsys, "-i", inv, "--wide", "doctor")  # the table's fix column says it too
    assert f"ssh -p {silent.port} root@127.0.0.1" in out, out


def test_every_doctor_finding_that_is_not_ok_has_a_fix(demo: Path, capsys: Capsys) -> None:
    _, doc, _, err = run_cli(capsys, "-i", str(demo), "doctor", "--all", "--json")
    findings = [f for r in doc["robots"] for f in r["data"]["findings"]]
    assert findings, err
    assert all(f["fix"] for f in findings if f["state"] != "ok"), findings


@pytest.mark.parametrize("argv", [["inventory", "validate"], ["status", "--all"]])
def test_a_tab_in_the_inventory_is_named_as_a_tab(argv: list[str], tmp_path: Path, capsys: Capsys) -> None:
    inv = tmp_path / "inv.yaml"
    inv.write_text("robots:\n  r1:\n    host: 10.15.20.2\n\tport: 22\n")
    code, _, err = run(capsys, "-i", str(inv), *argv)
    assert code == 2 and f"{inv}:4: invalid YAML: tab character at line 4 col 1; YAML indents with spaces" in err, err


def test_a_tab_in_a_file_read_round_trip_is_named_as_a_tab(tmp_path: Path, capsys: Capsys) -> None:
    hosts = tmp_path / "hosts.yaml"  # the shutdown hosts file: read by the round-trip (ruamel) parser
    hosts.write_text("hosts:\n  - ip: 10.15.20.3\n  \t username: husarion\n")
    code, _, err = run(capsys, "shutdown", "hosts", "validate", str(hosts))
    assert code == 2 and "tab character at line 3 col 3; YAML indents with spaces" in err, err
