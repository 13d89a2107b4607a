"""What the operator reads (issue 16, findings 2, 3, 5, 6, 7, 8, 10), on the demo fleet."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.core.fleet.templates import template_path
from tests.clirun import run

from .termrun import piped

Capsys = pytest.CaptureFixture[str]


# -- finding 2: read-only commands and dry runs ------------------------------------------------
def test_a_dry_run_summary_says_would_change(demo: Path, capsys: Capsys) -> None:
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "--all", "--dry-run")
    assert code == 0
    assert "4 robots: 4 would change in" in err and "4 changed" not in err
    assert "dry run: nothing was written" in err


def test_a_dry_run_table_says_would_change_not_changed(demo: Path, capsys: Capsys) -> None:
    """The result column as well as the summary: nothing changed in a dry run."""
    code, out, _ = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "--all", "--dry-run")
    assert code == 0
    rows = [[c.strip() for c in line.split("│")[1:-1]] for line in out.splitlines() if line.startswith("│ panther-")]
    assert [r[:2] for r in rows] == [[f"panther-0{i}", "would change"] for i in (1, 2, 3, 4)], out


def test_webui_set_dry_run_says_would_change(demo: Path, capsys: Capsys) -> None:
    """The snap keys' plan (current -> new) is a change not yet made, as every other plan."""
    argv = ("-i", str(demo), "webui", "set", "webui.port=8081", "-r", "panther-01", "--dry-run")
    code, out, err = run(capsys, *argv)
    assert code == 0 and "1 robot: 1 would change in" in err, err
    row = next(line for line in out.splitlines() if line.startswith("│ panther-01"))
    assert [c.strip() for c in row.split("│")[1:-1]] == ["panther-01", "would change",
                                                         "webui.port: 8080 -> 8081"], out  # said once (issue 26)
    code, out, _ = run(capsys, *argv, "--json")
    robot = json.loads(out)["robots"][0]
    assert (robot["outcome"], robot["data"]["dry_run"]) == ("changed", True), robot


def test_the_live_recap_of_a_dry_run_says_would_change() -> None:
    """The progress view's count and recap (on a terminal) use the same words as the table."""
    import io

    from rich.console import Console

    from panther_ops.cli import progress as progress_mod
    from panther_ops.results import Outcome, RobotResult

    progress = progress_mod.FleetProgress(["panther-01", "panther-02"], enabled=True)
    progress.phase("panther-01", "plan")
    progress(RobotResult("panther-01", Outcome.CHANGED, "would change: wheel_type:=WH02", data={"dry_run": True}))
    progress.phase("panther-02", "plan")
    progress(RobotResult("panther-02", Outcome.OK, "nothing to change"))
    buf = io.StringIO()
    Console(file=buf, width=100).print(progress._render(10))
    assert "2/2 robots done  1 would change  1 ok" in buf.getvalue()
def test_the_plan_shown_before_the_question_says_would_change(demo: Path, capsys: Capsys) -> None:
    """Refused for want of --yes (stdin is no terminal here): nothing changed, and the plan says so."""
    code, out, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "--all")
    assert code == 2 and "changes need confirmation: pass --yes" in err
    assert "4 robots: 4 would change in" in err and "4 changed" not in err
    assert out.count("│ would change │ wheel_type:=WH02") == 4 and "dry run" not in out + err


def test_config_diff_does_not_speak_of_a_dry_run(demo: Path, capsys: Capsys) -> None:
    code, out, err = run(capsys, "-i", str(demo), "config", "diff", "--all")
    assert code == 0 and "+++ b/panther-01/home/husarion/compose.yaml" in out  # several robots: one patch
    assert "dry run" not in out + err and "nothing was written" not in out + err
    assert "2 would change" in err and "2 ok" in err  # panther-01: desired WH02 (warehouse), panther-04 as panther-03


