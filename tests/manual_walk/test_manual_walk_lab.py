"""Issue 24 acceptance: the Panther manual's operator procedures walked through panther-ops, as a
new user would, on robots built from Husarion's own files (docs/lab.md, "The manual walk").

One lab of three robots: r01 panther_ros 2.0.4, r02 panther_ros 2.1.1 (compose files of
husarion/panther-docker@2.0.4/@2.1.1 demo/compose.minimal-setup.yaml) and r03 husarion_ugv
2.2.2 (husarion_ugv_ros@2.2.2 docker/demo/compose.hardware.yaml) whose ~/config is replaced by
templates/config-tree/husarion-ugv-2.2 (the tree the 2.2.2 image lays out, each file naming its
upstream source) instead of the lab's stand-in tree. Behind each robot, on its LAN, a User
Computer (sshd, sudo with a password, the husarion-webui snap stand-in; behind r03 also the
husarion-shutdown service) and a RUTX11 router stand-in.

The tests run in file order, which is the manual's order; each step is parametrized by stack
and does what the manual says through panther-ops: `--dry-run` first (nothing changes on the
robot), then `--yes`, then reads back (config get/pull, status) and asserts what the robot now
has (its compose.yaml, its files, the running containers, the stand-ins' own records).
"""

from __future__ import annotations

import getpass
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.fleet.templates import template_path
from tests.clirun import run_cli
from tests.lab import Lab, missing_requirements
from tests.lab.computers import ComputerSpec, HttpService
from tests.lab.nmea_image import use_nmea_image
from tests.lab.router import Router, add_router
from tests.labtools import COMPOSE, containers, user_computer_inventory

pytestmark = pytest.mark.lab

ROOT = Path(__file__).resolve().parents[2]
TREE = ROOT / "templates" / "config-tree" / "husarion-ugv-2.2"
ROBOT = {"2.0.4": "r01", "2.1.1": "r02", "2.2.2": "r03"}
COMPUTER = {"r01": "u1", "r02": "u2", "r03": "u3"}
VERSIONS = list(ROBOT)
PASSWORD = "walk-user-computer-password"
SECRET = "walk-shutdown-secret"
ROUTER_PASSWORD = "walk-router-password"
STANDIN = "/var/lib/ros2-standin"
HOSTS = {"2.0.4": "/home/husarion/config/panther_bringup/config/shutdown_hosts.yaml",
         "2.1.1": "/home/husarion/config/panther_manager/config/shutdown_hosts_config.yaml",
         "2.2.2": "/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"}


class Walk:
    """The lab, its routers and the user's inventory (User Computers set)."""

    def __init__(self, lab: Lab, inventory: Path, routers: dict[str, Router]) -> None:
        self.lab, self.inventory, self.routers = lab, inventory, routers
        self.factory = {n: lab.read(n, COMPOSE) for n in ROBOT.values()}

    def cli(self, capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any], str]:
        code, doc, out, err = run_cli(capsys, "-i", str(self.inventory), "--color", "never", *argv)
        return code, doc, out + err

    def compose(self, name: str) -> str:
        return self.lab.read(name, COMPOSE)

    def driver(self, name: str) -> dict[str, Any]:
        return containers(self.lab, name)[self.lab.robot(name).driver_container]

    def in_driver(self, name: str, script: str) -> str:
        r = self.lab.robot(name)
        return str(self.lab.docker(name, "exec", r.driver_container, "sh", "-c", script, check=True).stdout)


def _upstream_tree(lab: Lab, name: str, *, recreate: bool = True) -> None:
    """The robot's ~/config as the 2.2.2 image lays it out (templates/config-tree), owned by husarion."""
    lab.sh(name, "rm -rf /home/husarion/config")
    for f in sorted(p for p in TREE.rglob("*") if p.is_file()):
        lab.write(name, f"/home/husarion/config/{f.relative_to(TREE)}", f.read_bytes())
    lab.sh(name, "chown -R husarion:husarion /home/husarion/config")
    if not recreate:
        return
    cp = lab.compose(name, "up", "-d", "--force-recreate")
    assert cp.returncode == 0, cp.stderr


