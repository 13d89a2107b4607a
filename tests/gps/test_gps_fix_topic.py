"""`gps status` once the NMEA driver holds the port (issue 24, finding 9): the robot's own fix
topic, echoed once in the driver container, decides. Without a lab: the topic names per
driver mode (as `gps enable` writes compose.yaml on the demo fleet), `ros2 topic echo`'s
NavSatFix text parsed, and the status task against a robot whose port is held, the driver
container's script run by sh with a `ros2` that prints what a real CLI prints."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import subprocess
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.transport.base import Command, CommandResult

#: What `ros2 topic echo --once /panther/gps/fix sensor_msgs/msg/NavSatFix` prints (Humble:
#: rosidl_runtime_py.message_to_yaml, block style, then `---`) for the message
#: nmea_navsat_driver publishes from `$GPGGA,...,5311.868738,N,01822.394736,E,1,09,0.8,120.4,M,34.5,M,,`
#: with the 2.1.1 launch file's frame (tf_prefix = namespace, frame_id gps); covariances from
#: HDOP and the default errors (epe_quality1 4.0 m; ros-drivers/nmea_navsat_driver@2.0.1:
#: src/libnmea_navsat_driver/driver.py), altitude = GGA altitude + geoid separation.
ECHO_FIX = """header:
  stamp:
    sec: 1795490517
    nanosec: 60718000
  frame_id: panther/gps
status:
  status: 0
  service: 1
latitude: 53.1978123
longitude: 18.3732456
altitude: 154.9
position_covariance:
- 10.240000000000002
- 0.0
- 0.0
- 0.0
- 10.240000000000002
- 0.0
- 0.0
- 0.0
- 163.84000000000003
position_covariance_type: 1
---
"""

#: GGA with fix quality 0 (no position fields): status -1, NaN coordinates, unknown covariance.
ECHO_NO_FIX = """header:
  stamp:
    sec: 1795490518
    nanosec: 0
  frame_id: panther/gps
status:
  status: -1
  service: 1
