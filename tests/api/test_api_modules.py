"""panther_ops.api, what the collection's action plugins call: module options checked, a host's
variables as a robot, and a module run on a demo-fleet robot as the CLI runs the command
(docs/ansible.md)."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.api import MODULES, ArgumentError, check_arguments, robot_from_hostvars, run_module
from panther_ops.errors import InventoryError
from tests.clirun import run_cli


def test_defaults_and_types() -> None:
    assert check_arguments("config", {"key": "wheel_type", "value": "WH02"}) == {
        "state": "set", "key": "wheel_type", "value": "WH02", "src": None, "as": None, "force": False,
        "restart": True, "settle": 5.0}
    a = check_arguments("gps", {"port": "5001", "restart": "no", "settle": 2})
    assert (a["port"], a["restart"], a["settle"]) == (5001, False, 2.0)


@pytest.mark.parametrize(("module", "args", "words"), [
    ("config", {"colour": "red"}, "config: unknown option 'colour'"),
    ("driver", {}, "driver: option 'state' is required"),
    ("driver", {"state": "stopped"}, "'stopped' is not allowed"),
    ("config", {"force": "maybe"}, "'maybe' is not a boolean"),
    ("gps", {"port": "５０００"}, "gps: option 'port'"),
    ("teleop", {}, "unknown module 'teleop'"),
])
def test_bad_options_are_refused(module: str, args: dict[str, object], words: str) -> None:
    with pytest.raises(ArgumentError) as err:
        check_arguments(module, args)
    assert words in str(err.value) and err.value.exit_code == 2


def test_every_module_and_option_is_documented() -> None:
    doc = (Path(__file__).resolve().parents[2] / "docs/ansible.md").read_text()
    for module, options in MODULES.items():
        assert f"| `{module}` |" in doc
        for name in options:
            assert f"`{name}`" in doc or name in ("state",), (module, name)


def test_hostvars_map_onto_the_robot(tmp_path: Path) -> None:
    inv, robot = robot_from_hostvars("panther-07", {
        "ansible_host": "10.0.0.7", "ansible_port": 2207, "ansible_user": "ops",
        "ansible_ssh_private_key_file": "/keys/id", "panther_ops_known_hosts": str(tmp_path / "kh"),
        "panther_ops_namespace": "p7"})
    assert (robot.name, robot.host, robot.port, robot.user, robot.identity_file, robot.namespace) == \
        ("panther-07", "10.0.0.7", 2207, "ops", "/keys/id", "p7")
    assert inv.known_hosts == (str(tmp_path / "kh"),)
    _, bare = robot_from_hostvars("panther-08", {})
    assert bare.host == "panther-08"  # inventory_hostname is the address, as in Ansible
    with pytest.raises(InventoryError) as err:
        robot_from_hostvars("panther-07", {"ansible_port": 0})
    assert err.value.key == "panther-07.ansible_port" and "is not a TCP port" in str(err.value)


def test_check_run_again_and_refusal_on_a_demo_robot(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    root = demo / "robots/panther-01"
    inv, robot = robot_from_hostvars("panther-01", {"panther_ops_transport": "local", "panther_ops_root": str(root)})
    compose = root / "home/husarion/compose.yaml"
    before = compose.read_bytes()
    args = {"key": "wheel_type", "value": "WH04", "restart": False}

    checked = run_module("config", args, inv, robot, check=True)
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH04", "-r", "panther-01",
                              "--dry-run", "--json")
    assert code == 0 and checked["changed"] is True and checked["failed"] is False
    assert checked["diff"]["prepared"] == "".join(d["unified"] for d in doc["robots"][0]["diffs"])
    assert compose.read_bytes() == before

    ran = run_module("config", args, inv, robot)
    assert (ran["changed"], ran["outcome"]) == (True, "changed") and b"wheel_type:=WH04" in compose.read_bytes()
    after = compose.read_bytes()
    again = run_module("config", args, inv, robot)
    assert (again["changed"], again["outcome"]) == (False, "ok") and compose.read_bytes() == after

    refused = run_module("config", {"key": "wheel_type", "value": "WH99"}, inv, robot)
    code, _, _, err = run_cli(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH99", "-r", "panther-01",
                              "--yes")
    assert code == 2 and refused["failed"] is True and refused["rc"] == 2
    assert "error " + " ".join(refused["msg"].split()) in " ".join(err.split())
    assert compose.read_bytes() == after


INPUTS = Path(__file__).resolve().parents[1] / "golden/inputs"


@pytest.mark.parametrize(("module", "args", "argv"), [
    ("gps", {"state": "enabled"}, ["gps", "enable"]),
    ("gps", {"state": "disabled"}, ["gps", "disable"]),
    ("driver", {"state": "updated", "tag": "humble-2.1.2-20241125"}, ["driver", "update", "humble-2.1.2-20241125"]),
    ("driver", {"state": "restarted"}, ["driver", "restart"]),
    ("shutdown_hosts", {"src": str(INPUTS / "shutdown_hosts-manual.yaml")},
     ["config", "push", str(INPUTS / "shutdown_hosts-manual.yaml"), "--as", "shutdown-hosts"]),
    ("apply", {}, ["apply"]),
    ("estop", {"state": "reset"}, ["estop", "reset"]),
])
def test_check_mode_is_the_dry_run(demo: Path, capsys: pytest.CaptureFixture[str], module: str,
                                   args: dict[str, object], argv: list[str]) -> None:
    """Each module's check mode is its command's --dry-run: the same outcome, message and diffs."""
    from panther_ops.core.fleet.inventory_file import load_inventory

    inv = load_inventory(str(demo))  # the demo fleet's panther-01, its desired state included
    robot = inv.robots["panther-01"]
    before = sorted((p, p.read_bytes()) for p in (demo / "robots").rglob("*") if p.is_file())
    checked = run_module(module, args, inv, robot, check=True)
    code, doc, _, _ = run_cli(capsys, "-i", str(demo), *argv, "-r", "panther-01", "--dry-run", "--json")
    assert code in (0, 6), doc
    (r,) = doc["robots"]
    assert (checked["outcome"], checked["msg"]) == (r["outcome"], r["message"])
    assert checked.get("diff", {}).get("prepared", "") == "".join(d["unified"] for d in r["diffs"])
    assert sorted((p, p.read_bytes()) for p in (demo / "robots").rglob("*") if p.is_file()) == before


def test_estop_check_mode_contacts_nothing(tmp_path: Path) -> None:
    inv, robot = robot_from_hostvars("panther-09", {"ansible_host": "127.0.0.1", "ansible_port": 1})
    out = run_module("estop", {}, inv, robot, check=True)
    assert (out["changed"], out["failed"]) == (True, False) and "would trigger" in out["msg"]
    ran = run_module("estop", {}, inv, robot)  # nothing listens: panther-ops's own unreachable result
    assert (ran["failed"], ran["outcome"]) == (True, "unreachable")
