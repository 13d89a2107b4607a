"""Shutdown acceptance on the lab: user computers (namespaces with sshd, sudo, power-off
stand-ins, a husarion-shutdown stand-in) on the robots' LANs and on the lab bridge.

Nothing here powers anything off for real: every host's /sbin/shutdown, /sbin/poweroff and
/sbin/reboot are the lab's stand-ins (checked with `lab.standins` before any shutdown is
asked for), which record the call and take the host's links down. Every address is a lab
address (10.200.x.y); the stock hosts file's 10.15.20.3 entry is removed through the
pipeline before any command that contacts hosts runs on that robot.
"""

from __future__ import annotations

import json
import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from tests.clirun import run_cli
from tests.lab import Lab, missing_requirements
from tests.lab._sys import wait_for
from tests.lab.computers import ComputerSpec, HttpService, is_silent, service_log, trust_on_robot

pytestmark = pytest.mark.lab

COMPOSE = "/home/husarion/compose.yaml"
HOSTS_21 = "/home/husarion/config/panther_manager/config/shutdown_hosts_config.yaml"
HOSTS_22 = "/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"
C1_PASSWORD = "c1-lab-password"
H1_SECRET = "h1-lab-secret"
H3_SECRET = "h3-lab-secret"
STANDIN_TARGETS = {"/sbin/shutdown", "/sbin/poweroff", "/sbin/reboot"}


# ---------------------------------------------------------------------------------------------
# the lab: r01 (2.1.1) and r02 (2.2.2) with their LANs, r03 (2.1.1) for the pipeline test, r04 (2.3.2)
# with its LAN
# ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def slab() -> Iterator[Lab]:
    why = missing_requirements(docker=True)
    if why:
        pytest.skip("simulated robot lab unavailable: " + "; ".join(why))
    lab = Lab(4, docker=True, images=("2.1.1", "2.2", "2.1.1", "2.3.2"), ephemeral=True).up()
    try:
        lab.add_computers([
            # r01's LAN (SSH era)
            ComputerSpec("c1", behind="r01", password=C1_PASSWORD, admin="limited", operator_key=False),
            ComputerSpec("c2", behind="r01", robot_key=True),  # the robot's key, no sudo rule
            ComputerSpec("c3", behind="r01", sudo_rule=True),  # the sudo rule, not the robot's key
            ComputerSpec("c4", behind="r01", admin="nopasswd"),  # the operator's key, passwordless sudo
            # r02's LAN (HTTP era)
            ComputerSpec("h1", behind="r02", http=HttpService(3003, H1_SECRET), poweroff_delay=0.5),
            ComputerSpec("h2", behind="r02"),  # no husarion-shutdown
            # r04's LAN: husarion_ugv 2.3.2 (Jazzy), the same HTTP shutdown as 2.2
            ComputerSpec("h3", behind="r04", http=HttpService(3003, H3_SECRET)),
            # the lab bridge, reachable from here: `shutdown --hosts FILE`
            *(ComputerSpec(f"d{i}", sudo_rule=True, poweroff_delay=float(i)) for i in range(1, 5)),
            ComputerSpec("d5", poweroff_delay=5.0, http=HttpService(3003, "d5-lab-secret")),
        ])
        yield lab
    finally:
        lab.down()


def cli(capsys: pytest.CaptureFixture[str], lab: Lab, *argv: str) -> tuple[int, dict[str, Any], str, str]:
    return run_cli(capsys, "-i", str(lab.inventory_path), *argv)


def ip(lab: Lab, name: str) -> str:
    return str(lab.computer(name).ip)


def no_live_addresses_but_lab(text: str) -> None:
    """A hosts file about to be used must only name lab addresses."""
    for addr in re.findall(r"\bip:\s*(\S+)", text):
        assert addr.startswith("10.200."), f"not a lab address: {addr}"


def assert_standins(lab: Lab, *names: str) -> None:
    for n in names:
        assert set(lab.standins(n)) >= STANDIN_TARGETS, f"{n}: power-off stand-ins not in place"


