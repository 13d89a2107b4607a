"""`gps enable|disable` on the demo fleet (local robot roots, no docker): the change per stack,
exact diffs, idempotence, byte-identical disable, bad input refused with nothing changed."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.clirun import run_cli

ROBOT_ROOT = "robots/{}/home/husarion"


def run(capsys: pytest.CaptureFixture[str], demo: Path, *argv: str) -> tuple[int, dict[str, Any], str]:
    code, doc, _, err = run_cli(capsys, "-i", str(demo), *argv)
    return code, doc, err


def snapshot(demo: Path) -> dict[str, bytes]:
    """Every file under the robots' homes except panther-ops' own backups."""
    return {str(p.relative_to(demo)): p.read_bytes() for p in sorted((demo / "robots").rglob("*"))
            if p.is_file() and ".panther-ops" not in p.parts}


def compose(demo: Path, robot: str) -> str:
    return (demo / ROBOT_ROOT.format(robot) / "compose.yaml").read_text()


def test_dry_run_plans_per_stack(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    before = snapshot(demo)
    code, doc, _ = run(capsys, demo, "gps", "enable", "--all", "--dry-run", "--json")
    assert code == 0 and snapshot(demo) == before
    by = {r["robot"]: r for r in doc["robots"]}
    assert {r["outcome"] for r in doc["robots"]} == {"changed"}
    # 2.1.1: the argument on the driver
    (d1,) = by["panther-01"]["diffs"]
    assert "+    command: ros2 launch panther_bringup bringup.launch.py launch_nmea_gps:=True\n" in d1["unified"]
    assert by["panther-01"]["data"]["mode"] == "argument"
    # 2.0.4: the manual's service, appended; nothing else touched
    (d2,) = by["panther-02"]["diffs"]
    added = [ln[1:] for ln in d2["unified"].splitlines() if ln.startswith("+") and not ln.startswith("+++")]
    assert [ln for ln in d2["unified"].splitlines() if ln.startswith("-") and not ln.startswith("---")] == []
    assert added == ["", "  nmea-gps:", "    image: husarion/nmea-gps:humble-2.0.1-20240617", "    <<: *common-config",
                     "    network_mode: host", "    restart: always", "    command: >-",
                     "      ros2 launch /husarion_utils/nmea_navsat.launch.py", "      robot_namespace:=panther"]
    # 2.2: the argument, the stack's boolean spelling
    (d3,) = by["panther-03"]["diffs"]
    assert "launch_gamepad:=true launch_nmea_gps:=true\n" in d3["unified"]


def test_enable_twice_then_disable_restores_bytes(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    before = snapshot(demo)
    code, doc, _ = run(capsys, demo, "gps", "enable", "--all", "--yes", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["changed"] * 4
    assert "robot_namespace:=panther" in compose(demo, "panther-02")
    code, doc, _ = run(capsys, demo, "gps", "enable", "--all", "--yes", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["ok"] * 4
    assert "already" in doc["robots"][0]["message"]
    code, doc, _ = run(capsys, demo, "gps", "disable", "--all", "--yes", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["changed"] * 4
    assert snapshot(demo) == before
    code, doc, _ = run(capsys, demo, "gps", "disable", "--all", "--yes", "--json")
    assert [r["outcome"] for r in doc["robots"]] == ["ok"] * 4


def test_port_on_22_writes_params_file_and_disable_removes_it(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    before = snapshot(demo)
    code, doc, _ = run(capsys, demo, "gps", "enable", "-r", "panther-03", "--port", "5001", "--yes", "--json")
    assert code == 0, doc
    params = demo / ROBOT_ROOT.format("panther-03") / "config/husarion_ugv_localization/config/nmea_navsat.yaml"
    text = params.read_text()
    assert "    port: 5001\n" in text and "    ip: 10.15.20.2\n" in text
    assert "nmea_params_path:=/config/husarion_ugv_localization/config/nmea_navsat.yaml" in compose(demo, "panther-03")
    code, doc, _ = run(capsys, demo, "gps", "disable", "-r", "panther-03", "--yes", "--json")
    assert code == 0 and not params.exists() and snapshot(demo) == before


def test_port_on_211_writes_params_file_mounts_it_and_disable_removes_it(capsys: pytest.CaptureFixture[str],
                                                                         demo: Path) -> None:
    """Issue 24 finding 4: panther_ros 2.1.1's NMEA launch file declares params_file
    (panther_ros@2.1.1:panther_localization/launch/nmea_navsat.launch.py)."""
    before = snapshot(demo)
    code, doc, err = run(capsys, demo, "gps", "enable", "-r", "panther-01", "--port", "5001", "--yes", "--json")
    assert code == 0, err
    rel = "config/panther_localization/config/nmea_navsat_params.yaml"
    params = demo / ROBOT_ROOT.format("panther-01") / rel
    text = params.read_text()
    assert "      port: 5001\n" in text and "      timeout_sec: 2\n" in text
    assert f"params_file:=/{rel}" in compose(demo, "panther-01")
    assert f"/home/husarion/{rel}:/{rel}:ro" in compose(demo, "panther-01")
    # back to port 5000: the image's own params again (no stale params_file)
    code, doc, err = run(capsys, demo, "gps", "enable", "-r", "panther-01", "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed", err
    assert " params_file:=" not in compose(demo, "panther-01") and rel not in compose(demo, "panther-01")
    assert not params.exists()
    assert "launch_nmea_gps:=True" in compose(demo, "panther-01")
    code, doc, _ = run(capsys, demo, "gps", "enable", "-r", "panther-01", "--port", "5001", "--yes", "--json")
    code, doc, _ = run(capsys, demo, "gps", "disable", "-r", "panther-01", "--yes", "--json")
    assert code == 0 and not params.exists() and snapshot(demo) == before


def test_container_port_and_namespace_on_204(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    code, _doc, _ = run(capsys, demo, "gps", "enable", "-r", "panther-02", "--port", "5002", "--namespace", "rover",
                        "--yes", "--json")
    assert code == 0
    text = compose(demo, "panther-02")
    assert "-p ip:=10.15.20.2 -p port:=5002" in text and "-r __ns:=/rover" in text
    # another port replaces the service (one service, not two)
    code, doc, _ = run(capsys, demo, "gps", "enable", "-r", "panther-02", "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed"
    assert compose(demo, "panther-02").count("  nmea-gps:\n") == 1 and "robot_namespace:=panther" in compose(demo, "panther-02")


@pytest.mark.parametrize(("argv", "says"), [
    (["--port", "70000"], "'--port': '70000' is not a port"),  # the option's parser: ASCII digits, 1-65535
    (["--port", "0"], "'--port': '0' is not a port"),
    (["--namespace", "my robot"], "--namespace"),
    (["--ip", "10.15.20"], "--ip"),
])
def test_bad_input_exit_2_nothing_changed(capsys: pytest.CaptureFixture[str], demo: Path, argv: list[str],
                                          says: str) -> None:
    before = snapshot(demo)
    code, _doc, err = run(capsys, demo, "gps", "enable", "--all", "--yes", *argv)
    assert code == 2 and says in err and snapshot(demo) == before


def test_mixed_modes_refused(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    assert run(capsys, demo, "gps", "enable", "-r", "panther-01", "--yes")[0] == 0
    before = snapshot(demo)
    code, _doc, err = run(capsys, demo, "gps", "enable", "-r", "panther-01", "--container", "--yes")
    assert code == 2 and "launch_nmea_gps:=True" in err and snapshot(demo) == before


def test_desired_gps_in_config_diff_and_apply(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    inv = demo / "inventory.yaml"
    text = inv.read_text()
    for name, block in (("panther-02", "gps: {enabled: true, namespace: rover}"),
                        ("panther-03", "gps: {enabled: true, router: {enabled: true}}")):
        assert f"  {name}:\n" in text
        text = text.replace(f"  {name}:\n", f"  {name}:\n    desired:\n      {block}\n", 1)
    inv.write_text(text)
    code, doc, _ = run(capsys, demo, "config", "diff", "--all", "--json")
    assert code == 0
    by = {r["robot"]: r for r in doc["robots"]}
    assert by["panther-02"]["outcome"] == "changed" and "add service nmea-gps" in by["panther-02"]["message"]
    assert "robot_namespace:=rover" in by["panther-02"]["diffs"][0]["unified"]
    assert "launch_nmea_gps:=true" in by["panther-03"]["message"]
    assert any("desired.gps.router" in w for w in by["panther-03"]["warnings"])
    code, doc, _ = run(capsys, demo, "apply", "--all", "--yes", "--json")
    assert code == 0, doc
    assert "    command: >-\n      ros2 launch /husarion_utils/nmea_navsat.launch.py\n      robot_namespace:=rover\n" \
        in compose(demo, "panther-02")
    code, doc, _ = run(capsys, demo, "config", "diff", "--all", "--json")
    assert [r["outcome"] for r in doc["robots"]] == ["ok"] * 4
    inv.write_text(inv.read_text().replace("gps: {enabled: true, router: {enabled: true}}", "gps: {enabled: false}"))
    code, doc, _ = run(capsys, demo, "config", "diff", "-r", "panther-03", "--json")
    assert doc["robots"][0]["outcome"] == "changed" and "unset launch_nmea_gps" in doc["robots"][0]["message"]
    inv.write_text(inv.read_text().replace("gps: {enabled: false}", "gps: {enabled: yes please}"))
    code, _doc, err = run(capsys, demo, "config", "diff", "-r", "panther-03")
    assert code == 2 and "desired.gps.enabled" in err


def test_service_shares_the_drivers_dds_domain_and_rmw(capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    """The manual's nmea-gps service alone runs on domain 0 with the image's default RMW: on a
    robot whose driver has another ROS_DOMAIN_ID its /<ns>/gps/fix is never seen. The service
    merges the driver's common-config, so both resolve to the same DDS settings."""
    from panther_ops.core.robot.compose import ComposeFile

    path = demo / ROBOT_ROOT.format("panther-02") / "compose.yaml"
    path.write_text(path.read_text().replace("ROS_DOMAIN_ID=${ROS_DOMAIN_ID:-0}", "ROS_DOMAIN_ID=42"))
    code, doc, _ = run(capsys, demo, "gps", "enable", "-r", "panther-02", "--yes", "--json")
    assert code == 0, doc
    written = ComposeFile.parse(path.read_text())
    env = written.environment("nmea-gps")
    assert env == written.environment(written.driver_service())
    assert env["ROS_DOMAIN_ID"] == "42" and env["RMW_IMPLEMENTATION"] == "rmw_cyclonedds_cpp"


def test_service_copies_the_drivers_environment_when_it_merges_no_anchor(
        capsys: pytest.CaptureFixture[str], demo: Path) -> None:
    from panther_ops.core.robot.compose import ComposeFile

    path = demo / ROBOT_ROOT.format("panther-02") / "compose.yaml"
    flat = path.read_text().replace("    <<: *common-config\n", "    network_mode: host\n    environment:\n"
                                    "      - RMW_IMPLEMENTATION=rmw_cyclonedds_cpp\n      - ROS_DOMAIN_ID=7\n", 1)
    assert flat != path.read_text()
    path.write_text(flat)
    code, doc, _ = run(capsys, demo, "gps", "enable", "-r", "panther-02", "--yes", "--json")
    assert code == 0, doc
    written = ComposeFile.parse(path.read_text())
    assert written.merged_anchor("nmea-gps") is None
    assert written.environment("nmea-gps") == {"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp", "ROS_DOMAIN_ID": "7"}
