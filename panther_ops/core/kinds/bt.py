"""BT projects: `validate_bt_project` (as `bt validate`), and every include kept inside the project.

An ``<include path="...">`` is resolved against the including file and must stay inside the
directory of the ``.btproj``: the included files are copied beside it on the robot, so a
path that leaves it (``../../.ssh/authorized_keys``, an absolute path, a link out) would
read or write anywhere. ``ros_pkg`` includes are resolved on the robot (not copied).

A node's ``service_name`` port (CallSetBoolService, CallTriggerService,
CallSetLedAnimationService...) is a ROS service name: a literal one is checked by the one parser
of ROS names (`core/parse/ros_names.py`, `service_name_findings`), in `bt validate` and every
path that carries a project (the runtime manager, archived alone onto the robot, cannot import it).
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING

from panther_ops.core.kinds.common import text_of
from panther_ops.core.kinds.lights import on_disk, split
from panther_ops.core.kinds.registry import FileKindError, Target
from panther_ops.core.parse.ros_names import RosNameError, service_name

if TYPE_CHECKING:
    from panther_ops.manager.findings import Finding

WHAT = "BT project"


def project_files(main: Path) -> dict[str, Path]:
    """Every file a project includes (relative name -> local path), each confined to the
    project's directory; raises `FileKindError` naming the first path that leaves it."""
    root = main.parent.resolve()
    found: dict[str, Path] = {}
    todo = [main]
    seen: set[Path] = set()
    while todo:
        current = todo.pop()
        real = current.resolve()
        if real in seen:
            continue
        seen.add(real)
        try:
            tree = ET.fromstring(current.read_bytes())  # noqa: S314 - the operator's own file, no DTD/entities used
        except (OSError, ET.ParseError) as exc:
            raise FileKindError(str(main), WHAT, [f"{current}: not readable XML: {exc}"]) from None
        for inc in tree.iter("include"):
            rel = inc.get("path") or ""
            if inc.get("ros_pkg"):
                continue
            problem = confine(rel, current.parent, root)
            if problem:
                inside = real.relative_to(root).as_posix() if root in real.parents else current.name
                raise FileKindError(str(main), WHAT, [f"<include path=\"{rel}\"> in {inside}: {problem}"],
                                    hint="keep the included files in the .btproj's directory (or below it)")
            target = (current.parent / rel).resolve()
            name = target.relative_to(root).as_posix()
            if target.is_file():
                found[name] = target
                todo.append(target)
    return found


def confine(rel: str, base: Path, root: Path) -> str | None:
    """Why ``rel`` (relative to ``base``) may not be used inside ``root``; None when it may."""
    if not rel:
        return "an include without a path"
    if any(ord(c) < 32 for c in rel):
        return "the path holds a control character"
    if os.path.isabs(rel) or rel.startswith("~"):
        return f"{rel} is not relative to the project's directory"
    target = (base / rel).resolve()
    if target != root and root not in target.parents:
        return f"{rel} leaves the project's directory (it resolves to {target})"
    return None


def service_name_findings(path: Path) -> list[Finding]:
    """An error for each literal ``service_name`` of the project's trees that is not a ROS
    service name (a ``{blackboard}`` reference is left to the tree); an unreadable project: none
    (`validate_bt_project` says why)."""
    from panther_ops.manager.bt.builder import is_ref, node_id
    from panther_ops.manager.bt.project import load_bt_project
    from panther_ops.manager.errors import BtProjectError
    from panther_ops.manager.findings import error

    try:
        project = load_bt_project(path)
    except BtProjectError:
        return []
    out: list[Finding] = []
    for tree_id, tree in project.trees.items():
        for element in tree.element.iter():
            value = element.get("service_name")
            if value is None or is_ref(value):
                continue
            try:
                service_name(value)
            except RosNameError as exc:
                out.append(error("bt-service-name", f"<{node_id(element)}> service_name={value!r}: {exc}",
                                 f"{tree.source}: {tree_id}"))
    return out


def check_bt_project(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    """Any BT project (`bt validate`)."""
    return _check(source, data, local, (), "")


def check_lights_project(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    """The Lights manager's project: `bt validate`, and a Lights tree."""
    return _check(source, data, local, ("Lights",), "bt-lights")


def check_safety_project(source: str, data: bytes, local: Path | None, target: Target, force: bool) -> list[str]:
    """The Safety manager's project: `bt validate`, and Safety and Shutdown trees."""
    return _check(source, data, local, ("Safety", "Shutdown"), "bt-safety")


def _check(source: str, data: bytes, local: Path | None, trees: tuple[str, ...], kind: str) -> list[str]:
    from panther_ops.manager.bt.project import load_bt_project
    from panther_ops.manager.bt.validate import validate_bt_project

    text_of(source, data, WHAT)
    if local is not None:
        project_files(local)

    def check(path: Path) -> list[str]:
        errors, warnings = split(validate_bt_project(path) + service_name_findings(path))
        if errors:
            raise FileKindError(source, WHAT, errors, hint=f"panther-ops bt validate {source}")
        present = set(load_bt_project(path).trees)
        missing = [t for t in trees if t not in present]
        if missing:
            raise FileKindError(source, WHAT, [
                f"a project for {kind} needs the tree(s) {' and '.join(repr(t) for t in trees)}; missing: "
                f"{', '.join(missing)} (this project has: {', '.join(sorted(present)) or 'none'})"])
        return warnings

    return on_disk(source, data, local, check)
