"""Husarion's own default files are accepted on a robot of their release, and the templates are
those files (issue 24, findings 1 and 5).

The inputs are built here from small tables of upstream facts (each table names the file it
was read from, ``repo@tag:path``); no upstream file is copied into the tests.
"""

from __future__ import annotations

from typing import Any

import pytest
import yaml

from panther_ops.core.fleet.templates import read_template
from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file
from panther_ops.core.robot.files import config_file, template_source
from panther_ops.core.stack import stack_from_version

# ---------------------------------------------------------------- wheel files
# husarion_ugv_ros@2.2.0 and @2.2.2:husarion_ugv_description/config/WH0X.yaml (the same at both tags):
# wheel_radius, wheel_width, mount_point_offset, mass, inertia (ixx, iyy, izz), folder_path, mecanum
WHEELS_22 = {
    "WH01": (0.1825, 0.14, 0.091, 3.0, (0.022510, 0.034850, 0.022510), False),
    "WH02": (0.1016, 0.08, 0.08165, 2.4, (0.010050, 0.016496, 0.010068), True),
    "WH04": (0.1016, 0.04, 0.06, 0.85, (0.003099, 0.005849, 0.003101), False),
    "WH05": (0.1348, 0.09, 0.06, 2.036, (0.014738, 0.02593, 0.014738), False),
}
# panther_ros@2.0.4 and @2.1.1:panther_description/config/WH0X.yaml: wheel_separation instead of
# mount_point_offset; mecanum from 2.1 on
SEPARATION_21 = {"WH01": 0.697, "WH02": 0.6785, "WH04": 0.616}


def wheel_22(wheel: str) -> dict[str, Any]:
    radius, width, offset, mass, (ixx, iyy, izz), mecanum = WHEELS_22[wheel]
    return {"wheel_radius": radius, "wheel_width": width, "mount_point_offset": offset, "mass": mass,
            "inertia": {"ixx": ixx, "iyy": iyy, "izz": izz}, "inertia_y_offset": 0.0,
            "mesh_package": "husarion_ugv_description", "folder_path": f"meshes/{wheel}", "mecanum": mecanum}


def wheel_2x(wheel: str, version: str) -> dict[str, Any]:
    doc = {k: v for k, v in wheel_22(wheel).items() if k not in ("mount_point_offset", "mecanum")}
    doc.update(wheel_separation=SEPARATION_21[wheel], mesh_package="panther_description")
    if version >= "2.1":
        doc["mecanum"] = WHEELS_22[wheel][5]
    return doc


def dump(doc: Any) -> bytes:
    return yaml.safe_dump(doc, sort_keys=False).encode()


@pytest.mark.parametrize("version", ["2.2.0", "2.2.2"])
@pytest.mark.parametrize("wheel", sorted(WHEELS_22))
def test_husarion_ugv_22_wheel_files_are_accepted(version: str, wheel: str) -> None:
    target = Target(stack_from_version(version), wheel)
    assert check_file(FileKind.WHEEL, f"{wheel}.yaml", dump(wheel_22(wheel)), target=target) == []
    assert check_file(FileKind.WHEEL, f"{wheel}.yaml", dump(wheel_22(wheel))) == []  # before a robot is read


@pytest.mark.parametrize("version", ["2.0.4", "2.1.1"])
@pytest.mark.parametrize("wheel", sorted(SEPARATION_21))
def test_panther_ros_wheel_files_are_accepted(version: str, wheel: str) -> None:
    target = Target(stack_from_version(version), wheel)
    assert check_file(FileKind.WHEEL, f"{wheel}.yaml", dump(wheel_2x(wheel, version)), target=target) == []


@pytest.mark.parametrize(("version", "doc", "said"), [
    ("2.1.1", wheel_22("WH01"), "wheel_separation is required on panther_ros 2.1.1"),
    ("2.2.2", wheel_2x("WH01", "2.1.1"), "mount_point_offset is required on husarion_ugv 2.2.2"),
    ("2.2.0", {k: v for k, v in wheel_22("WH01").items() if k != "mass"}, "mass is required on husarion_ugv 2.2.0"),
    ("2.0.4", {k: v for k, v in wheel_2x("WH04", "2.0.4").items() if k != "folder_path"},
     "folder_path is required on panther_ros 2.0.4"),
])
def test_a_wheel_file_the_releases_urdf_cannot_load_is_refused(version: str, doc: dict[str, Any], said: str) -> None:
    with pytest.raises(FileKindError) as exc:
        check_file(FileKind.WHEEL, "w.yaml", dump(doc), target=Target(stack_from_version(version), "WH01"))
    assert said in str(exc.value)