@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Walk]:
    why = missing_requirements(docker=True)
    if why:  # a lab test: a failure under CI=true (conftest's hook)
        pytest.skip("simulated robot lab unavailable: " + "; ".join(why))
    lab = Lab(3, docker=True, images=("2.0", "2.1.1", "2.2"), ephemeral=True).up()
    try:
        assert {lab.robot(n).image.split(":")[1].split("-")[1] for n in ROBOT.values()} == set(ROBOT)
        _upstream_tree(lab, ROBOT["2.2.2"])
        lab.add_computers([
            ComputerSpec("u1", behind="r01", password=PASSWORD, admin="group", webui=True),
            ComputerSpec("u2", behind="r02", password=PASSWORD, admin="group", webui=True),
            ComputerSpec("u3", behind="r03", password=PASSWORD, admin="group", webui=True,
                         http=HttpService(3003, SECRET)),
        ])
        routers = {n: add_router(lab, n, name=f"rt{n[-1]}", password=ROUTER_PASSWORD) for n in ROBOT.values()}
        use_nmea_image(lab, ROBOT["2.0.4"])
        inv = user_computer_inventory(lab, tmp_path_factory.mktemp("walk") / "inventory.yaml", COMPUTER)
        yield Walk(lab, inv, routers)
    finally:
        lab.down()


