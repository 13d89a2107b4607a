"""The 2.2 -> 2.3 translators (panther_ops/core/driver/migrate/): upstream's 2.2.2 defaults
become upstream's 2.3.x defaults (read from the local mirror of husarion/husarion_ugv_ros;
skipped without it), customised files keep the operator's values, and what has no 2.3 form is
refused naming the file and the key (exit 2)."""

from __future__ import annotations

import math
import os
import subprocess
from pathlib import Path

import pytest
from ruamel.yaml import YAML

from panther_ops.core.driver.migrate.components import translate_components
from panther_ops.core.driver.migrate.controller import translate_controller
from panther_ops.core.driver.migrate.joy2twist import translate_joy2twist
from panther_ops.core.driver.migrate.launch import migrate_launch
from panther_ops.core.driver.migrate.lights_tree import same_tree, translate_lights_tree
from panther_ops.core.driver.migrate.localization import translate_localization
from panther_ops.core.driver.migrate.stock import stock_text
from panther_ops.core.driver.migrate.translated import MigrationRefused
from panther_ops.core.kinds import FileKind, Target, check_file
from panther_ops.core.stack import Stack
from panther_ops.errors import ExitCode

MIRROR = Path(os.environ.get("PANTHER_OPS_UPSTREAM_MIRROR", "/work/.mirror/husarion+husarion_ugv_ros/repo"))
needs_mirror = pytest.mark.skipif(not MIRROR.is_dir(), reason="no local mirror of husarion_ugv_ros")
T232, T231 = (2, 3, 2), (2, 3, 1)


def show(tag: str, path: str) -> str:
    return subprocess.run(["git", "-C", str(MIRROR), "show", f"{tag}:{path}"], capture_output=True, text=True,
                          check=True).stdout


def load(text: str) -> object:
    return YAML(typ="safe", pure=True).load(text)


def same(a: object, b: object) -> bool:
    """Semantic equality, NaN equal to NaN."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    return type(a) is type(b) and a == b


# ------------------------------------------------------------------ golden: upstream defaults

GOLDEN = [
    *[(f"husarion_ugv_controller/config/{w}_controller.yaml", f"husarion_ugv_controller/config/{w}_controller.yaml",
       translate_controller) for w in ("WH01", "WH02", "WH04", "WH05")],
    *[(f"husarion_ugv_localization/config/{e}.yaml", f"husarion_ugv_localization/config/{e}.yaml",
       translate_localization) for e in ("enu_localization", "enu_localization_with_gps", "relative_localization",
                                         "relative_localization_with_gps")],
    ("husarion_ugv_description/config/components.yaml", "husarion_ugv_description/config/components.yaml",
     translate_components),
]


@needs_mirror
@pytest.mark.parametrize("tag", ["2.3.1", "2.3.2"])
@pytest.mark.parametrize(("old", "new", "translate"), GOLDEN, ids=[g[0].rsplit("/", 1)[-1] for g in GOLDEN])
def test_stock_2_2_2_becomes_stock_2_3(tag: str, old: str, new: str, translate: object) -> None:
    target = tuple(int(p) for p in tag.split("."))
    out = translate(show("2.2.2", old), "/home/husarion/config/" + old, target)  # type: ignore[operator]
    assert same(load(out.text), load(show(tag, new)))
    if not new.endswith("components.yaml"):  # components: 2.3's example comments differ, the value is equal
        assert out.text == show(tag, new)  # the layout and comments too


WHEELS = ("WH01", "WH02", "WH04", "WH05")
S232 = Stack("husarion/husarion-ugv:jazzy-2.3.2-20260622", "jazzy", T232, "20260622")
TEMPLATE_22 = Path(__file__).resolve().parents[3] / "templates/config/husarion-ugv-2.2/husarion_ugv_controller/config"


def customised(text: str, wheel: str) -> tuple[str, dict[str, float]]:
    """``text`` with a slower linear.x and gentler braking (in block or flow style alike), and the values
    2.3.2's file then holds."""
    x = load(text)["/**"]["drive_controller"]["ros__parameters"]["linear"]["x"]  # type: ignore[index]
    v, a = x["max_velocity"], x["max_acceleration"]
    text = text.replace(f"max_velocity: {v}", f"max_velocity: {v / 2}", 1)
    text = text.replace(f"max_acceleration: {a}", f"max_acceleration: {a / 2}", 1)
    return text, {"max_velocity": v / 2, "min_velocity": -v / 2, "max_acceleration": a / 2,
                  "max_deceleration": -a / 2, "max_acceleration_reverse": -a / 2, "max_deceleration_reverse": a / 2}