# -- finding 3: the simulation piped shows the shutdown --------------------------------------------
def test_manager_run_piped_shows_the_mode_the_shutdown_and_the_power_off() -> None:
    scenario = template_path("manager", "scenarios", "battery_overheat.yaml")
    result = piped(["manager", "run", "--sim", "--scenario", str(scenario)])
    assert result.code == 0, result.err
    lines = result.out.splitlines()
    assert all(" mode=" in line for line in lines if " bat=" in line)
    assert any("mode=running" in line for line in lines)
    shutting = [i for i, line in enumerate(lines) if "shutting down: Fatal battery temperature" in line]
    off = [i for i, line in enumerate(lines) if line.endswith("powered off")]
    assert len(shutting) == 1 and len(off) == 1 and shutting[0] < off[0]
    assert any("mode=shutting_down" in line for line in lines[shutting[0]:off[0]])


# -- finding 5: broken and doubled messages -----------------------------------------------------------
def test_a_manager_deploy_dry_run_says_what_it_would_do(demo: Path, capsys: Capsys) -> None:
    code, out, _ = run(capsys, "-i", str(demo), "manager", "deploy", "-r", "panther-01", "--dry-run", "--json")
    message = json.loads(out)["robots"][0]["message"]
    assert code == 0 and message.startswith("would deploy manager "), message


def test_the_battery_push_warns_once(demo: Path, tmp_path: Path, capsys: Capsys) -> None:
    battery = tmp_path / "battery.yaml"
    code, _, _ = run(capsys, "-i", str(demo), "config", "pull", "battery", "-r", "panther-01", "-o", str(battery))
    assert code == 0
    code, _, err = run(capsys, "-i", str(demo), "config", "push", str(battery), "--as", "battery", "-r",
                       "panther-01", "--dry-run")
    assert code == 0
    warnings = [line for line in err.splitlines() if line.startswith("warning panther-01")]
    assert len(warnings) == 1 and "simulation" in warnings[0], err


def test_shutdown_setup_says_its_error_once(demo: Path) -> None:
    result = piped(["-i", str(demo), "shutdown", "setup", "-r", "panther-01", "--host", "10.15.20.3", "--yes"])
    assert result.code == 3
    text = result.out + result.err
    assert text.count("needs a robot reached over SSH") == 1, text


# -- finding 6: demo robots, one way ---------------------------------------------------------------------
def test_manager_logs_on_a_demo_robot_is_skipped_like_driver_logs(demo: Path, capsys: Capsys) -> None:
    for command in ("driver", "manager"):
        code, _, err = run(capsys, "-i", str(demo), command, "logs", "--all")
        assert code == 0, (command, err)
        assert err.count("skipped: demo robot: no docker engine") == 4, (command, err)


def test_config_pull_bt_lights_falls_back_to_the_template(demo: Path, tmp_path: Path, capsys: Capsys) -> None:
    code, out, err = run(capsys, "-i", str(demo), "config", "pull", "bt-lights", "-r", "panther-01")
    assert code == 0, err
    # the release's stock project, written from upstream's (issue 24): not panther-ops' own trees
    assert out == template_path("config", "panther-2.1", "panther_manager", "behavior_trees",
                                "PantherLightsBT.btproj").read_text()
    assert "written from panther_ros@2.1.1:panther_manager/behavior_trees/PantherLightsBT.btproj" in err


def test_shutdown_check_on_a_demo_robot_is_skipped(demo: Path, capsys: Capsys) -> None:
    code, out, _ = run(capsys, "-i", str(demo), "shutdown", "check", "--all", "--json")
    doc = json.loads(out)
    assert code == 0 and {r["outcome"] for r in doc["robots"]} == {"skipped"}
    assert all(r["message"].startswith("demo robot: no LAN") for r in doc["robots"])


def test_shutdown_via_a_demo_robot_is_refused_in_a_dry_run_too(demo: Path, tmp_path: Path) -> None:
    hosts = tmp_path / "hosts.yaml"
    hosts.write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    for extra in (["--dry-run"], ["--yes"]):
        result = piped(["-i", str(demo), "shutdown", "--hosts", str(hosts), "--via", "panther-01", *extra])
        assert result.code == 2, (extra, result.err)
        assert "needs a robot reached over SSH" in result.err


# -- finding 7: where a file comes from ------------------------------------------------------------------
def test_pull_says_which_content_a_demo_robot_uses(demo: Path, capsys: Capsys) -> None:
    code, _, err = run(capsys, "-i", str(demo), "config", "pull", "controller", "-r", "panther-01")
    assert code == 0
    assert "not found in the image" not in err
    assert "panther-ops' template for panther_ros 2.1.1" in err and "(a demo robot has no image)" in err
    assert "the image's file is panther_ros@2.1.1:panther_controller/config/WH01_controller.yaml" in err


