"""The shutdown hosts file: validation (with data), round-trip edits, masking; sudo listings;
the executor driven the CLI's way with test doubles. No network: addresses are RFC 5737
documentation addresses or the manual's examples, used as data only."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.fleet.plan import mask_secrets
from panther_ops.core.kinds.hostsfile import (
    Mode,
    add_host,
    check_entry,
    is_power_off_command,
    load_hosts_file,
    new_entry,
    parse_hosts,
    remove_host,
    valid_address,
)
from panther_ops.core.shutdown.check import nopasswd_for, parse_sudo_listing, sudo_probe
from panther_ops.core.shutdown.run import result_of, shutdown_hosts, summary
from panther_ops.errors import UsageError
from panther_ops.manager.clock import ManualClock
from panther_ops.manager.shutdown_executor import (
    CommandOutcome,
    InlineDispatcher,
    ShutdownBackends,
    ShutdownHost,
    SubprocessRunner,
)

SEED = """## My shutdown_hosts_config.yaml
hosts:
  # Intel NUC, user computer
  - ip: 10.15.20.3
    username: husarion
  # Universal robots UR5
  - ip: 10.15.20.4
    username: root
  # My Raspberry pi that requires very long shutdown sequence
  - ip: 10.15.20.12
    timeout: 40
    username: pi
    command: /home/pi/my_long_shutdown_sequence.sh
