"""`apply` and `config diff` with ``desired.webui`` on the demo fleet (recorded User Computers),
and the WebUI's ``ros.namespace`` defaulting to the robot's namespace."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.remote.webui.defaults import RobotNamespace, with_robot_namespace

WAREHOUSE = """      launch_args:
        wheel_type: WH02
"""


@pytest.fixture
def demo(tmp_path: Path) -> Path:
    """The demo fleet, its warehouse group (panther-01 running the WebUI, panther-02 without a
    User Computer) and field group (panther-03, WebUI stopped) wanting WebUI settings."""
    path = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(path)]) == 0
    inv = path / "inventory.yaml"
    text = inv.read_text().replace(WAREHOUSE, WAREHOUSE + "      webui:\n        port: 8081\n")
    assert "        layout: panther\n" in text  # the demo's field group wants what panther-03 has
    text = text.replace("        layout: panther\n", "        layout: husarion-ugv\n")
    inv.write_text(text)
    return inv


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, dict[str, object]]]:
    capsys.readouterr()
    code = main([*argv, "--json"])
    doc = json.loads(capsys.readouterr().out)
    return code, {r["robot"]: r for r in doc["robots"]}


def test_the_demo_fleets_desired_webui_matches_its_recording(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(path)]) == 0
    code, robots = run(capsys, "-i", str(path), "config", "diff", "-r", "panther-03")
    assert code == 0 and robots["panther-03"]["outcome"] == "ok"
    assert robots["panther-03"]["message"] == "matches the inventory's desired state"
    assert robots["panther-03"]["data"]["webui"]["plan"] == []


def test_config_diff_reports_webui_drift_beside_the_files(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, robots = run(capsys, "-i", str(demo), "config", "diff", "--all")
    assert code == 0
    one, two, three = robots["panther-01"], robots["panther-02"], robots["panther-03"]
    assert one["outcome"] == "changed" and one["diffs"]  # wheel_type in compose.yaml and the WebUI port
    assert one["message"] == "would change wheel_type:=WH02; set WebUI webui.port: 8080 -> 8081 and restart it"
    assert one["data"]["webui"]["plan"] == [{"key": "webui.port", "current": "8080", "new": "8081"}]
    assert two["message"] == "would change: wheel_type:=WH02"  # no User Computer recorded: said, not guessed
    assert two["warnings"] == ["desired.webui not converged: demo robot: no User Computer recorded (demo robot)"]
    assert three["outcome"] == "changed" and not three["diffs"]
    assert three["message"] == "would set WebUI webui.layout: panther -> husarion-ugv"
    assert three["data"]["webui"]["namespace"] == "ros.namespace panther kept"


def test_apply_on_demo_robots_skips_the_webui_and_says_so(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, robots = run(capsys, "-i", str(demo), "apply", "--all", "--dry-run")
    assert code == 0 and robots["panther-03"]["message"] == "would set WebUI webui.layout: panther -> husarion-ugv"
    code, robots = run(capsys, "-i", str(demo), "apply", "--all", "--yes")
    assert code == 0
    assert robots["panther-01"]["outcome"] == "changed" and robots["panther-01"]["message"] == "wheel_type:=WH02"
    assert "WebUI not set: demo robot, no User Computer to change" in robots["panther-01"]["warnings"]
    assert robots["panther-03"]["outcome"] == "skipped"
    code, robots = run(capsys, "-i", str(demo), "config", "diff", "--all")  # the files converged, the WebUI not
    assert robots["panther-01"]["message"] == "would set WebUI webui.port: 8080 -> 8081 and restart it"


def test_namespace_defaults_to_the_robots_only_where_the_snap_has_none() -> None:
    robot = RobotNamespace("panther", "the robot's namespace, ROBOT_NAMESPACE in compose.yaml")
    assert with_robot_namespace({"webui.port": "8081"}, "", robot) == (
        {"webui.port": "8081", "ros.namespace": "panther"},
        "ros.namespace panther: the robot's namespace, ROBOT_NAMESPACE in compose.yaml")
    assert with_robot_namespace({"ros.namespace": "x"}, "", robot) == ({"ros.namespace": "x"}, "")
    kept, note = with_robot_namespace({}, "other", robot)
    assert kept == {} and "webui set ros.namespace=panther" in note
    none = RobotNamespace(None, "the robot's driver runs without a namespace: ros.namespace left unset")
    assert with_robot_namespace({}, "", none) == ({}, none.note)


def test_config_get_namespace_reads_robot_namespace_where_the_stack_does(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(path)]) == 0
    code, robots = run(capsys, "-i", str(path), "config", "get", "namespace", "--all")
    assert code == 0
    assert {n: (r["data"]["value"], r["data"]["source"]) for n, r in robots.items()} == {
        "panther-01": ("panther", "ROBOT_NAMESPACE in compose.yaml"),
        "panther-02": ("panther", "compose.yaml"),
        "panther-03": ("panther", "ROBOT_NAMESPACE in /home/husarion/config/common/.env"),
        "panther-04": ("panther", "ROBOT_NAMESPACE in /home/husarion/config/common/.env")}
