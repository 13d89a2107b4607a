"""`panther-ops shutdown` without a lab: bad files refused before anything is contacted, the
command forms, local hosts-file edits, and the robot's file through the pipeline on the demo
fleet (local transport). Addresses are RFC 5737 documentation addresses (data only)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main

BAD = """hosts:
  - ip: "10.15.20.3; rm -rf /"
    username: husarion
  - ip: 192.0.2.4
    username: "bad user"
  - ip: 192.0.2.5
    username: pi
    timeout: -3
"""

GOOD = """# the lab bench
hosts:
  # NUC on the bench
  - ip: 192.0.2.3
    username: husarion
    timeout: 3
  - ip: 192.0.2.5
    port: 3003
    secret: {env: BENCH_SECRET} # from the environment
"""


@pytest.fixture
def no_network(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Fail the test if anything tries to reach a host (ping, SSH, HTTP, the executor)."""
    import http.client
    import subprocess

    import paramiko

    from panther_ops.core.shutdown import run as run_mod

    attempts: list[str] = []

    def refuse(what: str) -> Any:
        def fn(*a: Any, **k: Any) -> Any:
            attempts.append(what)
            raise AssertionError(f"{what} must not run")

        return fn

    monkeypatch.setattr(subprocess, "run", refuse("subprocess.run"))
    monkeypatch.setattr(paramiko.SSHClient, "connect", refuse("ssh"))
    monkeypatch.setattr(http.client.HTTPConnection, "request", refuse("http"))
    monkeypatch.setattr(run_mod, "ShutdownExecutor", refuse("executor"))
    return attempts


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, " ".join(err.split())  # rich wraps long lines at 160 columns


def test_bad_entries_exit_2_and_nothing_is_contacted(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                      no_network: list[str]) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(BAD)
    code, _, err = run(capsys, "shutdown", "hosts", "validate", str(bad))
    assert code == 2
    assert "hosts[0].ip (line 2): '10.15.20.3; rm -rf /' is not an IP address or host name" in err
    assert "hosts[1].username (line 5): 'bad user' is not a POSIX user name" in err
    assert "hosts[2].timeout (line 8): -3 is not a number of seconds > 0" in err
    for extra in ([], ["--yes"], ["--yes", "--dry-run"], ["--yes", "--json"]):
        code, _out, err = run(capsys, "shutdown", "--hosts", str(bad), *extra)
        assert code == 2, extra
        assert "3 error(s)" in err and "nothing was run" in err
    code, _, err = run(capsys, "shutdown", "hosts", "validate", str(bad), "--json")
    assert code == 2
    assert no_network == []


def test_validate_a_good_file_and_for_a_stack(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                              no_network: list[str]) -> None:
    good = tmp_path / "good.yaml"
    good.write_text(GOOD)
    code, out, err = run(capsys, "shutdown", "hosts", "validate", str(good))
    assert code == 0 and "2 hosts valid, 0 warnings\n" in out
    code, out, err = run(capsys, "shutdown", "hosts", "validate", str(good), "--stack", "2.1.1")
    assert code == 2 and "no username: this robot's manager (<= 2.2.0, SSH) skips the entry" in err
    code, out, err = run(capsys, "shutdown", "hosts", "validate", str(good), "--stack", "2.2.2")
    assert code == 2 and "shuts computers down over HTTP" in err
    code, out, _ = run(capsys, "shutdown", "hosts", "list", str(good), "--json")
    doc = json.loads(out)
    assert [h["ip"] for h in doc["robots"][0]["data"]["hosts"]] == ["192.0.2.3", "192.0.2.5"]
    assert doc["robots"][0]["data"]["hosts"][1]["secret"] == "env BENCH_SECRET"
    assert no_network == []


