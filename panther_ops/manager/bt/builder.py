"""Build py_trees behaviours from BT.CPP v4 XML elements.

Ports: ``"{key}"`` reads blackboard entry `key` at tick time (``"{=}"``: the entry named like
the port); anything else is a literal converted to the port's type. Pre- and
post-conditions (``_skipIf`` ...) wrap the node in a `Guard`. ``<SubTree ID="X">`` builds
tree X in its own scope: entries remapped with ``port="{parent_key}"`` (or all of them with
``_autoremap="true"``) are the parent's, literals are set once, other names are private;
``@name`` is always the root tree's entry.
"""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from typing import Any

import py_trees

from panther_ops.manager.bt.expression import truthy
from panther_ops.manager.bt.project import BtProject
from panther_ops.manager.bt.registry import (
    GENERIC_TAGS,
    POSTCONDITIONS,
    PRECONDITIONS,
    REGISTRY,
)
from panther_ops.manager.errors import BtProjectError, ScriptError
from panther_ops.manager.nodes.base import NodeContext, Ref, ScriptProgram
from panther_ops.manager.nodes.decorators import Guard, SubTree

_GUARD_ARGS = {"_failureIf": "failure_if", "_successIf": "success_if", "_skipIf": "skip_if",
               "_while": "while_", "_onSuccess": "on_success", "_onFailure": "on_failure",
               "_post": "post"}
_ids = itertools.count(1)


class Scope:
    """How names of one (sub)tree map to blackboard keys of the tree's blackboard."""

    def __init__(self, prefix: str = "", parent: Scope | None = None,
                 remap: dict[str, str] | None = None, autoremap: bool = False) -> None:
        self.prefix = prefix
        self.parent = parent
        self.remap = remap or {}
        self.autoremap = autoremap

    def root(self) -> Scope:
        return self if self.parent is None else self.parent.root()

    def resolve(self, name: str) -> str:
        if name.startswith("@"):
            return self.root().resolve(name[1:])
        if self.parent is None:
            return name
        target = self.remap.get(name)
        if target is not None and is_ref(target):
            return self.parent.resolve(ref_key(target, name))
        if target is None and self.autoremap:
            return self.parent.resolve(name)
        return f"{self.prefix}/{name}"


def is_ref(value: str) -> bool:
    """``{key}`` (a blackboard reference) rather than a literal."""
    text = value.strip()
    return text.startswith("{") and text.endswith("}")


def ref_key(value: str, port: str) -> str:
    """The key of ``{key}``; ``{=}`` means the entry named like the port."""
    key = value.strip()[1:-1].strip()
    return port if key == "=" else key


def node_id(element: ET.Element) -> str:
    """The node type of an element (``<X>`` or v3-style ``<Action ID="X">``)."""
    if element.tag in GENERIC_TAGS and element.get("ID"):
        return str(element.get("ID"))
    return element.tag


def port_attributes(element: ET.Element) -> dict[str, str]:
    """Attributes that are ports (not name, ID, or ``_``-prefixed settings)."""
    skip = {"name"} | ({"ID"} if element.tag in GENERIC_TAGS else set())
    return {k: v for k, v in element.attrib.items() if k not in skip and not k.startswith("_")}


class Builder:
    """Builds the trees of one project for one tree context."""

    def __init__(self, project: BtProject, ctx: NodeContext) -> None:
        self.project = project
        self.ctx = ctx
        self.stack: list[str] = []

    def build_tree(self, tree_id: str, scope: Scope | None = None) -> py_trees.behaviour.Behaviour:
        tree = self.project.trees.get(tree_id)
        if tree is None:
            known = ", ".join(sorted(self.project.trees)) or "none"
            raise BtProjectError(f"{self.project.path}: no tree '{tree_id}' (trees: {known})")
        if tree_id in self.stack:
            raise BtProjectError(f"subtree recursion: {' -> '.join([*self.stack, tree_id])}")
        roots = list(tree.element)
        if len(roots) != 1:
            raise BtProjectError(f"{tree.source}: tree '{tree_id}' needs exactly one root node")
        self.stack.append(tree_id)
        try:
            return self.build_node(roots[0], scope or Scope(), f"{tree.source}: {tree_id}")
        finally:
            self.stack.pop()

    def build_node(self, element: ET.Element, scope: Scope, where: str) -> py_trees.behaviour.Behaviour:
        kind = node_id(element)
        name = element.get("name") or kind
        here = f"{where}/{kind}" + (f" '{element.get('name')}'" if element.get("name") else "")
        ctx = self.ctx.scoped(scope.resolve)
        try:
            if kind == "SubTree":
                node = self._subtree(element, scope, name, here)
            else:
                node_type = REGISTRY.get(kind)
                if node_type is None:
                    raise BtProjectError(f"unknown node <{kind}>")
                children = [self.build_node(child, scope, here) for child in element]
                low, high = node_type.children
                if len(children) < low or (high is not None and len(children) > high):
                    raise BtProjectError(f"<{kind}> cannot have {len(children)} children")
                ports: dict[str, Any] = {
                    port: Ref(ref_key(value, port)) if is_ref(value) and port not in node_type.scripts
                    else value
                    for port, value in port_attributes(element).items()
                }
                node = node_type.build(name, ctx, ports, children)
            return self._guard(node, element, ctx)
        except BtProjectError as exc:
            if str(exc).startswith(where):
                raise
            raise BtProjectError(f"{here}: {exc}") from None
        except ScriptError as exc:
            raise BtProjectError(f"{here}: {exc}") from None

    def _guard(self, node: py_trees.behaviour.Behaviour, element: ET.Element,
               ctx: NodeContext) -> py_trees.behaviour.Behaviour:
        programs = {_GUARD_ARGS[attr]: ScriptProgram(element.attrib[attr])
                    for attr in PRECONDITIONS + POSTCONDITIONS if element.get(attr)}
        return Guard(node, ctx, **programs) if programs else node

    def _subtree(self, element: ET.Element, scope: Scope, name: str,
                 where: str) -> py_trees.behaviour.Behaviour:
        tree_id = element.get("ID")
        if not tree_id:
            raise BtProjectError("<SubTree> without an ID")
        remap = port_attributes(element)
        remap.pop("ID", None)
        autoremap = truthy(element.get("_autoremap", "false"))
        inner = Scope(f"{scope.prefix}/{name}_{next(_ids)}".lstrip("/"), scope, remap, autoremap)
        for port, value in remap.items():
            if not is_ref(value):
                self.ctx.blackboard.set(inner.resolve(port), value)
        return SubTree(name, self.build_tree(tree_id, inner))