@needs_mirror
@pytest.mark.parametrize("custom", [False, True], ids=["stock", "customised"])
@pytest.mark.parametrize("source", ["upstream", "template"])
@pytest.mark.parametrize("wheel", WHEELS)
def test_every_2_2_2_controller_becomes_2_3_2s_and_passes_its_check(wheel: str, source: str, custom: bool) -> None:
    """Upstream's 2.2.2 file (block style) and panther-ops' 2.2 template of it (compact ``{ type: ... }``
    flow style in the controller manager), stock and customised: semantically 2.3.2's file (with the
    customised values), and accepted by the 2.3.2 controller check every write path uses."""
    name = f"{wheel}_controller.yaml"
    text = (show("2.2.2", f"husarion_ugv_controller/config/{name}") if source == "upstream"
            else (TEMPLATE_22 / name).read_text())
    expected = load(show("2.3.2", f"husarion_ugv_controller/config/{name}"))
    if custom:
        text, values = customised(text, wheel)
        expected["/**"]["drive_controller"]["ros__parameters"]["linear"]["x"].update(values)  # type: ignore[index]
    out = translate_controller(text, "/home/husarion/config/husarion_ugv_controller/config/" + name, T232)
    assert same(load(out.text), expected)
    assert check_file(FileKind.CONTROLLER, name, out.text.encode(), target=Target(S232, wheel, "")) == []


@needs_mirror
@pytest.mark.parametrize("model", ["panther", "lynx"])
@pytest.mark.parametrize(("tag", "package"), [("2.3.2", "husarion_ugv_teleop"), ("2.3.1", "husarion_ugv_bringup")])
def test_stock_joy2twist_becomes_2_3(model: str, tag: str, package: str) -> None:
    target = tuple(int(p) for p in tag.split("."))
    out = translate_joy2twist(show("2.2.2", f"husarion_ugv_bringup/config/joy2twist_{model}.yaml"), "j.yaml", target)
    assert out.text == show(tag, f"{package}/config/joy2twist_{model}.yaml")


LIGHTS = "husarion_ugv_manager/behavior_trees/lights.xml"


@needs_mirror
def test_the_safety_tree_loses_its_line_continuations_as_upstream() -> None:
    safety = "husarion_ugv_manager/behavior_trees/safety.xml"
    assert translate_lights_tree(show("2.2.2", safety), safety, T232).text == show("2.3.2", safety)


@needs_mirror
@pytest.mark.parametrize("source", ["upstream", "template"])
def test_a_stock_lights_tree_becomes_2_3_2s(source: str) -> None:
    """Upstream's 2.2.2 lights.xml, or panther-ops' template of it: 2.3.2's tree, keyed on the twist mux's
    source; nothing to review. 2.3.1 ships 2.2.2's tree: kept byte-identical."""
    text = show("2.2.2", LIGHTS) if source == "upstream" else stock_text(LIGHTS)
    out = translate_lights_tree(text, "/home/husarion/config/" + LIGHTS, T232)
    assert same_tree(out.text, show("2.3.2", LIGHTS)) and not same_tree(out.text, show("2.2.2", LIGHTS))
    assert 'topic_name="twist_mux_controller/source"' in out.text and "drive_state" not in out.text
    assert not out.review and "2.3.2's" in out.notes[0]
    assert same_tree(show("2.3.1", LIGHTS), show("2.2.2", LIGHTS))
    assert translate_lights_tree(text, LIGHTS, T231).text == text


@needs_mirror
def test_a_customised_lights_tree_is_kept_and_named_for_review_where_it_reads_drive_state() -> None:
    stock = show("2.2.2", LIGHTS)
    custom = stock.replace('delay_msec="2500"', 'delay_msec="2000"', 1)
    assert custom != stock
    out = translate_lights_tree(custom, "/home/husarion/config/" + LIGHTS, T232)
    assert "\\&#10;" not in out.text and 'delay_msec="2000"' in out.text and "drive_state" in out.text
    assert out.review and any("drive_state" in n and "twist_mux_controller/source" in n for n in out.notes)
    assert not translate_lights_tree(custom, LIGHTS, T231).review  # 2.3.1's lights manager still sets drive_state
    keyed = translate_lights_tree(custom.replace("drive_state", "e_stop_state"), LIGHTS, T232)
    assert not keyed.review and "2.3.2's stock tree" in keyed.notes[-1]