"""


def errors(text: str, mode: Mode | None = None, **kw: Any) -> list[str]:
    return [str(f) for f in parse_hosts(text, "t.yaml", mode=mode, **kw).errors]


def warnings(text: str, mode: Mode | None = None, **kw: Any) -> list[str]:
    return [str(f) for f in parse_hosts(text, "t.yaml", mode=mode, **kw).warnings]


def one(entry: str) -> str:
    return "hosts:\n" + "".join(f"  {'-' if i == 0 else ' '} {line}\n" for i, line in enumerate(entry.split("|")))


def test_the_seed_example_is_valid_with_two_warnings_for_the_raspberry_pi() -> None:
    hf = parse_hosts(SEED, "seed.yaml", mode=Mode.SSH)
    assert hf.errors == []
    assert [(e.ip, e.username, e.port, e.timeout, e.command) for e in hf.entries] == [
        ("10.15.20.3", "husarion", 22, 5.0, "sudo shutdown now"),
        ("10.15.20.4", "root", 22, 5.0, "sudo shutdown now"),
        ("10.15.20.12", "pi", 22, 40.0, "/home/pi/my_long_shutdown_sequence.sh"),
    ]
    ws = [str(w) for w in hf.warnings]
    assert len(ws) == 2
    assert "hosts[2].timeout (line 11): 40 s is longer than the ~15 s" in ws[1] or \
        "hosts[2].timeout (line 11): 40 s is longer than the ~15 s" in ws[0]
    assert any("is not a shutdown/poweroff command" in w for w in ws)
    hosts = hf.hosts()
    assert hosts[0] == ShutdownHost("10.15.20.3", "husarion")


@pytest.mark.parametrize(("entry", "message"), [
    ('ip: "10.15.20.3; rm -rf /"|username: husarion', "hosts[0].ip (line 2): '10.15.20.3; rm -rf /' is not an IP"),
    ("ip: 10.15.20.3|username: bad user", "hosts[0].username (line 3): 'bad user' is not a POSIX user name"),
    ("ip: 10.15.20.3|username: Husarion", "is not a POSIX user name"),
    ("ip: 10.15.20.3|username: '-rf'", "is not a POSIX user name"),
    ("ip: 10.15.20.3|username: husarion|timeout: -1", "hosts[0].timeout (line 4): -1 is not a number of seconds > 0"),
    ("ip: 10.15.20.3|username: husarion|timeout: 0", "is not a number of seconds > 0"),
    ("ip: 10.15.20.3|username: husarion|timeout: soon", "is not a number of seconds > 0"),
    ("ip: 10.15.20.3|username: husarion|timeout: .inf", "is not a number of seconds > 0"),
    ("ip: 10.15.20.3|username: husarion|port: 0", "0 is not a TCP port"),
    ("ip: 10.15.20.3|username: husarion|port: 70000", "70000 is not a TCP port"),
    ("ip: 10.15.20.3|username: husarion|port: 22x", "'22x' is not a TCP port"),
    ("ip: 10.15.20.3|username: husarion|port: true", "True is not a TCP port"),
    ("ip: 999.1.1.1|username: husarion", "'999.1.1.1' is not an IP address or host name"),
    ("ip: 10.15.20|username: husarion", "is not an IP address or host name"),
    ("ip: nuc_1.local|username: husarion", "is not an IP address or host name"),
    ("ip: 10.15.20.3", "hosts[0] (line 2): no username: this robot's manager (<= 2.2.0, SSH) skips the entry"),
    ("username: husarion", "hosts[0] (line 2): ip is required"),
    ("ip: 10.15.20.3|username: husarion|timout: 3", "hosts[0].timout (line 4): unknown key"),
    ("ip: 10.15.20.3|username: husarion|secret: x", "not a key of an SSH (has a username) entry"),
    ("ip: 10.15.20.3|username: husarion|ping_for_success: yes", "'yes' is not true or false"),
    ('ip: 10.15.20.3|username: husarion|command: "sudo shutdown now\\nrm -rf /"', "must be a one-line command"),
])
def test_bad_entries_are_errors_naming_key_and_line(entry: str, message: str) -> None:
    errs = errors(one(entry), Mode.SSH)
    assert any(message in e for e in errs), errs


@pytest.mark.parametrize("entry", [
    "ip: 10.15.20.3|username: husarion",
    "ip: nuc.local|username: husarion|port: 2222|timeout: 3.5",
    "ip: fe80::1|username: pi|ping_for_success: false",
    "ip: 10.15.20.3|username: root|command: /sbin/poweroff|timeout: '7'",
    "ip: 10.15.20.3|username: svc_user-1|port: '22'",
])
def test_good_ssh_entries(entry: str) -> None:
    assert errors(one(entry), Mode.SSH) == []


def test_duplicates_are_same_ip_user_and_port() -> None:
    text = one("ip: 192.0.2.3|username: husarion") + "  - ip: 192.0.2.3\n    username: husarion\n    port: 22\n"
    assert errors(text) == ["hosts[1] (line 4): duplicate of hosts[0] (husarion@192.0.2.3:22)"]
    other_user = one("ip: 192.0.2.3|username: husarion") + "  - ip: 192.0.2.3\n    username: root\n"
    other_port = one("ip: 192.0.2.3|username: husarion") + "  - ip: 192.0.2.3\n    username: husarion\n    port: 2222\n"
    assert errors(other_user) == [] and errors(other_port) == []


def test_http_entries_and_the_robots_era() -> None:
    http = one("ip: 192.0.2.5|port: 3003|secret: s3cret|timeout: 10")
    assert errors(http, Mode.HTTP) == []
    hf = parse_hosts(http, "t.yaml", mode=Mode.HTTP)
    assert hf.hosts()[0].secret == "s3cret" and hf.hosts()[0].port == 3003
    assert "no username: this robot's manager (<= 2.2.0, SSH) skips the entry" in errors(http, Mode.SSH)[0]
    ssh = one("ip: 192.0.2.5|username: husarion")
    assert "shuts computers down over HTTP" in errors(ssh, Mode.HTTP)[0]
    assert errors(ssh) == [] and errors(http) == []  # no stack given: either form
    assert any("the default 'husarion' is used" in w for w in warnings(one("ip: 192.0.2.5|port: 3003"), Mode.HTTP))
    assert any("the default secret" in w for w in warnings(one("ip: 192.0.2.5|secret: husarion"), Mode.HTTP))


def test_secret_references_resolve_only_in_local_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "nuc.secret").write_text("from-a-file\n")
    text = ("hosts:\n  - ip: 192.0.2.5\n    secret: {env: NUC_SECRET}\n"
            "  - ip: 192.0.2.6\n    secret: {file: nuc.secret}\n")
    path = tmp_path / "hosts.yaml"
    path.write_text(text)
    hf = load_hosts_file(path)
    assert hf.errors == []
    assert [e.row()["secret"] for e in hf.entries] == ["env NUC_SECRET", "file nuc.secret"]
    with pytest.raises(UsageError, match="NUC_SECRET is not set"):
        hf.hosts()
    monkeypatch.setenv("NUC_SECRET", "from-env")
    assert [h.secret for h in hf.hosts()] == ["from-env", "from-a-file"]
    assert "for local files" in errors(text, allow_refs=False)[0]


def test_power_budget_warning_follows_the_option() -> None:
    text = one("ip: 192.0.2.3|username: husarion|timeout: 12")
    assert warnings(text) == []
    assert "12 s is longer than the ~10 s" in warnings(text, power_budget=10.0)[0]


def test_file_level_problems() -> None:
    assert errors("- 1\n- 2\n") == ["file: must be a mapping with a 'hosts' list"]
    assert errors("hosts: 3\n") == ["hosts (line 1): must be a list of hosts"]
    assert "not valid YAML" in errors("hosts: [\n")[0]
    assert "no hosts" in warnings("hosts: []\n")[0] and errors("hosts: []\n") == []
    assert "no hosts" in warnings("")[0]
    assert "hosts[0] (line 2): must be a mapping" in errors("hosts:\n  - 192.0.2.3\n")[0]


@pytest.mark.parametrize(("command", "ok"), [
    ("sudo shutdown now", True), ("sudo -n shutdown -h now", True), ("sudo /sbin/poweroff", True),
    ("/usr/sbin/shutdown +0", True), ("sudo systemctl poweroff", True), ("shutdown -P now", True),
    ("sudo reboot", False), ("sudo shutdown -r now", False), ("sudo shutdown -c", False), ("halt", False),
    ("/home/pi/my_long_shutdown_sequence.sh", False), ("sudo 'unterminated", False),
])
def test_power_off_command_forms(command: str, ok: bool) -> None:
    assert is_power_off_command(command) is ok


@pytest.mark.parametrize(("value", "ok"), [
    ("10.15.20.3", True), ("fe80::1", True), ("nuc.local", True), ("NUC-2", True), ("a" * 64, False),
    ("10.15.20.3; rm -rf /", False), ("$(reboot)", False), ("-oProxyCommand=x", False), ("10.15.20.256", False),
])
def test_addresses(value: str, ok: bool) -> None:
    assert valid_address(value) is ok


# ---------------------------------------------------------------------------------------------
# edits keep everything else byte for byte
# ---------------------------------------------------------------------------------------------
def test_add_update_and_remove_keep_comments() -> None:
    added = add_host(SEED, new_entry("192.0.2.20", username="ops", timeout=3))
    assert added.changed and added.message == "added ops@192.0.2.20"
    assert added.text == SEED + "  - ip: 192.0.2.20\n    username: ops\n    timeout: 3.0\n"
    again = add_host(added.text, new_entry("192.0.2.20", username="ops", timeout=3))
    assert not again.changed and again.text == added.text and "already listed" in again.message
    updated = add_host(added.text, new_entry("192.0.2.20", username="ops", timeout=4))
    assert updated.changed and updated.message == "updated ops@192.0.2.20: timeout"
    assert updated.text == added.text.replace("timeout: 3.0\n", "timeout: 4.0\n")
    removed = remove_host(updated.text, "192.0.2.20")
    assert removed.changed and removed.text == SEED
    # the UR5 only, by user: its entry and the comment above it go, the others' comments stay
    ur5 = remove_host(SEED, "10.15.20.4", username="root")
    assert ur5.text == SEED.replace("  # Universal robots UR5\n  - ip: 10.15.20.4\n    username: root\n", "")
    assert "# Intel NUC, user computer" in ur5.text and "# My Raspberry pi" in ur5.text
    assert not remove_host(SEED, "10.15.20.4", username="pi").changed
    assert not remove_host(SEED, "192.0.2.99").changed


@pytest.mark.parametrize("start", ["", "# just a comment\n", "hosts: []\n", "hosts:\n"])
def test_add_to_an_empty_file(start: str) -> None:
    edit = add_host(start, new_entry("192.0.2.7", port=3003, secret={"env": "X"}))
    hf = parse_hosts(edit.text, "t.yaml")
    assert hf.errors == [] and [e.ip for e in hf.entries] == ["192.0.2.7"]
    assert edit.text.startswith(start.split("hosts", maxsplit=1)[0])


def test_new_entries_write_only_what_differs_from_the_defaults() -> None:
    assert new_entry("192.0.2.3", username="husarion") == {"ip": "192.0.2.3", "username": "husarion"}
    assert new_entry("192.0.2.3", username="pi", port=2222, command="sudo poweroff", timeout=8,
                     ping_for_success=False) == {"ip": "192.0.2.3", "username": "pi", "port": 2222,
                                                 "command": "sudo poweroff", "timeout": 8.0, "ping_for_success": False}
    assert new_entry("192.0.2.3") == {"ip": "192.0.2.3", "port": 3003}
    assert [str(f) for f in check_entry(new_entry("10.15.20.3; rm", username="a b"))] == [
        "host.ip: '10.15.20.3; rm' is not an IP address or host name",
        "host.username: 'a b' is not a POSIX user name (lowercase letters, digits, '_' and '-', starting with a "
        "letter or '_')",
    ]


def test_secrets_are_masked() -> None:
    text = "hosts:\n  - ip: 192.0.2.5\n    secret: s3cret # the NUC\n  - secret: \"q w\"\n    ip: 192.0.2.6\n" \
           "  - ip: 192.0.2.7\n    secret: {env: X}\n"
    masked = mask_secrets(text)
    assert "s3cret" not in masked and "q w" not in masked
    assert "secret: **** # the NUC" in masked and "- secret: ****" in masked and "secret: {env: X}" in masked


# ---------------------------------------------------------------------------------------------
# sudo -l listings: the last matching entry decides
# ---------------------------------------------------------------------------------------------
LISTING = """Matching Defaults entries for husarion on nuc:
    env_reset, mail_badpass, use_pty

