"""BehaviorTree.CPP v4 projects: a Groot2 ``.btproj`` (or one ``.xml``) and what it includes.

``<root BTCPP_format="4">`` files hold ``<BehaviorTree ID="...">`` trees, ``<include
path="..."/>`` other files (relative to the including file; ``ros_pkg`` via
AMENT_PREFIX_PATH) and ``<TreeNodesModel>`` port descriptions for Groot2.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from panther_ops.manager.errors import BtProjectError

if TYPE_CHECKING:
    import py_trees

    from panther_ops.manager.nodes.base import NodeContext


@dataclass(frozen=True)
class TreeDef:
    """A ``<BehaviorTree>``: its ID, element and the file it is in."""

    id: str
    element: ET.Element
    source: Path


@dataclass(frozen=True)
class NodeModel:
    """A ``<TreeNodesModel>`` entry: node kind, ID and port names with defaults."""

    kind: str
    id: str
    ports: dict[str, str | None]
    source: Path


@dataclass
class BtProject:
    """Every tree and node model reachable from a project file."""

    path: Path
    files: list[Path] = field(default_factory=list)
    trees: dict[str, TreeDef] = field(default_factory=dict)
    models: dict[str, NodeModel] = field(default_factory=dict)
    formats: dict[Path, str | None] = field(default_factory=dict)

    def build(self, tree_id: str, ctx: NodeContext) -> py_trees.behaviour.Behaviour:
        """Build tree `tree_id` into py_trees behaviours bound to `ctx`."""
        from panther_ops.manager.bt.builder import Builder

        return Builder(self, ctx).build_tree(tree_id)


def _parse(path: Path) -> ET.Element:
    try:
        root = ET.parse(path).getroot()  # noqa: S314 - see the import note
    except OSError as exc:
        raise BtProjectError(f"{path}: cannot read: {exc.strerror or exc}") from exc
    except ET.ParseError as exc:
        raise BtProjectError(f"{path}: not well-formed XML: {exc}") from exc
    if root.tag != "root":
        raise BtProjectError(f"{path}: the top element must be <root>, not <{root.tag}>")
    return root


def _include_path(element: ET.Element, base: Path) -> Path:
    target = element.get("path")
    if not target:
        raise BtProjectError(f"{base}: <include> without a path")
    package = element.get("ros_pkg")
    if package:
        for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
            share = Path(prefix) / "share" / package
            if share.is_dir():
                return share / target
        raise BtProjectError(f"{base}: <include ros_pkg='{package}'>: no such ROS package here")
    path = Path(target)
    return path if path.is_absolute() else base.parent / path


def _read_models(element: ET.Element, source: Path, models: dict[str, NodeModel]) -> None:
    for entry in element:
        node_id = entry.get("ID")
        if node_id is None:
            continue
        ports: dict[str, str | None] = {}
        for port in entry:
            if port.tag.endswith("_port") and port.get("name"):
                ports[str(port.get("name"))] = port.get("default")
        models[node_id] = NodeModel(entry.tag, node_id, ports, source)


def _load(path: Path, project: BtProject, stack: tuple[Path, ...]) -> None:
    resolved = path.resolve()
    if resolved in stack:
        chain = " -> ".join(str(p) for p in (*stack, resolved))
        raise BtProjectError(f"include cycle: {chain}")
    if resolved in project.files:
        return
    root = _parse(path)
    project.files.append(resolved)
    project.formats[resolved] = root.get("BTCPP_format")
    for element in root:
        if element.tag == "include":
            target = _include_path(element, path)
            if not target.is_file():
                raise BtProjectError(f"{path}: included file {target} does not exist")
            _load(target, project, (*stack, resolved))
        elif element.tag == "BehaviorTree":
            tree_id = element.get("ID")
            if not tree_id:
                raise BtProjectError(f"{path}: <BehaviorTree> without an ID")
            if tree_id in project.trees:
                other = project.trees[tree_id].source
                raise BtProjectError(f"{path}: tree '{tree_id}' is already defined in {other}")
            project.trees[tree_id] = TreeDef(tree_id, element, path)
        elif element.tag == "TreeNodesModel":
            _read_models(element, path, project.models)


def load_bt_project(path: str | Path) -> BtProject:
    """Load a ``.btproj`` or BT.CPP ``.xml`` file and everything it includes.

    Raises:
        BtProjectError: unreadable or malformed XML, a missing include, a duplicate tree ID.
    """
    project = BtProject(Path(path))
    _load(Path(path), project, ())
    return project