@pytest.mark.parametrize("wheel", sorted(WHEELS_22))
def test_the_22_wheel_templates_are_the_release_files(wheel: str) -> None:
    for version in ("2.2.0", "2.2.2"):
        cf = config_file(stack_from_version(version), FileKind.WHEEL, wheel_type=wheel)
        text = cf.template_text()
        assert yaml.safe_load(text) == wheel_22(wheel), (version, wheel)
        assert template_source(text) == f"husarion_ugv_ros@2.2.2:husarion_ugv_description/config/{wheel}.yaml"
        check_file(FileKind.WHEEL, cf.filename, text.encode(), target=Target(stack_from_version(version), wheel))


# ---------------------------------------------------------------- panther_animations.yaml (2.2)
# husarion_ugv_ros@2.2.0 and @2.2.2:husarion_ugv_lights/config/panther_animations.yaml (the same at both):
# (id, name, priority, kind, image stem, duration, repeat, moving image parameters)
#   kind "sides": ImageAnimation on front and rear, images <stem>_front/_rear.png
#   kind "all": ImageAnimation on all, image <stem>.png
#   kind "moving"/"moving-sides": MovingImageAnimation on front and rear (one image / one per side),
#       rear image_mirrored and position_mirrored; parameters (center_offset, object_width, splash_duration)
#   kind "blinker": MovingImageAnimation on all, (center_offset, object_width, default_image_position,
#       splash_duration, mirrored)
ANIMATIONS_22: list[tuple[Any, ...]] = [
    (0, "E_STOP", 3, "sides", "estop", 6, None, None),
    (1, "READY", 3, "sides", "ready", 6, None, None),
    (2, "ERROR", 0, "all", "error", 2, 2, None),
    (3, "NO_ERROR", 0, "all", "empty", 1, 1, None),
    (4, "MANUAL_ACTION", 3, "sides", "manual_action", 6, None, None),
    (5, "LOW_BATTERY", 2, "moving", "low_battery", 10, 1, (24, 2, 10.0)),
    (6, "CRITICAL_BATTERY", 2, "moving", "critical_battery", 10, 1, (24, 2, 10.0)),
    (7, "CHARGING_BATTERY", 2, "moving-sides", "charging_battery", 10, 1, (38, 1, 10.0)),
    (8, "BATTERY_CHARGED", 2, "moving-sides", "battery_charged", 10, 1, (38, 1, 10.0)),
    (9, "CHARGER_INSERTED", 1, "sides", "charger_inserted", 8, None, None),
    (10, "BATTERY_NOMINAL", 2, "all", "empty", 1, 1, None),
    (11, "AUTONOMOUS_READY", 3, "sides", "autonomous_ready", 6, None, None),
    (12, "AUTONOMOUS_ACTION", 3, "sides", "autonomous_action", 6, None, None),
    (13, "GOAL_ACHIEVED", 1, "sides", "goal_achieved", 4, None, None),
    (14, "BLINKER_LEFT", 1, "blinker", "blinker", 2, 3, (17, 1, 0.2, 2.0, True)),
    (15, "BLINKER_RIGHT", 1, "blinker", "blinker", 2, 3, (17, 1, 0.2, 2.0, False)),
]
IMAGE = "$(find husarion_ugv_lights)/animations/panther/{}.png"
T_IMAGE, T_MOVING = "husarion_ugv_lights::ImageAnimation", "husarion_ugv_lights::MovingImageAnimation"


def _part(kind: str, segments: str, image: str, duration: int, repeat: int | None,
          extra: dict[str, Any] | None = None) -> dict[str, Any]:
    animation: dict[str, Any] = {"image": IMAGE.format(image), "duration": duration}
    if repeat is not None:
        animation["repeat"] = repeat
    return {"type": kind, "segments": segments, "animation": {**animation, **(extra or {})}}


