"""The lights behaviour tree in the config tree (``husarion_ugv_manager/behavior_trees/lights.xml``).

Sources: husarion_ugv_ros@2.2.2 and @2.3.2:husarion_ugv_manager/behavior_trees/{lights,safety}.xml
and husarion_ugv_manager/src/lights_manager_node.cpp:

- A **stock** 2.2.2 tree (semantically equal to 2.2.2's: comments and layout aside) becomes
  2.3.2's stock tree, which keys the state animation on the twist mux's active input
  (``CheckStringMsg`` on ``twist_mux_controller/source``: manual, autonomous, else ready).
  ``git diff 2.2.2 2.3.1 -- husarion_ugv_manager/behavior_trees`` is empty: for a 2.3.1 target
  the stock tree is already the target's and stays byte-identical.
- A **customised** tree is kept, without the ``\\`` line continuations inside the script
  attributes (``_skipIf``, ``_onSuccess``) that 2.3.2 removed when it bumped BehaviorTree.CPP
  to 4.9.0 (commit cfba7551): each line keeps its text, without the trailing `` \\``. If it
  still reads the blackboard entry ``drive_state`` (2.2's lights manager set it from the
  gamepad's dead-man button, ``joy``; 2.3.2's sets it no more), the plan names it for review:
  on 2.3.2 that script reads an entry nobody writes.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

from panther_ops.core.driver.migrate.stock import stock_text
from panther_ops.core.driver.migrate.translated import MUX_SINCE, Translated

TREE = "husarion_ugv_manager/behavior_trees/lights.xml"
_CONTINUATION = re.compile(r"[ \t]*\\\n|\\(?=&#10;)")
"""A line continuation: a space and backslash before a newline (safety.xml's form) or a backslash before the
``&#10;`` entity (lights.xml's form); upstream removed the first with its space, the second alone."""
_REMOVED = re.compile(r"\bdrive_state\b")
"""The blackboard entry husarion_ugv 2.3.2's lights manager no longer writes (2.2.2: lights_manager_node.cpp
sets ``drive_state`` from ``joy``'s dead-man button; 2.3.2 has no ``joy`` subscription)."""
_Shape = tuple[str, tuple[tuple[str, str], ...], str, tuple["_Shape", ...]]


def _shape(element: ET.Element) -> _Shape:
    children = tuple(_shape(c) for c in element if isinstance(c.tag, str))
    return element.tag, tuple(sorted(element.attrib.items())), (element.text or "").strip(), children


def same_tree(a: str, b: str) -> bool:
    """Whether two BT XML files are equal as BehaviorTree.CPP reads them (comments and layout ignored); a file
    that declares a document type or entities is not compared (never stock)."""
    if any(mark in t for t in (a, b) for mark in ("<!DOCTYPE", "<!ENTITY")):
        return False
    try:
        return (_shape(ET.fromstring(a.encode()))  # noqa: S314 - no DTD or entity (refused above)
                == _shape(ET.fromstring(b.encode())))  # noqa: S314 - no DTD or entity (refused above)
    except ET.ParseError:
        return False


def translate_lights_tree(text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """2.2.2's stock lights tree -> the stock tree of ``target``; any other tree without the script line
    continuations BehaviorTree.CPP 4.9 no longer takes (named for review where it reads ``drive_state``)."""
    name = path.rsplit("/", 1)[-1]
    if name == "lights.xml" and same_tree(text, stock_text(TREE)):
        if target < MUX_SINCE:
            return Translated(text, (f"{name}: 2.2.2's stock tree, which 2.3.1 ships unchanged: kept",))
        return Translated(stock_text(TREE, (2, 3, 2)), (
            f"{name}: 2.2.2's stock tree -> 2.3.2's (the state animation follows twist_mux_controller/source)",))
    out, n = _CONTINUATION.subn(lambda m: "\n" if m.group().endswith("\n") else "", text)
    notes = [f"{name}: {n} script line continuation(s) removed (BehaviorTree.CPP 4.9, as husarion_ugv 2.3.2)"] if n \
        else []
    review = name == "lights.xml" and target >= MUX_SINCE and bool(_REMOVED.search(out))
    if review:
        notes.append(f"needs review: {path} is customised and kept; it reads drive_state, which husarion_ugv "
                     "2.3.2's lights manager no longer sets (2.2 set it from the gamepad's dead-man button): "
                     "those conditions never hold on 2.3.2. Key them on twist_mux_controller/source "
                     "(CheckStringMsg, data manual or autonomous) as 2.3.2's stock tree does, then "
                     "`panther-ops config push` it")
    elif name == "lights.xml" and "twist_mux_controller/source" not in out:
        notes.append(f"{name}: kept as on 2.2; 2.3.2's stock tree shows manual/autonomous driving from "
                     "twist_mux_controller/source: take it with `panther-ops lights` once you want it")
    return Translated(out, tuple(notes), review)
