"""Custom wheels the manual's way, and a wheel or controller file for the other kind of wheels
(issue 24, finding 9).

The manual (Changing Wheel Type): "If you want to use custom wheels, all you need to do is point
to the new wheel and controller configuration files using the wheel_config_path and
controller_config_path parameters. These files should be based on the default files, i.e.
WH01_controller.yaml and WH01.yaml." At every release (panther_ros@2.0.4/2.1.1:
panther_controller/launch/controller.launch.py, husarion_ugv_ros@2.2.0/2.2.2:
husarion_ugv_controller/launch/controller.launch.py) ``wheel_type:=custom`` only makes the
default paths ``custom.yaml``/``custom_controller.yaml``, which no image has: both paths must be
given. The files start from the project's templates of WH01 (semantically upstream's, see
docs/conformance.md).
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import pytest
from ruamel.yaml import YAML

from panther_ops.cli.app import main
from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file
from panther_ops.core.robot.files import config_file
from panther_ops.core.stack import stack_from_version

RELEASES = ("2.0.4", "2.1.1", "2.2.0", "2.2.2")
DEMO = {"panther-02": "2.0.4", "panther-01": "2.1.1", "panther-03": "2.2.2"}


def custom_wheel(version: str) -> bytes:
    """WH01.yaml of the release with a custom radius and width (and separation where it has one)."""
    text = config_file(stack_from_version(version), FileKind.WHEEL, wheel_type="WH01").template_text()
    text = re.sub(r"(?m)^wheel_radius: .*$", "wheel_radius: 0.2", text)
    text = re.sub(r"(?m)^wheel_width: .*$", "wheel_width: 0.16", text)
    return re.sub(r"(?m)^wheel_separation: .*$", "wheel_separation: 0.75", text).encode()


def custom_controller(version: str, max_velocity: str = "2.5") -> bytes:
    """WH01_controller.yaml of the release for wheels of 0.2 m on a 0.75 m track, faster than WH01's 2.0 m/s."""
    text = config_file(stack_from_version(version), FileKind.CONTROLLER, wheel_type="WH01").template_text()
    text = re.sub(r"(?m)^(\s+wheel_radius): 0\.1825", r"\1: 0.2", text)
    text = re.sub(r"(?m)^(\s+wheel_separation): 0\.697", r"\1: 0.75", text)
    text, count = re.subn(r"(?m)^(\s+max_velocity): 2\.0\b", rf"\1: {max_velocity}", text)
    assert count == 1
    return text.encode()


def dump(data: object) -> bytes:
    out = io.StringIO()
    YAML().dump(data, out)
    return out.getvalue().encode()


def stock(version: str, kind: FileKind, wheel: str) -> bytes:
    return config_file(stack_from_version(version), kind, wheel_type=wheel).template_text().encode()


@pytest.mark.parametrize("version", RELEASES)
@pytest.mark.parametrize("robot_wheel", ["WH01", "WH02", "WH04", "custom"])
def test_custom_wheel_files_are_accepted_without_force(version: str, robot_wheel: str) -> None:
    target = Target(stack_from_version(version), robot_wheel, "")
    check_file(FileKind.WHEEL, "my_wheel.yaml", custom_wheel(version), target=target)
    warnings = check_file(FileKind.CONTROLLER, "my_controller.yaml", custom_controller(version), target=target)
    assert any("custom wheels" in w and "wheel_radius=0.2" in w for w in warnings), warnings


@pytest.mark.parametrize("version", RELEASES)
def test_what_the_robot_rejects_is_still_refused_in_a_custom_file(version: str) -> None:
    target = Target(stack_from_version(version), "custom", "")
    with pytest.raises(FileKindError, match=r"max_velocity=3 is an integer"):  # ROS refuses an int for a double
        check_file(FileKind.CONTROLLER, "c.yaml", custom_controller(version, "3"), target=target)
    wheel = YAML(typ="safe").load(custom_wheel(version))
    wheel.pop("wheel_width")  # the URDF reads it
    with pytest.raises(FileKindError, match="wheel_width is required"):
        check_file(FileKind.WHEEL, "w.yaml", dump(wheel), target=target)