@pytest.fixture(scope="module")
def r01_ready(slab: Lab) -> Lab:
    """r01's hosts file mounted from ~/config with no hosts (the stock 10.15.20.3 entry removed
    through the pipeline), so that nothing outside the lab is ever contacted."""
    code = main(["-i", str(slab.inventory_path), "shutdown", "hosts", "remove", "-r", "r01", "--ip", "10.15.20.3",
                 "--yes", "--settle", "1"])
    assert code == 0
    assert "10.15.20." not in slab.read("r01", HOSTS_21)
    return slab


@pytest.fixture(scope="module")
def c1_setup(r01_ready: Lab) -> list[tuple[int, dict[str, Any], str]]:
    """`shutdown setup` of c1 (password login and sudo with the password), run twice."""
    lab = r01_ready
    import getpass

    runs = []
    saved = getpass.getpass
    getpass.getpass = lambda prompt="": C1_PASSWORD  # type: ignore[assignment]
    try:
        for _ in range(2):
            import io
            from contextlib import redirect_stderr, redirect_stdout

            out, err = io.StringIO(), io.StringIO()
            with redirect_stdout(out), redirect_stderr(err):
                code = main(["-i", str(lab.inventory_path), "shutdown", "setup", "-r", "r01", "--host", ip(lab, "c1"),
                             "--user", "husarion", "--ask-password", "--yes", "--settle", "1", "--json"])
            runs.append((code, json.loads(out.getvalue()), err.getvalue()))
    finally:
        getpass.getpass = saved  # type: ignore[assignment]
    return runs


@pytest.fixture
def r01_hosts(r01_ready: Lab) -> Iterator[Any]:
    """Set r01's (mounted) hosts file for one test; put the previous content back after."""
    lab = r01_ready
    before = lab.read("r01", HOSTS_21)

    def set_hosts(text: str) -> None:
        no_live_addresses_but_lab(text)
        lab.write("r01", HOSTS_21, text)

    yield set_hosts
    lab.write("r01", HOSTS_21, before)


def steps(doc: dict[str, Any]) -> dict[str, str]:
    return {s["step"]: s["outcome"] for s in doc["robots"][0]["data"]["steps"]}


