"""Controller limits: keys, wheel limits, controller key per version, default files."""

from __future__ import annotations

import math

import pytest

from panther_ops.core.kinds import FileKind, FileKindError
from panther_ops.core.kinds import controller_limits as lim
from panther_ops.core.robot import controller as ctl
from panther_ops.core.robot.files import config_file
from panther_ops.core.stack import Stack, stack_from_version
from panther_ops.errors import UsageError

S204, S211, S222 = (stack_from_version(v) for v in ("2.0.4", "2.1.1", "2.2.2"))


def test_parse_limit_keys() -> None:
    assert lim.parse_limit_key("controller.linear.x.max_velocity") == lim.LimitKey("linear.x", "max_velocity")
    assert lim.parse_limit_key("angular.z.has_jerk_limits").dotted == "controller.angular.z.has_jerk_limits"
    assert lim.LimitKey("angular.z", "max_acceleration").unit == "rad/s²"
    assert lim.LimitKey("linear.x", "max_acceleration").path("drive_controller") == (
        "/**", "drive_controller", "ros__parameters", "linear", "x", "max_acceleration")
    with pytest.raises(lim.ControllerError, match="max_velocity"):
        lim.parse_limit_key("controller.linear.z.max_velocity")
    assert "controller.linear.y.max_velocity" in lim.all_limit_keys("WH02")
    assert "controller.linear.y.max_velocity" not in lim.all_limit_keys("WH01")


@pytest.mark.parametrize(
    ("wheel", "key", "limit"),
    [
        ("WH01", "controller.linear.x.max_velocity", 2.0),
        ("WH01", "controller.linear.x.max_acceleration", 2.7),
        ("WH01", "controller.angular.z.max_velocity", 4.0),
        ("WH01", "controller.angular.z.max_acceleration", 5.74),
        ("WH02", "controller.linear.y.max_velocity", 1.1),
        ("WH04", "controller.linear.x.max_acceleration", 1.5),
        ("WH04", "controller.angular.z.max_velocity", 2.2),
        ("WH02", "controller.angular.z.max_acceleration", 3.2),
    ],
)
def test_wheel_limits_are_enforced(wheel: str, key: str, limit: float) -> None:
    assert lim.validate_limit(S211, wheel, key, limit).value == limit
    with pytest.raises(lim.LimitExceededError) as err:
        lim.validate_limit(S211, wheel, key, limit + 0.1)
    assert f"exceeds the {wheel} limit of {limit}" in str(err.value) and isinstance(err.value, UsageError)
    forced = lim.validate_limit(S211, wheel, key, limit + 0.1, force=True)
    assert forced.value == pytest.approx(limit + 0.1) and "(forced)" in forced.warnings[0]


def test_value_checks() -> None:
    assert lim.validate_limit(S211, "WH01", "controller.linear.x.has_velocity_limits", "False").value is False
    assert lim.validate_limit(S211, "WH01", "controller.linear.x.max_velocity", "1").value == 1.0
    with pytest.raises(lim.ControllerError, match="not a number"):
        lim.validate_limit(S211, "WH01", "controller.linear.x.max_velocity", "fast")
    with pytest.raises(lim.ControllerError, match="not a boolean"):
        lim.validate_limit(S211, "WH01", "controller.linear.x.has_jerk_limits", "yes please")
    with pytest.raises(lim.ControllerError, match="negative"):
        lim.validate_limit(S211, "WH01", "controller.linear.x.max_velocity", -1)
    with pytest.raises(lim.ControllerError, match="positive"):
        lim.validate_limit(S211, "WH01", "controller.linear.x.min_velocity", 1)
    with pytest.raises(lim.ControllerError, match="mecanum"):
        lim.validate_limit(S211, "WH01", "controller.linear.y.max_velocity", 1)
    with pytest.raises(lim.ControllerError, match="finite"):
        lim.validate_limit(S211, "WH01", "controller.linear.x.max_jerk", "inf")
    custom = lim.validate_limit(S211, "custom", "controller.linear.x.max_velocity", 3.0)
    assert "no reference limits" in custom.warnings[0]


@pytest.mark.parametrize("stack", [S204, S211, S222], ids=["2.0.4", "2.1.1", "2.2.2"])
@pytest.mark.parametrize("wheel", ["WH01", "WH02", "WH04"])
def test_default_files_carry_the_wheel_limits(stack: object, wheel: str) -> None:
    config = ctl.ControllerConfig.default(stack, wheel)  # type: ignore[arg-type]
    assert config.controller_key == stack.controller_key  # type: ignore[attr-defined]
    limits = lim.WHEEL_LIMITS[wheel]
    assert config.get("controller.linear.x.max_velocity") == limits.linear_velocity
    assert config.get("controller.linear.x.max_acceleration") == limits.linear_acceleration
    assert config.get("controller.angular.z.max_velocity") == limits.angular_velocity
    assert config.get("controller.angular.z.max_acceleration") == limits.angular_acceleration
    assert (config.get("controller.linear.y.max_velocity") is not None) == (wheel == "WH02")
    assert config.check() == []
    assert ctl.default_controller_text(stack, wheel) == config.text()  # type: ignore[arg-type]