def test_dry_run_and_confirmation_contact_nothing(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                  no_network: list[str], monkeypatch: pytest.MonkeyPatch) -> None:
    good = tmp_path / "good.yaml"
    good.write_text(GOOD)
    monkeypatch.setenv("BENCH_SECRET", "bench-secret-value")
    code, out, err = run(capsys, "shutdown", "--hosts", str(good), "--dry-run")
    assert code == 0
    assert "husarion@192.0.2.3:22" in out and "ssh: sudo shutdown now" in out and "http://192.0.2.5:3003" in out
    assert "GET /shutdown?ts=…&sig=…" in out and "bench-secret-value" not in out + err
    code, out, err = run(capsys, "shutdown", "--hosts", str(good))  # stdin is not a terminal, no --yes
    assert code == 2
    assert "husarion@192.0.2.3:22" in err and "http://192.0.2.5:3003" in err and "--yes" in err
    monkeypatch.delenv("BENCH_SECRET")
    code, out, err = run(capsys, "shutdown", "--hosts", str(good), "--yes")
    assert code == 2 and "BENCH_SECRET is not set" in err
    assert no_network == []


def test_command_forms(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "shutdown")
    assert code == 0 and "hosts" in out and "setup" in out and "check" in out and "robot" in out
    good = tmp_path / "good.yaml"
    good.write_text(GOOD)
    code, _, err = run(capsys, "shutdown", "--hosts", str(good), "hosts", "list", str(good))
    assert code == 2 and "without a subcommand" in err
    code, _, err = run(capsys, "shutdown", "hosts", "add", str(good), "--ip", "192.0.2.9", "--user", "x",
                       "-r", "panther-01")
    assert code == 2 and "not both" in err
    code, _, err = run(capsys, "shutdown", "hosts", "add", str(good), "--ip", "192.0.2.9")
    assert code == 2 and "needs --user" in err
    code, _, err = run(capsys, "shutdown", "hosts", "add", str(good), "--ip", "192.0.2.9", "--http", "--user", "x")
    assert code == 2 and "have no --user" in err