# ------------------------------------------------------------------ customised files keep their values

CUSTOM = """\
/**:
  controller_manager:
    ros__parameters:
      drive_controller:
        type: diff_drive_controller/DiffDriveController
      imu_broadcaster:
        type: imu_sensor_broadcaster/IMUSensorBroadcaster
  imu_broadcaster:
    ros__parameters:
      static_covariance_orientation: [2.0e-3, 0.0, 0.0, 0.0, 2.0e-3, 0.0, 0.0, 0.0, 2.0e-3]
  drive_controller:
    ros__parameters:
      cmd_vel_timeout: 0.3 # ours
      use_stamped_vel: false
      linear:
        x:
          has_velocity_limits: true
          has_acceleration_limits: true
          has_jerk_limits: false
          max_velocity: 1.25 # slow site
          max_acceleration: 1.5
          min_acceleration: -0.8 # gentle braking
          max_jerk: 0.0
      angular:
        z:
          has_velocity_limits: false
          has_acceleration_limits: false
          has_jerk_limits: true
          max_velocity: 3.0
          max_acceleration: 4.0
          max_jerk: 9.0
"""


def test_customised_controller_keeps_the_operators_values() -> None:
    out = translate_controller(CUSTOM, "/home/husarion/config/husarion_ugv_controller/config/WH01_controller.yaml",
                               T232)
    doc = load(out.text)
    p = doc["/**"]["drive_controller"]["ros__parameters"]  # type: ignore[index]
    x, z = p["linear"]["x"], p["angular"]["z"]
    assert (x["max_velocity"], x["min_velocity"]) == (1.25, -1.25)
    assert (x["max_acceleration"], x["max_deceleration"], x["max_acceleration_reverse"],
            x["max_deceleration_reverse"]) == (1.5, -0.8, -0.8, 1.5)
    assert math.isnan(x["max_jerk"]) and math.isnan(x["min_jerk"])
    assert all(math.isnan(z[k]) for k in ("max_velocity", "min_velocity", "max_acceleration", "max_deceleration",
                                          "max_acceleration_reverse", "max_deceleration_reverse"))
    assert (z["max_jerk"], z["min_jerk"]) == (9.0, -9.0)
    assert not any(k.startswith("has_") or k == "min_acceleration" for k in (*x, *z))
    assert "use_stamped_vel" not in p and p["cmd_vel_timeout"] == 0.3 and p["publish_limited_velocity"] is False
    assert "# slow site" in out.text and "# ours" in out.text  # comments kept
    imu = doc["/**"]["imu_broadcaster"]["ros__parameters"]  # type: ignore[index]
    assert imu["static_covariance_orientation"][0] == 2.0e-3  # customised: kept (and named)
    assert doc["/**"]["twist_mux_controller"]["ros__parameters"]["holonomic"] is False  # type: ignore[index]
    notes = " ".join(out.notes)
    assert "angular.z.has_velocity_limits false" in notes and "static_covariance_orientation kept" in notes
    assert "min_acceleration -0.8" in notes


def test_customised_linear_y_is_refused_naming_file_and_key() -> None:
    text = CUSTOM.replace("      angular:\n", "        y:\n          has_velocity_limits: true\n"
                          "          max_velocity: 0.5\n      angular:\n")
    with pytest.raises(MigrationRefused) as err:
        translate_controller(text, "/home/husarion/config/husarion_ugv_controller/config/WH02_controller.yaml", T232)
    assert err.value.exit_code is ExitCode.USAGE
    assert "WH02_controller.yaml" in err.value.message and "drive_controller.linear.y" in err.value.message
    assert err.value.hint and "linear.y" in err.value.hint


def test_a_has_limits_flag_that_is_no_bool_is_refused() -> None:
    with pytest.raises(MigrationRefused, match=r"WH01_controller.yaml:\d+ \[.*has_jerk_limits\]"):
        translate_controller(CUSTOM.replace("has_jerk_limits: true", "has_jerk_limits: maybe"),
                             "WH01_controller.yaml", T232)


