"""`validate_bt_project`: required trees, known nodes and ports, scripts, kept safety behaviours.

The manual: "The project should consist of Lights behavior tree or both Safety and Shutdown
behavior tree" and "exercise caution when modifying the trees responsible for safety or
shutdown and ensure that default behaviors are not removed". The second is checked by
comparing what a custom Safety / Shutdown tree does (services called, nodes used, battery
conditions read) with the shipped default trees, and warning for each default behaviour gone.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from panther_ops.manager import keys
from panther_ops.manager.bt.builder import is_ref, node_id, port_attributes, ref_key
from panther_ops.manager.bt.expression import parse
from panther_ops.manager.bt.project import BtProject, load_bt_project
from panther_ops.manager.bt.registry import REGISTRY, SCRIPT_ATTRIBUTES
from panther_ops.manager.config import (
    LightsParams,
    SafetyParams,
    lights_constants,
    safety_constants,
    shutdown_constants,
)
from panther_ops.manager.constants import ANIMATION_ID_CONSTANTS_22, LIGHTS_TREE, SAFETY_TREE, SHUTDOWN_TREE
from panther_ops.manager.errors import BtProjectError, ScriptError
from panther_ops.manager.findings import Finding, error, warning
from panther_ops.manager.nodes.base import REQUIRED, convert
from panther_ops.manager.paths import BEHAVIOR_TREES

KNOWN_NAMES: dict[str, set[str]] = {
    LIGHTS_TREE: {*lights_constants(LightsParams()), *keys.LIGHTS_INPUTS, *keys.LIGHTS_STATE,
                  *ANIMATION_ID_CONSTANTS_22, *keys.LIGHTS_STATE_22},  # 2.2's stock Lights tree too
    SAFETY_TREE: {*safety_constants(SafetyParams()), *keys.SAFETY_INPUTS, *keys.SAFETY_STATE},
    SHUTDOWN_TREE: {*shutdown_constants(SafetyParams()), keys.SIGNAL_SHUTDOWN},
}
FEATURES: dict[tuple[str, ...], str] = {
    ("call", "hardware/e_stop_trigger", ""): "trigger the E-stop (hardware/e_stop_trigger)",
    ("call", "hardware/aux_power_enable", "false"): "turn AUX power off",
    ("call", "hardware/fan_enable", "true"): "turn the fan on",
    ("call", "hardware/fan_enable", "false"): "turn the fan off",
    ("node", "SignalShutdown"): "signal a robot shutdown",
    ("node", "RunOnce"): "run the fan at start-up (RunOnce)",
    ("node", "TickAfterTimeout"): "keep the fan on at least FAN_TURN_OFF_TIMEOUT (TickAfterTimeout)",
    ("node", "ShutdownHostsFromFile"): "shut down the hosts of the shutdown hosts file",
    ("robot",): "shut the robot itself down (ExecuteCommand or ShutdownSingleHost)",
    ("name", "POWER_SUPPLY_HEALTH_OVERHEAT"): "react to battery OVERHEAT",
    ("name", "POWER_SUPPLY_HEALTH_DEAD"): "react to a DEAD battery",
    ("name", "POWER_SUPPLY_HEALTH_OVERVOLTAGE"): "react to battery OVERVOLTAGE",
    ("name", "CRITICAL_BAT_TEMP"): "act above CRITICAL_BAT_TEMP (E-stop and AUX off)",
    ("name", "FATAL_BAT_TEMP"): "act above FATAL_BAT_TEMP (shutdown)",
}
_ROBOT_SHUTDOWN = {"ExecuteCommand", "ShutdownSingleHost"}


@dataclass
class _Walk:
    project: BtProject
    tree: str
    findings: list[Finding] = field(default_factory=list)
    features: set[tuple[str, ...]] = field(default_factory=set)
    reads: dict[str, str] = field(default_factory=dict)
    writes: set[str] = field(default_factory=set)
    stack: list[str] = field(default_factory=list)


def _elements(element: ET.Element, where: str) -> Iterator[tuple[ET.Element, str]]:
    yield element, where
    for child in element:
        yield from _elements(child, f"{where}/{node_id(child)}")


def _scripts(element: ET.Element, walk: _Walk, where: str, script_ports: frozenset[str]) -> None:
    sources = [(a, element.attrib[a]) for a in SCRIPT_ATTRIBUTES if element.get(a)]
    sources += [(p, element.attrib[p]) for p in script_ports if element.get(p)]
    for attr, code in sources:
        try:
            script = parse(code)
        except ScriptError as exc:
            walk.findings.append(error("bt-script-syntax", f"{attr}: {exc}", where))
            continue
        for name in script.reads:
            walk.reads.setdefault(name.lstrip("@"), f"{where} ({attr})")
            walk.features.add(("name", name.lstrip("@")))
        walk.writes |= {n.lstrip("@") for n in script.writes}


def _ports(element: ET.Element, kind: str, walk: _Walk, where: str) -> None:
    node_type = REGISTRY[kind]
    given = port_attributes(element)
    canonical = {node_type.aliases.get(p, p): v for p, v in given.items()}
    for port, value in given.items():
        name = node_type.aliases.get(port, port)
        if name not in node_type.ports:
            known = ", ".join(node_type.ports) or "none"
            walk.findings.append(error("bt-port-unknown", f"<{kind}> has no port '{port}' "
                                       f"(ports: {known})", where))
        elif is_ref(value):
            walk.reads.setdefault(ref_key(value, name), f"{where} ({port})")
        elif name not in node_type.scripts:
            try:
                convert(value, node_type.ports[name].kind)
            except ScriptError as exc:
                walk.findings.append(error("bt-port-value", f"<{kind}> port '{port}': {exc}",
                                           where))
    for name, spec in node_type.ports.items():
        if spec.default is REQUIRED and name not in canonical:
            walk.findings.append(error("bt-port-missing", f"<{kind}> needs port '{name}'", where))
    service = canonical.get("service_name", "")
    if kind in {"CallTriggerService", "CallSetBoolService"} and not is_ref(service):
        data = canonical.get("data", "").strip().lower()
        walk.features.add(("call", service.strip("/"), data))
    walk.features.add(("node", kind))
    if kind in _ROBOT_SHUTDOWN:
        walk.features.add(("robot",))


def _walk_tree(tree_id: str, walk: _Walk, where: str) -> None:
    tree = walk.project.trees.get(tree_id)
    if tree is None:
        walk.findings.append(error("bt-subtree-unknown", f"no tree '{tree_id}' in the project",
                                   where))
        return
    if tree_id in walk.stack:
        walk.findings.append(error("bt-subtree-recursive", f"tree '{tree_id}' includes itself",
                                   where))
        return
    roots = list(tree.element)
    if len(roots) != 1:
        walk.findings.append(error("bt-tree-root", f"tree '{tree_id}' needs exactly one root "
                                   f"node, has {len(roots)}", f"{tree.source}: {tree_id}"))
        return
    walk.stack.append(tree_id)
    base = f"{tree.source}: {tree_id}"
    for element, path in _elements(roots[0], f"{base}/{node_id(roots[0])}"):
        _node(element, walk, path)
    walk.stack.pop()


def _node(element: ET.Element, walk: _Walk, where: str) -> None:
    kind = node_id(element)
    for attr in element.attrib:
        if attr.startswith("_") and attr not in SCRIPT_ATTRIBUTES and attr != "_autoremap":
            walk.findings.append(warning("bt-attribute-ignored", f"attribute '{attr}' is not "
                                         "supported and is ignored", where))
    if kind == "SubTree":
        target = element.get("ID", "")
        if element.get("_autoremap", "false").lower() == "true":
            _walk_tree(target, walk, where)
        elif target not in walk.project.trees:
            walk.findings.append(error("bt-subtree-unknown", f"no tree '{target}' in the project",
                                       where))
        _scripts(element, walk, where, frozenset())
        return
    node_type = REGISTRY.get(kind)
    if node_type is None:
        walk.findings.append(error("bt-node-unknown", f"unknown node <{kind}>; supported: "
                                   f"{', '.join(sorted(REGISTRY))}, SubTree", where))
        return
    low, high = node_type.children
    count = len(list(element))
    if count < low or (high is not None and count > high):
        wanted = f"{low}" if low == high else f"at least {low}"
        walk.findings.append(error("bt-children", f"<{kind}> needs {wanted} child node(s), has "
                                   f"{count}", where))
    _ports(element, kind, walk, where)
    _scripts(element, walk, where, node_type.scripts)
    if kind == "Parallel":
        _parallel(element, count, walk, where)


def _parallel(element: ET.Element, children: int, walk: _Walk, where: str) -> None:
    """BT.CPP refuses a Parallel whose counts its children cannot reach (LogicError at its first
    tick, BehaviorTree/BehaviorTree.CPP@4.6.2:src/controls/parallel_node.cpp)."""
    from panther_ops.manager.nodes.controls import Parallel

    for port, what in (("success_count", "succeed"), ("failure_count", "fail")):
        value = element.get(port, str(Parallel.PORTS[port].default))
        try:
            count = int(convert(value, "int"))
        except ScriptError:
            continue  # a reference, or a value _ports already reported
        if children < Parallel.threshold(count, children):
            walk.findings.append(error("bt-parallel-count", f"<Parallel> {port}={count} with {children} "
                                       f"children: it can never {what}", where))


@lru_cache(maxsize=4)
def _default_features(tree_id: str) -> frozenset[tuple[str, ...]]:
    project = load_bt_project(BEHAVIOR_TREES / "PantherSafetyBT.btproj")
    walk = _Walk(project, tree_id)
    _walk_tree(tree_id, walk, tree_id)
    return frozenset(f for f in walk.features if f in FEATURES)


def _caution(tree_id: str, walk: _Walk, where: str) -> list[Finding]:
    findings = []
    for feature in sorted(_default_features(tree_id) - walk.features):
        findings.append(warning("bt-safety-dropped", f"this {tree_id} tree drops a default "
                                f"behaviour: {FEATURES[feature]} (the manual: keep the default "
                                "safety and shutdown behaviours)", where))
    return findings


def validate_bt_project(path: str | Path) -> list[Finding]:
    """Check a BehaviorTree project (``.btproj`` or ``.xml``); empty when all is well.

    Errors: unreadable files, missing required trees (Lights; or Safety and Shutdown),
    unknown nodes or ports, missing required ports, bad literal values, script syntax.
    Warnings: unknown blackboard names, ignored attributes, a non-v4 format, and each
    default Safety / Shutdown behaviour a custom tree dropped.
    """
    try:
        project = load_bt_project(path)
    except BtProjectError as exc:
        return [error("bt-project-unreadable", str(exc), str(path))]
    findings: list[Finding] = []
    for file, version in project.formats.items():
        if version != "4":
            findings.append(warning("bt-format", f"BTCPP_format is {version!r}; this manager "
                                    "reads BehaviorTree.CPP v4 files (Groot2)", str(file)))
    present = set(project.trees)
    if LIGHTS_TREE not in present and not present & {SAFETY_TREE, SHUTDOWN_TREE}:
        findings.append(error("bt-tree-missing", "the project has neither a 'Lights' tree nor "
                              "'Safety' and 'Shutdown' trees", str(path)))
    for needed, other in ((SAFETY_TREE, SHUTDOWN_TREE), (SHUTDOWN_TREE, SAFETY_TREE)):
        if other in present and needed not in present:
            findings.append(error("bt-tree-missing", f"a safety project needs both 'Safety' and "
                                  f"'Shutdown' trees; '{needed}' is missing", str(path)))
    for tree_id in (LIGHTS_TREE, SAFETY_TREE, SHUTDOWN_TREE):
        if tree_id not in present:
            continue
        walk = _Walk(project, tree_id)
        _walk_tree(tree_id, walk, str(path))
        findings += walk.findings
        known = KNOWN_NAMES[tree_id] | walk.writes
        for name, where in sorted(walk.reads.items()):
            if name not in known:
                findings.append(warning("bt-name-unknown", f"'{name}' is not a blackboard entry "
                                        f"of the {tree_id} tree", where))
        if tree_id in (SAFETY_TREE, SHUTDOWN_TREE):
            findings += _caution(tree_id, walk, f"{project.trees[tree_id].source}: {tree_id}")
    return findings
