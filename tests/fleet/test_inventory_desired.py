"""The inventory's desired: blocks, checked whole when it loads (core/fleet/inventory_desired.py).

The bad-input corpus (tests/badinput/test_inputs.py, DESIRED) runs each refusal through
`inventory validate`, `doctor`, `apply --dry-run` and `config diff`; here: the values the
commands read, the lines named, what still loads, and the rules shared with `gps enable`.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_desired import DesiredError, check_desired, nmea_ip
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.gps.plan import GpsOptions
from panther_ops.errors import InventoryError, UsageError

EVERY_BLOCK = """\
version: 1
defaults:
  desired:
    controller: {linear.x.max_velocity: 1.0}
groups:
  field:
    desired:
      manager: {mode: sim, scenario: charging, params: {low_battery_threshold_percent: 0.3}}
      launch_args: {led_config_file: /config/a.yaml}
robots:
  r1:
    host: panther-01
    groups: [field]
    desired:
      launch_args: {wheel_type: WH02, use_ekf: false, led_config_file: /config/b.yaml}
      controller: {linear.x.max_velocity: 0.8, controller.angular.z.max_velocity: 1.5}
      gps: {enabled: false, port: "5001", ip: 10.15.20.2, namespace: rover, container: true, router: {enabled: true}}
      manager: {enabled: false, params: {low_battery_threshold_percent: 0.2}, shutdown_hosts: /home/husarion/h.yaml}
      shutdown_hosts: [{ip: 10.15.20.3, username: husarion}, {ip: 10.15.20.4, port: 3003, secret: {env: S}}]
      webui: {port: 8080}
      image: husarion/panther:humble-2.1.1-20240828
"""


def load(tmp: Path, text: str) -> Inventory:
    path = tmp / "fleet.yaml"
    path.write_text(text)
    return load_inventory(str(path))


def test_every_block_loads_and_a_later_layer_replaces_the_same_name(tmp_path: Path) -> None:
    inv = load(tmp_path, EVERY_BLOCK)
    desired = inv.robots["r1"].desired
    assert desired["launch_args"]["led_config_file"] == "/config/b.yaml"
    assert desired["controller"] == {"linear.x.max_velocity": 0.8, "controller.angular.z.max_velocity": 1.5}
    assert desired["manager"]["params"] == {"low_battery_threshold_percent": 0.2}
    assert desired["manager"]["mode"] == "sim" and desired["manager"]["enabled"] is False


def test_a_port_is_read_as_the_number_the_commands_use(tmp_path: Path) -> None:
    """desired.gps.port "5001" (ASCII digits) is 5001 for `apply` and `doctor` alike: before,
    the text went on, and `doctor` ran int() over whatever it was."""
    inv = load(tmp_path, EVERY_BLOCK)
    assert inv.robots["r1"].desired["gps"]["port"] == 5001


@pytest.mark.parametrize(("block", "where"), [
    ("      gps:\n        enabled: false\n        port: 70000\n", ":8 [robots.r1.desired.gps.port]"),
    ("      shutdown_hosts:\n        - ip: 10.15.20.3\n          username: husarion\n          port: 0\n",
     ":9 [robots.r1.desired.shutdown_hosts.0.port]"),
    ("      manager:\n        params:\n          cpu.temp.fan_on: 70\n          cpu_fan_on_temp: 75\n",
     ":9 [robots.r1.desired.manager.params.cpu_fan_on_temp]"),
])
def test_a_refusal_names_the_line_of_the_key(tmp_path: Path, block: str, where: str) -> None:
    text = "version: 1\nrobots:\n  r1:\n    host: panther-01\n    desired:\n" + block
    with pytest.raises(InventoryError) as exc:
        load(tmp_path, text)
    assert where in str(exc.value) and "fleet.yaml" in str(exc.value)


def test_the_validator_names_the_path_inside_desired() -> None:
    with pytest.raises(DesiredError) as exc:
        check_desired({"gps": {"enabled": True, "port": "5000/udp"}})
    assert exc.value.path == ("gps", "port") and "'5000/udp'" in exc.value.message
    assert "ASCII digits" in (exc.value.hint or "")
    assert check_desired({"gps": {"port": "5000"}}) == {"gps": {"port": 5000}}


def test_the_planners_refuse_a_block_given_to_them_directly() -> None:
    """`desired_gps` and `manager_settings` call the same validator (no second set of rules)."""
    from panther_ops.core.manager_ops.settings import manager_settings

    with pytest.raises(UsageError, match=r"desired\.manager\.enabled 'no'"):
        manager_settings({"manager": {"enabled": "no"}})
    assert manager_settings({"manager": {"enabled": False}}).enabled is False


def test_gps_enable_takes_the_same_ascii_only_address_rule() -> None:
    """`gps enable --ip` and desired.gps.ip share one rule: ASCII digits only (``\\d`` took
    any script's digits before)."""
    assert nmea_ip("10.15.20.2") and not nmea_ip("10.15.20.\uff12")
    with pytest.raises(UsageError, match="IPv4"):
        GpsOptions(ip="10.15.20.\uff12")  # a fullwidth 2: accepted before
    assert GpsOptions(ip="10.15.20.7").ip == "10.15.20.7"
