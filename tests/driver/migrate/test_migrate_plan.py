"""`driver update <2.3 tag>` on a husarion_ugv 2.2 robot of the demo fleet (local robot roots,
the real pipeline; a demo robot has no docker engine, so nothing is recreated): one plan with
every tree file translated, the operator's customisations kept in their 2.3 form, files whose
schema did not change byte-identical, a second run changes nothing, a refusal exits 2 naming
file and key with nothing written, and `driver update <2.2 tag>` restores the migration's backup."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from ruamel.yaml import YAML

from tests.clirun import run_cli

JAZZY = "jazzy-2.3.2-20260622"
HUMBLE = "humble-2.2.2-20250702"
ROBOT = "panther-03"


def home(demo: Path) -> Path:
    return demo / "robots" / ROBOT / "home" / "husarion"


def tree_files(demo: Path) -> dict[str, bytes]:
    root = home(demo)
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and ".panther-ops" not in p.parts}


def customise(demo: Path) -> None:
    """An operator's 2.2 robot: slower limits with gentle braking, a faster gamepad, a named lidar,
    a user animation, a second shutdown host."""
    cfg = home(demo) / "config"
    ctrl = cfg / "husarion_ugv_controller/config/WH01_controller.yaml"
    ctrl.write_text(ctrl.read_text().replace("max_velocity: 2.0 # m/s", "max_velocity: 1.2 # m/s (site rule)")
                    .replace("max_acceleration: 2.7 # m/s^2",
                             "max_acceleration: 1.0 # m/s^2\n          min_acceleration: -0.6"))
    joy = cfg / "husarion_ugv_bringup/config/joy2twist_panther.yaml"
    joy.write_text(joy.read_text().replace("fast: 2.0", "fast: 1.5"))
    comp = cfg / "husarion_ugv_description/config/components.yaml"
    comp.write_text("components:\n  - type: LDR06 # front lidar\n    parent_link: cover_link\n"
                    "    xyz: 0.2 0.0 0.0\n    rpy: 0.0 0.0 0.0\n    device_namespace: front_lidar\n")
    user = cfg / "husarion_ugv_lights/config/user_animations.yaml"
    user.write_text(user.read_text() + "\n# operator's note: keep\n")
    hosts = cfg / "husarion_ugv_manager/config/shutdown_hosts.yaml"
    hosts.write_text(hosts.read_text() + "  - ip: 10.15.20.4 # second computer\n")


def load(path: Path) -> object:
    return YAML(typ="safe", pure=True).load(path.read_text())


def test_migration_translates_keeps_and_goes_back(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    customise(demo)
    before = tree_files(demo)
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes",
                              "--canary", "1", "--json")
    assert code == 0, doc
    (r,) = doc["robots"]
    assert r["outcome"] == "changed" and r["data"]["backup"]
    assert r["data"]["stack_to"] == "husarion_ugv 2.3.2"
    migration = r["data"]["migration"]
    after = tree_files(demo)
    assert f"image: husarion/husarion-ugv:{JAZZY}" in after["compose.yaml"].decode()
    # controller: the operator's values in the Jazzy schema
    ctrl = load(home(demo) / "config/husarion_ugv_controller/config/WH01_controller.yaml")
    x = ctrl["/**"]["drive_controller"]["ros__parameters"]["linear"]["x"]  # type: ignore[index]
    assert (x["max_velocity"], x["min_velocity"], x["max_acceleration"], x["max_deceleration"],
            x["max_acceleration_reverse"], x["max_deceleration_reverse"]) == (1.2, -1.2, 1.0, -0.6, -0.6, 1.0)
    assert math.isnan(x["max_jerk"]) and "has_velocity_limits" not in x
    assert b"# m/s (site rule)" in after["config/husarion_ugv_controller/config/WH01_controller.yaml"]
    # joy2twist moved to husarion_ugv_teleop, re-pointed, its factor kept
    assert "config/husarion_ugv_bringup/config/joy2twist_panther.yaml" not in after
    joy = load(home(demo) / "config/husarion_ugv_teleop/config/joy2twist_panther.yaml")
    params = joy["/**"]["ros__parameters"]  # type: ignore[index]
    assert params["cmd_vel_topic"] == "manual/cmd_vel" and params["cmd_vel_stamped"] is True
    assert params["linear_velocity_factor"]["fast"] == 1.5
    # components: device_namespace -> name
    comp = load(home(demo) / "config/husarion_ugv_description/config/components.yaml")
    assert comp == {"components": [{"type": "LDR06", "parent_link": "cover_link", "xyz": "0.2 0.0 0.0",
                                    "rpy": "0.0 0.0 0.0", "name": "front_lidar"}]}
    # files whose schema did not change: byte-identical, and named as kept
    for rel in ("config/husarion_ugv_lights/config/user_animations.yaml",
                "config/husarion_ugv_manager/config/shutdown_hosts.yaml",
                "config/husarion_ugv_lights/config/panther_animations.yaml",
                "config/husarion_ugv_manager/behavior_trees/LightsBT.btproj"):
        assert after[rel] == before[rel]
        assert "/home/husarion/" + rel in migration["kept"]
    assert migration["removed"] == ["/home/husarion/config/husarion_ugv_bringup/config/joy2twist_panther.yaml"]

    # a second run changes nothing
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"
    assert tree_files(demo) == after

    # the way back: the migration's backup, byte for byte
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", HUMBLE, "-r", ROBOT, "--yes", "--json")
    assert code == 0, doc
    assert doc["robots"][0]["data"]["backup_restored"] == r["data"]["backup"]
    assert tree_files(demo) == before
    assert not (home(demo) / "config/husarion_ugv_teleop").exists()  # the migration made it: gone with it


def test_refusal_exits_2_naming_file_and_key_and_writes_nothing(demo: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    comp = home(demo) / "config/husarion_ugv_description/config/components.yaml"
    comp.write_text("components:\n  - type: CAM01\n    name: camera\n    device_namespace: front_cam\n")
    before = tree_files(demo)
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes")
    assert code == 2
    assert "components.yaml:3 [components[0].name]" in err and "nothing was changed" in err
    assert tree_files(demo) == before


def test_way_back_without_a_migration_backup_is_refused(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    compose = home(demo) / "compose.yaml"
    compose.write_text(compose.read_text().replace(HUMBLE, JAZZY))
    before = tree_files(demo)
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", HUMBLE, "-r", ROBOT, "--yes")
    assert code == 2 and "no backup of a migration" in err
    assert tree_files(demo) == before


def test_migration_to_2_3_0_is_refused_naming_the_supported_ones(demo: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", "jazzy-2.3.0-20250425", "-r", ROBOT,
                              "--yes")
    assert code == 2 and "2.3.1 and 2.3.2" in err


def test_a_stack_pin_does_not_make_a_2_3_robot_migrate_again(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The inventory pins stack: 2.2.2; the robot already runs 2.3.2: moving it to 2.3.1 is no
    migration from 2.2 (the image tells the files' schema): the way back to 2.3.1, which has no
    backup here (the robot came from 2.2.2), is refused; the pin is named."""
    code, _, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes")
    assert code == 0
    inv = demo / "inventory.yaml"
    text = inv.read_text()
    assert "  panther-03:\n" in text
    inv.write_text(text.replace("  panther-03:\n", "  panther-03:\n    stack: 2.2.2\n", 1))
    before = tree_files(demo)
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", "jazzy-2.3.1-20250701", "-r", ROBOT,
                              "--dry-run")
    assert code == 2 and "no backup of a migration from 2.3.1" in err and "pins stack: 2.2.2" not in err
    assert tree_files(demo) == before