# ---------------------------------------------------------------------------------------------
# hosts add through the pipeline (2.1: mount + argument, recreate)
# ---------------------------------------------------------------------------------------------
def test_hosts_add_goes_through_the_pipeline_on_21(slab: Lab, capsys: pytest.CaptureFixture[str]) -> None:
    lab = slab
    compose_before = lab.read("r03", COMPOSE)
    ctr_before = lab.docker("r03", "inspect", "-f", "{{.Id}}", "panther_ros", check=True).stdout.strip()
    target = ip(lab, "c4")
    try:
        code, doc, _, _ = cli(capsys, lab, "shutdown", "hosts", "add", "-r", "r03", "--ip", target, "--user",
                              "husarion", "--timeout", "3", "--dry-run", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed" and doc["robots"][0]["data"]["dry_run"]
        assert lab.read("r03", COMPOSE) == compose_before

        code, doc, _, _ = cli(capsys, lab, "shutdown", "hosts", "add", "-r", "r03", "--ip", target, "--user",
                              "husarion", "--timeout", "3", "--yes", "--settle", "1", "--json")
        assert code == 0, doc
        res = doc["robots"][0]
        assert res["outcome"] == "changed", res
        diffs = {d["path"]: d["unified"] for d in res["diffs"]}
        assert set(diffs) == {COMPOSE, HOSTS_21}
        assert ("+      - /home/husarion/config/panther_manager/config/shutdown_hosts_config.yaml:"
                "/config/panther_manager/config/shutdown_hosts_config.yaml:ro") in diffs[COMPOSE]
        assert "shutdown_hosts_config_path:=/config/panther_manager/config/shutdown_hosts_config.yaml" in diffs[COMPOSE]
        backup = res["data"]["backup"]
        assert lab.sh("r03", f"test -f /home/husarion/.panther-ops/backups/{backup}/manifest.json").returncode == 0
        # the file: the stack's default (comments kept) plus the new host
        text = lab.read("r03", HOSTS_21)
        assert text.startswith("# Hosts shut down together with the robot")
        assert f"  - ip: {target}\n    username: husarion\n    timeout: 3.0\n" in text
        # recreated with the argument and the mount
        state = json.loads(lab.docker("r03", "inspect", "-f", "{{json .}}", "panther_ros", check=True).stdout)
        assert state["Id"] != ctr_before and state["State"]["Status"] == "running"
        assert "shutdown_hosts_config_path:=/config/panther_manager/config/shutdown_hosts_config.yaml" in \
            state["Config"]["Cmd"]
        mounts = {m["Destination"]: m["Source"] for m in state["Mounts"]}
        assert mounts["/config/panther_manager/config/shutdown_hosts_config.yaml"] == HOSTS_21

        # again: nothing to change
        code, doc, _, _ = cli(capsys, lab, "shutdown", "hosts", "add", "-r", "r03", "--ip", target, "--user",
                              "husarion", "--timeout", "3", "--yes", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "ok"
        assert "already listed" in doc["robots"][0]["message"]
        # list and remove (the mounted file is edited in place now)
        code, doc, _, _ = cli(capsys, lab, "shutdown", "hosts", "list", "-r", "r03", "--json")
        assert code == 0
        assert [h["ip"] for h in doc["robots"][0]["data"]["hosts"]] == ["10.15.20.3", target]
        code, doc, _, _ = cli(capsys, lab, "shutdown", "hosts", "remove", "-r", "r03", "--ip", target, "--yes",
                              "--settle", "1", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed"
        assert [d["path"] for d in doc["robots"][0]["diffs"]] == [HOSTS_21]
        assert target not in lab.read("r03", HOSTS_21)
    finally:
        lab.write("r03", COMPOSE, compose_before)
        lab.sh("r03", "rm -rf /home/husarion/config /home/husarion/.panther-ops")
        lab.compose("r03", "up", "-d", "--force-recreate")


# ---------------------------------------------------------------------------------------------
# setup
# ---------------------------------------------------------------------------------------------
def test_setup_with_the_password_twice(r01_ready: Lab, c1_setup: list[tuple[int, dict[str, Any], str]]) -> None:
    lab = r01_ready
    (code1, doc1, err1), (code2, doc2, err2) = c1_setup
    assert code1 == 0, doc1
    assert steps(doc1) == {"robot-key": "ok", "reach": "ok", "host-key": "changed", "authorized-key": "changed",
                           "login": "ok", "sudoers": "changed", "hosts-file": "changed"}
    assert code2 == 0, doc2
    assert doc2["robots"][0]["outcome"] == "ok"
    assert set(steps(doc2).values()) == {"ok"}
    assert C1_PASSWORD not in json.dumps(doc1) + err1 + json.dumps(doc2) + err2
    # the robot's key, once
    robot_pub = lab.read("r01", "/home/husarion/.ssh/id_rsa.pub").split()[1]
    assert lab.read("c1", "/home/husarion/.ssh/authorized_keys").count(robot_pub) == 1
    # the computer's host key, once, in the robot's known_hosts
    c1_key = (lab.computer("c1").dir / "etc/ssh/ssh_host_ed25519_key.pub").read_text().split()[1]
    assert lab.read("r01", "/home/husarion/.ssh/known_hosts").count(c1_key) == 1
    # the sudoers drop-in: valid, 0440 root:root, exactly the three commands
    assert lab.exec("c1", ["visudo", "-c"]).returncode == 0
    assert lab.exec("c1", ["visudo", "-cf", "/etc/sudoers.d/panther-shutdown"]).returncode == 0
    assert lab.exec("c1", ["stat", "-c", "%a %U %G", "/etc/sudoers.d/panther-shutdown"]).stdout.split() == \
        ["440", "root", "root"]
    assert "husarion ALL=(root) NOPASSWD: /sbin/poweroff, /sbin/reboot, /sbin/shutdown" in \
        lab.read("c1", "/etc/sudoers.d/panther-shutdown")
    assert lab.exec("c1", ["sudo", "-n", "-l", "/bin/sh"], user="husarion").returncode != 0
    assert lab.exec("c1", ["sudo", "-n", "-l", "/sbin/shutdown"], user="husarion").returncode == 0
    assert not lab.exec("c1", ["sh", "-c", "ls -A /etc/sudoers.d | grep panther-ops"]).stdout.strip()
    # /etc/sudoers itself untouched (the lab's is the host's file, read only)
    assert lab.read("c1", "/etc/sudoers") == Path("/etc/sudoers").read_text()
    # the host in the robot's hosts file
    assert f"- ip: {ip(lab, 'c1')}\n    username: husarion" in lab.read("r01", HOSTS_21)


def test_a_candidate_visudo_refuses_is_not_installed(r01_ready: Lab) -> None:
    from panther_ops.core.fleet.inventory_file import load_inventory
    from panther_ops.core.fleet.runner import open_transport
    from panther_ops.core.shutdown.setup import SUDOERS_PATH, install_sudoers
    from panther_ops.transport.lan import RobotLink, TargetError, host_keys_from_text

    lab = r01_ready
    inv = load_inventory(str(lab.inventory_path))
    transport = open_transport(inv, inv.robots["r01"])
    transport.connect()
    listing = "ls -A /etc/sudoers.d"
    before = lab.exec("c4", ["sh", "-c", listing]).stdout
    try:
        link = RobotLink(transport, "r01")
        keys = host_keys_from_text(lab.computers_known_hosts_path.read_text())
        client = link.open_ssh(ip(lab, "c4"), 22, "husarion", key_files=(str(lab.identity_file),), host_keys=keys)
        try:
            with pytest.raises(TargetError, match="fails visudo -cf, nothing installed"):
                install_sudoers(client, "husarion", login_user="husarion", password=None,
                                content="husarion ALL=(root) NOPASSWD /sbin/poweroff\n")  # the ':' is missing
            assert lab.exec("c4", ["sh", "-c", listing]).stdout == before
            assert lab.exec("c4", ["test", "-e", SUDOERS_PATH]).returncode != 0
            # the generated rule on the same host: installed, then unchanged
            assert install_sudoers(client, "husarion", login_user="husarion", password=None) == (True, "installed")
            assert install_sudoers(client, "husarion", login_user="husarion", password=None) == (False, "unchanged")
            assert lab.exec("c4", ["visudo", "-c"]).returncode == 0
        finally:
            client.close()
    finally:
        transport.close()
        lab.exec("c4", ["rm", "-f", SUDOERS_PATH])


def test_setup_with_the_operators_key_asks_to_trust_the_host_key(r01_ready: Lab, r01_hosts: Any,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    lab = r01_ready
    c4 = ip(lab, "c4")
    c4_key = (lab.computer("c4").dir / "etc/ssh/ssh_host_ed25519_key.pub").read_text().split()[1]
    known = "/home/husarion/.ssh/known_hosts"
    robot_pub = lab.read("r01", "/home/husarion/.ssh/id_rsa.pub").split()[1]
    try:
        # not interactive, no --yes: the fingerprint is shown, nothing is recorded or changed
        code, doc, _, err = cli(capsys, lab, "shutdown", "setup", "-r", "r01", "--host", c4, "--json")
        assert code == 2
        assert steps(doc)["host-key"] == "failed" and "not trusted" in doc["robots"][0]["message"]
        assert lab.host_fingerprint("r01") not in err  # the computer's, not the robot's
        assert "SHA256:" in err and c4 in err
        assert c4_key not in (lab.read("r01", known) if lab.exec("r01", ["test", "-f", known]).returncode == 0
                              else "")
        assert robot_pub not in lab.read("c4", "/home/husarion/.ssh/authorized_keys")
        # --yes: logs in with the operator's key; passwordless sudo already covers the commands
        code, doc, _, _ = cli(capsys, lab, "shutdown", "setup", "-r", "r01", "--host", c4, "--yes", "--settle", "1",
                              "--json")
        assert code == 0, doc
        got = {s["step"]: s for s in doc["robots"][0]["data"]["steps"]}
        assert "logged in with the operator's key" in got["authorized-key"]["message"]
        assert got["sudoers"]["outcome"] == "ok" and "already" in got["sudoers"]["message"]
        assert lab.exec("c4", ["test", "-e", "/etc/sudoers.d/panther-shutdown"]).returncode != 0
    finally:
        lab.sh("c4", f"sed -i '/{robot_pub[-20:].replace('/', '.')}/d' /home/husarion/.ssh/authorized_keys")
        lab.sh("r01", f"sed -i '/{c4_key[-20:].replace('/', '.')}/d' {known}")


def test_setup_http_host_on_22(slab: Lab, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    lab = slab
    before = lab.read("r02", HOSTS_22)
    try:
        monkeypatch.setenv("H1_SECRET", "not-the-secret")
        code, doc, out, err = cli(capsys, lab, "shutdown", "setup", "-r", "r02", "--host", ip(lab, "h1"),
                                  "--secret-env", "H1_SECRET", "--yes", "--settle", "1", "--json")
        assert code == 3 and steps(doc) == {"reach": "ok", "service": "ok", "secret": "failed"}
        assert "refused" in doc["robots"][0]["message"]
        assert lab.read("r02", HOSTS_22) == before

        code, doc, _, _ = cli(capsys, lab, "shutdown", "setup", "-r", "r02", "--host", ip(lab, "h2"), "--yes", "--json")
        assert code == 3 and steps(doc) == {"reach": "ok", "service": "failed"}
        assert "sudo snap install husarion-shutdown" in doc["robots"][0]["data"]["hint"]

        monkeypatch.setenv("H1_SECRET", H1_SECRET)
        code, doc, out, err = cli(capsys, lab, "shutdown", "setup", "-r", "r02", "--host", ip(lab, "h1"),
                                  "--secret-env", "H1_SECRET", "--yes", "--settle", "1", "--json")
        assert code == 0, doc
        assert steps(doc) == {"reach": "ok", "service": "ok", "secret": "ok", "hosts-file": "changed"}
        assert H1_SECRET not in out + err  # masked in the diff
        assert "secret: ****" in doc["robots"][0]["diffs"][0]["unified"]
        assert f"- ip: {ip(lab, 'h1')}\n    port: 3003\n    secret: {H1_SECRET}\n" in lab.read("r02", HOSTS_22)
        code, doc, _, _ = cli(capsys, lab, "shutdown", "setup", "-r", "r02", "--host", ip(lab, "h1"),
                              "--secret-env", "H1_SECRET", "--yes", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "ok"
        assert lab.power_calls("h1") == [] and lab.power_calls("h2") == []
        assert 200 not in [e.get("status") for e in service_log(lab, "h1")]
    finally:
        lab.write("r02", HOSTS_22, before)


# ---------------------------------------------------------------------------------------------
# check
# ---------------------------------------------------------------------------------------------
def test_check_names_the_failing_step(r01_ready: Lab, c1_setup: Any, r01_hosts: Any,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    lab = r01_ready
    trust_on_robot(lab, "r01", "c2")
    trust_on_robot(lab, "r01", "c3")
    r01_hosts("hosts:\n" + "".join(f"  - ip: {ip(lab, n)}\n    username: husarion\n" for n in ("c1", "c2", "c3")))
    code, doc, _, _ = cli(capsys, lab, "shutdown", "check", "-r", "r01", "--json")
    assert code == 3
    rows = {h["host"].split("@")[1].split(":")[0]: h for h in doc["robots"][0]["data"]["hosts"]}
    assert rows[ip(lab, "c1")]["ok"] and rows[ip(lab, "c1")]["step"] == "ok"
    assert rows[ip(lab, "c2")]["step"] == "sudo" and "without a password" in rows[ip(lab, "c2")]["message"]
    assert "shutdown setup" in rows[ip(lab, "c2")]["fix"]
    assert rows[ip(lab, "c3")]["step"] == "login"
    assert "authorized_keys" in rows[ip(lab, "c3")]["fix"]
    for n in ("c1", "c2", "c3"):
        assert lab.power_calls(n) == [], f"check powered {n} off"

    # the human table names step and fix
    code, _, out, _ = cli(capsys, lab, "shutdown", "check", "-r", "r01")
    assert code == 3 and "sudo" in out and "login" in out and "setup" in out


def test_check_http_secret(slab: Lab, capsys: pytest.CaptureFixture[str]) -> None:
    lab = slab
    before = lab.read("r02", HOSTS_22)
    h1 = ip(lab, "h1")
    try:
        for secret, ok in (("wrong-secret", False), (H1_SECRET, True)):
            lab.write("r02", HOSTS_22, f"hosts:\n  - ip: {h1}\n    port: 3003\n    secret: {secret}\n")
            code, doc, out, err = cli(capsys, lab, "shutdown", "check", "-r", "r02", "--json")
            (row,) = doc["robots"][0]["data"]["hosts"]
            assert row["ok"] is ok, row
            assert row["step"] == ("ok" if ok else "secret")
            assert code == (0 if ok else 3)
            assert secret not in out + err
        assert lab.power_calls("h1") == []
        statuses = [e.get("status") for e in service_log(lab, "h1") if "status" in e]
        assert 403 in statuses and 401 in statuses and 200 not in statuses
    finally:
        lab.write("r02", HOSTS_22, before)


# ---------------------------------------------------------------------------------------------
# shutdown --hosts FILE (from here): side by side
# ---------------------------------------------------------------------------------------------
def test_check_and_list_on_a_2_3_2_robot(slab: Lab, capsys: pytest.CaptureFixture[str]) -> None:
    """husarion_ugv 2.3.2 keeps 2.2's shutdown hosts file and HTTP shutdown (husarion_ugv_ros@2.3.2:
    husarion_ugv_manager/config/shutdown_hosts.yaml): `shutdown hosts list` and `shutdown check` on
    a 2.3.2 robot read its file and check its LAN host as on 2.2.2, nothing powered off."""
    lab = slab
    before = lab.read("r04", HOSTS_22)
    h3 = ip(lab, "h3")
    try:
        lab.write("r04", HOSTS_22, f"hosts:\n  - ip: {h3}\n    port: 3003\n    secret: {H3_SECRET}\n")
        code, doc, out, err = cli(capsys, lab, "shutdown", "hosts", "list", "-r", "r04", "--json")
        assert code == 0, out + err
        assert HOSTS_22 in doc["robots"][0]["message"]
        code, doc, out, err = cli(capsys, lab, "shutdown", "check", "-r", "r04", "--json")
        (row,) = doc["robots"][0]["data"]["hosts"]
        assert code == 0 and row["ok"] is True and row["step"] == "ok", out + err
        assert H3_SECRET not in out + err and lab.power_calls("h3") == []
    finally:
        lab.write("r04", HOSTS_22, before)


def test_shutdown_hosts_file_side_by_side(slab: Lab, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    lab = slab
    names = ["d1", "d2", "d3", "d4", "d5"]
    timeouts = {"d1": 2.0, "d2": 3.0, "d3": 4.0, "d4": 5.0, "d5": 6.0}  # the stand-in: timeout - 1 s
    entries = "".join(f"  - ip: {ip(lab, n)}\n    username: husarion\n    timeout: {timeouts[n]}\n"
                      for n in names[:4])
    entries += f"  - ip: {ip(lab, 'd5')}\n    port: 3003\n    secret: {{env: D5_SECRET}}\n    timeout: 6.0\n"
    hosts = tmp_path / "hosts.yaml"
    hosts.write_text("# five lab computers\nhosts:\n" + entries)
    no_live_addresses_but_lab(hosts.read_text())
    monkeypatch.setenv("D5_SECRET", "d5-lab-secret")
    assert_standins(lab, *names)
    common = ["shutdown", "--hosts", str(hosts), "--known-hosts", str(lab.computers_known_hosts_path),
              "--identity", str(lab.identity_file)]
    lab.link_down("d3")  # unreachable
    try:
        # not interactive, no --yes: refused, naming every host; nothing contacted
        code, _, _, err = cli(capsys, lab, *common)
        assert code == 2 and all(ip(lab, n) in err for n in names)
        assert all(lab.power_calls(n) == [] for n in names)

        start = time.monotonic()
        code, doc, _, _ = cli(capsys, lab, *common, "--yes", "--json")
        wall = time.monotonic() - start
        assert code == 0, doc
        by = {r["data"]["ip"]: r for r in doc["robots"]}
        for n in ("d1", "d2", "d4", "d5"):
            assert by[ip(lab, n)]["outcome"] == "changed", by[ip(lab, n)]
            assert by[ip(lab, n)]["message"] == "went down"
            assert len(lab.power_calls(n)) == 1, n
            assert is_silent(lab, n), f"{n} still answers"
        assert by[ip(lab, "d3")]["outcome"] == "skipped"
        assert lab.power_calls("d3") == []
        assert lab.power_calls("d1")[0]["sudo_user"] == "husarion"
        assert lab.power_calls("d5")[0]["user"] == "root"  # the service ran it
        assert wall <= max(timeouts.values()) + 1.0, f"{wall:.2f} s"
        assert sum(timeouts.values()) - timeouts["d3"] > wall + 5  # one by one could not have made it
    finally:
        lab.link_up("d3")
        for n in names:
            lab.power_on(n)
    assert not any(is_silent(lab, n) for n in names)


# ---------------------------------------------------------------------------------------------
# bad entries: exit 2, nothing contacted
# ---------------------------------------------------------------------------------------------
BAD = """hosts:
  - ip: "10.15.20.3; rm -rf /"
    username: husarion
  - ip: 10.200.250.4
    username: "bad user"
  - ip: 10.200.250.5
    username: pi
    timeout: -3
"""


def test_bad_entries_exit_2_and_nothing_runs(r01_ready: Lab, r01_hosts: Any, tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    lab = r01_ready
    bad = tmp_path / "bad.yaml"
    bad.write_text(BAD)
    accepts = lab.sshd_accepts("r01")
    code, _, _, err = cli(capsys, lab, "shutdown", "hosts", "validate", str(bad))
    assert code == 2
    assert "is not an IP address or host name" in err and "not a POSIX user name" in err and "> 0" in err
    code, _, _, err = cli(capsys, lab, "shutdown", "--hosts", str(bad), "--yes")
    assert code == 2 and "nothing was run" in err
    # the same entries in the robot's file: validate and `shutdown robot` refuse before any host
    lab.write("r01", HOSTS_21, BAD)
    code, _, _, err = cli(capsys, lab, "shutdown", "hosts", "validate", "-r", "r01")
    assert code == 2 and "not a POSIX user name" in err
    before = len(lab.power_calls("r01"))
    code, _, _, err = cli(capsys, lab, "shutdown", "robot", "-r", "r01", "--yes")
    assert code == 2 and "nothing was shut down" in err
    assert len(lab.power_calls("r01")) == before
    # the validate and robot runs only read the file (one connection each), nothing else
    assert lab.sshd_accepts("r01") - accepts == 2


# ---------------------------------------------------------------------------------------------
# shutdown robot: its hosts first (through it), then the Built-in Computer
# ---------------------------------------------------------------------------------------------
def test_shutdown_robot_hosts_first_then_itself(r01_ready: Lab, c1_setup: Any, r01_hosts: Any,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    lab = r01_ready
    c1, c3 = ip(lab, "c1"), ip(lab, "c3")
    r01_hosts(f"hosts:\n  - ip: {c1}\n    username: husarion\n    timeout: 3\n"
              f"  - ip: {c3}\n    username: husarion\n    timeout: 2\n")  # c3 fails: no robot key there
    assert_standins(lab, "r01", "c1", "c3")
    code, _, out, err = cli(capsys, lab, "shutdown", "robot", "-r", "r01", "--dry-run")
    assert code == 0 and c1 in out and c3 in out
    code, _, _, err = cli(capsys, lab, "shutdown", "robot", "-r", "r01")
    assert code == 2 and "r01" in err and c1 in err and c3 in err  # not interactive: names all, refuses
    assert lab.power_calls("r01") == [] and lab.power_calls("c1") == []
    try:
        code, doc, _, _ = cli(capsys, lab, "shutdown", "robot", "-r", "r01", "--yes", "--json")
        assert code == 0, doc
        res = doc["robots"][0]
        assert res["outcome"] == "changed"
        hosts = {h["data"]["ip"]: h for h in res["data"]["hosts"]}
        assert hosts[c1]["outcome"] == "changed" and hosts[c3]["outcome"] == "failed"
        assert any(c3 in w for w in res["warnings"])
        (c1_call,), (r01_call,) = lab.power_calls("c1"), lab.power_calls("r01")
        assert lab.power_calls("c3") == []
        assert r01_call["time"] > c1_call["time"]  # the robot after its hosts
        assert r01_call["sudo_user"] == "husarion" and r01_call["action"] == "poweroff"
        # the power-off stand-ins take their interfaces down after their delay: wait for it
        wait_for(lambda: is_silent(lab, "c1") and is_silent(lab, "r01"), 5.0, "c1 and r01 to go silent")
    finally:
        for n in ("r01", "c1", "c3"):
            lab.power_on(n)
    assert not is_silent(lab, "r01")
    assert lab.ssh("r01", "true").returncode == 0


def test_shutdown_hosts_via_the_robot(r01_ready: Lab, c1_setup: Any, tmp_path: Path,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    lab = r01_ready
    hosts = tmp_path / "lan.yaml"
    hosts.write_text(f"hosts:\n  - ip: {ip(lab, 'c1')}\n    username: husarion\n    timeout: 3\n"
                     f"  - ip: {ip(lab, 'c2')}\n    username: husarion\n    ping_for_success: false\n")
    trust_on_robot(lab, "r01", "c2")
    assert_standins(lab, "c1", "c2")
    try:
        code, doc, _, _ = cli(capsys, lab, "shutdown", "--hosts", str(hosts), "--via", "r01", "--yes", "--json")
        by = {r["data"]["ip"]: r for r in doc["robots"]}
        assert by[ip(lab, "c1")]["outcome"] == "changed"
        # c2: the robot's key logs in, but sudo wants a password: the command fails, nothing runs
        assert by[ip(lab, "c2")]["outcome"] == "failed" and "exited with 1" in by[ip(lab, "c2")]["message"]
        assert code == 3
        assert len(lab.power_calls("c1")) >= 1 and lab.power_calls("c2") == []
        assert is_silent(lab, "c1") and not is_silent(lab, "c2")
    finally:
        for n in ("c1", "c2"):
            lab.power_on(n)


def test_shutdown_hosts_via_a_2_3_2_robot(slab: Lab, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """`shutdown --hosts FILE --via r04`: a husarion_ugv 2.3.2 robot reaches its LAN's HTTP host
    (husarion-shutdown, the secret from the environment) as a 2.2 robot does."""
    lab = slab
    hosts = tmp_path / "lan.yaml"
    hosts.write_text(f"hosts:\n  - ip: {ip(lab, 'h3')}\n    port: 3003\n    secret: {{env: H3_SECRET}}\n")
    monkeypatch.setenv("H3_SECRET", H3_SECRET)
    try:
        code, doc, out, err = cli(capsys, lab, "shutdown", "--hosts", str(hosts), "--via", "r04", "--yes", "--json")
        (row,) = doc["robots"]
        assert code == 0 and row["outcome"] == "changed", out + err
        assert len(lab.power_calls("h3")) >= 1 and H3_SECRET not in out + err
    finally:
        lab.power_on("h3")
