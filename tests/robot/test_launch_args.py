"""Launch-argument catalogue: names and availability per version, values, cross rules."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.kinds import arg_catalogue
from panther_ops.core.robot import arg_edits
from panther_ops.core.robot import launch_args as la
from panther_ops.core.robot.compose import ComposeFile
from panther_ops.core.stack import Stack, stack_from_version
from panther_ops.errors import UsageError

S200, S201, S204, S210, S211, S220, S222 = (
    stack_from_version(v) for v in ("2.0.0", "2.0.1", "2.0.4", "2.1.0", "2.1.1", "2.2.0", "2.2.2")
)
ROOT = Path(__file__).resolve().parents[2]


def test_catalogue_is_consistent() -> None:
    keys = [s.key for s in arg_catalogue.CATALOGUE]
    assert len(keys) == len(set(keys))
    names = [n for s in arg_catalogue.CATALOGUE for n in s.all_names()]
    assert len(names) == len(set(names))
    for s in arg_catalogue.CATALOGUE:
        if s.type is arg_catalogue.ArgType.CHOICE:
            assert s.choices and s.default_for(S222 if s.since >= (2, 2, 0) else S211) in s.choices_for(S222)


@pytest.mark.parametrize(
    ("stack", "key", "available"),
    [
        (S200, "disable_manager", False),
        (S201, "disable_manager", True),
        (S201, "components_config_path", False),
        (S204, "components_config_path", True),
        (S210, "launch_nmea_gps", False),
        (S211, "launch_nmea_gps", True),
        (S211, "common_dir_path", False),
        (S220, "common_dir_path", True),
        (S201, "ekf_config_path", True),
        (S204, "ekf_config_path", False),
        (S204, "localization_mode", True),
        (S201, "localization_mode", False),
        (S200, "simulation_engine", True),
        (S211, "simulation_engine", False),
        (S222, "robot_model", True),
    ],
)
def test_availability_per_version(stack: object, key: str, available: bool) -> None:
    assert la.spec(key).available(stack) is available
    if not available:
        with pytest.raises(la.UnavailableArgError):
            la.validate_arg(stack, key, "True")  # type: ignore[arg-type]


def test_nmea_launch_file_arguments_of_211() -> None:
    """Issue 24 finding 4: panther_ros@2.1.1:panther_localization/launch/nmea_navsat.launch.py
    (included by localization.launch.py with launch_nmea_gps) declares params_file and
    device_namespace; husarion_ugv 2.2 calls the first nmea_params_path and fixes the second to gps."""
    params, device = la.spec("params_file"), la.spec("device_namespace")
    assert la.spec("nmea_params_path") is params
    assert [params.available(s) for s in (S210, S211, S220, S222)] == [False, True, True, True]
    assert [device.available(s) for s in (S210, S211, S220, S222)] == [False, True, False, False]
    assert (params.name_for(S211), params.name_for(S222)) == ("params_file", "nmea_params_path")
    assert params.default_for(S211) == "$(find panther_localization)/config/nmea_navsat_params.yaml"
    assert params.default_for(S222) == "$(find husarion_ugv_localization)/config/nmea_navsat.yaml"
    assert device.default_for(S211) == "gps"
    assert la.validate_arg(S211, "params_file", "/config/p.yaml").name == "params_file"
    assert la.validate_arg(S211, "device_namespace", "gnss").value == "gnss"
    assert arg_edits.migrate_args(S211, S222, {"params_file": "/x.yaml", "device_namespace": "gps"}) == \
        arg_edits.ArgMigration({"params_file": "nmea_params_path"}, ("device_namespace",))


def test_names_per_version_and_aliases() -> None:
    assert la.validate_arg(S211, "led_config_file", "/config/x.yaml").name == "led_config_file"
    v = la.validate_arg(S222, "led_config_file", "/config/x.yaml")
    assert v.name == "animations_config_path" and "called animations_config_path" in v.warnings[0]
    v = la.validate_arg(S211, "animations_config_path", "/config/x.yaml")
    assert (v.key, v.name) == ("led_config_file", "led_config_file")
    assert la.validate_arg(S222, "user_led_animations_file", "/c/u.yaml").name == "user_led_animations_path"
    alias = la.validate_arg(S211, "user_animations_file", "/c/u.yaml")
    assert alias.name == "user_led_animations_file" and "not a declared launch argument" in alias.warnings[0]


@pytest.mark.parametrize(
    ("stack", "value", "written"),
    [(S211, "true", "True"), (S211, "FALSE", "False"), (S201, "1", "True"), (S222, "True", "true"), (S222, "0", "false")],
)
def test_booleans_are_normalised_as_the_stack_expects(stack: object, value: str, written: str) -> None:
    assert la.validate_arg(stack, "disable_manager", value).value == written  # type: ignore[arg-type]


def test_bad_values_list_what_is_allowed() -> None:
    with pytest.raises(la.InvalidArgValueError, match="allowed: True, False"):
        la.validate_arg(S211, "use_ekf", "maybe")
    with pytest.raises(la.InvalidArgValueError, match="allowed: relative, enu"):
        la.validate_arg(S211, "localization_mode", "gps")
    with pytest.raises(la.InvalidArgValueError, match=r"\$\(find <package>\)"):
        la.validate_arg(S211, "controller_config_path", "config/WH01_controller.yaml")
    with pytest.raises(la.InvalidArgValueError):
        la.validate_arg(S211, "namespace", "1robot")
    with pytest.raises(la.InvalidArgValueError, match="DEBUG, INFO"):
        la.validate_arg(S222, "log_level", "verbose")
    assert la.validate_arg(S222, "log_level", "debug").value == "DEBUG"
    assert la.validate_arg(S211, "wheel_type", "wh02").value == "WH02"
    assert la.validate_arg(S211, "namespace", "fleet/panther_01").value == "fleet/panther_01"
    assert la.validate_arg(S211, "components_config_path", "None").value == "None"
    assert la.validate_arg(S211, "wheel_config_path", "$(find panther_description)/config/WH02.yaml")
    assert issubclass(la.InvalidArgValueError, UsageError)


def test_unknown_keys_suggest_and_force_passes() -> None:
    with pytest.raises(la.UnknownArgError) as err:
        la.validate_arg(S211, "wheel_typ", "WH01")
    assert "wheel_type" in str(err.value)
    forced = la.validate_arg(S211, "my_arg", "x", force=True)
    assert forced.name == "my_arg" and forced.warnings


def test_wh05_is_lynx_only() -> None:
    with pytest.raises(la.InvalidArgValueError, match="WH01, WH02, WH04, custom"):
        la.validate_arg(S211, "wheel_type", "WH05")
    with pytest.raises(la.InvalidArgValueError, match="Lynx wheel"):
        la.validate_arg(S222, "wheel_type", "WH05", context={"robot_model": "panther"})
    assert la.validate_arg(S222, "wheel_type", "WH05", context={"robot_model": "lynx"}).value == "WH05"
    forced = la.validate_arg(S222, "wheel_type", "WH05", force=True, context={"robot_model": "panther"})
    assert "(forced)" in forced.warnings[-1]
    # issue 24 finding 8: no robot known yet (the pre-check of `config set`): a choice of 2.2, not refused;
    # a robot whose model is not known: said, not refused
    assert la.validate_arg(S222, "wheel_type", "WH05").warnings == ()
    assert "model is not known" in la.validate_arg(S222, "wheel_type", "WH05", context={}).warnings[0]


def test_battery_config_is_simulation_only_before_2_2() -> None:
    assert "only matters in simulation" in la.validate_arg(S211, "battery_config_path", "/c/b.yaml").warnings[0]
    assert la.validate_arg(S211, "battery_config_path", "/c/b.yaml", simulation=True).warnings == ()
    assert la.validate_arg(S222, "battery_config_path", "/config/b.yaml").warnings == ()


def test_defaults_per_version() -> None:
    shutdown = la.spec("shutdown_hosts_config_path")
    assert shutdown.default_for(S210) == "$(find panther_bringup)/config/shutdown_hosts.yaml"
    assert shutdown.default_for(S211) == "$(find panther_manager)/config/shutdown_hosts_config.yaml"
    assert "husarion_ugv_manager/config/shutdown_hosts.yaml" in shutdown.default_for(S222)
    assert la.spec("wheel_type").default_for(S211) == "WH01"
    assert la.bool_word(S211, True) == "True" and la.bool_word(S222, True) == "true"
    assert len(la.args_for(S222)) > len(la.args_for(S200))


def _messages(findings: list[la.Finding], level: str) -> list[str]:
    return [f.rule for f in findings if f.level == level]


def test_cross_rules() -> None:
    assert _messages(la.check_args(S211, {"wheel_type": "custom"}), "error") == ["custom-wheels"]
    ok = {"wheel_type": "custom", "wheel_config_path": "/c/w.yaml", "controller_config_path": "/c/c.yaml"}
    assert _messages(la.check_args(S211, ok), "error") == []
    assert _messages(la.check_args(S222, {"wheel_type": "WH05"}, robot_model="panther"), "error") == ["wh05-lynx"]
    assert _messages(la.check_args(S222, {"wheel_type": "WH05"}), "warning") == ["wh05-lynx"]  # model unknown
    assert _messages(la.check_args(S222, {"wheel_type": "WH05"}, robot_model="lynx"), "error") == []
    assert _messages(la.check_args(S222, {"wheel_type": "WH05", "robot_model": "lynx"}), "error") == []
    assert "battery-sim-only" in _messages(la.check_args(S211, {"battery_config_path": "/x.yaml"}), "warning")
    assert "gps-source" in _messages(la.check_args(S211, {"fuse_gps": "True"}), "warning")
    assert "gps-source" not in _messages(la.check_args(S211, {"fuse_gps": "True", "launch_nmea_gps": "True"}), "warning")
    assert "enu-without-gps" in _messages(la.check_args(S211, {"localization_mode": "enu"}), "warning")


def test_names_of_other_versions_in_a_command_are_errors() -> None:
    findings = la.check_args(S222, {"led_config_file": "/x", "user_animations_file": "/y", "typo_arg": "1"})
    assert sorted(_messages(findings, "error")) == ["declared-name", "declared-name"]
    assert _messages(findings, "warning") == ["unknown-arg"]
    assert _messages(la.check_args(S204, {"launch_nmea_gps": "True"}), "error") == ["unavailable-arg"]
    with pytest.raises(la.ArgConflictError):
        la.raise_for_errors(findings)
    assert len(la.raise_for_errors(findings, force=True)) == 3


def test_paths_outside_volumes_are_flagged() -> None:
    compose = ComposeFile.parse((ROOT / "templates/compose/husarion-ugv-2.2.2.yaml").read_text())
    findings = la.check_args(S222, {"controller_config_path": "/elsewhere/c.yaml", "common_dir_path": "/config"},
                             volumes=compose.list_volumes())
    assert [f.keys for f in findings if f.rule == "path-mounted"] == [("controller_config_path",)]


def test_migrate_args() -> None:
    m = arg_edits.migrate_args(S211, S222, {"led_config_file": "/a", "user_animations_file": "/b", "wheel_type": "WH01"})
    assert m.renamed == {"led_config_file": "animations_config_path", "user_animations_file": "user_led_animations_path"}
    assert arg_edits.migrate_args(S201, S204, {"ekf_config_path": "/e"}).dropped == ("ekf_config_path",)


def test_set_launch_args_on_a_compose_file() -> None:
    compose = ComposeFile.parse((ROOT / "tests/golden/inputs/compose-2.1-folded-command.yaml").read_text())
    with pytest.raises(la.ArgConflictError):
        arg_edits.set_launch_args(compose, {"wheel_type": "custom"})
    assert not compose.changed
    change = arg_edits.set_launch_args(compose, {"user_animations_file": "/config/panther_lights/config/user.yaml"})
    assert change.changed and compose.args["user_led_animations_file"] == "/config/panther_lights/config/user.yaml"
    assert "user_animations_file" not in compose.args
    same = arg_edits.set_launch_args(compose, {"wheel_type": "WH04"})
    assert same.changed is False
    assert arg_edits.unset_launch_arg(compose, "user_led_animations_path").changed
    assert "user_led_animations_file" not in compose.args


def test_stale_alias_in_command_is_replaced() -> None:
    text = ("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n"
            "    volumes: [/home/husarion/config:/config]\n"
            "    command: ros2 launch panther_bringup bringup.launch.py user_animations_file:=/config/a.yaml\n")
    compose = ComposeFile.parse(text)
    change = arg_edits.set_launch_args(compose, {"user_led_animations_file": "/config/b.yaml"})
    assert compose.args == {"user_led_animations_file": "/config/b.yaml"}
    assert any("replaced user_animations_file" in w for w in change.warnings)


# issue 23 item 9: a path argument is a path inside the container, of the characters config paths have
@pytest.mark.parametrize(("value", "bad"), [
    ("/config/a;b.yaml", "';'"), ("/config/my ctrl.yaml", "' '"), ("/config/x$(id).yaml", "'$'"),
    ("/config/é.yaml", "'é'"), ("/config/a|b.yaml", "'|'"), ("/config/a&&b.yaml", "'&'"), ("/config/~x.yaml", "'~'"),
    ("$(find panther_controller)/config/a b.yaml", "' '"), ("/config/x'.yaml", '"\'"'), ("/config/a:b.yaml", "':'"),
])
def test_path_characters_are_refused_even_forced(value: str, bad: str) -> None:
    for force in (False, True):
        with pytest.raises(la.InvalidArgValueError) as exc:
            la.validate_arg(S211, "controller_config_path", value, force=force)
        assert f"{bad} is not a character of a config path" in str(exc.value)
        assert "ASCII letters, digits, '_', '.', '+', '-' and '/'" in str(exc.value)


def test_path_with_dotdot_is_refused() -> None:
    with pytest.raises(la.InvalidArgValueError, match=r"holds '\.\.'"):
        la.validate_arg(S222, "controller_config_path", "/config/../etc/WH01_controller.yaml", force=True)


@pytest.mark.parametrize("value", ["/config/husarion_ugv_controller/config/WH01+mine_v-1.2.yaml",
                                   "$(find panther_controller)/config/WH01_controller.yaml",
                                   "$(find-pkg-share panther_controller)/config/WH01_controller.yaml",
                                   "${CONFIG_DIR:-/config}/WH01_controller.yaml", "/config/${MODEL}_controller.yaml"])
def test_paths_of_config_characters_pass(value: str) -> None:
    assert la.validate_arg(S222, "controller_config_path", value).value == value


def test_a_path_no_volume_mounts_is_an_error_naming_the_mounts() -> None:
    compose = ComposeFile.parse((ROOT / "templates/compose/husarion-ugv-2.2.2.yaml").read_text())
    volumes = compose.list_volumes()
    [found] = [f for f in la.check_args(S222, {"controller_config_path": "/elsewhere/c.yaml"}, volumes=volumes)
               if f.rule == "path-mounted"]
    assert found.level == "error"
    assert "/config" in found.message and "/root/.ssh/id_rsa" in found.message
    assert "the driver cannot open it" in found.message
    image = "/ros2_ws/install/husarion_ugv_controller/share/husarion_ugv_controller/config/WH01_controller.yaml"
    [warning] = [f for f in la.check_args(S222, {"controller_config_path": image}, volumes=volumes)
                 if f.rule == "path-mounted"]
    assert warning.level == "warning" and "must exist in the image" in warning.message
    assert not [f for f in la.check_args(S222, {"controller_config_path": "/config//x/./c.yaml"},
                                                volumes=volumes) if f.rule == "path-mounted"]


def test_set_launch_args_refuses_an_unmounted_path_even_one_it_did_not_change() -> None:
    text = ("services:\n  panther_ros:\n    image: husarion/panther:humble-2.1.1-20240828\n"
            "    volumes: [/home/husarion/config:/config]\n"
            "    command: ros2 launch panther_bringup bringup.launch.py controller_config_path:=/elsewhere/c.yaml\n")
    compose = ComposeFile.parse(text)
    with pytest.raises(la.ArgConflictError, match=r"controller_config_path=/elsewhere/c.yaml is neither inside"):
        arg_edits.set_launch_args(compose, {"wheel_type": "WH02"})
    assert not compose.changed
    forced = arg_edits.set_launch_args(compose, {"wheel_type": "WH02"}, force=True)
    assert any("the driver cannot open it" in w and w.endswith("(forced)") for w in forced.warnings)


S230, S231, S232 = (stack_from_version(v) for v in ("2.3.0", "2.3.1", "2.3.2"))


@pytest.mark.parametrize(
    ("stack", "key", "available"),
    [
        (S222, "publish_robot_state", True),  # husarion_ugv_ros@2.2.2:husarion_ugv_controller/launch/controller.launch.py
        (S230, "publish_robot_state", False),  # gone from it on 2.3.0-2.3.2
        (S232, "publish_robot_state", False),
        (S230, "launch_gamepad", False),  # 2.3.0 (branched after 2.2.1): the gamepad_controller compose service
        (S231, "launch_gamepad", True),  # bringup.launch.py, as 2.2.2
        (S232, "launch_gamepad", True),  # husarion_ugv_teleop/launch/teleop.launch.py
        (S231, "use_madgwick_filter", False),
        (S232, "use_madgwick_filter", True),  # controller.launch.py and load_urdf.launch.py of 2.3.2
        (S222, "use_madgwick_filter", False),
    ],
)
def test_availability_on_jazzy(stack: Stack, key: str, available: bool) -> None:
    assert la.spec(key).available(stack) is available


def test_jazzy_defaults_and_where_they_are_read_from() -> None:
    """2.3.0 reads the animations from the image (as 2.2.0); 2.3.1 and 2.3.2 from ~/config (as 2.2.2)."""
    anim = la.spec("led_config_file")
    assert anim.default_for(S230).startswith("$(find husarion_ugv_lights)/") and not anim.default_in_tree(S230)
    assert anim.default_in_tree(S231) and anim.default_in_tree(S232)
    assert la.spec("use_madgwick_filter").default_for(S232) == "False"
    assert la.spec("launch_gamepad").availability() == "2.2.2+ but 2.3.0"
    assert la.validate_arg(S232, "use_madgwick_filter", "TRUE").value == "true"


def test_launch_gamepad_false_is_refused_where_the_gamepad_always_runs() -> None:
    """husarion_ugv_ros@2.3.2:bringup.launch.py includes teleop with launch_gamepad True: false has no effect."""
    with pytest.raises(UsageError, match=r"launch_gamepad:=false has no effect on husarion_ugv 2\.3\.2"):
        la.validate_arg(S232, "launch_gamepad", "false")
    forced = la.validate_arg(S232, "launch_gamepad", "false", force=True)
    assert forced.value == "false" and any("(forced)" in w for w in forced.warnings)
    assert la.validate_arg(S231, "launch_gamepad", "false").value == "false"  # 2.3.1's bringup honours it
    assert la.validate_arg(S232, "launch_gamepad", "true").value == "true"
    with pytest.raises(UsageError, match="gamepad_controller"):  # 2.3.0: the compose service
        la.validate_arg(S230, "launch_gamepad", "true")
    with pytest.raises(UsageError, match=r"publish_robot_state needs .*2\.0\.0-2\.2\.2"):
        la.validate_arg(S232, "publish_robot_state", "true")