def test_files_named_by_launch_arguments_are_translated_too(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A customised EKF file mounted and named by localization_config_path: translated with the tree."""
    (home(demo) / "my_ekf.yaml").write_text("/**:\n  ekf_filter:\n    ros__parameters:\n      use_control: true\n"
                                           "      control_timeout: 0.5\n")
    compose = home(demo) / "compose.yaml"
    text = compose.read_text()
    compose.write_text(text.replace("      - /home/husarion/config:/config\n",
                                    "      - /home/husarion/config:/config\n"
                                    "      - /home/husarion/my_ekf.yaml:/ekf/my_ekf.yaml\n")
                       .replace("launch_gamepad:=true", "launch_gamepad:=true localization_config_path:=/ekf/my_ekf.yaml"))
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes", "--json")
    assert code == 0, doc
    assert "/home/husarion/my_ekf.yaml" in doc["robots"][0]["data"]["migration"]["translated"]
    assert load(home(demo) / "my_ekf.yaml") == {"/**": {"ekf_filter": {"ros__parameters": {
        "use_control": True, "stamped_control": True, "control_timeout": 0.2}}}}


def test_2_3_1_to_2_3_2_is_translated_and_goes_back(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """2.2.2 -> 2.3.1 -> 2.3.2 -> 2.3.1 -> 2.2.2: 2.3.1 -> 2.3.2 runs the same translators (joy2twist moved to
    husarion_ugv_teleop on manual/cmd_vel, the twist mux section, the IMU placeholder, components' name); each way
    back restores its migration's backup byte for byte, the teleop directory gone with it."""
    customise(demo)
    original = tree_files(demo)

    def update(tag: str) -> dict[str, object]:
        code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", tag, "-r", ROBOT, "--yes", "--json")
        assert code == 0, doc
        (r,) = doc["robots"]
        return r  # type: ignore[no-any-return]

    first = update("jazzy-2.3.1-20250701")
    on_231 = tree_files(demo)
    bringup = "config/husarion_ugv_bringup/config/joy2twist_panther.yaml"
    assert b"cmd_vel_stamped: true" in on_231[bringup] and b"manual/cmd_vel" not in on_231[bringup]
    second = update(JAZZY)
    assert second["data"]["migration"]["from"] == "2.3.1"  # type: ignore[index]
    on_232 = tree_files(demo)
    assert bringup not in on_232
    joy = load(home(demo) / "config/husarion_ugv_teleop/config/joy2twist_panther.yaml")
    params = joy["/**"]["ros__parameters"]  # type: ignore[index]
    assert params["cmd_vel_topic"] == "manual/cmd_vel" and params["linear_velocity_factor"]["fast"] == 1.5
    ctrl = load(home(demo) / "config/husarion_ugv_controller/config/WH01_controller.yaml")
    assert "twist_mux_controller" in ctrl["/**"]  # type: ignore[operator,index]
    assert ctrl["/**"]["drive_controller"]["ros__parameters"]["linear"]["x"]["max_velocity"] == 1.2  # type: ignore[index]
    assert update(JAZZY)["outcome"] == "ok"  # a second run changes nothing
    back = update("jazzy-2.3.1-20250701")
    assert back["data"]["backup_restored"] == second["data"]["backup"]
    assert tree_files(demo) == on_231 and not (home(demo) / "config/husarion_ugv_teleop").exists()
    assert update(HUMBLE)["data"]["backup_restored"] == first["data"]["backup"]
    assert tree_files(demo) == original


def test_a_translation_the_2_3_validator_refuses_is_a_refusal_naming_file_key_and_fix(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The translated controller goes through the 2.3.2 controller check (the one `config push` uses): a limit
    beyond 2.3.2's bound for WH01 is carried over by the translator, and refused by the check."""
    ctrl = home(demo) / "config/husarion_ugv_controller/config/WH01_controller.yaml"
    ctrl.write_text(ctrl.read_text().replace("max_velocity: 2.0 # m/s", "max_velocity: 9.0 # m/s"))
    before = tree_files(demo)
    code, _, _, err = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes")
    assert code == 2, err
    assert "WH01_controller.yaml" in err and "refused by the controller check" in err
    assert "linear.x.max_velocity" in err and "nothing was changed" in err
    assert tree_files(demo) == before


def test_a_stock_lights_tree_becomes_2_3_2s_and_a_customised_one_is_named_for_review(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from panther_ops.core.driver.migrate.lights_tree import same_tree
    from panther_ops.core.driver.migrate.stock import stock_text

    rel = "husarion_ugv_manager/behavior_trees/lights.xml"
    lights = home(demo) / "config" / rel
    assert same_tree(lights.read_text(), stock_text(rel))  # the demo robot's tree is 2.2.2's
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--dry-run", "--json")
    assert code == 0, doc
    (r,) = doc["robots"]
    robot_path = "/home/husarion/config/" + rel
    assert r["data"]["migration"]["review"] == [] and robot_path in r["data"]["migration"]["translated"]
    lights.write_text(lights.read_text().replace('delay_msec="2500"', 'delay_msec="2000"', 1))
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "driver", "update", JAZZY, "-r", ROBOT, "--yes", "--json")
    assert code == 0, doc
    (r,) = doc["robots"]
    assert r["data"]["migration"]["review"] == [robot_path]
    assert any("needs review" in w and "drive_state" in w for w in r["warnings"])
    assert 'delay_msec="2000"' in lights.read_text() and "drive_state" in lights.read_text()
