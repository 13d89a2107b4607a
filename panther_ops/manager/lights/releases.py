"""What each release's lights controller accepts: animation plugins, priorities, stock images.

Read from the releases themselves (``repo@tag:path``; husarion_ugv_ros holds the whole history):

panther_ros 2.0.4 and 2.1.1 (package ``panther_lights``):
  * plugins ``panther_lights::ImageAnimation`` and ``panther_lights::ChargingAnimation``
    (panther_ros@2.0.4:panther_lights/plugins.xml, panther_ros@2.1.1:panther_lights/plugins.xml);
  * priorities 1, 2, 3, default 3 (``kValidPriorities``, ``kDefaultPriority`` in
    panther_ros@2.1.1:panther_lights/include/panther_lights/led_components/led_animations_queue.hpp,
    2.0.4: include/panther_lights/led_animations_queue.hpp);
  * a user animation needs an ID of 20 or more and may not use priority 1 (``LoadUserAnimations``
    in panther_ros@2.1.1:panther_lights/src/lights_controller_node.cpp, 2.0.4: src/controller_node.cpp);
  * ``brightness`` in [0, 1] (panther_ros@2.1.1:panther_lights/include/panther_lights/animation/animation.hpp);
  * images ``animations/<name>.png`` (panther_ros@2.1.1:panther_lights/animations/, the same at 2.0.4).

husarion_ugv 2.2.0 and 2.2.2 (package ``husarion_ugv_lights``):
  * plugins ``husarion_ugv_lights::ImageAnimation`` and ``husarion_ugv_lights::MovingImageAnimation``
    (husarion_ugv_ros@2.2.0:husarion_ugv_lights/plugins.xml; no ChargingAnimation);
  * priorities 0 (ERROR), 1, 2, 3, default 3 (``AnimationPriority`` in
    husarion_ugv_ros@2.2.0:husarion_ugv_lights/include/husarion_ugv_lights/led_components/led_segment.hpp,
    ``kValidPriorities`` in .../led_components/led_animation.hpp);
  * a user animation needs an ID of 20 or more and may not use priority 0
    (husarion_ugv_ros@2.2.0:husarion_ugv_lights/src/lights_controller_node.cpp);
  * ``brightness`` is no longer read (husarion_ugv_ros@2.2.0:husarion_ugv_lights/CHANGELOG.rst, "removed brightness");
  * MovingImageAnimation reads ``center_offset``, ``object_width`` (int16), ``start_offset``,
    ``splash_duration``, ``default_image_position`` (float) and ``image_mirrored``,
    ``position_mirrored`` (bool), each optional: a value of the wrong type is ignored
    (husarion_ugv_ros@2.2.0:husarion_ugv_lights/src/animation/moving_image_animation.cpp);
  * images ``animations/<model>/<name>.png`` for the models panther and lynx
    (husarion_ugv_ros@2.2.0:husarion_ugv_lights/animations/, the same at 2.2.2), installed with the
    package (CMakeLists.txt ``install(DIRECTORY animations ...)``): they are in the robot's image,
    panther-ops does not ship them.

husarion_ugv 2.3.0-2.3.2 (the same package): plugins, priorities and rules as 2.2 (no change to
husarion_ugv_lights' sources but the header guards, ``git diff 2.2.2 2.3.2 -- husarion_ugv_lights``);
2.3.2 adds the images ``goal_failed_front``, ``goal_failed_rear`` and ``flood_light`` for both
models (husarion_ugv_ros@2.3.2:husarion_ugv_lights/animations/{panther,lynx}/), used by its
animations 16 GOAL_FAILED and 17 FLOOD_LIGHT (husarion_ugv_ros@2.3.2:husarion_ugv_lights/config/
{panther,lynx}_animations.yaml).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

from panther_ops.manager.paths import LIGHTS, TEMPLATES
from panther_ops.manager.versions import Version, by_release

_PANTHER_ROS_IMAGES = ("battery_critical", "battery_low", "strip01_purple", "strip01_red", "triangle01_blue",
                       "triangle01_cyan", "triangle01_green", "triangle01_orange", "triangle01_purple",
                       "triangle01_red", "triangle01_yellow")
_UGV_IMAGES = ("autonomous_action_front", "autonomous_action_rear", "autonomous_ready_front",
               "autonomous_ready_rear", "battery_charged_front", "battery_charged_rear", "blinker",
               "charger_inserted_front", "charger_inserted_rear", "charging_battery_front",
               "charging_battery_rear", "critical_battery", "empty", "error", "estop_front", "estop_rear",
               "goal_achieved_front", "goal_achieved_rear", "low_battery", "manual_action_front",
               "manual_action_rear", "ready_front", "ready_rear")
_UGV_MODELS = ("panther", "lynx")
_UGV_2_3_2_IMAGES = ("flood_light", "goal_failed_front", "goal_failed_rear")
"""Images new in husarion_ugv 2.3.2."""


@dataclass(frozen=True)
class LightsRelease:
    """The lights controller of one release family, as its source states it."""

    name: str
    package: str
    types: tuple[str, ...]
    """Animation plugin classes (``<package>::<class>``)."""
    priorities: tuple[int, ...]
    user_forbidden_priority: int
    reads_brightness: bool
    images: frozenset[str]
    """Stock images, relative to the package's share directory."""
    local_images: Path | None
    """Where panther-ops keeps drawable images of the same names (None: only in the robot's image)."""
    default_led_config: Path
    """The animations file a user file builds on (panels, segments, system IDs)."""
    source: str

    def plugin(self, cls: str) -> str:
        return f"{self.package}::{cls}"

    @property
    def plugins(self) -> tuple[str, ...]:
        return tuple(self.plugin(t) for t in self.types)

    def user_priorities(self) -> tuple[int, ...]:
        return tuple(p for p in self.priorities if p != self.user_forbidden_priority)

    def image_dirs(self) -> str:
        dirs = sorted({posix.rsplit("/", 1)[0] for posix in self.images})
        return ", ".join(f"{d}/" for d in dirs)