latitude: .nan
longitude: .nan
altitude: 154.9
position_covariance:
- 640000000000.0
- 0.0
- 0.0
- 0.0
- 640000000000.0
- 0.0
- 0.0
- 0.0
- 10240000000000.0
position_covariance_type: 0
---
"""


def test_echo_text_parsed() -> None:
    from panther_ops.core.gps.fix_topic import parse_fix

    fix = parse_fix(ECHO_FIX)
    assert fix is not None and fix.has_fix
    assert (fix.lat, fix.lon, fix.altitude_m, fix.status, fix.service) == (53.1978123, 18.3732456, 154.9, 0, 1)
    assert fix.frame_id == "panther/gps" and fix.stamp == pytest.approx(1795490517.060718)
    assert fix.to_json()["fix"] == "fix"
    # the CLI's own warning before the message does not matter
    warned = "WARNING: topic [/panther/gps/fix] does not appear to be published yet\n" + ECHO_FIX
    assert parse_fix(warned) == fix
    no = parse_fix(ECHO_NO_FIX)
    assert no is not None and not no.has_fix and no.status == -1 and math.isnan(no.lat)
    assert no.to_json()["lat"] is None and no.to_json()["fix"] == "no fix"
    assert parse_fix("") is None
    assert parse_fix("header:\n  frame_id: x\nstatus: [1\n") is None  # not YAML
    assert parse_fix("header:\n  frame_id: x\nlatitude: 1.0\n") is None  # no status


@pytest.fixture
def demo(tmp_path: Path) -> Path:
    dest = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(dest)]) == 0
    return dest


def _compose(demo: Path, robot: str) -> str:
    return (demo / "robots" / robot / "home/husarion/compose.yaml").read_text()


def test_topic_names_per_driver_mode(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """panther-01 2.1.1 and panther-03 2.2.2: launch_nmea_gps (relative gps/fix, resolved in the
    driver's namespace); panther-02 2.0.4: the nmea-gps service, launch form /NS/gps/fix, or the
    socket driver run with __ns (another port): /NS/fix."""
    from panther_ops.core.gps.fix_topic import fix_topic, service_topic
    from panther_ops.core.gps.plan import GpsOptions, service_mapping
    from panther_ops.core.robot.robot_config import ComposeRead, parse_config

    assert main(["-i", str(demo), "gps", "enable", "--all", "--yes"]) == 0

    def topic(robot: str, mode: str, service: str, text: str | None = None) -> str:
        raw = ComposeRead("/home/husarion", "/home/husarion/compose.yaml", (text or _compose(demo, robot)).encode())
        return fix_topic(parse_config(raw, "auto"), mode, service)

    assert topic("panther-01", "argument", "panther_ros") == "gps/fix"
    assert topic("panther-03", "argument", "husarion_ugv_ros") == "gps/fix"
    assert topic("panther-02", "service", "nmea-gps") == "/panther/gps/fix"
    # 2.1.1 declares device_namespace (the topic's sub-namespace); 2.2 fixes it to gps
    text = _compose(demo, "panther-01").replace("launch_nmea_gps:=True", "launch_nmea_gps:=True device_namespace:=gnss")
    assert topic("panther-01", "argument", "panther_ros", text) == "gnss/fix"
    capsys.readouterr()
    assert main(["-i", str(demo), "gps", "enable", "-r", "panther-02", "--port", "5002", "--namespace", "rover",
                 "--yes", "--json"]) == 0
    assert topic("panther-02", "service", "nmea-gps") == "/rover/fix"
    # the plan names that topic (the socket driver's own `fix`, not /rover/gps/fix)
    assert json.loads(capsys.readouterr().out)["robots"][0]["message"].endswith(", udp 10.15.20.2:5002, /rover/fix)")
    # what `gps enable` names in its plan is that topic
    assert service_topic(service_mapping("rover", GpsOptions(port=5002))) == "/rover/fix"
    assert service_topic(service_mapping("robot3", GpsOptions())) == "/robot3/gps/fix"
    assert service_topic({"command": "ros2 launch /husarion_utils/nmea_navsat.launch.py"}) == "/gps/fix"
    assert service_topic({"command": ["ros2", "launch", "/husarion_utils/nmea_navsat.launch.py"],
                          "environment": {"ROBOT_NAMESPACE": "p2"}}) == "/p2/gps/fix"


FAKE_ROS2 = r"""#!/bin/sh
# the driver image's `ros2`, as far as this test needs: records its words, prints the
# echo's text ($FAKE/echo) or, without one, waits until `timeout` kills it (exit 124)
echo "$*" >> "$FAKE/log"
[ -f "$FAKE/echo" ] || exit 124
cat "$FAKE/echo"
"""
FAKE_TIMEOUT = '#!/bin/sh\nshift\nexec "$@"\n'


class HeldPort:
    """A robot whose NMEA port a listener holds, no gpsd (no SSH client: gpsd's view is
    None), the driver container answering the docker exec by running its script with sh."""

    client = None

    def __init__(self, compose: str, fake: Path, env: dict[str, str]) -> None:
        self.compose, self.fake, self.env = compose, fake, env
        self.execs: list[list[str]] = []

    def run(self, cmd: Command, timeout: float | None = None, **_: Any) -> CommandResult:
        script = cmd.script or ""
        if cmd.argv[:2] == ("python3", "-c"):  # the capture: the port is held
            out = json.dumps({"lan_ip": "10.15.20.2", "bind": "Address already in use"}) + "\n"
            return CommandResult("capture", 0, out, "", raw_stdout=out.encode())
        if "docker.sock" in script:  # the exec in the driver container
            argv = json.loads(str(cmd.argv[0]))["Cmd"]
            assert argv[0] == "/ros_entrypoint.sh"
            self.execs.append(argv)
            cp = subprocess.run(argv[1:], capture_output=True, check=False, timeout=20,
                                env={**os.environ, **self.env, "FAKE": str(self.fake),
                                     "PATH": f"{self.fake / 'bin'}:{os.environ['PATH']}"})
            frame = bytes([1, 0, 0, 0]) + len(cp.stdout).to_bytes(4, "big") + cp.stdout
            return CommandResult("exec", 0, "", "@@container panther_ros\n", raw_stdout=frame)
        if "$HOME" in script:  # compose.yaml with the home on its first line
            raw = b"/home/husarion\n" + self.compose.encode()
            return CommandResult("read", 0, raw.decode(), "", raw_stdout=raw)
        raise AssertionError(f"unexpected command {cmd}")


def _status(demo: Path, tmp_path: Path, robot: str, echo: str | None, *, namespace: str | None = None,
            env: dict[str, str] | None = None) -> tuple[Any, HeldPort]:
    from panther_ops.core.gps.status import StatusOptions, status_task

    fake = tmp_path / "fake"
    (fake / "bin").mkdir(parents=True, exist_ok=True)
    for name, text in (("ros2", FAKE_ROS2), ("timeout", FAKE_TIMEOUT)):
        (fake / "bin" / name).write_text(text)
        (fake / "bin" / name).chmod(0o755)
    (fake / "log").unlink(missing_ok=True)
    (fake / "echo").unlink(missing_ok=True)
    if echo is not None:
        (fake / "echo").write_text(echo)
    inv = load_inventory(str(demo))
    target = dataclasses.replace(inv.robots[robot], transport="ssh", host="10.15.20.2", root=None, namespace=namespace)
    held = HeldPort(_compose(demo, robot), fake, env or {})
    result = status_task(StatusOptions(window_s=1.0))(RobotContext(target, held, inv))  # type: ignore[arg-type]
    return result, held


def test_status_confirms_the_fix_from_the_fix_topic(demo: Path, tmp_path: Path) -> None:
    """After `gps enable` (2.0.4: the nmea-gps service holds udp :5000) `gps status` reports the
    fix the robot's /panther/gps/fix carries, with its source, not `port busy`."""
    assert main(["-i", str(demo), "gps", "enable", "-r", "panther-02", "--yes"]) == 0
    result, held = _status(demo, tmp_path, "panther-02", ECHO_FIX)
    d = result.data
    assert (result.outcome.value, d["verdict"]) == ("ok", "fix"), result.message
    assert d["source"] == "ros topic /panther/gps/fix" and d["container"] == "panther_ros"
    assert d["fix"]["lat"] == 53.1978123 and d["fix"]["lon"] == 18.3732456 and d["fix"]["altitude_m"] == 154.9
    assert d["fix"]["status"] == 0 and d["driver"]["mode"] == "service"
    assert "53.1978123 18.3732456, alt 154.9 m, status 0 (fix) on /panther/gps/fix" in result.message
    # one exec: the echo of that topic, bounded by the window plus the CLI's start
    (argv,) = held.execs
    assert argv[5:] == ["6", "", "/panther/gps/fix", "sensor_msgs/msg/NavSatFix"]
    assert (tmp_path / "fake/log").read_text() == "topic echo --once /panther/gps/fix sensor_msgs/msg/NavSatFix\n"


def test_status_no_fix_and_nothing_published(demo: Path, tmp_path: Path) -> None:
    assert main(["-i", str(demo), "gps", "enable", "-r", "panther-02", "--yes"]) == 0
    result, _ = _status(demo, tmp_path, "panther-02", ECHO_NO_FIX)
    assert (result.outcome.value, result.data["verdict"]) == ("failed", "data but no fix"), result.message
    assert result.data["fix"]["status"] == -1 and "/panther/gps/fix: status -1 (no fix)" in result.message

    result, _ = _status(demo, tmp_path, "panther-02", None)
    assert (result.outcome.value, result.data["verdict"]) == ("failed", "no fix message"), result.message
    assert "nothing published on /panther/gps/fix within 6 s (asked in container panther_ros)" in result.message
    assert result.data["fix"] is None and result.data["source"] == "ros topic /panther/gps/fix"


def test_status_on_the_drivers_argument_resolves_the_drivers_namespace(demo: Path, tmp_path: Path) -> None:
    """2.1.1 with launch_nmea_gps:=True: gps/fix in the driver's namespace (the inventory's,
    else ROBOT_NAMESPACE / namespace:= as the driver container tells)."""
    assert main(["-i", str(demo), "gps", "enable", "-r", "panther-01", "--yes"]) == 0
    result, held = _status(demo, tmp_path, "panther-01", ECHO_FIX, env={"ROBOT_NAMESPACE": "panther"})
    assert result.data["verdict"] == "fix" and result.data["topic"] == "/panther/gps/fix", result.message
    assert held.execs[0][5:7] == ["6", ""] and held.execs[0][7] == "gps/fix"
    result, _ = _status(demo, tmp_path, "panther-01", None, namespace="rover", env={"ROBOT_NAMESPACE": "panther"})
    assert result.data["verdict"] == "no fix message" and "nothing published on /rover/gps/fix" in result.message
    assert (tmp_path / "fake/log").read_text() == "topic echo --once /rover/gps/fix sensor_msgs/msg/NavSatFix\n"


def test_a_listener_that_is_not_the_nmea_driver_is_still_port_busy(demo: Path, tmp_path: Path) -> None:
    result, held = _status(demo, tmp_path, "panther-02", ECHO_FIX)  # no NMEA driver in compose.yaml
    assert (result.outcome.value, result.data["verdict"]) == ("skipped", "port busy") and held.execs == []
