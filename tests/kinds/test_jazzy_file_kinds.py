"""husarion_ugv 2.3's file kinds and templates, per release (2.3.0, 2.3.1, 2.3.2): which template
directory and package each file comes from, and the rules that changed (joy2twist stamped and
on the twist mux, components' name, 2.3.2's animation images). Facts: docs/jazzy.md."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file
from panther_ops.core.robot.files import config_file, family_dirs
from panther_ops.core.stack import Stack, stack_from_version
from panther_ops.errors import UsageError


def jazzy(version: str) -> Stack:
    """The stack a husarion_ugv 2.3 image tag gives (core/stack.py does not accept it yet)."""
    return Stack(f"husarion/husarion-ugv:jazzy-{version}-20250701", "jazzy",
                 tuple(int(p) for p in version.split(".")), "20250701")  # type: ignore[arg-type]


S230, S231, S232 = (jazzy(v) for v in ("2.3.0", "2.3.1", "2.3.2"))
S222 = stack_from_version("2.2.2")


def test_template_directories_per_release() -> None:
    assert family_dirs(S230) == ("husarion-ugv-2.3", "husarion-ugv-2.2")
    assert family_dirs(S231) == ("husarion-ugv-2.3.1", "husarion-ugv-2.3", "husarion-ugv-2.2")
    assert family_dirs(S232) == ("husarion-ugv-2.3.2", "husarion-ugv-2.3", "husarion-ugv-2.2")
    assert family_dirs(S222) == ("husarion-ugv-2.2",)
    assert config_file(S230, FileKind.CONTROLLER).template == \
        "husarion-ugv-2.3/husarion_ugv_controller/config/WH01_controller.yaml"
    assert config_file(S232, FileKind.LED).template == \
        "husarion-ugv-2.3.2/husarion_ugv_lights/config/panther_animations.yaml"
    assert config_file(S231, FileKind.WHEEL).template == "husarion-ugv-2.2/husarion_ugv_description/config/WH01.yaml"


def test_joy2twist_moves_with_the_release() -> None:
    with pytest.raises(UsageError, match=r"2\.3\.0"):
        config_file(S230, FileKind.JOY2TWIST)
    assert config_file(S231, FileKind.JOY2TWIST).template == \
        "husarion-ugv-2.3.1/husarion_ugv_bringup/config/joy2twist_panther.yaml"
    teleop = config_file(S232, FileKind.JOY2TWIST, robot_model="lynx")
    assert teleop.package == "husarion_ugv_teleop"
    assert teleop.template == "husarion-ugv-2.3.2/husarion_ugv_teleop/config/joy2twist_lynx.yaml"


def joy(extra: str) -> bytes:
    return f"/**:\n  ros__parameters:\n{extra}    linear_velocity_factor: {{fast: 1.0}}\n".encode()


def test_joy2twist_rules_per_release() -> None:
    stock_232 = config_file(S232, FileKind.JOY2TWIST).template_text().encode()
    assert check_file(FileKind.JOY2TWIST, "j", stock_232, target=Target(S232)) == []
    unstamped = joy("    cmd_vel_stamped: false\n")
    assert check_file(FileKind.JOY2TWIST, "j", unstamped, target=Target(S222)) == []
    with pytest.raises(FileKindError, match="takes only TwistStamped"):
        check_file(FileKind.JOY2TWIST, "j", unstamped, target=Target(S231))
    with pytest.raises(FileKindError, match="not an input of"):
        check_file(FileKind.JOY2TWIST, "j", joy("    cmd_vel_stamped: true\n    cmd_vel_topic: teleop/cmd_vel\n"),
                   target=Target(S232))
    low = check_file(FileKind.JOY2TWIST, "j", joy("    cmd_vel_stamped: true\n"), target=Target(S232))
    assert len(low) == 1 and "lower priority" in low[0]
    assert check_file(FileKind.JOY2TWIST, "j", joy("    cmd_vel_stamped: true\n"), target=Target(S231)) == []


def test_components_name_is_2_3_2s_key() -> None:
    data = b"components:\n  - {type: LDR06, parent_link: cover_link, device_namespace: lidar}\n"
    assert check_file(FileKind.COMPONENTS, "c", data, target=Target(S231)) == []
    (warning,) = check_file(FileKind.COMPONENTS, "c", data, target=Target(S232))
    assert "write name: lidar" in warning


def test_2_3_2_animations_need_2_3_2s_images() -> None:
    stock = config_file(S232, FileKind.LED).template_text().encode()
    assert check_file(FileKind.LED, "a", stock, target=Target(S232)) == []
    with pytest.raises(FileKindError, match=r"flood_light|goal_failed"):
        check_file(FileKind.LED, "a", stock, target=Target(S231))


def test_manager_deploys_2_3_2s_stock_projects(tmp_path: Path) -> None:
    """`manager deploy` on 2.3.2: 2.3.2's Lights project and safety.xml over 2.2's SafetyBT.btproj and
    shutdown.xml (core/manager_ops/projects.py), and the manager validates what it deploys."""
    from panther_ops.core.manager_ops.projects import deployed_projects
    from panther_ops.manager.bt.validate import validate_bt_project

    projects = deployed_projects(S232)
    origin = {name: path.parent.parent.parent.name for name, (path, _) in projects.files.items()}
    assert origin == {"LightsBT.btproj": "husarion-ugv-2.3.2", "lights.xml": "husarion-ugv-2.3.2",
                      "safety.xml": "husarion-ugv-2.3.2", "SafetyBT.btproj": "husarion-ugv-2.2",
                      "shutdown.xml": "husarion-ugv-2.2"}
    out = tmp_path
    for name, (path, _) in projects.files.items():
        (out / name).write_bytes(path.read_bytes())
    assert validate_bt_project(out / projects.lights) == []
    assert validate_bt_project(out / projects.safety) == []
    assert "CheckStringMsg" in (out / "lights.xml").read_text()