User husarion may run the following commands on nuc:
{rules}
"""


@pytest.mark.parametrize(("rules", "resolved", "verdict"), [
    ("    (ALL : ALL) ALL\n    (root) NOPASSWD: /sbin/poweroff, /sbin/reboot, /sbin/shutdown",
     "/usr/sbin/shutdown now", True),
    ("    (root) NOPASSWD: /sbin/poweroff, /sbin/reboot, /sbin/shutdown\n    (ALL : ALL) ALL",
     "/usr/sbin/shutdown now", False),
    ("    (ALL) NOPASSWD: ALL", "/usr/sbin/shutdown now", True),
    ("    (www-data) NOPASSWD: /sbin/shutdown", "/usr/sbin/shutdown now", None),
    ("    (root) NOPASSWD: /sbin/shutdown -h now", "/usr/sbin/shutdown now", None),
    ("    (root) NOPASSWD: /sbin/shutdown now", "/usr/sbin/shutdown now", True),
    ("    (root) NOPASSWD: /sbin/poweroff, PASSWD: /sbin/shutdown", "/usr/sbin/shutdown now", False),
    ("    (ALL : ALL) ALL", "/usr/sbin/shutdown now", False),
    ("    (root) NOPASSWD: /usr/local/bin/shutdown", "/usr/sbin/shutdown now", None),
])
def test_nopasswd_from_the_listing(rules: str, resolved: str, verdict: bool | None) -> None:
    assert nopasswd_for(LISTING.format(rules=rules), resolved) is verdict


def test_listing_parser_and_probe() -> None:
    rules = parse_sudo_listing(LISTING.format(rules="    (root) NOPASSWD: SETENV: /a, /b, PASSWD: /c"))
    assert rules == [("root", True, "/a"), ("root", True, "/b"), ("root", False, "/c")]
    assert sudo_probe("sudo shutdown now", "husarion") == ["sudo", "-n", "-l", "shutdown", "now"]
    assert sudo_probe("sudo -n /sbin/poweroff", "husarion") == ["sudo", "-n", "-l", "/sbin/poweroff"]
    assert sudo_probe("/home/pi/bye.sh", "pi") is None


# ---------------------------------------------------------------------------------------------
# the executor, the CLI's way: side by side, one result per host
# ---------------------------------------------------------------------------------------------
class Pinger:
    def __init__(self, clock: ManualClock, down_at: dict[str, float | None]) -> None:
        self.clock, self.down_at = clock, down_at

    def is_reachable(self, ip: str) -> bool:
        if ip not in self.down_at:
            return False
        at = self.down_at[ip]
        return at is None or self.clock.now() < at


class Remote:
    def __init__(self, clock: ManualClock, pinger: Pinger, fail: set[str]) -> None:
        self.clock, self.pinger, self.fail = clock, pinger, fail
        self.requests: list[str] = []

    def request(self, host: ShutdownHost) -> CommandOutcome:
        self.requests.append(host.ip)
        if host.ip in self.fail:
            return CommandOutcome(False, error="command exited with 1: sudo: a password is required")
        self.pinger.down_at[host.ip] = self.clock.now() + host.timeout - 1.0  # goes silent 1 s before its timeout
        return CommandOutcome(True)


def test_hosts_go_down_side_by_side_and_each_ends_once() -> None:
    clock = ManualClock()
    pinger = Pinger(clock, {f"192.0.2.{i}": None for i in (1, 2, 3, 5)})  # .4 does not answer
    remote = Remote(clock, pinger, fail={"192.0.2.5"})
    backends = ShutdownBackends(pinger, remote, remote, SubprocessRunner(), InlineDispatcher())
    hosts = [ShutdownHost(f"192.0.2.{i}", "husarion", timeout=float(i + 1)) for i in range(1, 6)]
    hosts.append(ShutdownHost("192.0.2.6", port=3003, secret="s", timeout=2.0))  # HTTP, not answering either
    fleet = shutdown_hosts(hosts, backends, clock=clock, ping_interval=0.05)
    by = {r.data["ip"]: r for r in fleet.results}
    assert [by[f"192.0.2.{i}"].outcome.value for i in range(1, 7)] == [
        "changed", "changed", "changed", "skipped", "failed", "skipped"]
    assert by["192.0.2.1"].message == "went down"
    assert "password is required" in by["192.0.2.5"].message
    assert remote.requests == ["192.0.2.1", "192.0.2.2", "192.0.2.3", "192.0.2.5"]
    assert summary(fleet) == "3 down, 2 skipped, 1 failed" and int(fleet.exit_code) == 3
    # side by side: the slowest host (.3, timeout 4 s, silent after 3 s) sets the pace
    assert clock.now() == pytest.approx(3.0, abs=0.2)
    assert by["192.0.2.3"].duration_s < 4.0


def test_result_rows_never_carry_the_secret() -> None:
    from panther_ops.manager.shutdown_executor import HostResult, HostState

    row = result_of(HostResult(ShutdownHost("192.0.2.5", port=3003, secret="s3cret"), HostState.SUCCESS, "host is down"))
    assert "s3cret" not in repr(row.to_json())
    assert row.to_json()["robot"] == "http://192.0.2.5:3003"
    row = result_of(HostResult(ShutdownHost("192.0.2.3", "pi", ping_for_success=False), HostState.SUCCESS, "x"))
    assert row.message == "shutdown requested (ping_for_success: false)"


# issue 23 item 10: a chained command is a warning; a control character anywhere is an error
@pytest.mark.parametrize(("command", "ops"), [
    ("sudo shutdown now; rm -rf /tmp/x", ["';'"]), ("sync && sudo shutdown now", ["'&&'"]),
    ("sudo shutdown now || sudo poweroff", ["'||'"]), ("echo bye | wall", ["'|'"]),
    ("sudo shutdown now &", ["'&'"]), ("a ;b && c", ["';'", "'&&'"]),
])
def test_chained_commands_are_warned_of(command: str, ops: list[str]) -> None:
    hf = parse_hosts(f"hosts:\n  - ip: 10.15.20.5\n    username: pi\n    command: '{command}'\n")
    assert not hf.errors
    [warning] = [str(w) for w in hf.warnings if "command" in w.where]
    assert f"chains commands with {', '.join(ops)}" in warning
    assert "/home/pi/my_long_shutdown_sequence.sh" in warning
    [found] = check_entry(new_entry("10.15.20.5", username="pi", command=command))
    assert found.where == "host.command" and "chains commands" in found.message


@pytest.mark.parametrize("command", ["sudo shutdown now", "sudo poweroff",
                                     "sudo shutdown -h now >/dev/null 2>&1", "sudo shutdown now # stop; bye",
                                     "/home/pi/my_long_shutdown_sequence.sh", "sudo shutdown 'now;'"])
def test_quoted_operators_redirections_and_comments_are_not_chains(command: str) -> None:
    hf = parse_hosts(f"hosts:\n  - ip: 10.15.20.5\n    username: pi\n    command: \"{command}\"\n")
    assert not [w for w in hf.warnings if "chains" in str(w)], command


@pytest.mark.parametrize(("escaped", "shown"), [("\\r", "'\\r', U+000D"), ("\\x1b[31m", "'\\x1b', U+001B"),
                                                ("\\u2028", "'\\u2028', U+2028"), ("\\u200b", "'\\u200b', U+200B")])
def test_control_characters_in_a_command_are_errors(escaped: str, shown: str) -> None:
    hf = parse_hosts(f'hosts:\n  - ip: 10.15.20.5\n    username: pi\n    command: "sudo shutdown now{escaped}"\n')
    [error] = [str(e) for e in hf.errors]
    assert "hosts[0].command" in error and "must be a one-line command of printable text" in error
    assert shown in error