PANTHER_ROS = LightsRelease(
    name="panther_ros 2.0-2.1",
    package="panther_lights",
    types=("ImageAnimation", "ChargingAnimation"),
    priorities=(1, 2, 3),
    user_forbidden_priority=1,
    reads_brightness=True,
    images=frozenset(f"animations/{n}.png" for n in _PANTHER_ROS_IMAGES),
    local_images=LIGHTS,
    default_led_config=LIGHTS / "led_config.yaml",
    source="panther_ros@2.1.1:panther_lights/plugins.xml",
)
HUSARION_UGV_2_2 = LightsRelease(
    name="husarion_ugv 2.2",
    package="husarion_ugv_lights",
    types=("ImageAnimation", "MovingImageAnimation"),
    priorities=(0, 1, 2, 3),
    user_forbidden_priority=0,
    reads_brightness=False,
    images=frozenset(f"animations/{m}/{n}.png" for m in _UGV_MODELS for n in _UGV_IMAGES),
    local_images=None,
    default_led_config=TEMPLATES / "config" / "husarion-ugv-2.2" / "husarion_ugv_lights" / "config"
    / "panther_animations.yaml",
    source="husarion_ugv_ros@2.2.0:husarion_ugv_lights/plugins.xml",
)
HUSARION_UGV_2_3_2 = replace(
    HUSARION_UGV_2_2,
    name="husarion_ugv 2.3.2",
    images=HUSARION_UGV_2_2.images | {f"animations/{m}/{n}.png" for m in _UGV_MODELS for n in _UGV_2_3_2_IMAGES},
    default_led_config=TEMPLATES / "config" / "husarion-ugv-2.3.2" / "husarion_ugv_lights" / "config"
    / "panther_animations.yaml",
    source="husarion_ugv_ros@2.3.2:husarion_ugv_lights/plugins.xml",
)
RELEASES = (PANTHER_ROS, HUSARION_UGV_2_2)
"""One per lights package (a file checked without a robot: `release_of`)."""
PACKAGES = {r.package: r for r in RELEASES}
IMAGES_2_3_2 = (2, 3, 2)


def release_for(version: Version) -> LightsRelease:
    """The lights rules of a stack version (2.0.x-2.1.x: panther_ros; 2.2.x-2.3.1: husarion_ugv;
    2.3.2+: husarion_ugv with 2.3.2's images)."""
    return by_release(version, ((IMAGES_2_3_2, HUSARION_UGV_2_3_2), ((2, 2, 0), HUSARION_UGV_2_2)), PANTHER_ROS)


def release_of(types: Iterable[str]) -> LightsRelease:
    """For a file checked without a robot: the release whose package its first stock type names
    (panther_ros when none does)."""
    for kind in types:
        package = kind.split("::", 1)[0]
        if package in PACKAGES:
            return PACKAGES[package]
    return PANTHER_ROS