# -- finding 8: refusals name the way forward -------------------------------------------------------------
def test_refusals_name_the_service_that_does_it(demo: Path, capsys: Capsys) -> None:
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "launch_nmea_gps", "true", "-r", "panther-02",
                       "--dry-run")
    assert code == 2 and "nmea-gps" in err and "panther-ops gps enable" in err
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "launch_gamepad", "true", "-r", "panther-01",
                       "--dry-run")
    assert code == 2 and "gamepad_controller" in err and "service" in err


# -- finding 10: read-only commands just answer -------------------------------------------------------------
def test_config_get_without_targets_answers_for_every_robot(demo: Path, capsys: Capsys) -> None:
    code, out, err = run(capsys, "-i", str(demo), "config", "get", "wheel_type", "--json")
    assert code == 0, err
    assert [r["robot"] for r in json.loads(out)["robots"]] == ["panther-01", "panther-02", "panther-03", "panther-04"]
    # a change still insists on a choice
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH02", "--dry-run")
    assert code == 2 and "choose with --robot" in err


def test_inventory_show_of_a_demo_robot_has_no_ssh_address(demo: Path, capsys: Capsys) -> None:
    code, out, _ = run(capsys, "-i", str(demo), "inventory", "show", "panther-01")
    assert code == 0
    assert "host:" not in out and "localhost" not in out and "\nport:" not in out
    assert "transport: local" in out and "root: " in out


NEWER_READ_ONLY = (["gps", "status"], ["estop", "status"], ["webui", "status"], ["webui", "get"], ["webui", "url"],
                   ["reimage", "plan"], ["manager", "status"], ["manager", "logs"], ["driver", "logs"])
"""The newer groups' read-only commands: they answer without a choice too (rule 10)."""


@pytest.mark.parametrize("argv", NEWER_READ_ONLY, ids=" ".join)
def test_newer_read_only_commands_answer_for_every_robot_when_none_is_chosen(argv: list[str], demo: Path,
                                                                             capsys: Capsys) -> None:
    code, out, err = run(capsys, "-i", str(demo), *argv, "--json")
    doc = json.loads(out)
    assert [r["robot"] for r in doc["robots"]] == ["panther-01", "panther-02", "panther-03", "panther-04"], err
    assert "no robot chosen: reading all 4 (choose with -r, -g)" in err and "choose with --robot" not in err
    assert doc["command"] == " ".join(argv)  # `webui get` says so (it said `webui status`)
    assert code == 0


def test_a_default_group_answers_read_only_commands(demo: Path, capsys: Capsys) -> None:
    inventory = demo / "inventory.yaml"
    inventory.write_text(inventory.read_text().replace("defaults:", "settings:\n  default_group: field\ndefaults:", 1))
    for argv in (["config", "get", "wheel_type"], ["status"], ["driver", "status"], ["config", "diff"],
                 ["doctor"], ["config", "history"], ["driver", "versions"], *NEWER_READ_ONLY):
        code, out, err = run(capsys, "-i", str(demo), *argv, "--json")
        assert code == 0, (argv, err)
        assert [r["robot"] for r in json.loads(out)["robots"]] == ["panther-03", "panther-04"], argv
        assert "no robot chosen: group field (settings.default_group)" in err
    inventory.write_text(inventory.read_text().replace("default_group: field", "default_group: nope"))
    code, _, err = run(capsys, "-i", str(demo), "status")
    assert code == 2 and "default_group 'nope' is not a group of the inventory" in err and "field" in err


# -- finding 11: progress of reimage flash/verify like the fleet's --------------------------------
@pytest.mark.parametrize(("json_out", "quiet", "shown"), [(False, False, True), (True, False, False),
                                                           (False, True, False)])
def test_reimage_progress_is_silent_with_json_or_quiet(json_out: bool, quiet: bool, shown: bool,
                                                        capsys: Capsys) -> None:
    from panther_ops.cli.output import configure
    from panther_ops.cli.views.reimage import progress

    configure(quiet=quiet)
    try:
        with progress(json_out) as step:  # stderr is not a terminal here: plain lines, when wanted
            step("write", 1 << 20, 1 << 20)
    finally:
        configure()
    err = capsys.readouterr().err
    assert ("writing: 1.0 MiB of 1.0 MiB (100%)" in err) is shown, err


