from __future__ import annotations

import pytest

from panther_ops.core.fleet.facts import clock_offset, parse_env, parse_probe
from panther_ops.core.stack import (
    Family,
    Generation,
    find_driver,
    has_changes_of,
    parse_image,
    stack_from_version,
    stack_option,
)
from panther_ops.errors import RemoteStateError, UsageError


@pytest.mark.parametrize(
    ("image", "version", "gen", "service", "controller"),
    [
        ("husarion/panther:humble-2.0.0-20240402", "2.0.0", Generation.G2_0_0, "panther_ros", "panther_base_controller"),
        ("husarion/panther:humble-2.0.1-20240410", "2.0.1", Generation.G2_0_0, "panther_ros", "panther_base_controller"),
        ("husarion/panther:humble-2.0.4-20240628", "2.0.4", Generation.G2_0_2, "panther_ros", "panther_base_controller"),
        ("husarion/panther:humble-2.1.0-20240723", "2.1.0", Generation.G2_1_0, "panther_ros", "drive_controller"),
        ("husarion/panther:humble-2.1.1-20240828", "2.1.1", Generation.G2_1_1, "panther_ros", "drive_controller"),
        ("husarion/panther:humble-2.1.2-20241125-stable", "2.1.2", Generation.G2_1_1, "panther_ros", "drive_controller"),
        ("husarion/husarion-ugv:humble-2.2.0-20240227", "2.2.0", Generation.G2_2_0, "husarion_ugv_ros", "drive_controller"),
        ("docker.io/husarion/husarion-ugv:humble-2.2.2-20250702", "2.2.2", Generation.G2_2_1, "husarion_ugv_ros",
         "drive_controller"),
        # the tags of husarion_ugv_ros@2.3.0/2.3.1/2.3.2:docker/demo/compose.hardware.yaml
        ("husarion/husarion-ugv:jazzy-2.3.0-20250425", "2.3.0", Generation.G2_3_0, "husarion_ugv_ros",
         "drive_controller"),
        ("husarion/husarion-ugv:jazzy-2.3.1-20250701", "2.3.1", Generation.G2_3_1, "husarion_ugv_ros",
         "drive_controller"),
        ("husarion/husarion-ugv:jazzy-2.3.2-20260622", "2.3.2", Generation.G2_3_2, "husarion_ugv_ros",
         "drive_controller"),
    ],
)
def test_stack_from_image(image: str, version: str, gen: Generation, service: str, controller: str) -> None:
    s = parse_image(image)
    assert s.version_str == version
    assert s.generation is gen
    assert s.driver_service == service
    assert s.controller_key == controller
    assert s.shutdown_over_http is (s.version >= (2, 2, 1))
    assert (s.family is Family.HUSARION_UGV) is (s.version >= (2, 2, 0))
    assert s.jazzy is (s.version >= (2, 3, 0)) and s.distro == ("jazzy" if s.jazzy else "humble")
    assert stack_from_version(version).generation is gen  # an inventory's `stack:` picks the distro


def test_2_3_0_lacks_2_2_2s_changes() -> None:
    """husarion_ugv_ros 2.3.0 branched off after 2.2.1 (2.2.1 is an ancestor of tag 2.3.0, 2.2.2 is not)."""
    assert not has_changes_of(stack_from_version("2.3.0"), (2, 2, 2))
    assert has_changes_of(stack_from_version("2.3.0"), (2, 2, 1))
    assert all(has_changes_of(stack_from_version(v), (2, 2, 2)) for v in ("2.2.2", "2.3.1", "2.3.2"))