def test_local_file_edits_keep_comments(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "hosts.yaml"
    path.write_text(GOOD)
    code, out, _ = run(capsys, "shutdown", "hosts", "add", str(path), "--ip", "192.0.2.7", "--user", "pi",
                       "--timeout", "8", "--dry-run")
    assert code == 0 and "+  - ip: 192.0.2.7" in out and path.read_text() == GOOD
    code, out, _ = run(capsys, "shutdown", "hosts", "add", str(path), "--ip", "192.0.2.7", "--user", "pi",
                       "--timeout", "8", "--yes")
    assert code == 0
    assert path.read_text() == GOOD + "  - ip: 192.0.2.7\n    username: pi\n    timeout: 8.0\n"
    code, out, _ = run(capsys, "shutdown", "hosts", "add", str(path), "--ip", "192.0.2.8", "--http",
                       "--secret-env", "NUC8_SECRET", "--yes")
    assert code == 0 and "  - ip: 192.0.2.8\n    port: 3003\n    secret: {env: NUC8_SECRET}\n" in path.read_text()
    code, out, _ = run(capsys, "shutdown", "hosts", "add", str(path), "--ip", "192.0.2.7", "--user", "pi",
                       "--timeout", "8", "--yes")
    assert code == 0 and "already listed" in out
    code, _, _ = run(capsys, "shutdown", "hosts", "remove", str(path), "--ip", "192.0.2.7", "--yes")
    code, _, _ = run(capsys, "shutdown", "hosts", "remove", str(path), "--ip", "192.0.2.8", "--yes")
    assert code == 0 and path.read_text() == GOOD
    new = tmp_path / "new.yaml"
    code, _, _ = run(capsys, "shutdown", "hosts", "add", str(new), "--ip", "192.0.2.3", "--user", "husarion", "--yes")
    assert code == 0 and new.read_text() == "hosts:\n  - ip: 192.0.2.3\n    username: husarion\n"
    code, _, err = run(capsys, "shutdown", "hosts", "add", str(new), "--ip", "192.0.2.3; reboot", "--user", "x",
                       "--yes")
    assert code == 2 and "is not an IP address" in err


def test_local_file_edits_go_through_the_pipeline_with_a_backup(tmp_path: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "hosts.yaml"
    path.write_text(GOOD)
    code, out, _ = run(capsys, "shutdown", "hosts", "add", str(path), "--ip", "192.0.2.7", "--user", "pi",
                       "--yes", "--json")
    doc = json.loads(out)  # one document
    assert code == 0 and doc["robots"][0]["outcome"] == "changed"
    backup_id = doc["robots"][0]["data"]["backup"]
    bdir = tmp_path / ".panther-ops" / "backups" / backup_id
    assert (bdir / "files" / "0").read_text() == GOOD  # the previous content, beside the file
    manifest = json.loads((bdir / "manifest.json").read_text())
    assert manifest["command"] == "shutdown hosts add pi@192.0.2.7"
    assert manifest["files"][0]["path"] == str(path.resolve()) and "+  - ip: 192.0.2.7" in manifest["files"][0]["diff"]
    assert (bdir / "status").read_text().strip() == "applied"
    assert "192.0.2.7" in path.read_text()
    # a secret asked for lands in a new file only its owner reads; the diff masks it
    new = tmp_path / "new.yaml"
    code, out, _ = run(capsys, "shutdown", "hosts", "add", str(new), "--ip", "192.0.2.8", "--http",
                       "--secret-env", "NUC_SECRET", "--yes")
    assert code == 0 and new.stat().st_mode & 0o777 == 0o600


def test_a_local_file_changed_since_it_was_read_is_not_written(tmp_path: Path) -> None:
    from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
    from panther_ops.core.fleet.runner import RobotContext, open_transport
    from panther_ops.core.kinds.hostsfile import add_host, new_entry
    from panther_ops.core.shutdown.localfile import local_target, plan_local_hosts_edit
    from panther_ops.results import Outcome

    path = tmp_path / "hosts.yaml"
    path.write_text(GOOD)
    inv, target = local_target(path)
    transport = open_transport(inv, target)
    transport.connect()
    try:
        ctx = RobotContext(target, transport, inv)
        plan = plan_local_hosts_edit(ctx, path, lambda text: add_host(text, new_entry("192.0.2.7", username="pi")))
        assert "+  - ip: 192.0.2.7" in plan.diffs[0].unified
        path.write_text(GOOD + "# edited meanwhile\n")
        res = apply_plan(ctx, plan, ApplyOptions(restart=False, command="shutdown hosts add"))
    finally:
        transport.close()
    assert res.outcome is Outcome.FAILED and "changed on the robot since it was read" in res.message
    assert path.read_text() == GOOD + "# edited meanwhile\n"


def test_robot_file_through_the_pipeline_on_the_demo_fleet(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    inv = str(demo)
    hosts_21 = "/home/husarion/config/panther_manager/config/shutdown_hosts_config.yaml"
    code, out, _ = run(capsys, "-i", inv, "shutdown", "hosts", "add", "-r", "panther-01", "--ip", "192.0.2.10",
                       "--user", "husarion", "--yes", "--json")
    assert code == 0
    res = json.loads(out)["robots"][0]
    assert res["outcome"] == "changed" and res["data"]["backup"]
    diffs = {d["path"]: d["unified"] for d in res["diffs"]}
    assert "shutdown_hosts_config_path:=/config/panther_manager/config/shutdown_hosts_config.yaml" in \
        diffs["/home/husarion/compose.yaml"]
    assert "+  - ip: 192.0.2.10\n+    username: husarion\n" in diffs[hosts_21]
    code, out, _ = run(capsys, "-i", inv, "shutdown", "hosts", "list", "-r", "panther-01", "--json")
    data = json.loads(out)["robots"][0]["data"]
    assert data["hosts_file"].startswith(hosts_21 + " (mounted")
    assert data["mode"] == "ssh" and [h["ip"] for h in data["hosts"]] == ["10.15.20.3", "192.0.2.10"]
    # 2.2.2 (HTTP era): an SSH entry is refused, an HTTP one goes into the config tree, secret masked
    code, _, err = run(capsys, "-i", inv, "shutdown", "hosts", "add", "-r", "panther-03", "--ip", "192.0.2.11",
                       "--user", "husarion", "--yes")
    assert code == 2 and "shuts computers down over HTTP" in err
    secret = demo / "s"
    secret.write_text("demo-secret-value\n")
    code, out, err = run(capsys, "-i", inv, "shutdown", "hosts", "add", "-r", "panther-03", "--ip", "192.0.2.11",
                         "--http", "--secret-file", str(secret), "--timeout", "8", "--yes", "--json")
    assert code == 0, err
    res = json.loads(out)["robots"][0]
    assert [d["path"] for d in res["diffs"]] == ["/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"]
    assert "secret: ****" in res["diffs"][0]["unified"] and "demo-secret-value" not in out + err
    code, out, err = run(capsys, "-i", inv, "shutdown", "hosts", "validate", "-r", "panther-03")
    assert code == 0 and "demo-secret-value" not in out + err
    # remove: back to the stock entry only
    code, _, _ = run(capsys, "-i", inv, "shutdown", "hosts", "remove", "-r", "panther-01", "--ip", "192.0.2.10",
                     "--yes")
    assert code == 0
    code, out, _ = run(capsys, "-i", inv, "shutdown", "hosts", "list", "-r", "panther-01", "--json")
    assert [h["ip"] for h in json.loads(out)["robots"][0]["data"]["hosts"]] == ["10.15.20.3"]


def test_the_first_change_of_a_robots_file_warns_once_with_its_power_budget(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The first change on a 2.0/2.1 robot pushes the image's default, edited: each finding of
    the file is said once (docs/shutdown.md's lab sample showed the "no hosts" warning twice),
    and the timeout is weighed against --power-budget as on every later change (it was the
    default 15 s there)."""
    inv = str(demo)
    code, out, _ = run(capsys, "-i", inv, "shutdown", "hosts", "remove", "-r", "panther-01", "--ip", "10.15.20.3",
                       "--yes", "--json")
    res = json.loads(out)["robots"][0]
    assert code == 0 and "/home/husarion/compose.yaml" in [d["path"] for d in res["diffs"]]  # the default pushed
    assert [w for w in res["warnings"] if w.startswith("hosts")] == [
        "hosts: no hosts: nothing is shut down with the robot (the manager reports a failure and goes on with "
        "the robot itself)"]
    argv = ["shutdown", "hosts", "add", "--ip", "192.0.2.10", "--user", "husarion", "--timeout", "40", "--yes",
            "--json"]
    # panther-02's first change (2.0.4), panther-01's second; then a budget both 40 s hosts exceed
    for robot, budget, warned in (("panther-02", "60", 0), ("panther-01", "60", 0), ("panther-01", "30", 2)):
        if warned:  # 192.0.2.10 is listed now: add another one
            argv[argv.index("192.0.2.10")] = "192.0.2.11"
        code, out, _ = run(capsys, "-i", inv, *argv, "-r", robot, "--power-budget", budget)
        res = json.loads(out)["robots"][0]
        assert code == 0 and res["outcome"] == "changed", res
        timeouts = [w for w in res["warnings"] if ".timeout" in w]
        assert len(timeouts) == warned and all(f"~{budget} s" in w for w in timeouts), (robot, res)


def test_setup_check_and_robot_need_an_ssh_robot(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    inv = str(demo)
    code, _, err = run(capsys, "-i", inv, "shutdown", "setup", "-r", "panther-01", "--host", "192.0.2.3; reboot",
                       "--yes")
    assert code == 2 and "is not an IP address" in err
    code, out, _ = run(capsys, "-i", inv, "shutdown", "check", "-r", "panther-01", "--json")
    robot = json.loads(out)["robots"][0]  # a demo robot: skipped, as in every command (issue 16)
    assert code == 0 and robot["outcome"] == "skipped" and robot["message"].startswith("demo robot: no LAN")
    code, out, err = run(capsys, "-i", inv, "shutdown", "robot", "-r", "panther-01", "--dry-run")
    assert code == 0 and "10.15.20.3" in out  # the plan names the hosts; nothing is contacted
    row = next(line for line in out.splitlines() if line.startswith("│ panther-01"))  # a plan: "would"
    assert [c.strip() for c in row.split("│")[1:-1]] == [
        "panther-01", "would change", "would shut down 1 host(s) first (husarion@10.15.20.3:22), then the Built-in "
        "Computer"], out
    assert "1 robot: 1 would change in" in err, err
    code, _, err = run(capsys, "-i", inv, "shutdown", "robot", "-r", "panther-01")
    assert code == 2 and "panther-01" in err and "husarion@10.15.20.3:22" in err


def test_a_chained_command_is_a_warning_of_validate_and_of_every_plan_that_writes_it(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], no_network: list[str]) -> None:
    """Issue 23 item 10: `shutdown hosts validate`, `config push --as shutdown-hosts` and
    `shutdown hosts add` (a local file and a robot's) show it; the files stay as they were."""
    chained = tmp_path / "chained.yaml"
    chained.write_text("hosts:\n  - ip: 10.15.20.5\n    username: pi\n    command: sudo shutdown now; rm -rf /tmp/x\n")
    said = "hosts[0].command (line 4): 'sudo shutdown now; rm -rf /tmp/x' chains commands with ';'"
    code, out, err = run(capsys, "shutdown", "hosts", "validate", str(chained))
    assert code == 0 and "1 warning\n" in out and said in err
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    inv = ["-i", str(tmp_path / "demo")]
    code, _, err = run(capsys, *inv, "config", "push", str(chained), "--as", "shutdown-hosts", "-r", "panther-01",
                       "--dry-run")
    assert code == 0 and said in err
    local = tmp_path / "hosts.yaml"
    local.write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    code, _, err = run(capsys, "shutdown", "hosts", "add", str(local), "--ip", "10.15.20.9", "--user", "pi",
                       "--command", "sync && sudo shutdown now", "--dry-run")
    assert code == 0 and "hosts[1].command (line 6): 'sync && sudo shutdown now' chains commands with '&&'" in err
    code, _, err = run(capsys, *inv, "shutdown", "hosts", "add", "-r", "panther-01", "--ip", "10.15.20.9", "--user",
                       "pi", "--command", "sudo shutdown now | tee /tmp/log", "--dry-run")
    assert code == 0 and "'sudo shutdown now | tee /tmp/log' chains commands with '|'" in err
    assert local.read_text() == "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
    assert no_network == []


def test_the_hosts_are_the_changes_subjects(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                            no_network: list[str], monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 28: `shutdown --hosts` is a change through fleet.change: one target per host (subject
    `host`), each planned (what it would get) in the change's envelope; the secret never shown."""
    good = tmp_path / "good.yaml"
    good.write_text(GOOD)
    monkeypatch.setenv("BENCH_SECRET", "bench-secret-value")
    code, out, err = run(capsys, "shutdown", "--hosts", str(good), "--dry-run", "--json")
    doc = json.loads(out)
    assert code == doc["exit_code"] == 0 and doc["command"] == "shutdown --hosts good.yaml", err
    assert doc["notes"] == ["dry run: nothing was contacted"] and doc["summary"]["changed"] == 2
    ssh, http = doc["robots"]
    assert ssh["robot"] == "husarion@192.0.2.3:22" and ssh["message"].startswith("would shut down husarion@")
    assert ssh["data"] == {"ip": "192.0.2.3", "method": "ssh", "port": 22, "timeout": 3.0, "username": "husarion",
                           "command": "sudo shutdown now", "ping_for_success": True, "via": None, "dry_run": True}
    assert http["robot"] == "http://192.0.2.5:3003" and http["data"]["secret"] == "env BENCH_SECRET"
    assert "bench-secret-value" not in out + err and no_network == []
    code, out, err = run(capsys, "shutdown", "--hosts", str(good), "--dry-run")
    assert code == 0 and "2 hosts" in out + err, out + err
