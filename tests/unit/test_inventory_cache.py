"""The inventory's YAML read back from the cache: the same document, or none at all."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

from panther_ops.core.fleet import inventory_cache
from panther_ops.core.fleet.inventory import load_inventory
from panther_ops.core.yaml.located import LineDict, LineList, load_yaml_file
from panther_ops.errors import InputError, InventoryError

INVENTORY = """\
version: 1
settings:
  forks: 8            # a comment
defaults:
  user: husarion
robots:
  r01:
    host: 10.200.9.11
    groups: [lab, "quoted"]
    vars: {floor: 2, ratio: 0.5, on: true, none: null}
  r02: {host: 10.200.9.12, port: 2222}
groups: {lab: {}, quoted: {}}
"""


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    d = tmp_path / "cache"
    monkeypatch.setenv("PANTHER_OPS_CACHE_DIR", str(d))
    return d


def _shape(value: object) -> object:
    """A document with its line numbers, comparable."""
    if isinstance(value, LineDict):
        return ("d", value.line, [(k, value.line_of(k), _shape(v)) for k, v in value.items()])
    if isinstance(value, LineList):
        return ("l", value.line, value.item_lines, [_shape(v) for v in value])
    return (type(value).__name__, value)


def test_a_cached_document_is_the_parsed_one(tmp_path: Path, cache: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text(INVENTORY)
    first = inventory_cache.load(f, load_yaml_file)
    assert len(list(cache.glob("*.json"))) == 1
    parsed: list[Path] = []
    again = inventory_cache.load(f, parsed.append)  # must not parse again
    assert parsed == []
    assert _shape(again) == _shape(first) == _shape(load_yaml_file(f))
    assert oct(cache.stat().st_mode & 0o777) == "0o700"
    assert all(oct(p.stat().st_mode & 0o777) == "0o600" for p in cache.glob("*.json"))


def test_a_changed_file_is_parsed_again(tmp_path: Path, cache: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text(INVENTORY)
    load_inventory(str(f))
    f.write_text(INVENTORY.replace("10.200.9.12", "10.200.9.13"))
    assert load_inventory(str(f)).robots["r02"].host == "10.200.9.13"


def test_errors_name_the_same_lines_from_the_cache(tmp_path: Path, cache: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text(INVENTORY.replace("port: 2222", "port: many"))
    messages = []
    for _ in range(2):  # parsed, then from the cache
        with pytest.raises(InventoryError) as exc:
            load_inventory(str(f))
        messages.append(str(exc.value))
    assert messages[0] == messages[1] and ":11" in messages[0]
    assert len(list(cache.glob("*.json"))) == 1


def test_values_json_cannot_carry_are_not_kept(tmp_path: Path, cache: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text("robots:\n  r01:\n    host: 10.200.9.11\n    since: 2026-11-22\n")
    doc = inventory_cache.load(f, load_yaml_file)
    assert str(doc["robots"]["r01"]["since"]) == "2026-11-22"
    assert list(cache.glob("*.json")) == []


def test_a_yaml_error_keeps_nothing(tmp_path: Path, cache: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text("robots: [\n")
    with pytest.raises(InputError):
        load_inventory(str(f))
    assert list(cache.glob("*.json")) == []


def test_off_or_not_private_means_no_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text(INVENTORY)
    monkeypatch.setenv("PANTHER_OPS_CACHE_DIR", "")
    assert inventory_cache.cache_dir() is None
    shared = tmp_path / "shared"
    shared.mkdir(mode=0o777)
    os.chmod(shared, 0o777)
    monkeypatch.setenv("PANTHER_OPS_CACHE_DIR", str(shared))
    assert inventory_cache.cache_dir() is None
    inventory_cache.load(f, load_yaml_file)
    assert list(shared.iterdir()) == []


def test_a_damaged_entry_is_replaced(tmp_path: Path, cache: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text(INVENTORY)
    inventory_cache.load(f, load_yaml_file)
    [entry] = cache.glob("*.json")
    entry.write_text("{not json")
    assert _shape(inventory_cache.load(f, load_yaml_file)) == _shape(load_yaml_file(f))
    json.loads(entry.read_text())


def test_old_entries_are_dropped(tmp_path: Path, cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(inventory_cache, "KEEP", 3)
    for i in range(5):
        f = tmp_path / f"fleet{i}.yaml"
        f.write_text(INVENTORY)
        inventory_cache.load(f, load_yaml_file)
    assert len(list(cache.glob("*.json"))) == 3


def test_an_unchanged_inventory_is_read_without_pyyaml(tmp_path: Path) -> None:
    import subprocess

    f = tmp_path / "fleet.yaml"
    f.write_text(INVENTORY)
    env = {**os.environ, "PANTHER_OPS_CACHE_DIR": str(tmp_path / "cache")}
    code = ("import sys; from panther_ops.core.fleet.inventory import load_inventory; "
            f"inv = load_inventory({str(f)!r}); print(sorted(inv.robots), 'yaml' in sys.modules)")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True).stdout
            for _ in range(2)]
    assert runs == ["['r01', 'r02'] True\n", "['r01', 'r02'] False\n"]
