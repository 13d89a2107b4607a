"""Config file templates and the per-version catalogue of config files."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from panther_ops.core.fleet.templates import TemplateNotFound, read_template, template_file
from panther_ops.core.kinds import FileKind
from panther_ops.core.robot.files import config_file, config_files
from panther_ops.core.stack import stack_from_version
from panther_ops.core.yaml.document import YamlDocument
from panther_ops.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "templates" / "config"
TREE = ROOT / "templates" / "config-tree" / "husarion-ugv-2.2"
ALL_YAML = sorted(CONFIG.rglob("*.yaml"))
VERSIONS = ("2.0.0", "2.0.4", "2.1.0", "2.1.1", "2.1.2", "2.2.0", "2.2.1", "2.2.2")


@pytest.mark.parametrize("path", ALL_YAML, ids=[str(p.relative_to(CONFIG)) for p in ALL_YAML])
def test_every_template_parses_with_both_parsers(path: Path) -> None:
    text = path.read_text()
    assert text.endswith("\n") and "\t" not in text
    assert _comparable(YamlDocument(text, str(path)).to_plain()) == _comparable(yaml.safe_load(text))


def _comparable(value: object) -> object:
    """``value`` with every NaN (Jazzy's ``.NAN`` limits: NaN != NaN) as one marker."""
    if isinstance(value, dict):
        return {k: _comparable(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_comparable(v) for v in value]
    return "<nan>" if isinstance(value, float) and math.isnan(value) else value


def test_config_tree_files_are_copies_of_the_templates() -> None:
    files = [p for p in TREE.rglob("*") if p.is_file()]
    assert {p.relative_to(TREE).parts[0] for p in files} >= {
        "common", "husarion_ugv_controller", "husarion_ugv_lights", "husarion_ugv_manager", "husarion_ugv_description"}
    for path in files:
        rel = path.relative_to(TREE)
        if rel.parts[0] == "common":
            continue
        assert path.read_text() == (CONFIG / "husarion-ugv-2.2" / rel).read_text(), rel
    env = (TREE / "common" / ".env").read_text()
    assert "RMW_IMPLEMENTATION=rmw_cyclonedds_cpp" in env


@pytest.mark.parametrize("version", VERSIONS)
def test_every_listed_file_of_a_version_resolves(version: str) -> None:
    stack = stack_from_version(version)
    files = config_files(stack)
    kinds = {f.kind for f in files}
    assert {FileKind.WHEEL, FileKind.CONTROLLER, FileKind.SHUTDOWN_HOSTS, FileKind.LED} <= kinds
    for f in files:
        if f.template is not None:
            assert yaml.safe_load(f.template_text()) is not None or f.kind is FileKind.COMPONENTS


@pytest.mark.parametrize(
    ("version", "package", "filename", "marker"),
    [
        ("2.0.4", "panther_bringup", "shutdown_hosts.yaml", "username"),
        ("2.1.0", "panther_bringup", "shutdown_hosts.yaml", "username"),
        ("2.1.1", "panther_manager", "shutdown_hosts_config.yaml", "username"),
        ("2.2.0", "husarion_ugv_manager", "shutdown_hosts.yaml", "timeout"),
        ("2.2.1", "husarion_ugv_manager", "shutdown_hosts.yaml", "port: 3003"),
    ],
)
def test_shutdown_hosts_file_per_version(version: str, package: str, filename: str, marker: str) -> None:
    f = config_file(stack_from_version(version), FileKind.SHUTDOWN_HOSTS)
    assert (f.package, f.filename, f.launch_arg) == (package, filename, "shutdown_hosts_config_path")
    text = f.template_text()
    assert marker in text
    hosts = yaml.safe_load(text)["hosts"]
    assert hosts[0]["ip"] == "10.15.20.3"
    assert ("username" in hosts[0]) is (version != "2.2.1")


def test_family_specific_shapes() -> None:
    s20, s21, s22 = (stack_from_version(v) for v in ("2.0.4", "2.1.1", "2.2.2"))
    wh20 = yaml.safe_load(config_file(s20, FileKind.WHEEL, wheel_type="WH02").template_text())
    wh21 = yaml.safe_load(config_file(s21, FileKind.WHEEL, wheel_type="WH02").template_text())
    wh22 = yaml.safe_load(config_file(s22, FileKind.WHEEL, wheel_type="WH01").template_text())
    assert "mecanum" not in wh20 and wh21["mecanum"] is True
    assert "wheel_separation" not in wh22 and wh22["mount_point_offset"] == 0.091
    assert yaml.safe_load(config_file(s22, FileKind.WHEEL, wheel_type="WH05").template_text())["wheel_radius"] == 0.1348
    bat20 = yaml.safe_load(config_file(s20, FileKind.BATTERY).template_text())
    bat21 = yaml.safe_load(config_file(s21, FileKind.BATTERY).template_text())
    # panther_ros 2.0.1+ reads a 0-1 fraction and capacity (panther_ros@2.0.4:panther_gazebo/config/
    # battery_plugin_config.yaml); 2.0.0's percent file has no template (issue 24 finding 8)
    assert bat20["initial_charge_percentage"] == 0.7 and bat20["capacity"] == 20.0
    assert config_file(stack_from_version("2.0.0"), FileKind.BATTERY).template is None
    assert bat21["initial_charge_percentage"] == 0.7 and bat21["capacity"] == 20.0
    led = yaml.safe_load(config_file(s21, FileKind.LED).template_text())
    assert [a["id"] for a in led["led_animations"]] == [0, 1, 2, 3, 4, 5, 6, 7, 9]
    anim22 = config_file(s22, FileKind.LED)
    assert anim22.filename == "panther_animations.yaml" and "husarion_ugv_lights::" in anim22.template_text()
    driver = yaml.safe_load(config_file(s22, FileKind.LIGHTS_DRIVER).template_text())
    assert driver["channel_1_num_led"] == 46  # flat: the driver is a ComposableNode (no ros__parameters)
    assert yaml.safe_load(config_file(s22, FileKind.USER_ANIMATIONS).template_text())["user_animations"] == []
    mgr = yaml.safe_load(config_file(s21, FileKind.SAFETY_MANAGER).template_text())
    assert mgr["/**"]["safety_manager"]["ros__parameters"]["cpu"]["temp"]["fan_on"] == 75.0
    assert config_file(s20, FileKind.LIGHTS_MANAGER).filename == "lights_manager_config.yaml"
    assert config_file(stack_from_version("2.0.0"), FileKind.MANAGER_BT).template is not None


def test_paths_of_a_customised_copy() -> None:
    f = config_file(stack_from_version("2.1.1"), FileKind.CONTROLLER, wheel_type="WH02")
    assert f.package_path == "$(find panther_controller)/config/WH02_controller.yaml"
    assert f.robot_path == "/home/husarion/config/panther_controller/config/WH02_controller.yaml"
    assert f.container_path == "/config/panther_controller/config/WH02_controller.yaml"


def test_files_a_stack_does_not_have() -> None:
    s20, s22 = stack_from_version("2.0.0"), stack_from_version("2.2.2")
    for kind in (FileKind.COMPONENTS, FileKind.LIGHTS_DRIVER, FileKind.LIGHTS_MANAGER):
        with pytest.raises(UsageError):
            config_file(s20, kind)
    with pytest.raises(UsageError):
        config_file(s20, FileKind.WHEEL, wheel_type="WH05")
    for old in ("2.1.1", "2.2.0"):  # bringup reads the gamepad's file from 2.2.2 (launch_gamepad)
        with pytest.raises(UsageError):
            config_file(stack_from_version(old), FileKind.JOY2TWIST)
    missing = config_file(s22, FileKind.LIGHTS_DRIVER, robot_model="lynx")  # lynx_driver.yaml: no template
    assert missing.template is None
    with pytest.raises(UsageError, match="no default"):
        missing.template_text()


def test_template_helpers() -> None:
    assert read_template("compose", "panther-2.1.1.yaml").startswith("# Panther ROS 2")
    with pytest.raises(TemplateNotFound):
        template_file("config", "nope.yaml")
