"""The conformance failures known today, each tied to the finding of issue #24 that fixes it.

A key is an ``fnmatch`` pattern over a result's id (``<tag>:<check>:<item>``). The report
marks a failure with its finding; tests/unit/test_conformance.py expects these items to fail
(``xfail(strict=True)``), so the test of an item turns red the day a fix makes it pass:
then delete its line here (and re-run scripts/conformance.py if the fix changed a
validator, so the recorded verdicts follow).

``new`` entries are failures the conformance tool found that issue #24 does not list.
"""

from __future__ import annotations

from fnmatch import fnmatchcase

FINDINGS: dict[str, str] = {
    "finding 1": "husarion_ugv 2.2's own files are refused",
    "finding 2": "controller templates lack the IMU's namespace prefix",
    "finding 3": "where 2.2 reads a default from (image or ~/config tree) is wrong in the catalogue",
    "finding 4": "2.1.1's NMEA launch arguments are missing from the catalogue",
    "finding 5": "templates that are not upstream's, or missing",
    "finding 8": "simulation files",
    "finding 9": "config pull joy2twist has no default to give",
    "new": "found by the conformance tool; not in issue #24's list",
}
"""Label -> what it is: the findings of issue #24 that known failures belong to."""

KNOWN: dict[str, tuple[str, str]] = {
    # 1. real 2.2 files refused
    "2.2.*:defaults:husarion_ugv_description/config/WH0[1245].yaml":
        ("finding 1", "mount_point_offset, no wheel_separation"),
    "2.2.*:defaults:husarion_ugv_lights/config/panther_animations.yaml":
        ("finding 1", "priority 0, images in the image"),
    "2.2.*:defaults:husarion_ugv_lights/config/lynx_animations.yaml":
        ("finding 1", "the Lynx's animations, same causes"),
    "2.2.*:defaults:husarion_ugv_manager/behavior_trees/LightsBT.btproj": ("finding 1", "Parallel and Delay"),
    # 2. the IMU sensor name on a namespaced robot
    "*:templates:config/*/*_controller/config/WH0?_controller.yaml": ("finding 2", ""),
    "2.2.*:templates:config-tree/*/*_controller/config/WH0?_controller.yaml": ("finding 2", ""),
    # 3. where 2.2 reads its defaults from
    "2.2.*:launch:wheel_config_path": ("finding 3", ""),
    "2.2.*:launch:system_monitor_config_path": ("finding 3", ""),
    "2.2.0:launch:animations_config_path": ("finding 3", ""),
    "2.2.*:launch:lights_bt_project_path": ("finding 3", ""),
    # 4. 2.1.1's NMEA launch file
    "2.1.1:launch:params_file": ("finding 4", ""),
    "2.1.1:launch:device_namespace": ("finding 4", ""),
    # 5. templates
    "2.2.*:templates:*/husarion_ugv_lights/config/panther_animations.yaml": ("finding 5", "the 2.1 file renamed"),
    "2.2.*:templates:config/husarion-ugv-2.2/husarion_ugv_lights/config/panther_driver.yaml":
        ("finding 5", "wrapped in ros__parameters; upstream's is flat"),
    "2.2.*:templates:(none) -> husarion_ugv_description/config/WH0[24].yaml": ("finding 5", "no template"),
    "2.2.*:templates:(none) -> husarion_ugv_controller/config/WH05_controller.yaml": ("finding 5", "no template"),
    "2.2.2:tree:panther": ("finding 5", "the demo's tree lacks files the image copies"),
    "2.0.4:templates:config/panther-2.0/panther_manager/config/*_manager_config.yaml":
        ("finding 5", "node names 2.0.2-2.0.4 no longer have"),
    # 8. simulation
    "2.0.4:templates:config/panther-2.0/panther_gazebo/config/battery_plugin_config.yaml":
        ("finding 8", "initial_charge_percentage: 2.0.1+ reads a 0-1 fraction"),
    # 9. joy2twist
    "2.2.2:templates:(none) -> husarion_ugv_bringup/config/joy2twist_*.yaml": ("finding 9", "no template"),
    # found by the conformance tool, not in the issue
    "*:templates:behavior_trees/*": ("new", "templates/behavior_trees differ from every release's; config pull "
                                     "bt-lights/bt-safety presents them as the image's default"),
    "2.2.*:templates:config/husarion-ugv-2.2/husarion_ugv_description/config/WH05.yaml":
        ("new", "inertia.iyy is not upstream's"),
    "2.2.*:templates:(none) -> husarion_ugv_gazebo/config/battery_plugin.yaml":
        ("new", "no template of 2.2's simulated battery (--as battery)"),
    "2.2.*:templates:(none) -> husarion_ugv_lights/config/lynx_animations.yaml":
        ("new", "no template of the Lynx's animations"),
    "2.2.*:launch:wheel_type": ("new", "on a Lynx 2.2 defaults wheel_type to WH05; the catalogue says WH01 "
                                "(related to finding 8)"),
}
"""Result id pattern -> (label in `FINDINGS`, what in particular)."""


def known(result_id: str) -> tuple[str, str] | None:
    """The label and note of a failing result, or None (not known: a regression or a new finding)."""
    for pattern, entry in KNOWN.items():
        if fnmatchcase(result_id, pattern):
            return entry
    return None
