"""Issue-14 teleop acceptance on the lab: `panther-ops teleop -r R` through a pseudo-terminal,
its keyboard program (python3 + rclpy: the lab's Python image with its rclpy stand-in) in the
driver container over the robot's SSH connection; key presses reach it and it publishes on
<ns>/cmd_vel at >= 10 Hz; refused while the E-stop is triggered; refused, naming python3 and
starting nothing, on an image without it (the busybox stand-in); a warning when another node
publishes on cmd_vel. The images have no teleop_twist_keyboard (issue 24): the stand-in answers
`ros2 run teleop_twist_keyboard` as the real CLI does, "Package ... not found".

The tests run in file order: the first two on the busybox image, the rest on the Python
image (`python_drivers`, module-scoped, put back when the module ends)."""

from __future__ import annotations

import itertools
import sys
import time
from collections.abc import Iterator
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.remote.teleop.program import BANNER
from tests.lab.pyimage import restore_driver_image, use_python_image
from tests.ux.termrun import keys_on_pty

pytestmark = pytest.mark.lab

LOG = "/var/lib/ros2-standin/cmd_vel.log"


@pytest.fixture(scope="module")
def tlab(lab_factory: Any) -> Any:
    return lab_factory(3, docker=True, images=("2.1.1", "2.2", "2.3.2"))


@pytest.fixture(scope="module")
def python_drivers(tlab: Any) -> Iterator[Any]:
    """Both robots' drivers recreated from the Python image (python3, rclpy stand-in)."""
    for name in tlab.names:
        use_python_image(tlab, name)
        cp = tlab.compose(name, "up", "-d", "--force-recreate", tlab.robot(name).driver_container)
        assert cp.returncode == 0, cp.stderr
    yield tlab
    for name in tlab.names:
        restore_driver_image(tlab, name)


def in_driver(lab: Any, name: str, script: str) -> str:
    robot = lab.robot(name)
    return str(lab.docker(name, "exec", robot.driver_container, "sh", "-c", script, check=True).stdout)


def drive(lab: Any, name: str, keys: list[tuple[bytes, float]]) -> tuple[int, str]:
    """Run `panther-ops teleop -r NAME` on a pseudo-terminal, type ``keys`` (each then a pause)."""
    argv = [sys.executable, "-m", "panther_ops.cli.app", "-i", str(lab.inventory_path), "teleop", "-r", name]
    return keys_on_pty(argv, keys, ready=BANNER, timeout=30)


def test_refused_while_the_e_stop_is_triggered(tlab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["-i", str(tlab.inventory_path), "estop", "trigger", "-r", "r01"]) == 0
    capsys.readouterr()
    assert main(["-i", str(tlab.inventory_path), "teleop", "-r", "r01"]) == 3
    err = capsys.readouterr().err
    assert "the E-stop is triggered" in err and "panther-ops estop reset -r r01 --yes" in err
    assert in_driver(tlab, "r01", f"cat {LOG} 2>/dev/null | wc -l").strip() == "0"


def test_refused_naming_python3_on_an_image_without_it(tlab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """The busybox stand-in has no python3 (nor teleop_twist_keyboard): refused before anything
    starts, one check in the driver container, nothing published."""
    name = "r01"
    assert main(["-i", str(tlab.inventory_path), "estop", "reset", "-r", name, "--yes"]) == 0
    in_driver(tlab, name, f"rm -f {LOG}")
    capsys.readouterr()
    assert main(["-i", str(tlab.inventory_path), "teleop", "-r", name]) == 3
    err = capsys.readouterr().err
    assert "the driver container panther_ros has no python3" in err and "nothing was started" in err, err
    assert in_driver(tlab, name, f"cat {LOG} 2>/dev/null | wc -l").strip() == "0"
    # what the manual's command does on that image (and on the real ones): the package is not there
    robot = tlab.robot(name)
    cp = tlab.docker(name, "exec", robot.driver_container, "/ros_entrypoint.sh", "ros2", "run",
                     "teleop_twist_keyboard", "teleop_twist_keyboard")
    assert cp.returncode == 1 and "Package 'teleop_twist_keyboard' not found" in cp.stderr


@pytest.mark.parametrize(("name", "registry"), [
    ("r01", "cmd_vel"),  # 2.1.1 (panther_ros)
    ("r02", "cmd_vel"),  # 2.2.2 (husarion_ugv_ros)
    ("r03", "manual_cmd_vel"),  # 2.3.2 (Jazzy): stamped twists on the twist mux's manual input
])
def test_keys_reach_the_robot_at_10_hz(python_drivers: Any, name: str, registry: str) -> None:
    tlab = python_drivers
    log = f"/var/lib/ros2-standin/{registry}.log"
    assert main(["-i", str(tlab.inventory_path), "estop", "reset", "-r", name, "--yes"]) == 0
    in_driver(tlab, name, f"rm -f {log}")
    code, out = drive(tlab, name, [(b"i", 2.0), (b"j", 1.0), (b"k", 0.5), (b"\x03", 1.0)])
    assert code == 0, out
    topic = "/panther/manual/cmd_vel" if registry == "manual_cmd_vel" else "/panther/cmd_vel"
    assert f"{BANNER} {topic} at 10 Hz" in out
    rows = [line.split() for line in in_driver(tlab, name, f"cat {log}").splitlines()]
    times = [float(r[0]) for r in rows]
    moves = [(float(r[1]), float(r[2])) for r in rows]
    span = times[-1] - times[0]
    assert span > 3
    assert len(rows) >= 10 * span - 1, f"{len(rows)} messages in {span:.2f} s"  # >= 10 Hz
    assert max(b - a for a, b in itertools.pairwise(times)) < 0.5  # never a gap the watchdog would stop on
    # the keys in the order typed: forward, turn left, stop
    seen = [m for i, m in enumerate(moves) if i == 0 or m != moves[i - 1]]
    assert (0.5, 0.0) in seen and (0.0, 1.0) in seen and seen[-1] == (0.0, 0.0)
    assert seen.index((0.5, 0.0)) < seen.index((0.0, 1.0))
    # the publisher is gone once teleop ended
    assert in_driver(tlab, name, f"ls /var/lib/ros2-standin/{registry}/ 2>/dev/null").strip() == ""


def test_warns_when_another_node_publishes(python_drivers: Any) -> None:
    tlab = python_drivers
    name = "r01"
    robot = tlab.robot(name)
    assert main(["-i", str(tlab.inventory_path), "estop", "reset", "-r", name, "--yes"]) == 0
    tlab.docker(name, "exec", "-d", robot.driver_container, "ros2", "topic", "pub", "/panther/cmd_vel",
                "geometry_msgs/msg/Twist", "{}", check=True)
    try:
        deadline = time.monotonic() + 5
        while not in_driver(tlab, name, "ls /var/lib/ros2-standin/cmd_vel/ 2>/dev/null").strip():
            assert time.monotonic() < deadline
            time.sleep(0.1)
        code, out = drive(tlab, name, [(b"k", 0.3), (b"\x03", 1.0)])
        assert code == 0
        assert "publishes on /panther/cmd_vel: do not control the robot from different sources" in out
    finally:
        in_driver(tlab, name, "for f in /var/lib/ros2-standin/cmd_vel/_ros2cli_*; do [ -f \"$f\" ] && "
                              "kill $(cat \"$f\"); done; true")