def animations_22() -> dict[str, Any]:
    entries = []
    for anim_id, name, priority, kind, stem, duration, repeat, params in ANIMATIONS_22:
        if kind == "sides":
            parts = [_part(T_IMAGE, side, f"{stem}_{side}", duration, repeat) for side in ("front", "rear")]
        elif kind == "all":
            parts = [_part(T_IMAGE, "all", stem, duration, repeat)]
        elif kind.startswith("moving"):
            center, width, splash = params
            moving = {"center_offset": center, "object_width": width, "splash_duration": splash}
            mirrored = {"image_mirrored": True, "position_mirrored": True}
            front, rear = (f"{stem}_front", f"{stem}_rear") if kind == "moving-sides" else (stem, stem)
            parts = [_part(T_MOVING, "front", front, duration, repeat, moving),
                     _part(T_MOVING, "rear", rear, duration, repeat, {**moving, **mirrored})]
        else:
            center, width, position, splash, mirror = params
            moving = {"center_offset": center, "object_width": width, "default_image_position": position,
                      "splash_duration": splash}
            if mirror:
                moving.update(image_mirrored=True, position_mirrored=True)
            parts = [_part(T_MOVING, "all", stem, duration, repeat, moving)]
        entries.append({"id": anim_id, "name": name, "priority": priority, "animations": parts})
    return {
        "panels": [{"channel": 1, "number_of_leds": 46}, {"channel": 2, "number_of_leds": 46}],
        "segments": [{"name": "front", "channel": 1, "led_range": "0-45"},
                     {"name": "rear", "channel": 2, "led_range": "45-0"}],
        "segments_map": {"all": ["front", "rear"], "front": ["front"], "rear": ["rear"]},
        "led_animations": entries,
    }


