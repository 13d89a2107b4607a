"""The husarion-webui settings validator (the snap configure hook's rules) and the inventory's
desired.webui checked with it: every refusal names the key, the value and what is allowed."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.kinds.webui_settings import SettingError, validate
from panther_ops.errors import ExitCode, InputError


def test_manual_panther_settings_pass_as_snap_keys() -> None:
    got = validate({"ros.namespace": "panther", "ros.transport": "rmw_cyclonedds_cpp", "webui.layout": "panther",
                    "webui.port": 8081, "ros.domain-id": 232, "ros.localhost-only": True})
    assert got == {"ros.namespace": "panther", "ros.transport": "rmw_cyclonedds_cpp", "webui.layout": "panther",
                   "webui.port": "8081", "ros.domain-id": "232", "ros.localhost-only": "1"}
    assert validate({"namespace": "panther_2", "port": "1", "domain_id": 0}) == {
        "ros.namespace": "panther_2", "webui.port": "1", "ros.domain-id": "0"}
    # the tokens husarion-snap-common@0.13.0:local-ros/configure_hook_ros.sh resolves itself
    for t in ("udp", "udp-lo", "shm", "udp-lo-cyclone", "rmw_fastrtps_cpp", "rmw_cyclonedds_cpp"):
        assert validate({"ros.transport": t}) == {"ros.transport": t}
    assert validate({"ros.localhost-only": ""}) == {"ros.localhost-only": ""}  # unset, as the install hook leaves it


@pytest.mark.parametrize(
    ("settings", "key", "allowed"),
    [
        ({"ros.namespace": "bad ns"}, "ros.namespace", "1-20 characters"),
        ({"ros.namespace": "Panther"}, "ros.namespace", "a-z"),
        ({"ros.namespace": "a" * 21}, "ros.namespace", "1-20 characters"),
        # issue 23 item 5: the snap's hook lets these through, ROS does not (core/parse/ros_names)
        ({"ros.namespace": "e-stop"}, "ros.namespace", "'-' is not allowed"),
        ({"ros.namespace": "2robot"}, "ros.namespace", "starts with a digit"),
        ({"ros.namespace": "panther-01"}, "ros.namespace", "a-z, 0-9 and '_'"),  # the hook's 0.13.0 regex
        ({"ros.namespace": "1panther"}, "ros.namespace", "not starting with a digit"),
        ({"ros.transport": "rmw_zenoh_cpp"}, "ros.transport", "zenoh is refused"),
        ({"ros.domain-id": "\uff18"}, "ros.domain-id", "ASCII digits"),
        ({"webui.port": 70000}, "webui.port", "from 1 to 65535"),
        ({"webui.port": 0}, "webui.port", "from 1 to 65535"),
        ({"webui.port": "80; reboot"}, "webui.port", "whole number"),
        ({"ros.domain-id": 300}, "ros.domain-id", "from 0 to 232"),
        ({"ros.domain-id": -1}, "ros.domain-id", "from 0 to 232"),
        ({"ros.localhost-only": 2}, "ros.localhost-only", "0 or 1"),
        ({"ros.transport": "../etc/passwd"}, "ros.transport", "DDS profile"),
        ({"ros.transport": "$(id)"}, "ros.transport", "DDS profile"),
        ({"webui.layout": "a b"}, "webui.layout", "layout name"),
        ({"webui.colour": "red"}, "webui.colour", "unknown key"),
        ({"ros.namespace": None}, "ros.namespace", "a single value"),
    ],
)
def test_refusals_name_key_value_and_rule(settings: dict[str, object], key: str, allowed: str) -> None:
    with pytest.raises(SettingError) as exc:
        validate(settings)
    assert exc.value.key == key
    assert allowed in str(exc.value)


def test_custom_transport_must_be_a_present_profile_when_known() -> None:
    assert validate({"ros.transport": "my-fastdds"}, dds_profiles={"my-fastdds"}) == {"ros.transport": "my-fastdds"}
    with pytest.raises(SettingError, match=r"no DDS profile /var/snap/husarion-webui/common/dds-config-other.xml"):
        validate({"ros.transport": "other"}, dds_profiles={"my-fastdds"})
    assert validate({"ros.transport": "other"}) == {"ros.transport": "other"}  # presence checked when applied
    # "builtin" was a token of husarion-snap-common 0.3.x only: now a profile name like any other
    with pytest.raises(SettingError, match=r"dds-config-builtin.xml \(custom profiles there: my-fastdds;"):
        validate({"ros.transport": "builtin"}, dds_profiles={"my-fastdds", "udp", "shm"})


def test_inventory_desired_webui_is_checked(tmp_path: Path) -> None:
    path = tmp_path / "fleet.yaml"
    path.write_text("robots:\n  r1:\n    host: a\n    desired:\n      webui:\n        namespace: panther\n"
                    "        webui.port: 8081\n        transport: rmw_cyclonedds_cpp\n")
    assert load_inventory(str(path)).robots["r1"].desired["webui"]["webui.port"] == 8081
    path.write_text("robots:\n  r1:\n    host: a\n    desired:\n      webui:\n        namespace: panther\n"
                    "        ros.domain-id: 300\n")
    with pytest.raises(InputError) as exc:
        load_inventory(str(path))
    assert f"{path}:7 [robots.r1.desired.webui.ros.domain-id]" in str(exc.value)
    assert "ros.domain-id='300' is not allowed: a whole number from 0 to 232" in str(exc.value)
    assert exc.value.exit_code is ExitCode.USAGE


@pytest.mark.parametrize("value", ["８０８１", "\u0668\u0660\u0668\u0661", "8_081", " 8081x"])
def test_numbers_in_ascii_digits_only(value: str) -> None:
    """Issue 23, finding 3: the configure hook's ``^[0-9]+$`` is ASCII; re's ``\\d`` was not."""
    for key in ("webui.port", "ros.domain-id"):
        with pytest.raises(SettingError, match="ASCII digits") as exc:
            validate({key: value})
        assert exc.value.key == key


def test_one_key_named_twice_is_refused_naming_both() -> None:
    """Issue 23, finding 4: ``port`` and ``webui.port`` in one block; the later one was kept."""
    from panther_ops.core.kinds.webui_settings import SettingConflict

    for settings, says in (({"port": 8081, "webui.port": 8082}, "port=8081 and webui.port=8082 both set webui.port"),
                           ({"ros.namespace": "a", "namespace": "a"}, "both set ros.namespace"),
                           ({"domain_id": 1, "ros.domain-id": 2}, "both set ros.domain-id")):
        with pytest.raises(SettingConflict, match=says):
            validate(settings)


def test_a_robots_key_replaces_its_groups_other_name_for_it(tmp_path: Path) -> None:
    """Across blocks (a group's ``port``, the robot's ``webui.port``) the robot's is the one kept,
    without a conflict: only one name of a setting reaches the plan."""
    path = tmp_path / "fleet.yaml"
    path.write_text("groups:\n  g:\n    desired:\n      webui: {port: 8081, layout: panther}\n"
                    "      controller: {linear.x.max_velocity: 1.0}\n"
                    "robots:\n  r1:\n    host: a\n    groups: [g]\n    desired:\n      webui: {webui.port: 8082}\n"
                    "      controller: {controller.linear.x.max_velocity: 1.5}\n"
                    "  r2:\n    host: b\n    groups: [g]\n")
    robots = load_inventory(str(path)).robots
    assert robots["r1"].desired["webui"] == {"layout": "panther", "webui.port": 8082}
    assert robots["r1"].desired["controller"] == {"controller.linear.x.max_velocity": 1.5}
    assert robots["r2"].desired["webui"] == {"port": 8081, "layout": "panther"}