def test_controller_key_must_match_the_stack() -> None:
    old = ctl.default_controller_text(S204, "WH01")
    with pytest.raises(lim.ControllerFileError, match="drive_controller"):
        ctl.ControllerConfig.parse(old, S211, "WH01", path="/config/WH01_controller.yaml")
    forced = ctl.ControllerConfig.parse(old, S211, "WH01", force=True)
    assert forced.controller_key == "panther_base_controller" and forced.doc.notes
    with pytest.raises(lim.ControllerFileError, match="no drive_controller"):
        ctl.ControllerConfig.parse("a: 1\n", S211, "WH01")


def test_set_unset_and_check() -> None:
    config = ctl.ControllerConfig.default(S211, "WH01")
    original = config.text()
    change = config.set("controller.linear.x.max_velocity", 1.5)
    assert change == ctl.LimitChange(True, "controller.linear.x.max_velocity", 1.5, ())
    assert config.set("controller.linear.x.max_velocity", "1.5").changed is False
    config.set("controller.linear.x.has_jerk_limits", True)
    assert any("limited to zero" in w for w in config.check())
    config.set("controller.linear.x.has_jerk_limits", False)
    config.set("controller.linear.x.min_velocity", -1.0)
    assert config.limits()["controller.linear.x.min_velocity"] == -1.0
    assert config.unset("controller.linear.x.min_velocity") is True
    config.set("controller.linear.x.max_velocity", 2.0)
    assert config.text() == original
    config.set("controller.linear.x.max_velocity", 2.5, force=True)
    assert any("exceeds" in w for w in config.check())


def test_no_default_for_custom_or_wh05_before_22() -> None:
    with pytest.raises(UsageError, match="custom"):
        ctl.default_controller_text(S211, "custom")
    with pytest.raises(UsageError):
        config_file(S211, FileKind.CONTROLLER, wheel_type="WH05")
    # husarion_ugv_ros@2.2.2:husarion_ugv_controller/config/WH05_controller.yaml (the Lynx wheels)
    assert "wheel_radius: 0.144" in ctl.default_controller_text(S222, "WH05")


S230 = Stack("husarion/husarion-ugv:jazzy-2.3.0-20250425", "jazzy", (2, 3, 0), "20250425")
S232 = Stack("husarion/husarion-ugv:jazzy-2.3.2-20260622", "jazzy", (2, 3, 2), "20260622")
"""husarion_ugv 2.3 (ROS 2 Jazzy): the stacks its image tags give (core/stack.py does not accept them yet)."""


@pytest.mark.parametrize("stack", [S230, S232], ids=["2.3.0", "2.3.2"])
def test_jazzy_limits_schema(stack: Stack) -> None:
    """ros2_controllers' jazzy schema: deceleration and reverse limits, .nan for no limit, signs per parameter."""
    assert lim.validate_limit(stack, "WH01", "controller.linear.x.max_deceleration", "-2.7").value == -2.7
    assert lim.validate_limit(stack, "WH01", "controller.angular.z.max_deceleration_reverse", 5.74).value == 5.74
    assert math.isnan(lim.validate_limit(stack, "WH01", "controller.linear.x.max_jerk", ".nan").value)
    assert math.isnan(lim.validate_limit(stack, "WH01", "controller.linear.x.max_velocity", float("nan")).value)
    with pytest.raises(lim.ControllerError, match="must not be positive"):
        lim.validate_limit(stack, "WH01", "controller.linear.x.max_acceleration_reverse", 1.0)
    with pytest.raises(lim.ControllerError, match="must not be negative"):
        lim.validate_limit(stack, "WH01", "controller.linear.x.max_deceleration_reverse", -1.0)
    with pytest.raises(lim.LimitExceededError, match="WH04 limit"):
        lim.validate_limit(stack, "WH04", "controller.linear.x.max_deceleration", -1.6)
    with pytest.raises(lim.ControllerError, match=r"\.nan for no limit"):
        lim.validate_limit(stack, "WH01", "controller.linear.x.has_velocity_limits", "true")
    with pytest.raises(lim.ControllerError, match="max_deceleration"):
        lim.validate_limit(stack, "WH01", "controller.linear.x.min_acceleration", -1.0)
    with pytest.raises(lim.ControllerError, match="finite"):
        lim.validate_limit(stack, "WH01", "controller.linear.x.max_jerk", "inf")


