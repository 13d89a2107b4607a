"""Ansible inventories read by -i (INI, YAML, `ansible-inventory --list` JSON) and
`inventory export --ansible` (docs/ansible.md, "Inventory")."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from panther_ops.core.fleet.inventory_ansible import export_ansible
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.errors import InventoryError
from tests.clirun import run_cli

INI = """\
[all:vars]
panther_ops_known_hosts=known_hosts
ansible_user=husarion
site=hq

[warehouse]
panther-01 ansible_host=10.0.0.1 ansible_port=2201 site=hall-b
panther-02 ansible_host=10.0.0.2 panther_ops_namespace=p2 panther_ops_stack=2.2.2

[outdoor]
panther-03 ansible_host=10.0.0.3 ansible_ssh_private_key_file=/keys/id_ed25519

[outdoor:vars]
ansible_user=field

[sites:children]
warehouse
outdoor
"""


def robots_of(path: Path) -> dict[str, tuple[object, ...]]:
    inv = load_inventory(str(path))
    return {r.name: (r.host, r.port, r.user, r.identity_file, r.namespace, r.stack, tuple(sorted(r.groups)), r.vars)
            for r in inv.robots.values()}


def test_ini_hosts_groups_and_variables(tmp_path: Path) -> None:
    (tmp_path / "hosts.ini").write_text(INI)
    inv = load_inventory(str(tmp_path / "hosts.ini"))
    r1, r2, r3 = (inv.robots[n] for n in ("panther-01", "panther-02", "panther-03"))
    assert (r1.host, r1.port, r1.user, r1.vars) == ("10.0.0.1", 2201, "husarion", {"site": "hall-b"})
    assert (r2.namespace, r2.stack, r2.vars) == ("p2", "2.2.2", {"site": "hq"})
    assert (r3.user, r3.identity_file) == ("field", "/keys/id_ed25519")  # the group's vars over all's
    assert set(r1.groups) == {"warehouse", "sites"} and set(r3.groups) == {"outdoor", "sites"}
    assert inv.known_hosts == (str(tmp_path / "known_hosts"),)


def test_yaml_and_ansible_inventory_list_read_as_the_ini(tmp_path: Path) -> None:
    ini = tmp_path / "hosts.ini"
    ini.write_text(INI)
    tool = shutil.which("ansible-inventory") or str(Path(sys.executable).parent / "ansible-inventory")
    listed = subprocess.run([tool, "-i", str(ini), "--list"], check=True, capture_output=True, text=True,
                            env={"LC_ALL": "C.UTF-8", "PATH": str(Path(sys.executable).parent)}).stdout
    (tmp_path / "list.json").write_text(listed)
    assert "_meta" in json.loads(listed)
    (tmp_path / "hosts.yaml").write_text(yaml.safe_dump({
        "all": {"vars": {"panther_ops_known_hosts": "known_hosts", "ansible_user": "husarion", "site": "hq"},
                "children": {"sites": {"children": {
                    "warehouse": {"hosts": {
                        "panther-01": {"ansible_host": "10.0.0.1", "ansible_port": 2201, "site": "hall-b"},
                        "panther-02": {"ansible_host": "10.0.0.2", "panther_ops_namespace": "p2",
                                       "panther_ops_stack": "2.2.2"}}},
                    "outdoor": {"vars": {"ansible_user": "field"}, "hosts": {
                        "panther-03": {"ansible_host": "10.0.0.3",
                                       "ansible_ssh_private_key_file": "/keys/id_ed25519"}}}}}}}}))
    expected = robots_of(ini)
    assert robots_of(tmp_path / "hosts.yaml") == expected
    assert robots_of(tmp_path / "list.json") == expected


def test_export_reads_back_to_the_same_robots(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "hosts.yaml"
    code, _, _, _ = run_cli(capsys, "-i", str(demo), "inventory", "export", "--ansible", "-o", str(out))
    assert code == 0
    native = load_inventory(str(demo))
    back = load_inventory(str(out))
    fields = ("host", "port", "user", "identity_file", "jump", "namespace", "stack", "groups", "desired",
              "transport", "root", "compose_file")
    assert list(back.robots) == list(native.robots)
    for name, r in native.robots.items():
        assert {f: getattr(back.robots[name], f) for f in fields} == {f: getattr(r, f) for f in fields}
    assert yaml.safe_load(out.read_text()) == export_ansible(native)


def test_export_needs_a_format(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, _, err = run_cli(capsys, "-i", str(demo), "inventory", "export")
    assert code == 2 and "--ansible" in err


@pytest.mark.parametrize(("text", "words", "key"), [
    ("[w]\nr1 ansible_host=10.0.0.1 ansible_port=99999\n", "port 99999 is not a TCP port", "r1.ansible_port"),
    ("[w]\nr1 panther_ops_colour=red\n", "unknown variable 'panther_ops_colour'", "r1.panther_ops_colour"),
    ("[w]\npanther-[01:20] ansible_user=husarion\n", "host range", "w.panther-[01:20]"),
    ("[w]\nr1 ansible_host\n", "expected key=value", "w.r1"),
    ("[w:hostz]\nr1\n", "unknown section kind 'hostz'", None),
    ("[a]\nr1 panther_ops_known_hosts=x\n[b]\nr2 panther_ops_known_hosts=y\n", "differs between hosts",
     "r2.panther_ops_known_hosts"),
    ("[w]\nr1 ansible_host='bad host'\n", "", "r1.ansible_host"),
])
def test_bad_ansible_inventory_is_exit_2_naming_file_and_key(tmp_path: Path, text: str, words: str,
                                                             key: str | None) -> None:
    path = tmp_path / "hosts.ini"
    path.write_text(text)
    with pytest.raises(InventoryError) as err:
        load_inventory(str(path))
    assert err.value.exit_code == 2
    assert err.value.path == str(path) and err.value.key == key
    assert words in str(err.value)


def test_native_inventory_is_not_taken_for_ansible(demo: Path) -> None:
    for f in demo.glob("*.yaml"):
        assert load_inventory(str(f)).robots  # a panther-ops file read as before
