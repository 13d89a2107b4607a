"""Which compose edits the robot's `docker compose config` need not check: only a service's
`command` or `image` text changed (values compared after loading both files)."""

from __future__ import annotations

import pytest

from panther_ops.core.fleet.pipeline import _compare_values

BASE = b"""\
x-common-config: &common
  network_mode: host
  restart: always
services:
  panther_ros:
    <<: *common
    image: husarion/panther:humble-2.1.1-20240828
    container_name: panther_ros
    command: ros2 launch panther_bringup bringup.launch.py
"""


@pytest.mark.parametrize(("after", "same"), [
    (BASE.replace(b"bringup.launch.py", b"bringup.launch.py wheel_type:=WH02"), True),
    (BASE.replace(b"20240828", b"20250101"), True),
    (BASE.replace(b"    command: ros2", b"    # a comment\n    command: ros2"), True),
    (BASE.replace(b"container_name: panther_ros", b"container_nam: panther_ros"), False),
    (BASE.replace(b"restart: always", b"restart: 'no'"), False),  # through the merge key
    (BASE + b"  extra:\n    image: x\n", False),
    (b"services: [\n", False),  # not YAML: the robot's compose judges
    (BASE.replace(b"container_name: panther_ros", b"container_name: panther_ros\n    container_name: x"), False),
])
def test_only_command_or_image_changes_need_no_compose_check(after: bytes, same: bool) -> None:
    assert _compare_values(BASE, after) is same