def test_customised_joy2twist_keeps_its_factors_and_a_custom_topic() -> None:
    text = "/**:\n  ros__parameters:\n    cmd_vel_stamped: false\n    linear_velocity_factor:\n      fast: 0.9\n"
    out = translate_joy2twist(text, "joy2twist_panther.yaml", T232)
    params = load(out.text)["/**"]["ros__parameters"]  # type: ignore[index]
    assert params == {"cmd_vel_topic": "manual/cmd_vel", "cmd_vel_stamped": True, "linear_velocity_factor":
                      {"fast": 0.9}}
    custom = translate_joy2twist(text.replace("    cmd_vel_stamped", "    cmd_vel_topic: teleop/cmd_vel\n"
                                              "    cmd_vel_stamped"), "joy2twist_panther.yaml", T232)
    assert load(custom.text)["/**"]["ros__parameters"]["cmd_vel_topic"] == "teleop/cmd_vel"  # type: ignore[index]
    assert custom.notes and "teleop/cmd_vel kept" in custom.notes[0]


def test_components_device_namespace_becomes_name() -> None:
    text = ("components:\n  - type: LDR06 # front\n    parent_link: mount_link\n    device_namespace: front_lidar\n"
            "  - type: CAM01\n    name: camera\n")
    out = translate_components(text, "components.yaml", T232)
    assert load(out.text) == {"components": [{"type": "LDR06", "parent_link": "mount_link", "name": "front_lidar"},
                                             {"type": "CAM01"}]}
    assert "# front" in out.text and len(out.notes) == 2


def test_components_with_two_different_names_is_refused() -> None:
    text = "components:\n  - type: CAM01\n    name: camera\n    device_namespace: front_cam\n"
    with pytest.raises(MigrationRefused) as err:
        translate_components(text, "/home/husarion/config/husarion_ugv_description/config/components.yaml", T232)
    assert "components.yaml:3 [components[0].name]" in err.value.message


def test_ekf_customised_timeout_is_kept_and_named() -> None:
    text = "/**:\n  ekf_filter:\n    ros__parameters:\n      use_control: true\n      control_timeout: 0.3\n"
    out = translate_localization(text, "enu_localization.yaml", T232)
    assert load(out.text) == {"/**": {"ekf_filter": {"ros__parameters": {
        "use_control": True, "stamped_control": True, "control_timeout": 0.3}}}}
    assert out.notes and "control_timeout 0.3 kept" in out.notes[0]


def test_launch_arguments_removed_or_refused() -> None:
    m = migrate_launch({"publish_robot_state": "True", "launch_gamepad": "true"}, T232, "~/compose.yaml")
    assert m.dropped == ("publish_robot_state",) and "publish_robot_state:=True removed" in m.notes[0]
    with pytest.raises(MigrationRefused, match=r"\[publish_robot_state\]"):
        migrate_launch({"publish_robot_state": "False"}, T232, "~/compose.yaml")
    with pytest.raises(MigrationRefused, match=r"\[launch_gamepad\]"):
        migrate_launch({"launch_gamepad": "false"}, T232, "~/compose.yaml")
    assert migrate_launch({"launch_gamepad": "false"}, T231, "~/compose.yaml").dropped == ()


@needs_mirror
def test_a_controller_file_already_in_the_jazzy_schema_is_kept() -> None:
    path = "husarion_ugv_controller/config/WH01_controller.yaml"
    stock = show("2.3.2", path)
    out = translate_controller(stock, path, T232)
    assert out.text == stock and any("already in the Jazzy schema" in n for n in out.notes)


def test_a_flow_mapping_that_needs_new_keys_is_refused_with_the_fix() -> None:
    from panther_ops.core.driver.migrate.plan import translated

    text = ("/**:\n  drive_controller:\n    ros__parameters:\n      linear:\n"
            "        x: {has_velocity_limits: true, max_velocity: 1.0}\n")
    with pytest.raises(MigrationRefused) as err:
        translated(translate_controller, text, "/home/husarion/config/WH01_controller.yaml", T231)
    assert err.value.message.startswith("/home/husarion/config/WH01_controller.yaml") and err.value.exit_code == 2
    assert "block mappings" in (err.value.hint or "")
