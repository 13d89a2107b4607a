"""Property-style tests over every real-shaped input (templates and golden inputs).

(templates/config-tree holds copies of templates/config files: test_config_files checks that.)

- setting a value to what it already is changes nothing;
- changing one scalar changes exactly that line, and setting it back restores the bytes;
- adding a key / an item and removing it again restores the bytes;
- compose: set_arg + unset_arg, add_volume + remove_volume, add_service + remove_service,
  set_env + unset_env restore the file byte for byte.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from panther_ops.core.robot.compose import ComposeFile
from panther_ops.core.yaml.diff import changed_lines, unified_diff
from panther_ops.core.yaml.document import PathPart, YamlDocument
from panther_ops.core.yaml.render import Block
from panther_ops.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
INPUTS = sorted(
    [
        *ROOT.glob("templates/compose/*.yaml"),
        *ROOT.glob("templates/config/**/*.yaml"),
        *ROOT.glob("tests/golden/inputs/*.yaml"),
    ]
)
COMPOSE_INPUTS = sorted(
    [*ROOT.glob("templates/compose/*.yaml"), *ROOT.glob("tests/golden/inputs/compose-*.yaml")]
)


def _ids(paths: list[Path]) -> list[str]:
    return [str(p.relative_to(ROOT)) for p in paths]


def _leaves(doc: YamlDocument, value: Any, path: tuple[PathPart, ...] = ()) -> Iterator[tuple[PathPart, ...]]:
    """Own (not inherited, not aliased) scalar leaves."""
    if path and (doc.origin(path) != "own" or doc.info(path).kind == "alias"):
        return
    if isinstance(value, dict):
        for key, sub in value.items():
            yield from _leaves(doc, sub, (*path, key))
    elif isinstance(value, list):
        for i, sub in enumerate(value):
            yield from _leaves(doc, sub, (*path, i))
    else:
        yield path


def _collections(doc: YamlDocument, value: Any, path: tuple[PathPart, ...] = ()) -> Iterator[tuple[tuple[PathPart, ...], Any]]:
    if path and (doc.origin(path) != "own" or doc.info(path).kind == "alias"):
        return
    if isinstance(value, dict | list):
        yield path, value
        items = value.items() if isinstance(value, dict) else enumerate(value)
        for key, sub in items:
            yield from _collections(doc, sub, (*path, key))


def _other(value: Any) -> Any:
    if isinstance(value, bool):
        return not value
    if isinstance(value, int):
        return value + 1
    if isinstance(value, float):
        return 1.0 if math.isnan(value) else value + 0.5  # .NAN (Jazzy's "no limit"): nan + 0.5 is nan
    if isinstance(value, str):
        return value + "x" if value else "x"
    return None


@pytest.mark.parametrize("path", INPUTS, ids=_ids(INPUTS))
def test_setting_current_values_changes_nothing(path: Path) -> None:
    text = path.read_text()
    doc = YamlDocument(text, str(path))
    for leaf in _leaves(doc, doc.to_plain()):
        assert doc.set(leaf, doc.get(leaf)) is False, leaf
    for coll_path, value in _collections(doc, doc.to_plain()):
        if coll_path:
            assert doc.set(coll_path, value) is False, coll_path
    assert doc.text == text


@pytest.mark.parametrize("path", INPUTS, ids=_ids(INPUTS))
def test_one_value_changes_exactly_its_line(path: Path) -> None:
    text = path.read_text()
    doc = YamlDocument(text, str(path))
    checked = 0
    leaves = list(_leaves(doc, doc.to_plain()))
    step = max(1, len(leaves) // 15)  # a spread sample keeps the run short
    for leaf in leaves[::step]:
        old = doc.get(leaf)
        new = _other(old)
        info = doc.info(leaf)
        if new is None or info.style in ("|", ">") or "\n" in info.raw:
            continue
        assert doc.set(leaf, new) is True
        lines = changed_lines(unified_diff(text, doc.text, "f.yaml"))
        assert len(lines) == 2 and lines[0][0] == "-" and lines[1][0] == "+", (leaf, lines)
        before, after = text.splitlines(), doc.text.splitlines()
        assert len(before) == len(after)
        assert [i for i, (a, b) in enumerate(zip(before, after, strict=True)) if a != b] == [info.line - 1]
        assert doc.get(leaf) == new
        doc.set(leaf, old)
        assert doc.text == text, leaf
        checked += 1
    assert checked or not leaves


@pytest.mark.parametrize("path", INPUTS, ids=_ids(INPUTS))
def test_add_then_remove_restores_the_bytes(path: Path) -> None:
    text = path.read_text()
    doc = YamlDocument(text, str(path))
    for coll_path, value in list(_collections(doc, doc.to_plain())):
        if isinstance(value, dict):
            key = (*coll_path, "zz_added_by_test")
            doc.set(key, "added")
            assert doc.get(key) == "added"
            assert doc.delete(key) is True
        else:
            doc.append(coll_path, "added")
            assert doc.get((*coll_path, len(value))) == "added"
            assert doc.delete((*coll_path, len(value))) is True
        assert doc.text == text, coll_path


@pytest.mark.parametrize("path", COMPOSE_INPUTS, ids=_ids(COMPOSE_INPUTS))
def test_compose_set_then_unset_arg_restores(path: Path) -> None:
    text = path.read_text()
    compose = ComposeFile.parse(text, str(path))
    for service in compose.services():
        try:
            args = compose.command(service).args
        except Exception:
            continue
        for name, value in [("zz_test_arg", "1"), ("wheel_config_path", "$(find panther_description)/config/WH02.yaml")]:
            if name in args:
                continue
            if "$" in value and compose.command(service).shell:  # inside bash -c "...": the shell would expand it
                with pytest.raises(InputError, match=r"wheel_config_path: the value '\$\(find"):
                    compose.set_arg(name, value, service)
                assert compose.text() == text, (service, name)
                continue
            assert compose.set_arg(name, value, service) is True
            assert compose.command(service).args[name] == value
            assert compose.set_arg(name, value, service) is False
            assert compose.unset_arg(name, service) is True
            assert compose.text() == text, (service, name)
        for name, value in args.items():
            assert compose.set_arg(name, value, service) is False
            if "$" in value and compose.command(service).shell:
                with pytest.raises(InputError, match=f"{name}: the value"):
                    compose.set_arg(name, value + "_x", service)
                assert compose.text() == text, (service, name)
                continue
            assert compose.set_arg(name, value + "_x", service) is True
            assert compose.set_arg(name, value, service) is True
            assert compose.text() == text, (service, name)


@pytest.mark.parametrize("path", COMPOSE_INPUTS, ids=_ids(COMPOSE_INPUTS))
def test_compose_volume_service_env_roundtrips(path: Path) -> None:
    text = path.read_text()
    compose = ComposeFile.parse(text, str(path))
    if compose.list_volumes():
        assert compose.add_volume("/home/husarion/maps", "/maps", ro=True) is True
        assert compose.add_volume("/home/husarion/maps", "/maps", ro=True) is False
        assert compose.remove_volume("/maps") is True
        assert compose.text() == text
    for vol in compose.list_volumes():
        assert compose.add_volume(vol.source or "", vol.target, vol.read_only) is False
    assert compose.add_service("zz_test", {"image": "busybox:1", "command": Block("sleep\n  infinity\n", ">")}) is True
    assert compose.remove_service("zz_test") is True
    assert compose.text() == text
    env_path = ("services", compose.driver_service(), "environment")
    origin = compose.doc.origin(env_path)
    if origin == "own":
        assert compose.set_env("ZZ_TEST", "1") is True
        assert compose.get_env("ZZ_TEST") == "1"
        assert compose.unset_env("ZZ_TEST") is True
        assert compose.text() == text
    elif origin is not None:
        assert compose.set_env("ZZ_TEST", "1", shared=True) is True
        assert compose.unset_env("ZZ_TEST", shared=True) is True
        assert compose.text() == text
        for key, value in compose.environment().items():
            if value is not None:
                assert compose.set_env(key, value) is False