@pytest.mark.parametrize(
    ("image", "why"),
    [
        ("husarion/husarion-ugv:jazzy-2.4.0-20270101", "stack jazzy 2.4.0 .* not a release panther-ops knows"),
        ("husarion/husarion-ugv:jazzy-2.3.3-20270101", "stack jazzy 2.3.3 "),
        ("husarion/husarion-ugv:rolling-2.3.2-20260622", "stack rolling 2.3.2: 2.3.2 is a jazzy release"),
        ("husarion/husarion-ugv:kilted-2.4.0-20260622", "stack kilted 2.4.0 "),
        ("husarion/husarion-ugv:humble-2.3.2-20260622", "stack humble 2.3.2: 2.3.2 is a jazzy release"),
        ("husarion/husarion-ugv:jazzy-2.2.2-20250702", "stack jazzy 2.2.2: 2.2.2 is a humble release"),
        ("husarion/panther:humble-1.0.0-20231205", "ROS 1"),
        ("husarion/panther:latest", "does not follow"),
        ("husarion/panther", "no tag"),
        ("nginx:1.25", "not a Panther driver image"),
    ],
)
def test_unsupported_images(image: str, why: str) -> None:
    with pytest.raises(RemoteStateError, match=why) as caught:
        parse_image(image)
    if "knows" in why or "release" in why:  # names every supported line
        assert caught.value.hint == ("panther-ops supports humble: panther_ros 2.0.x-2.1.x, husarion_ugv 2.2.x; "
                                     "jazzy: husarion_ugv 2.3.0, 2.3.1, 2.3.2")


def test_stack_option_refuses_an_unknown_line_as_usage() -> None:
    with pytest.raises(UsageError, match=r"--stack 2\.4\.0: stack 2\.4\.0 is not a release panther-ops knows") as caught:
        stack_option("2.4.0")
    assert int(caught.value.exit_code) == 2 and "jazzy: husarion_ugv 2.3.0, 2.3.1, 2.3.2" in (caught.value.hint or "")
    assert stack_option("2.3.2").image == "husarion/husarion-ugv:jazzy-2.3.2"


def test_find_driver() -> None:
    assert find_driver({"services": {"x": {"image": "a:b"}, "panther_ros": {"image": "husarion/panther:t"}}}) == (
        "panther_ros", "husarion/panther:t")
    assert find_driver({"services": {"drv": {"image": "husarion/husarion-ugv:humble-2.2.2-20250702"}}}) == (
        "drv", "husarion/husarion-ugv:humble-2.2.2-20250702")
    assert find_driver({"services": {"x": {"image": "a:b"}}}) is None
    assert find_driver("nonsense") is None


def test_parse_env() -> None:
    env = parse_env('# c\nexport A=1\nB="two words"\nC=\'x\' # tail\nbad line\n')
    assert env == {"A": "1", "B": "two words", "C": "x"}


def test_parse_probe() -> None:
    out = "\n".join([
        "@@hostname", "r01", "@@home", "/home/husarion",
        "@@env", "#file /run/husarion/panther_config.env", "PANTHER_SERIAL_NO=1234", "PANTHER_ROBOT_VERSION=1.2",
        "@@os", 'PRETTY_NAME="Ubuntu 22.04.4 LTS"', "@@compose", "services: {}", "@@df",
        "/dev/root 1000 400 600 40% /", "@@docker", "20.10.24 1.41", "2.40.3", "@@end",
    ])
    f = parse_probe(out)
    assert clock_offset("1700000010.5\n", 1700000000.0, 1700000001.0) == 10.0
    assert clock_offset("garbage", 1.0, 2.0) is None
    assert (f.hostname, f.serial, f.robot_model, f.robot_version) == ("r01", "1234", "panther", "1.2")
    assert f.os_name == "Ubuntu 22.04.4 LTS"
    assert f.compose_text == "services: {}\n"
    assert (f.disk_total_bytes, f.disk_free_bytes) == (1000 * 1024, 600 * 1024)
    assert (f.docker_server, f.docker_api, f.compose_version) == ("20.10.24", "1.41", "2.40.3")


def test_parse_probe_without_docker_compose() -> None:
    f = parse_probe("@@docker\n20.10.24 1.41\ndocker: 'compose' is not a docker command.\n@@end\n")
    assert f.compose_version is None and f.compose_error is not None
