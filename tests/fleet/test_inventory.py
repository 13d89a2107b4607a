from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.fleet.inventory_file import find_inventory, load_inventory
from panther_ops.errors import ExitCode, InputError, InventoryError


def write(tmp: Path, text: str, name: str = "fleet.yaml") -> Path:
    p = tmp / name
    p.write_text(text)
    return p


def refused(tmp: Path, text: str) -> str:
    """The inventory ``text`` (as ``tmp``/fleet.yaml) is refused as a usage error naming the
    file: the message."""
    path = write(tmp, text)
    with pytest.raises(InputError) as exc:
        load_inventory(str(path))
    assert str(path) in str(exc.value)
    assert exc.value.exit_code is ExitCode.USAGE
    return str(exc.value)


GOOD = """\
version: 1
settings:
  known_hosts: kh
  forks: 4
defaults:
  user: husarion
  identity_file: keys/id
  desired:
    launch_args: {wheel_type: WH01}
groups:
  warehouse:
    desired:
      launch_args: {wheel_type: WH02}
robots:
  p1: {host: panther-01, groups: [warehouse]}
  p2:
    host: 10.0.0.2
    port: 2222
    jump: p1
    desired:
      launch_args: {use_ekf: false}
  p3: {host: panther-03, jump: "op@gw.example.org:2200", stack: 2.2.2}
"""


def test_good_inventory_resolves_defaults_groups_and_paths(tmp_path: Path) -> None:
    inv = load_inventory(str(write(tmp_path, GOOD)))
    assert list(inv.robots) == ["p1", "p2", "p3"]
    p1, p2, p3 = inv.robots.values()
    assert p1.desired == {"launch_args": {"wheel_type": "WH02"}}
    assert p2.desired == {"launch_args": {"wheel_type": "WH01", "use_ekf": False}}
    assert p1.identity_file == str((tmp_path / "keys/id").resolve())
    assert inv.known_hosts == (str((tmp_path / "kh").resolve()),)
    assert inv.forks == 4
    ep = inv.endpoint(p2)
    assert ep.port == 2222 and ep.jump is not None and ep.jump.host == "panther-01"
    ep3 = inv.endpoint(p3)
    assert ep3.jump is not None and (ep3.jump.user, ep3.jump.host, ep3.jump.port) == ("op", "gw.example.org", 2200)
    assert p3.stack == "2.2.2"


def test_selection_globs_groups_all(tmp_path: Path) -> None:
    inv = load_inventory(str(write(tmp_path, GOOD)))
    assert [r.name for r in inv.select(["p[12]"], [], False)] == ["p1", "p2"]
    assert [r.name for r in inv.select([], ["warehouse"], False)] == ["p1"]
    assert len(inv.select([], [], True)) == 3
    with pytest.raises(InventoryError, match="choose with --robot"):
        inv.select([], [], False)
    with pytest.raises(InventoryError, match="no robot matches"):
        inv.select(["nope*"], [], False)
    with pytest.raises(InventoryError, match="no group 'x'"):
        inv.select([], ["x"], False)


def test_one_robot_inventory_needs_no_selection(tmp_path: Path) -> None:
    inv = load_inventory(str(write(tmp_path, "robots:\n  solo: {host: a}\n")))
    assert [r.name for r in inv.select([], [], False)] == ["solo"]


@pytest.mark.parametrize(
    ("text", "where", "what"),
    [
        ("robots:\n  r1: {host: a, port: 70000}\n", ":2 [robots.r1.port]", "not a TCP port"),
        ("robots:\n  r1:\n    host: a\n    user: Bad User\n", ":4 [robots.r1.user]", "not a POSIX user name"),
        ("robots:\n  r1: {host: a, colour: red}\n", "[robots.r1.colour]", "unknown key 'colour'"),
        ("robots:\n  r1: {port: 22}\n", "[robots.r1.host]", "missing `host:`"),
        ("robots:\n  r1: {host: a, stack: 2.4.0}\n", "[robots.r1.stack]", "not a release panther-ops knows"),
        ("robots:\n  r1: {host: a, jump: r9 x}\n", "[robots.r1.jump]", "neither a robot"),
        ("robots:\n  r1: {host: a, jump: r2}\n  r2: {host: b, jump: r1}\n", "", "loop"),
        ("robots:\n  r1:\n    host: a\n    vars:\n      router_password: Husarion1\n", ":5 [robots.r1.vars.router_password]",
         "plaintext secrets"),
        ("robots:\n  r1:\n    host: a\n    desired:\n      colour: 1\n", "[robots.r1.desired.colour]", "unknown desired"),
        ("robots: [a, b]\n", "[robots]", "must be a mapping"),
        ("robots:\n  r1: {host: a}\n  r1: {host: b}\n", ":3 [r1]", "duplicate key"),
        ("robots:\n  r1: {host: [a\n", ":3", "invalid YAML"),
        ("version: 2\nrobots: {r1: {host: a}}\n", "[version]", "unsupported inventory version"),
        ("settings: {forks: 0}\nrobots: {r1: {host: a}}\n", "[settings.forks]", "forks must be"),
    ],
)
def test_bad_inventory_names_file_line_key(tmp_path: Path, text: str, where: str, what: str) -> None:
    message = refused(tmp_path, text)
    assert where in message
    assert what in message


def test_secret_references_are_allowed(tmp_path: Path) -> None:
    text = ("robots:\n  r1:\n    host: a\n    vars:\n      router_password: {env: ROUTER_PW}\n"
            "      token: {file: ~/tok}\n      secret: {prompt: true}\n")
    inv = load_inventory(str(write(tmp_path, text)))
    assert inv.robots["r1"].vars["router_password"] == {"env": "ROUTER_PW"}


def test_directory_inventory_merges_files_and_refuses_duplicates(tmp_path: Path) -> None:
    write(tmp_path, "robots:\n  a: {host: a}\n", "1.yaml")
    write(tmp_path, "robots:\n  b: {host: b}\n", "2.yml")
    write(tmp_path, "not: loaded\n", "notes.txt")
    assert list(load_inventory(str(tmp_path)).robots) == ["a", "b"]
    write(tmp_path, "robots:\n  a: {host: c}\n", "3.yaml")
    with pytest.raises(InventoryError, match="defined twice"):
        load_inventory(str(tmp_path))


def test_lookup_order(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("PANTHER_OPS_INVENTORY", raising=False)
    assert find_inventory(None) == (Path("inventory"), "./inventory/ (default)")
    monkeypatch.setenv("PANTHER_OPS_INVENTORY", "/x/fleet.yaml")
    assert find_inventory(None) == (Path("/x/fleet.yaml"), "$PANTHER_OPS_INVENTORY")
    assert find_inventory("given.yaml") == (Path("given.yaml"), "-i")
    monkeypatch.delenv("PANTHER_OPS_INVENTORY")
    with pytest.raises(InventoryError, match="inventory not found"):
        load_inventory(None)


def test_shipped_example_is_valid() -> None:
    root = Path(__file__).resolve().parents[2]
    inv = load_inventory(str(root / "inventory" / "examples" / "fleet.yaml"))
    assert "panther-03" in inv.robots