def strict(a: Any, b: Any) -> bool:
    """Equal with the same types (an int is not a float: ROS and yaml-cpp tell them apart)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return list(a) == list(b) and all(strict(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(strict(x, y) for x, y in zip(a, b, strict=True))
    return bool(a == b)


@pytest.mark.parametrize("version", ["2.2.0", "2.2.2"])
def test_the_stock_22_animations_are_accepted(version: str) -> None:
    """Priority 0 is ERROR in 2.2, MovingImageAnimation is a registered plugin, the images are in the image."""
    data = dump(animations_22())
    assert check_file(FileKind.LED, "panther_animations.yaml", data, target=Target(stack_from_version(version))) == []
    assert check_file(FileKind.LED, "panther_animations.yaml", data) == []  # the file's own release


def test_the_22_animations_template_is_the_release_file() -> None:
    for version in ("2.2.0", "2.2.2"):
        cf = config_file(stack_from_version(version), FileKind.LED)
        assert cf.filename == "panther_animations.yaml"
        assert strict(yaml.safe_load(cf.template_text()), animations_22()), version
        assert template_source(cf.template_text()) == \
            "husarion_ugv_ros@2.2.2:husarion_ugv_lights/config/panther_animations.yaml"


@pytest.mark.parametrize(("version", "priority", "accepted"), [
    # user animations: panther_ros refuses priority 1 (2.1.1 lights_controller_node.cpp), 2.2 priority 0
    ("2.1.1", 1, False), ("2.1.1", 2, True), ("2.1.1", 0, False),
    ("2.2.2", 1, True), ("2.2.2", 0, False), ("2.2.0", 3, True), ("2.2.0", 4, False),
])
def test_user_animation_priorities_per_release(version: str, priority: int, accepted: bool) -> None:
    family = "husarion_ugv_lights" if version >= "2.2" else "panther_lights"
    image = IMAGE.format("ready_front") if version >= "2.2" else "$(find panther_lights)/animations/strip01_red.png"
    doc = {"user_animations": [{"id": 21, "name": "MINE", "priority": priority, "animations": [
        {"type": f"{family}::ImageAnimation", "segments": "all", "animation": {"image": image, "duration": 2}}]}]}
    target = Target(stack_from_version(version))
    if accepted:
        assert check_file(FileKind.USER_ANIMATIONS, "u.yaml", dump(doc), target=target) == []
    else:
        with pytest.raises(FileKindError, match=f"priority {priority}"):
            check_file(FileKind.USER_ANIMATIONS, "u.yaml", dump(doc), target=target)


# ---------------------------------------------------------------- other 2.2 templates
# husarion_ugv_ros@2.2.0 / @2.2.2:husarion_ugv_lights/config/panther_driver.yaml: flat (a ComposableNode)
DRIVER = {"2.2.0": {"channel_1_num_led": 46, "channel_2_num_led": 46},
          "2.2.2": {"frame_timeout": 0.1, "global_brightness": 1.0, "channel_1_num_led": 46, "channel_2_num_led": 46}}
# husarion_ugv_ros@2.2.0 / @2.2.2:husarion_ugv_controller/config/WH05_controller.yaml (drive_controller)
WH05_CONTROLLER = {"2.2.0": {"wheel_separation": 0.45, "wheel_radius": 0.1348, "wheel_separation_multiplier": 1.37,
                             "left_wheel_radius_multiplier": 1.0, "right_wheel_radius_multiplier": 1.0},
                   "2.2.2": {"wheel_separation": 0.45, "wheel_radius": 0.144, "wheel_separation_multiplier": 1.6,
                             "left_wheel_radius_multiplier": 0.964, "right_wheel_radius_multiplier": 0.964}}


@pytest.mark.parametrize("version", ["2.2.0", "2.2.2"])
def test_the_22_driver_and_wh05_controller_templates_are_the_release_files(version: str) -> None:
    stack = stack_from_version(version)
    driver = config_file(stack, FileKind.LIGHTS_DRIVER).template_text()
    assert strict(yaml.safe_load(driver), DRIVER[version])
    controller = config_file(stack, FileKind.CONTROLLER, wheel_type="WH05")
    params = yaml.safe_load(controller.template_text())["/**"]["drive_controller"]["ros__parameters"]
    assert {k: params[k] for k in WH05_CONTROLLER[version]} == WH05_CONTROLLER[version]
    assert template_source(controller.template_text()) == \
        f"husarion_ugv_ros@{version}:husarion_ugv_controller/config/WH05_controller.yaml"
    check_file(FileKind.CONTROLLER, "WH05_controller.yaml", controller.template_text().encode(),
               target=Target(stack, "WH05"))


# panther_ros@2.0.2..2.0.4:panther_manager/launch/manager_bt.launch.py names the nodes lights_manager_node and
# safety_manager_node (2.1.0: lights_manager, safety_manager); husarion_ugv_ros@2.2.x ships
# husarion_ugv_manager/config/{lights,safety}_manager.yaml (safety: execute_command_bt_node from 2.2.1,
# shutdown_single_host_bt_node before)
@pytest.mark.parametrize(("version", "kind", "node", "plugin"), [
    ("2.0.2", FileKind.LIGHTS_MANAGER, "lights_manager_node", "tick_after_timeout_bt_node"),
    ("2.0.4", FileKind.SAFETY_MANAGER, "safety_manager_node", "shutdown_single_host_bt_node"),
    ("2.1.0", FileKind.SAFETY_MANAGER, "safety_manager", "shutdown_single_host_bt_node"),
    ("2.2.0", FileKind.SAFETY_MANAGER, "safety_manager", "shutdown_single_host_bt_node"),
    ("2.2.2", FileKind.SAFETY_MANAGER, "safety_manager", "execute_command_bt_node"),
    ("2.2.2", FileKind.LIGHTS_MANAGER, "lights_manager", "tick_after_timeout_bt_node"),
])
def test_manager_parameter_templates_name_the_releases_nodes(version: str, kind: FileKind, node: str,
                                                             plugin: str) -> None:
    doc = yaml.safe_load(config_file(stack_from_version(version), kind).template_text())
    assert list(doc["/**"]) == [node]
    assert plugin in doc["/**"][node]["ros__parameters"]["plugin_libs"]


def test_the_20x_single_manager_template_lists_its_plugins() -> None:
    # panther_ros@2.0.1:panther_manager/config/manager_bt_config.yaml
    doc = yaml.safe_load(config_file(stack_from_version("2.0.1"), FileKind.MANAGER_BT).template_text())
    params = doc["/**"]["manager_bt_node"]["ros__parameters"]
    assert params["ros_plugin_libs"] == ["call_set_bool_service_bt_node", "call_trigger_service_bt_node",
                                         "call_set_led_animation_service_bt_node"]


def test_templates_name_their_source_at_their_directorys_release() -> None:
    """Where a template names its source, the tag is its directory's release."""
    from panther_ops.core.fleet.templates import template_path

    tags = {"panther-2.0": "2.0.4", "panther-2.0.0": "2.0.1", "panther-2.1": "2.1.1", "panther-2.1.0": "2.1.0",
            "husarion-ugv-2.2": "2.2.2", "husarion-ugv-2.2.0": "2.2.0"}
    root = template_path("config")
    named = 0
    for directory, tag in tags.items():
        for path in (root / directory).rglob("*"):
            if not path.is_file():
                continue
            source = template_source(path.read_text())
            if source is not None:
                named += 1
                assert source == f"{source.split('@')[0]}@{tag}:{path.relative_to(root / directory).as_posix()}"
    assert named >= 40
    assert template_source(read_template("config", "panther-2.1", "panther_lights", "config",
                                         "user_animations.yaml")) is None  # panther-ops' own
