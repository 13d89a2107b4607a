"""Issue 24 finding 2: a controller file's IMU broadcaster must read the IMU the URDF names
``${ns}imu`` under the robot's namespace (facts and sources: panther_ops/core/kinds/controller_imu.py).

The stock values below are upstream's at each tag (distilled, not copied): every supported
tag's stock file is accepted with and without a namespace, the templates carry the same
values, and the form the templates had before (no prefix flag, no ``<namespace>/``) is
refused on a namespaced robot.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.kinds import FileKind, FileKindError, Target, check_file
from panther_ops.core.kinds.controller_imu import imu_findings
from panther_ops.core.robot.files import config_file
from panther_ops.core.stack import stack_from_version

ROOT = Path(__file__).resolve().parents[2]

STOCK_IMU: dict[str, dict[str, Any]] = {
    # panther_ros@2.0.4:panther_controller/config/WH0{1,2,4}_controller.yaml
    "2.0.4": {"use_namespace_as_sensor_name_prefix": True, "sensor_name": "imu", "frame_id": "imu_link"},
    # panther_ros@2.1.1:panther_controller/config/WH0{1,2,4}_controller.yaml
    "2.1.1": {"use_namespace_as_sensor_name_prefix": True, "sensor_name": "imu", "frame_id": "imu_link"},
    # husarion_ugv_ros@2.2.0:husarion_ugv_controller/config/WH0{1,2,4,5}_controller.yaml
    "2.2.0": {"use_namespace_as_sensor_name_prefix": True, "sensor_name": "imu", "frame_id": "imu_link"},
    # husarion_ugv_ros@2.2.2:husarion_ugv_controller/config/WH0{1,2,4,5}_controller.yaml
    "2.2.2": {"sensor_name": "<namespace>/imu", "frame_id": "<namespace>/imu_link"},
}
OLD_TEMPLATE_IMU = {"sensor_name": "imu", "frame_id": "imu_link"}
"""What panther-ops' templates said before issue 24 (every version)."""


def imu_params(text: str) -> dict[str, Any]:
    params = yaml.safe_load(text)["/**"]["imu_broadcaster"]["ros__parameters"]
    return {k: v for k, v in params.items() if not k.startswith("static_covariance")}


def with_imu(version: str, imu: dict[str, Any], wheel: str = "WH01") -> bytes:
    """The template of ``version`` with the IMU broadcaster's parameters replaced by ``imu``."""
    doc = yaml.safe_load(config_file(stack_from_version(version), FileKind.CONTROLLER, wheel_type=wheel)
                         .template_text())
    params = doc["/**"]["imu_broadcaster"]["ros__parameters"]
    for key in ("use_namespace_as_sensor_name_prefix", "sensor_name", "frame_id"):
        params.pop(key, None)
    params.update(imu)
    return yaml.safe_dump(doc, sort_keys=False).encode()


@pytest.mark.parametrize("version", sorted(STOCK_IMU))
@pytest.mark.parametrize("wheel", ["WH01", "WH02", "WH04"])
def test_templates_carry_the_stock_imu_parameters(version: str, wheel: str) -> None:
    text = config_file(stack_from_version(version), FileKind.CONTROLLER, wheel_type=wheel).template_text()
    assert imu_params(text) == STOCK_IMU[version]


@pytest.mark.parametrize("version", sorted(STOCK_IMU))
@pytest.mark.parametrize("namespace", ["", "panther", "/robot_7"])
def test_the_stock_file_is_accepted_with_and_without_a_namespace(version: str, namespace: str) -> None:
    target = Target(stack_from_version(version), "WH01", namespace)
    warnings = check_file(FileKind.CONTROLLER, "stock.yaml", with_imu(version, STOCK_IMU[version]), target=target)
    assert not [w for w in warnings if "imu" in w.lower()], warnings


@pytest.mark.parametrize("version", sorted(STOCK_IMU))
def test_the_old_template_form_is_refused_on_a_namespaced_robot(version: str) -> None:
    target = Target(stack_from_version(version), "WH01", "panther")
    with pytest.raises(FileKindError) as info:
        check_file(FileKind.CONTROLLER, "ctrl.yaml", with_imu(version, OLD_TEMPLATE_IMU), target=target)
    message = info.value.message
    assert "imu_broadcaster" in message and "'imu'" in message and "'panther/imu'" in message
    assert "ctrl.yaml" in message
    assert ("use_namespace_as_sensor_name_prefix: true" if version <= "2.2.0" else "<namespace>/imu") \
        in (info.value.hint or "")


@pytest.mark.parametrize("version", sorted(STOCK_IMU))
def test_the_old_form_works_without_a_namespace_but_says_so(version: str) -> None:
    target = Target(stack_from_version(version), "WH01", "")
    warnings = check_file(FileKind.CONTROLLER, "ctrl.yaml", with_imu(version, OLD_TEMPLATE_IMU), target=target)
    assert any("works only while the robot has no namespace" in w for w in warnings), warnings


def test_forced_the_refusal_becomes_a_warning() -> None:
    target = Target(stack_from_version("2.0.4"), "WH01", "panther")
    warnings = check_file(FileKind.CONTROLLER, "ctrl.yaml", with_imu("2.0.4", OLD_TEMPLATE_IMU), target=target,
                          force=True)
    assert any("'panther/imu'" in w and w.endswith("(forced)") for w in warnings)


@pytest.mark.parametrize("version", ["2.0.4", "2.1.1", "2.2.0"])
def test_the_22_placeholder_is_not_replaced_before_221(version: str) -> None:
    """``<namespace>/imu`` (2.2.1+'s stock form) on a stack without ReplaceString: never the IMU."""
    for namespace in ("", "panther", None):
        with pytest.raises(FileKindError, match="does not replace '<namespace>'"):
            check_file(FileKind.CONTROLLER, "c.yaml", with_imu(version, STOCK_IMU["2.2.2"]),
                       target=Target(stack_from_version(version), "WH01", namespace))


def test_22x_frame_without_the_namespace_is_a_warning() -> None:
    found = imu_findings(yaml.safe_load(with_imu("2.2.2", {"sensor_name": "<namespace>/imu", "frame_id": "imu_link"})),
                         stack_from_version("2.2.2"), "panther")
    assert not found.errors
    assert any("frame 'imu_link'" in w and "<namespace>/imu_link" in w for w in found.warnings)


def test_a_file_written_for_this_namespace_is_accepted() -> None:
    """Without the flag, the sensor name as written: ``panther/imu`` is right under ``panther`` only."""
    data = with_imu("2.1.1", {"sensor_name": "panther/imu", "frame_id": "imu_link"})
    assert not [w for w in check_file(FileKind.CONTROLLER, "c.yaml", data,
                                      target=Target(stack_from_version("2.1.1"), "WH01", "panther")) if "imu" in w]
    with pytest.raises(FileKindError, match="'rover/imu'"):
        check_file(FileKind.CONTROLLER, "c.yaml", data, target=Target(stack_from_version("2.1.1"), "WH01", "rover"))