@pytest.fixture
def env(walk: Walk, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Passwords as a user gives them: prompts and environment variables, never arguments."""
    monkeypatch.setattr(getpass, "getpass", lambda prompt="": PASSWORD)
    monkeypatch.setenv("PANTHER_OPS_SUDO_PASSWORD", PASSWORD)
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PASSWORD", ROUTER_PASSWORD)
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PINS", str(tmp_path / "pins"))
    monkeypatch.setenv("WALK_SECRET", SECRET)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def one(doc: dict[str, Any]) -> dict[str, Any]:
    (r,) = doc["robots"]
    return dict(r)


def dry_then_yes(w: Walk, capsys: pytest.CaptureFixture[str], name: str, *argv: str,
                 paths: tuple[str, ...] = (), settle: str | None = "1") -> dict[str, Any]:
    """`argv --dry-run` (the robot's compose.yaml and ``paths`` unchanged), then `argv --yes`."""

    def snapshot() -> dict[str, str]:
        return {p: w.lab.sh(name, f"cat {p} 2>/dev/null || echo MISSING").stdout for p in (COMPOSE, *paths)}

    before = snapshot()
    code, doc, text = w.cli(capsys, *argv, "-r", name, "--dry-run", "--json")
    assert code == 0, text
    assert one(doc)["outcome"] == "changed", doc
    assert snapshot() == before, "a dry run changed the robot"
    extra = ("--settle", settle) if settle else ()
    code, doc, text = w.cli(capsys, *argv, "-r", name, "--yes", *extra, "--json")
    assert code == 0, text
    assert one(doc)["outcome"] == "changed", doc
    return one(doc)


# ---------------------------------------------------------------------------------------------
# Remote Control: E-stop reset (ROS service, WebUI or gamepad), /cmd_vel
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_01_estop_reset(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    """'To control the Panther robot with /cmd_vel topic E-stop state has to be reset'."""
    name = ROBOT[version]
    code, doc, text = walk.cli(capsys, "estop", "trigger", "-r", name, "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    assert walk.in_driver(name, f"cat {STANDIN}/e_stop").strip() == "true"
    code, doc, text = walk.cli(capsys, "estop", "reset", "-r", name, "--dry-run", "--json")
    assert code == 0, text
    assert walk.in_driver(name, f"cat {STANDIN}/e_stop").strip() == "true"
    code, doc, text = walk.cli(capsys, "estop", "reset", "-r", name, "--yes", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    assert walk.in_driver(name, f"cat {STANDIN}/e_stop").strip() == "false"
    code, doc, text = walk.cli(capsys, "estop", "status", "-r", name, "--json")
    assert code == 0 and one(doc)["data"]["e_stop"] is False and one(doc)["data"]["namespace"] == "/panther", text


# ---------------------------------------------------------------------------------------------
# Remote Control: Gamepad (Joy2Twist)
# ---------------------------------------------------------------------------------------------
JOY_DEFAULT = ROOT / "tests" / "lab" / "data" / "joy2twist_panther.yaml"


@pytest.mark.parametrize("version", VERSIONS)
def test_02_gamepad_parameters_pulled(walk: Walk, env: Path, version: str,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    """'the node can be configured to work with any Gamepad controller': first get the file in use."""
    name = ROBOT[version]
    code, _doc, text = walk.cli(capsys, "config", "pull", "joy2twist", "-r", name, "-o", "joy.yaml", "--json")
    assert code == 0, text
    pulled = yaml.safe_load((env / "joy.yaml").read_text())
    assert pulled["/**"]["ros__parameters"]["linear_velocity_factor"]["slow"] == 0.4  # joy2twist's default


@pytest.mark.parametrize("version", VERSIONS)
def test_02_gamepad_parameters_pushed(walk: Walk, env: Path, version: str,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    src = (TREE / "husarion_ugv_bringup/config/joy2twist_panther.yaml") if version == "2.2.2" else JOY_DEFAULT
    mine = env / "my_joy2twist.yaml"
    text = src.read_text()  # 2.2: the tree's file; <=2.1: joy2twist's default (the image's, not pullable)
    mine.write_text(text.replace("slow: 0.4", "slow: 0.25", 1))
    assert mine.read_text() != text
    if version == "2.2.2":
        robot_file = "/home/husarion/config/husarion_ugv_bringup/config/joy2twist_panther.yaml"
    else:
        robot_file = "/home/husarion/config/joy2twist/config/my_joy2twist.yaml"
    res = dry_then_yes(walk, capsys, name, "config", "push", str(mine), "--as", "joy2twist", paths=(robot_file,))
    assert walk.lab.read(name, robot_file) == mine.read_text(), res
    if version != "2.2.2":
        pad = containers(walk.lab, name)["gamepad_controller"]
        assert pad["state"] == "running"
        assert "joy2twist_params_file:=/config/joy2twist/config/my_joy2twist.yaml" in " ".join(pad["cmd"])
        assert pad["mounts"]["/config/joy2twist/config/my_joy2twist.yaml"] == robot_file
    else:  # the driver launches the gamepad (launch_gamepad:=true) with the tree's file
        assert walk.driver(name)["mounts"]["/config"] == "/home/husarion/config"
    code, _, out = walk.cli(capsys, "config", "pull", "joy2twist", "-r", name, "-o", "back.yaml", "--json")
    assert code == 0 and (env / "back.yaml").read_text() == mine.read_text(), out


# ---------------------------------------------------------------------------------------------
# Remote Control: WebUI (Installation, Configuration) on the User Computer
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_04_webui_on_the_user_computer(walk: Walk, env: Path, version: str,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    """sudo snap install husarion-webui --channel=humble; snap set ros.namespace, ros.transport,
    webui.layout; husarion-webui.start; then a custom DDS profile and webui.port."""
    name, computer = ROBOT[version], COMPUTER[ROBOT[version]]
    lab = walk.lab
    code, doc, text = walk.cli(capsys, "webui", "install", "-r", name, "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    settings = ("ros.namespace=panther", "ros.transport=rmw_cyclonedds_cpp", "webui.layout=panther")
    code, doc, text = walk.cli(capsys, "webui", "set", *settings, "-r", name, "--dry-run", "--json")
    assert code == 0, text
    code, doc, text = walk.cli(capsys, "webui", "get", "-r", name, "--json")
    assert one(doc)["data"]["settings"]["webui.layout"] != "panther", doc
    code, doc, text = walk.cli(capsys, "webui", "set", *settings, "-r", name, "--yes", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    code, doc, text = walk.cli(capsys, "webui", "start", "-r", name, "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    code, doc, text = walk.cli(capsys, "webui", "status", "-r", name, "--json")
    data = one(doc)["data"]
    assert data["running"] is True and data["ui_http"] == 200, data
    assert {k: data["settings"][k] for k in ("ros.namespace", "ros.transport", "webui.layout", "webui.port")} == {
        "ros.namespace": "panther", "ros.transport": "rmw_cyclonedds_cpp", "webui.layout": "panther",
        "webui.port": "8080"}
    assert data["url"] == f"http://{lab.computer(computer).ip}:8080/ui"
    # Configuration: a custom DDS configuration file and ros.transport={config}; another port
    profile = env / "walk.xml"
    profile.write_text('<?xml version="1.0" encoding="UTF-8"?>\n'
                       '<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any"/></CycloneDDS>\n')
    code, doc, text = walk.cli(capsys, "webui", "set", "--dds-file", str(profile), "webui.port=8081", "-r", name,
                               "--yes", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    common = "/var/snap/husarion-webui/common"
    assert lab.exec(computer, ["cat", f"{common}/dds-config-walk.xml"]).stdout == profile.read_text()
    code, doc, text = walk.cli(capsys, "webui", "status", "-r", name, "--json")
    data = one(doc)["data"]
    assert (data["settings"]["ros.transport"], data["settings"]["webui.port"], data["running"]) == ("walk", "8081",
                                                                                                   True), data
    assert data["ui_http"] == 200 and data["url"].endswith(":8081/ui"), data


# ---------------------------------------------------------------------------------------------
# ROS Packages Configuration: Changing Velocity Smoothing Parameters
# ---------------------------------------------------------------------------------------------
def controller_file(version: str, wheel: str = "WH01") -> str:
    pkg = "husarion_ugv_controller" if version == "2.2.2" else "panther_controller"
    return f"/home/husarion/config/{pkg}/config/{wheel}_controller.yaml"


@pytest.mark.parametrize("version", VERSIONS)
def test_05_velocity_limits(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    key = "controller.linear.x.max_velocity"
    code, doc, text = walk.cli(capsys, "config", "get", key, "-r", name, "--json")
    assert code == 0 and one(doc)["data"]["value"] == 2.0, text
    dry_then_yes(walk, capsys, name, "config", "set", key, "0.8", paths=(controller_file(version),))
    limits = yaml.safe_load(walk.lab.read(name, controller_file(version)))["/**"]
    drive = limits["panther_base_controller" if version == "2.0.4" else "drive_controller"]["ros__parameters"]
    assert drive["linear"]["x"]["max_velocity"] == 0.8
    code, doc, text = walk.cli(capsys, "config", "get", key, "-r", name, "--json")
    assert code == 0 and one(doc)["data"]["value"] == 0.8 and one(doc)["data"]["source"] == controller_file(version)
    driver = walk.driver(name)
    assert driver["state"] == "running"
    if version != "2.2.2":  # mounted and named by controller_config_path
        inside = controller_file(version).replace("/home/husarion", "")
        assert f"controller_config_path:={inside}" in driver["cmd"] and driver["mounts"][inside] == controller_file(
            version)


# ---------------------------------------------------------------------------------------------
# Changing Wheel Type (wheel_type; custom wheels: wheel_config_path + controller_config_path)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_06_wheel_type(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    dry_then_yes(walk, capsys, name, "config", "set", "wheel_type", "WH02")
    assert "wheel_type:=WH02" in walk.compose(name)
    driver = walk.driver(name)
    assert "wheel_type:=WH02" in driver["cmd"] and driver["state"] == "running"
    code, doc, text = walk.cli(capsys, "config", "get", "wheel_type", "-r", name, "--json")
    assert code == 0 and one(doc)["data"]["value"] == "WH02", text
    code, doc, text = walk.cli(capsys, "config", "get", "controller.linear.x.max_velocity", "-r", name, "--json")
    assert code == 0 and one(doc)["data"]["value"] == 0.8, text  # the limit set before the change, carried
    wh02 = yaml.safe_load(walk.lab.read(name, controller_file(version, "WH02")))["/**"]
    drive = wh02["panther_base_controller" if version == "2.0.4" else "drive_controller"]["ros__parameters"]
    assert drive["linear"]["x"]["max_velocity"] == 0.8 and drive["linear"]["y"]["max_velocity"] == 1.1


@pytest.mark.parametrize("version", VERSIONS)
def test_06_custom_wheels(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    """'point to the new wheel and controller configuration files ... based on the default files,
    i.e. WH01_controller.yaml and WH01.yaml'."""
    name = ROBOT[version]
    for kind, out in (("controller", "my_controller.yaml"), ("wheel", "my_wheel.yaml")):
        code, doc, text = walk.cli(capsys, "config", "pull", kind, "-r", name, "-o", out, "--json")
        assert code == 0, text
    code, doc, text = walk.cli(capsys, "config", "push", "my_wheel.yaml", "--as", "wheel", "-r", name, "--dry-run",
                               "--json")
    code, doc, text = walk.cli(capsys, "config", "push", "my_wheel.yaml", "--as", "wheel", "-r", name, "--yes",
                               "--settle", "1", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    code, doc, text = walk.cli(capsys, "config", "push", "my_controller.yaml", "--as", "controller", "-r", name,
                               "--yes", "--settle", "1", "--json")
    assert code == 0 and one(doc)["outcome"] in ("changed", "ok"), text
    cmd = " ".join(walk.driver(name)["cmd"])
    if version != "2.2.2":
        assert "wheel_config_path:=/config/" in cmd and "controller_config_path:=/config/" in cmd, cmd
    code, doc, text = walk.cli(capsys, "config", "get", "wheel_config_path", "-r", name, "--json")
    assert code == 0 and "my_wheel.yaml" in str(one(doc)["data"]["value"]), text


# ---------------------------------------------------------------------------------------------
# Use of GPS in Simulation; Linear Battery Plugin; Charging Process (files and Gazebo on this machine)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_07_simulation_gps_and_battery(walk: Walk, env: Path, version: str,
                                       capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    name = ROBOT[version]
    code, _doc, text = walk.cli(capsys, "config", "pull", "components", "-r", name, "-o", "components.yaml", "--json")
    assert code == 0, text
    before = (env / "components.yaml").read_text()
    code, _doc, text = walk.cli(capsys, "sim", "gps", "add", "components.yaml", "--dry-run")
    assert code == 0 and (env / "components.yaml").read_text() == before, text
    code, _doc, text = walk.cli(capsys, "sim", "gps", "add", "components.yaml", "--yes")
    assert code == 0, text
    comps = yaml.safe_load((env / "components.yaml").read_text())["components"]
    assert {"type": "ANT02", "parent_link": "cover_link", "xyz": "0.185 -0.12 0.0", "rpy": "0.0 0.0 3.14",
            "device_namespace": "gps"} in comps, comps
    world = env / "my_world.sdf"
    world.write_text('<?xml version="1.0"?>\n<sdf version="1.6">\n  <world name="my_world">\n  </world>\n</sdf>\n')
    code, _doc, text = walk.cli(capsys, "sim", "world", "set", str(world), "--latitude", "53.1978", "--longitude",
                               "18.3732", "--yes")
    assert code == 0, text
    assert "<latitude_deg>53.1978</latitude_deg>" in world.read_text()
    assert "<surface_model>EARTH_WGS84</surface_model>" in world.read_text()
    # the battery: simulate_discharging true in battery_plugin_config.yaml
    code, _doc, text = walk.cli(capsys, "config", "pull", "battery", "-r", name, "-o", "battery.yaml", "--json")
    assert code == 0, text
    battery = env / "battery.yaml"
    battery.write_text(battery.read_text().replace("simulate_discharging: false", "simulate_discharging: true"))
    assert "simulate_discharging: true" in battery.read_text()
    code, _doc, text = walk.cli(capsys, "sim", "battery", "check", str(battery))
    assert code == 0, text
    # charging: `ign service .../recharge/start|stop` through the Gazebo CLI stand-in
    services, calls = env / "services", env / "calls"
    services.write_text("/model/panther/battery/battery/recharge/start\n/model/panther/battery/battery/recharge/stop\n")
    monkeypatch.setenv("PATH", f"{ROOT / 'tests' / 'standins'}:{__import__('os').environ['PATH']}")
    monkeypatch.setenv("PANTHER_OPS_STANDIN_GZ_SERVICES", str(services))
    monkeypatch.setenv("PANTHER_OPS_STANDIN_GZ_CALLS", str(calls))
    code, _doc, text = walk.cli(capsys, "sim", "battery", "charge", "start", "--dry-run")
    assert code == 0 and not calls.exists(), text
    code, _doc, text = walk.cli(capsys, "sim", "battery", "charge", "start", "--yes")
    assert code == 0, text
    assert "/model/panther/battery/battery/recharge/start" in calls.read_text()


# ---------------------------------------------------------------------------------------------
# LED Animations: Defining Animations (a user animations file + its launch argument), test them
# ---------------------------------------------------------------------------------------------
EXAMPLE = template_path("lights", "user_animations.example.yaml")
"""The manual's user animations (ANIMATION_1: a stock image in a custom colour; ANIMATION_4: front
and rear bumpers apart), as panther-ops ships them for panther_lights (2.0, 2.1)."""
UGV_IMAGES = {"strip01_red.png": "panther/blinker.png", "triangle01_blue.png": "panther/estop_front.png",
              "triangle01_red.png": "panther/estop_rear.png"}
"""husarion_ugv_lights 2.2 ships other images than the manual's panther_lights ones."""


def my_animations(version: str) -> str:
    """The example as an operator of `version` writes it (2.2: its package and its images)."""
    text = EXAMPLE.read_text()
    if version != "2.2.2":
        return text
    for old, new in {"panther_lights": "husarion_ugv_lights", **UGV_IMAGES}.items():
        text = text.replace(old, new)
    return text


@pytest.mark.parametrize("version", VERSIONS)
def test_09_user_animations(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    mine = env / "my_awesome_user_animations.yaml"
    mine.write_text(my_animations(version))
    code, doc, text = walk.cli(capsys, "lights", "test", "21", "-r", name, "--json")
    assert code != 0 and "No animation with ID: 21" in one(doc)["message"], text  # not there yet
    code, doc, text = walk.cli(capsys, "lights", "validate", str(mine), "--stack", version, "--json")
    assert code == 0, text
    res = dry_then_yes(walk, capsys, name, "lights", "deploy", str(mine))
    cmd = " ".join(walk.driver(name)["cmd"])
    if version == "2.2.2":  # the tree's own user_animations.yaml, which bringup reads from common_dir_path
        inside = "/config/husarion_ugv_lights/config/user_animations.yaml"
    else:
        assert "user_led_animations_file:=" in cmd, (cmd, res)
        inside = cmd.split("user_led_animations_file:=")[1].split()[0]
        code, doc, text = walk.cli(capsys, "config", "get", "user_led_animations_file", "-r", name, "--json")
        assert code == 0 and one(doc)["data"]["value"] == inside, text
    on_robot = walk.in_driver(name, f"cat {inside}")
    assert [a["id"] for a in yaml.safe_load(on_robot)["user_animations"]] == [21, 24]
    code, doc, text = walk.cli(capsys, "lights", "test", "21", "--repeating", "-r", name, "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    assert "success=True" in one(doc)["data"]["response"]


# ---------------------------------------------------------------------------------------------
# Shutdown Behavior: the hosts file; ssh-copy-id and the sudoers rule on the User Computer
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_10_shutdown_hosts(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name, computer = ROBOT[version], COMPUTER[ROBOT[version]]
    lab, ip = walk.lab, walk.lab.computer(COMPUTER[ROBOT[version]]).ip
    code, doc, text = walk.cli(capsys, "shutdown", "hosts", "list", "-r", name, "--json")
    assert code == 0, text
    stock = [h["ip"] for h in one(doc)["data"]["hosts"]]
    if "10.15.20.3" in stock:  # the stock User Computer entry: this lab's computer has another address
        dry_then_yes(walk, capsys, name, "shutdown", "hosts", "remove", "--ip", "10.15.20.3")
    http = version == "2.2.2"
    who = ("--secret-env", "WALK_SECRET") if http else ("--user", "husarion", "--ask-password")
    code, doc, text = walk.cli(capsys, "shutdown", "setup", "-r", name, "--host", ip, *who, "--yes", "--settle", "1",
                               "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    hosts = lab.read(name, HOSTS[version])
    assert f"ip: {ip}" in hosts and "10.15.20.3" not in hosts, hosts
    if http:
        assert f"secret: {SECRET}" in hosts
    else:
        robot_pub = lab.read(name, "/home/husarion/.ssh/id_rsa.pub").split()[1]
        assert robot_pub in lab.exec(computer, ["cat", "/home/husarion/.ssh/authorized_keys"]).stdout
        rule = lab.exec(computer, ["cat", "/etc/sudoers.d/panther-shutdown"]).stdout
        assert "NOPASSWD: /sbin/poweroff, /sbin/reboot, /sbin/shutdown" in rule, rule
        inside = HOSTS[version].replace("/home/husarion", "")
        assert walk.driver(name)["mounts"][inside] == HOSTS[version]
    code, doc, text = walk.cli(capsys, "shutdown", "check", "-r", name, "--json")
    assert code == 0 and one(doc)["outcome"] == "ok", text
    assert lab.power_calls(computer) == []  # proved without powering anything off


# ---------------------------------------------------------------------------------------------
# BehaviorTree: Modifying Behavior Trees (a custom Lights project; bt_project_file / path)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_11_custom_lights_bt_project(walk: Walk, env: Path, version: str,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    out = env / "bt"
    out.mkdir()
    code, doc, text = walk.cli(capsys, "config", "pull", "bt-lights", "-r", name, "-o", str(out / "MyLightsBT.btproj"),
                               "--json")
    assert code == 0, text
    assert one(doc)["data"]["written"] == [str(out / "MyLightsBT.btproj"), str(out / "lights.xml")], text
    assert sorted(p.name for p in out.iterdir()) == ["MyLightsBT.btproj", "lights.xml"]
    code, doc, text = walk.cli(capsys, "bt", "validate", str(out / "MyLightsBT.btproj"))
    assert code == 0, text
    code, doc, text = walk.cli(capsys, "config", "push", str(out / "MyLightsBT.btproj"), "--as", "bt-lights", "-r",
                               name, "--dry-run", "--json")
    assert code == 0, text
    code, doc, text = walk.cli(capsys, "config", "push", str(out / "MyLightsBT.btproj"), "--as", "bt-lights", "-r",
                               name, "--yes", "--settle", "1", "--json")
    assert code == 0 and one(doc)["outcome"] in ("changed", "ok"), text
    assert walk.driver(name)["state"] == "running"


# ---------------------------------------------------------------------------------------------
# Manage ROS Nodes with Docker: stop, start, restart the driver
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_12_driver_container(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    code, doc, text = walk.cli(capsys, "driver", "status", "-r", name, "--json")
    assert code == 0, text
    first = walk.driver(name)
    code, doc, text = walk.cli(capsys, "driver", "stop", "-r", name, "--dry-run", "--json")
    assert code == 0 and walk.driver(name)["state"] == "running", text
    code, doc, text = walk.cli(capsys, "driver", "stop", "-r", name, "--yes", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    assert walk.driver(name)["state"] == "exited"
    code, doc, text = walk.cli(capsys, "driver", "start", "-r", name, "--yes", "--settle", "1", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    now = walk.driver(name)
    assert now["state"] == "running" and now["id"] == first["id"]  # the same container, started again
    code, doc, text = walk.cli(capsys, "driver", "restart", "-r", name, "--yes", "--settle", "1", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    again = walk.driver(name)
    assert again["state"] == "running" and again["id"] != first["id"] and again["cmd"] == first["cmd"]


# ---------------------------------------------------------------------------------------------
# Modification of configuration files: copy, modify, mount (volume), launch argument, recreate
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_13_modified_config_file(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    code, doc, text = walk.cli(capsys, "config", "pull", "controller", "-r", name, "-o", "controller_config.yaml",
                               "--json")
    assert code == 0, text
    mine = env / "controller_config.yaml"
    original = mine.read_text()
    assert "max_velocity: 2.2 # rad/s" in original or "max_velocity: 2.2" in original, original
    mine.write_text(original.replace("max_velocity: 2.2", "max_velocity: 1.5", 1))
    res = dry_then_yes(walk, capsys, name, "config", "push", str(mine), "--as", "controller")
    code, doc, text = walk.cli(capsys, "config", "get", "controller.angular.z.max_velocity", "-r", name, "--json")
    assert code == 0 and one(doc)["data"]["value"] == 1.5, (text, res)
    driver = walk.driver(name)
    assert driver["state"] == "running"
    if version != "2.2.2":
        assert "controller_config_path:=/config/panther_controller/config/controller_config.yaml" in driver["cmd"]
        assert "/config/panther_controller/config/controller_config.yaml" in walk.compose(name)


# ---------------------------------------------------------------------------------------------
# GNSS API: the RUTX11's NMEA forwarding, the NMEA driver, the fix topic
# ---------------------------------------------------------------------------------------------
def udp_ports(lab: Lab, name: str) -> set[int]:
    rows = lab.sh(name, "cat /proc/net/udp").stdout.splitlines()[1:]
    return {int(row.split()[1].rsplit(":", 1)[1], 16) for row in rows if row.strip()}


@pytest.mark.parametrize("version", VERSIONS)
def test_14_gnss(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    router = walk.routers[name]
    at = ("--address", router.ip)
    code, doc, text = walk.cli(capsys, "gps", "router", "show", "-r", name, *at, "--json")
    assert code == 0 and one(doc)["data"]["forwarding"] is False, text
    forward = ("--enable", "--hostname", router.robot_lan_ip, "--port", "5000")
    code, doc, text = walk.cli(capsys, "gps", "router", "set", "-r", name, *at, *forward, "--dry-run", "--json")
    assert code == 0 and router.state()["forwarding"]["enabled"] == "0", text
    code, doc, text = walk.cli(capsys, "gps", "router", "set", "-r", name, *at, *forward, "--yes", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    assert router.state()["forwarding"]["enabled"] == "1"
    dry_then_yes(walk, capsys, name, "gps", "enable")
    if version == "2.0.4":
        gps = [c for k, c in containers(walk.lab, name).items() if "nmea-gps" in k]
        assert [c["state"] for c in gps] == ["running"], gps
    else:
        assert any(w.lower() == "launch_nmea_gps:=true" for w in walk.driver(name)["cmd"])
    deadline = time.monotonic() + 10
    while 5000 not in udp_ports(walk.lab, name):
        assert time.monotonic() < deadline, "the NMEA driver does not hold UDP 5000"
        time.sleep(0.2)
    code, doc, text = walk.cli(capsys, "gps", "status", "-r", name, "--window", "2", "--json")
    d = one(doc)["data"]
    assert d["source"] == "ros topic /panther/gps/fix", d
    assert code == 0 and d["verdict"] == "fix", text


@pytest.mark.parametrize("version", VERSIONS)
def test_14_gnss_gga_forwarded(walk: Walk, env: Path, version: str, capsys: pytest.CaptureFixture[str]) -> None:
    """Forwarding GPGGA only (one sentence a datagram): the robot's own fix topic has the router's position."""
    name = ROBOT[version]
    router = walk.routers[name]
    code, doc, text = walk.cli(capsys, "gps", "router", "set", "-r", name, "--address", router.ip, "--sentences",
                               "GPGGA", "--yes", "--json")
    assert code == 0 and one(doc)["outcome"] == "changed", text
    code, doc, text = walk.cli(capsys, "gps", "status", "-r", name, "--window", "2", "--json")
    assert code == 0, text
    d = one(doc)["data"]
    assert (d["verdict"], d["source"]) == ("fix", "ros topic /panther/gps/fix"), d
    assert abs(d["fix"]["lat"] - 53.1978) < 1e-6 and abs(d["fix"]["lon"] - 18.3732) < 1e-6, d


# ---------------------------------------------------------------------------------------------
# Operating System Image Reinstallation: back up, (reinstall), restore
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("version", VERSIONS)
def test_15_reinstall_backup_and_restore(walk: Walk, env: Path, version: str,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    name = ROBOT[version]
    lab = walk.lab
    code, doc, text = walk.cli(capsys, "reimage", "plan", "-r", name, "--json")
    assert code == 0, text
    planned = {f["path"] for f in one(doc)["data"]["files"]}
    assert COMPOSE in planned, planned
    code, doc, text = walk.cli(capsys, "reimage", "backup", "-r", name, "-o", str(env / "backups"), "--json")
    assert code == 0, text
    archive = one(doc)["data"]["archive"]
    assert Path(archive).is_file()
    walked, walked_cmd = walk.compose(name), walk.driver(name)["cmd"]
    hosts = lab.read(name, HOSTS[version])
    old_fp = lab.host_fingerprint(name)
    # "reinstall": a new host key, the home's customisations gone, Husarion's compose file
    lab.rotate_host_key(name)
    lab.exec(name, ["rm", "-rf", "/home/husarion/config", "/home/husarion/panther-ops", "/home/husarion/.ssh/id_rsa",
                    "/home/husarion/.ssh/id_rsa.pub", "/home/husarion/.ssh/known_hosts"], check=True)
    if version == "2.2.2":
        _upstream_tree(lab, name, recreate=False)
    lab.write(name, COMPOSE, walk.factory[name])
    code, doc, text = walk.cli(capsys, "reimage", "restore", "-r", name, "--from", archive, "--yes")
    assert code == 2 and "panther-ops trust" in text and lab.host_fingerprint(name) != old_fp, text
    code, doc, text = walk.cli(capsys, "trust", name, "--replace", "--yes")
    assert code == 0, text
    code, doc, text = walk.cli(capsys, "reimage", "restore", "-r", name, "--from", archive, "--dry-run")
    assert code == 0 and walk.compose(name) == walk.factory[name], text
    code, doc, text = walk.cli(capsys, "reimage", "restore", "-r", name, "--from", archive, "--yes", "--settle", "1")
    assert code == 0, text
    assert walk.compose(name) == walked
    assert lab.read(name, HOSTS[version]) == hosts
    now = walk.driver(name)
    assert now["cmd"] == walked_cmd and now["state"] == "running"
