"""Issue 24 finding 2 on the demo fleet: a controller file panther-ops writes keeps the IMU of a
namespaced robot (panther-02: panther_ros 2.0.4, ``namespace:=panther``; panther-03:
husarion_ugv 2.2.2, ROBOT_NAMESPACE=panther in config/common/.env)."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from panther_ops.core.kinds.controller_imu import imu_findings
from panther_ops.core.stack import stack_from_version
from tests.clirun import run

HOME = "robots/{}/home/husarion"


def test_config_set_on_a_namespaced_204_writes_a_file_that_reads_panther_imu(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "1.5",
                       "-r", "panther-02", "--yes")
    assert code == 0, err
    written = demo / HOME.format("panther-02") / "config/panther_controller/config/WH01_controller.yaml"
    doc = yaml.safe_load(written.read_text())
    imu = doc["/**"]["imu_broadcaster"]["ros__parameters"]
    assert imu["use_namespace_as_sensor_name_prefix"] is True and imu["sensor_name"] == "imu"
    found = imu_findings(doc, stack_from_version("2.0.4"), "panther")
    assert found.errors == [] and found.warnings == []


def test_config_set_on_a_robot_file_that_breaks_the_imu_says_so(
        demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The tree's file of a 2.2.2 robot in the old form (``sensor_name: imu``): the edit goes through,
    with the problem named and the fix."""
    path = demo / HOME.format("panther-03") / "config/husarion_ugv_controller/config/WH01_controller.yaml"
    path.write_text(path.read_text().replace("<namespace>/imu", "imu"))
    code, out, err = run(capsys, "-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "1.5",
                         "-r", "panther-03", "--yes")
    assert code == 0, err
    said = " ".join((out + err).split())
    assert "the IMU would not start (already so on the robot)" in said
    assert "'panther/imu'" in said and "sensor_name: <namespace>/imu" in said