# -- finding 6: demo robots handled one way -----------------------------------------------------------
@pytest.mark.parametrize("argv", [["gps", "router", "show"], ["gps", "router", "set", "--enable", "--yes"],
                                  ["gps", "router", "set", "--enable", "--dry-run"]], ids=" ".join)
def test_the_router_of_a_demo_robot_is_skipped_by_show_and_set_alike(argv: list[str], demo: Path, capsys: Capsys,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PASSWORD", "demo")
    code, out, err = run(capsys, "-i", str(demo), *argv, "-r", "panther-01", "--json")
    assert code == 0, err
    (robot,) = json.loads(out)["robots"]
    assert robot["outcome"] == "skipped" and robot["message"] == "demo robot: reached without SSH, no router behind it"


@pytest.mark.parametrize("group", ["driver", "manager"])
def test_following_a_log_still_needs_one_robot_chosen(group: str, demo: Path, capsys: Capsys) -> None:
    code, _, err = run(capsys, "-i", str(demo), group, "logs", "-f")
    assert code == 2 and "choose with --robot" in err


@pytest.mark.parametrize("group", ["driver", "manager"])
def test_following_a_demo_robots_log_is_skipped_as_reading_it_is(group: str, demo: Path, capsys: Capsys) -> None:
    for follow in ([], ["-f"]):
        code, _, err = run(capsys, "-i", str(demo), group, "logs", "-r", "panther-01", *follow)
        assert code == 0, (follow, err)
        assert "panther-01: skipped: demo robot: no docker engine" in err and "error" not in err, follow


def test_gps_enable_router_on_a_demo_robot_plans_the_driver_and_says_the_router_is_left_out(
        demo: Path, capsys: Capsys, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PASSWORD", "demo")
    code, out, err = run(capsys, "-i", str(demo), "gps", "enable", "-r", "panther-01", "--router", "--dry-run", "--json")
    assert code == 0, err
    (robot,) = json.loads(out)["robots"]
    assert robot["message"] == "would change: launch_nmea_gps:=True on panther_ros"
    assert robot["warnings"] == ["router not set: demo robot: reached without SSH, no router behind it"]


def test_gps_status_router_on_a_demo_robot_says_it_was_not_read(demo: Path, capsys: Capsys,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PASSWORD", "demo")
    code, out, _ = run(capsys, "-i", str(demo), "gps", "status", "-r", "panther-01", "--router", "--json")
    (robot,) = json.loads(out)["robots"]
    assert code == 0 and robot["data"]["router"] is None
    assert robot["warnings"] == ["router not read: demo robot, no router behind it (as `gps router show`)"]


def test_a_local_file_is_called_a_file_not_a_robot(tmp_path: Path, capsys: Capsys,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """`shutdown hosts add|remove FILE`, `config history|rollback --file FILE`: the table's first
    column and the summary speak of the file (they said "robot" and "1 robot: 1 changed")."""
    monkeypatch.chdir(tmp_path)
    Path("hosts.yaml").write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
                                  "  - ip: 10.15.20.9\n    username: pi\n")
    for argv, summary in ((("shutdown", "hosts", "remove", "hosts.yaml", "--ip", "10.15.20.9", "--yes"),
                           "1 file: 1 changed"),
                          (("config", "history", "--file", "hosts.yaml"), "1 file: 1 ok"),
                          (("config", "rollback", "--file", "hosts.yaml", "--dry-run"), "1 file: 1 would change")):
        code, out, err = run(capsys, *argv)
        assert code == 0, err
        header = next(line for line in out.splitlines() if "hosts.yaml" not in line and "┃" in line)
        assert header.split("┃")[1].strip() == "file" and "robot" not in header, header
        assert summary in err and "robot" not in err, err
    # a refusal of the plan: nothing was changed (not "on any robot")
    code, _, err = run(capsys, "config", "rollback", "--file", "hosts.yaml", "--to", "nope", "--yes")
    assert code == 2 and "backup 'nope' not found for hosts.yaml" in err, err
    assert "nothing was changed" in err and "robot" not in err, err