@pytest.mark.parametrize("version", RELEASES)
def test_a_stock_wheels_file_keeps_that_wheels_limits(version: str) -> None:
    """WH01's own kinematics with 2.5 m/s: the WH01 limit (2.0 m/s) holds, whatever the robot's type."""
    text = stock(version, FileKind.CONTROLLER, "WH01").decode()
    text = re.sub(r"(?m)^(\s+max_velocity): 2\.0\b", r"\1: 2.5", text, count=1)
    for robot in ("WH01", "WH02", "custom"):
        with pytest.raises(FileKindError, match=r"exceeds the WH01 limit of 2\.0"):
            check_file(FileKind.CONTROLLER, "c.yaml", text.encode(), target=Target(stack_from_version(version),
                                                                                   robot, ""))


@pytest.mark.parametrize("version", RELEASES)
@pytest.mark.parametrize(("robot", "kind", "file_wheel"), [
    ("WH02", FileKind.WHEEL, "WH01"), ("WH02", FileKind.CONTROLLER, "WH01"),
    ("WH01", FileKind.WHEEL, "WH02"), ("WH04", FileKind.CONTROLLER, "WH02"),
])
def test_a_file_for_the_other_kind_of_wheels_is_warned_with_the_fix(version: str, robot: str, kind: FileKind,
                                                                    file_wheel: str) -> None:
    warnings = check_file(kind, "f.yaml", stock(version, kind, file_wheel),
                          target=Target(stack_from_version(version), robot, ""))
    (warning,) = [w for w in warnings if "mecanum" in w]
    base = f"{robot}.yaml" if kind is FileKind.WHEEL else f"{robot}_controller.yaml"
    assert f"wheel_type {robot} is" in warning and base in warning, warning
    assert f"config set wheel_type {file_wheel}" in warning, warning


@pytest.mark.parametrize("version", RELEASES)
def test_a_custom_file_for_the_other_kind_of_wheels_is_warned(version: str) -> None:
    warnings = check_file(FileKind.CONTROLLER, "c.yaml", custom_controller(version),
                          target=Target(stack_from_version(version), "WH02", ""))
    assert any("non-mecanum wheels (custom)" in w and "config set wheel_type custom" in w for w in warnings)


@pytest.mark.parametrize("version", RELEASES)
def test_the_same_kind_of_wheels_is_not_warned(version: str) -> None:
    for robot, wheel in (("WH02", "WH02"), ("WH01", "WH01"), ("WH04", "WH01"), ("custom", "WH02")):
        for kind in (FileKind.WHEEL, FileKind.CONTROLLER):
            warnings = check_file(kind, "f.yaml", stock(version, kind, wheel),
                                  target=Target(stack_from_version(version), robot, ""))
            assert not [w for w in warnings if "mecanum" in w], (robot, wheel, warnings)


@pytest.fixture()
def demo(tmp_path: Path) -> Path:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str]:
    capsys.readouterr()
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out + err


@pytest.mark.parametrize("robot", sorted(DEMO))
@pytest.mark.parametrize("start", ["WH01", "WH02"])
def test_the_manuals_procedure_needs_no_force(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                              robot: str, start: str) -> None:
    version = DEMO[robot]
    inv = ["-i", str(demo)]
    code, out = run(capsys, *inv, "config", "set", "wheel_type", start, "-r", robot, "--yes")
    assert code == 0, out
    (tmp_path / "my_wheel.yaml").write_bytes(custom_wheel(version))
    (tmp_path / "my_controller.yaml").write_bytes(custom_controller(version))
    for name, kind in (("my_wheel.yaml", "wheel"), ("my_controller.yaml", "controller")):
        code, out = run(capsys, *inv, "config", "push", str(tmp_path / name), "--as", kind, "-r", robot, "--yes")
        assert code == 0, out
    code, out = run(capsys, *inv, "config", "set", "wheel_type", "custom", "-r", robot, "--yes")
    assert code == 0, out
    compose = (demo / "robots" / robot / "home/husarion/compose.yaml").read_text()
    assert "wheel_type:=custom" in compose
    pkg = "husarion_ugv" if version.startswith("2.2") else "panther"
    assert f"wheel_config_path:=/config/{pkg}_description/config/my_wheel.yaml" in compose
    assert f"controller_config_path:=/config/{pkg}_controller/config/my_controller.yaml" in compose
    tree = demo / "robots" / robot / "home/husarion/config"
    assert (tree / f"{pkg}_controller/config/my_controller.yaml").read_bytes() == custom_controller(version)
    stock_file = tree / f"{pkg}_controller/config/WH01_controller.yaml"
    assert not stock_file.exists() or b"wheel_radius: 0.2" not in stock_file.read_bytes()  # the stock name keeps WH01
