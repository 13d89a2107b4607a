"""A wheel change (or any change of a file argument) leaves no mount of the old file that nothing
reads any more (issue 24, finding 9: "the stale wheel mount stays in compose after a wheel change").
On the demo fleet (panther-01: panther_ros 2.1.1, panther-02: 2.0.4; both mount pushed files)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from tests.config.test_custom_wheels import custom_controller, custom_wheel

ROBOTS = {"panther-01": "2.1.1", "panther-02": "2.0.4"}
CTRL = "/config/panther_controller/config"
WHEEL = "/config/panther_description/config"


@pytest.fixture()
def demo(tmp_path: Path) -> Path:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"


def cli(capsys: pytest.CaptureFixture[str], demo: Path, *args: str) -> str:
    capsys.readouterr()
    code = main(["-i", str(demo), *args, "--yes"])
    out, err = capsys.readouterr()
    assert code == 0, out + err
    return out + err


def compose(demo: Path, robot: str) -> str:
    return (demo / "robots" / robot / "home/husarion/compose.yaml").read_text()


def mounts(text: str) -> list[str]:
    return re.findall(r"(?m)^\s+- (/home/husarion/config/\S+)$", text)


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_a_wheel_change_unmounts_the_migrated_controller_file(demo: Path, capsys: pytest.CaptureFixture[str],
                                                             robot: str) -> None:
    cli(capsys, demo, "config", "set", "controller.linear.x.max_velocity", "0.8", "-r", robot)
    assert mounts(compose(demo, robot)) == [
        f"/home/husarion/config/panther_controller/config/WH01_controller.yaml:{CTRL}/WH01_controller.yaml:ro"]
    out = cli(capsys, demo, "config", "set", "wheel_type", "WH02", "-r", robot)
    after = compose(demo, robot)
    assert "WH01_controller.yaml" not in after  # neither the argument nor the mount
    assert mounts(after) == [
        f"/home/husarion/config/panther_controller/config/WH02_controller.yaml:{CTRL}/WH02_controller.yaml:ro"]
    assert "unmounted /home/husarion/config/panther_controller/config/WH01_controller.yaml" in out
    assert (demo / "robots" / robot / "home/husarion/config/panther_controller/config/WH01_controller.yaml").is_file()


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_custom_wheels_back_to_a_stock_wheel_leave_no_mount(demo: Path, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str], robot: str) -> None:
    """The manual's custom wheels, then back to WH02: the refusal's own fix (unset the wheel file)
    and the wheel change leave only the migrated controller mounted."""
    (tmp_path / "my_wheel.yaml").write_bytes(custom_wheel(ROBOTS[robot]))
    (tmp_path / "my_controller.yaml").write_bytes(custom_controller(ROBOTS[robot]))
    cli(capsys, demo, "config", "push", str(tmp_path / "my_wheel.yaml"), "--as", "wheel", "-r", robot)
    cli(capsys, demo, "config", "push", str(tmp_path / "my_controller.yaml"), "--as", "controller", "-r", robot)
    cli(capsys, demo, "config", "set", "wheel_type", "custom", "-r", robot)
    assert len(mounts(compose(demo, robot))) == 2
    cli(capsys, demo, "config", "unset", "wheel_config_path", "-r", robot)
    assert "my_wheel.yaml" not in compose(demo, robot)
    cli(capsys, demo, "config", "set", "wheel_type", "WH02", "-r", robot)
    after = compose(demo, robot)
    assert "my_controller.yaml" not in after and "my_wheel.yaml" not in after
    assert mounts(after) == [
        f"/home/husarion/config/panther_controller/config/WH02_controller.yaml:{CTRL}/WH02_controller.yaml:ro"]


def test_a_wheel_file_pushed_under_another_name_replaces_the_old_mount(demo: Path, tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    for name in ("wheels_a.yaml", "wheels_b.yaml"):
        (tmp_path / name).write_bytes(custom_wheel("2.1.1"))
        cli(capsys, demo, "config", "push", str(tmp_path / name), "--as", "wheel", "-r", "panther-01")
    assert mounts(compose(demo, "panther-01")) == [
        f"/home/husarion/config/panther_description/config/wheels_b.yaml:{WHEEL}/wheels_b.yaml:ro"]


def test_a_mount_something_else_mentions_stays(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Another service mounts the same file: panther-ops cannot show it unused, so it stays."""
    robot = "panther-01"
    cli(capsys, demo, "config", "set", "controller.linear.x.max_velocity", "0.8", "-r", robot)
    path = demo / "robots" / robot / "home/husarion/compose.yaml"
    host = "/home/husarion/config/panther_controller/config/WH01_controller.yaml"
    text = path.read_text().replace("    stop_signal: SIGINT\n",
                                    f"    stop_signal: SIGINT\n    volumes:\n      - {host}:/extra/WH01.yaml:ro\n", 1)
    assert "/extra/WH01.yaml" in text
    path.write_text(text)
    cli(capsys, demo, "config", "set", "wheel_type", "WH02", "-r", robot)
    assert f"{host}:{CTRL}/WH01_controller.yaml:ro" in compose(demo, robot)
