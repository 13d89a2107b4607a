"""The lights behaviour tree in the config tree (``husarion_ugv_manager/behavior_trees/lights.xml``).

Sources: husarion_ugv_ros@2.2.2 and @2.3.2:husarion_ugv_manager/behavior_trees/{lights,safety}.xml:
2.3.2 bumped BehaviorTree.CPP to 4.9.0 (commit cfba7551, "Bump behaviortree_cpp to 4.9.0")
and removed the ``\\`` line continuations inside the script attributes (``_skipIf``,
``_onSuccess``): each line keeps its text, without the trailing `` \\``. The rest of a
customised tree is kept; 2.3.2's own tree keys on the twist mux's source (``CheckStringMsg``
on ``twist_mux_controller/source``), which a 2.2 tree does not: the plan says so.
"""

from __future__ import annotations

import re

from panther_ops.core.driver.migrate.translated import Translated

_CONTINUATION = re.compile(r"[ \t]*\\\n|\\(?=&#10;)")
"""A line continuation: a space and backslash before a newline (safety.xml's form) or a backslash before the
``&#10;`` entity (lights.xml's form); upstream removed the first with its space, the second alone."""


def translate_lights_tree(text: str, path: str, target: tuple[int, int, int]) -> Translated:
    """``text`` without the script line continuations BehaviorTree.CPP 4.9 no longer takes."""
    out, n = _CONTINUATION.subn(lambda m: "\n" if m.group().endswith("\n") else "", text)
    name = path.rsplit("/", 1)[-1]
    notes = [f"{name}: {n} script line continuation(s) removed (BehaviorTree.CPP 4.9, as husarion_ugv 2.3.2)"] if n \
        else []
    if name == "lights.xml" and "twist_mux_controller/source" not in out:
        notes.append(f"{name}: kept as on 2.2 (it keys on drive_state); 2.3.2's stock tree shows manual/autonomous "
                     "driving from twist_mux_controller/source: take it with `panther-ops lights` once you want it")
    return Translated(out, tuple(notes))