def test_jazzy_limits_are_refused_on_humble() -> None:
    with pytest.raises(lim.ControllerError, match=r"husarion_ugv 2\.3"):
        lim.validate_limit(S222, "WH01", "controller.linear.x.max_deceleration", -1.0)
    with pytest.raises(lim.ControllerError, match="finite"):
        lim.validate_limit(S222, "WH01", "controller.linear.x.max_jerk", ".nan")


@pytest.mark.parametrize("stack", [S230, S232], ids=["2.3.0", "2.3.2"])
@pytest.mark.parametrize("wheel", ["WH01", "WH02", "WH04", "WH05"])
def test_jazzy_default_files_are_accepted_and_carry_the_wheel_limits(stack: Stack, wheel: str) -> None:
    from panther_ops.core.kinds import Target, check_file

    config = ctl.ControllerConfig.default(stack, wheel)
    assert check_file(FileKind.CONTROLLER, "f", config.text().encode(), target=Target(stack, wheel)) == []
    limits = lim.WHEEL_LIMITS[wheel]
    got = config.limits()
    assert got["controller.linear.x.max_deceleration"] == -limits.linear_acceleration
    assert got["controller.angular.z.min_velocity"] == -limits.angular_velocity
    assert math.isnan(got["controller.angular.z.min_jerk"])
    assert "controller.linear.x.has_velocity_limits" not in got
    humble = ctl.ControllerConfig.default(S222, wheel).text().encode()
    with pytest.raises(FileKindError, match="not a limit of husarion_ugv"):
        check_file(FileKind.CONTROLLER, "f", humble, target=Target(stack, wheel))


def test_covariance_placeholder_is_filled_from_2_3_2_only() -> None:
    from panther_ops.core.kinds import Target, check_file

    text = ctl.ControllerConfig.default(S232, "WH01").text()
    assert "<static_covariance_orientation>" in text
    assert check_file(FileKind.CONTROLLER, "f", text.encode(), target=Target(S232, "WH01")) == []
    with pytest.raises(FileKindError, match="replaces no placeholder"):
        check_file(FileKind.CONTROLLER, "f", text.encode(), target=Target(S230, "WH01"))


def test_jazzy_stock_limits_compare_equal_despite_nan() -> None:
    """A 2.3 file's NaN jerk (NaN != NaN) read as another NaN object: still the same limits, so a
    wheel change sees the stock limits as stock (core/robot/wheel_change.py)."""
    a = ctl.ControllerConfig.default(S232, "WH01").limits()
    b = {k: float("nan") if isinstance(v, float) and math.isnan(v) else v for k, v in a.items()}
    assert a != b  # plain equality fails on distinct NaN objects
    assert lim.same_limits(a, b)
    b["controller.linear.x.max_velocity"] = 1.0
    assert not lim.same_limits(a, b)


def test_twist_mux_is_needed_from_2_3_2() -> None:
    """2.3.2 spawns twist_mux_controller with the drive controller as a group: a 2.3.0 file (no mux)
    starts no controller there; 2.3.2's file on 2.3.1 declares a mux nobody spawns."""
    from panther_ops.core.kinds import Target, check_file

    file_230 = ctl.ControllerConfig.default(S230, "WH01").text().encode()
    with pytest.raises(FileKindError, match="activate-as-group"):
        check_file(FileKind.CONTROLLER, "f", file_230, target=Target(S232, "WH01"))
    forced = check_file(FileKind.CONTROLLER, "f", file_230, target=Target(S232, "WH01"), force=True)
    assert any("(forced)" in w for w in forced)
    file_232 = ctl.ControllerConfig.default(S232, "WH02").text()
    s231 = Stack("husarion/husarion-ugv:jazzy-2.3.1-20250701", "jazzy", (2, 3, 1), "20250701")
    no_placeholder = file_232.replace("<static_covariance_orientation>", "[1.8e-3, 0.0, 0.0, 0.0, 1.8e-3, 0.0, 0.0, "
                                                                          "0.0, 1.8e-3]")
    (warning,) = check_file(FileKind.CONTROLLER, "f", no_placeholder.encode(), target=Target(s231, "WH02"))
    assert "spawns no twist mux" in warning
    manual = "          timeout: 0.2\n          priority: 100\n"
    assert manual in file_232
    broken = file_232.replace(manual, "          timeout: 0\n          priority: high\n")
    with pytest.raises(FileKindError, match=r"manual\.timeout=0 .*\n.*manual\.priority='high'"):
        check_file(FileKind.CONTROLLER, "f", broken.encode(), target=Target(S232, "WH02"))
