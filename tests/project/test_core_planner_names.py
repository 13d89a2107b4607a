"""One name, one planner: no planner of panther_ops/core is defined twice (a pure planner and
an I/O wrapper of the same name, #28).

A planner name is a public top-level function whose name starts with ``plan`` in any core
module, or any public top-level function of a feature's ``plan.py`` (the pure planners and
the pure helpers they share). Each may be defined in one core module only: the reader that
reads what a planner asks for and calls it has a name of its own (``read_and_plan_*``), so
a reader never passes for the planner it wraps."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import panther_ops.core

CORE = Path(panther_ops.core.__file__).parent


def top_level_functions(source: str) -> list[str]:
    """Names of the public functions defined at the top of ``source``."""
    return [node.name for node in ast.parse(source).body
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_")]


def twice_defined(modules: dict[str, str]) -> dict[str, list[str]]:
    """Planner names (see the module's docstring) defined in more than one of ``modules``
    (relative path -> source), with the modules that define each."""
    where: dict[str, list[str]] = defaultdict(list)
    planners: set[str] = set()
    for path, source in modules.items():
        for name in top_level_functions(source):
            where[name].append(path)
            if name.startswith("plan") or Path(path).name == "plan.py":
                planners.add(name)
    return {name: sorted(where[name]) for name in sorted(planners) if len(where[name]) > 1}


def test_the_walk_finds_a_wrapper_named_as_its_planner_and_only_that() -> None:
    modules = {
        "gps/plan.py": "def plan_enable(raw, reads):\n    pass\ndef shared(cfg):\n    pass\ndef _own():\n    pass\n",
        "gps/service.py": "def plan_enable(ctx):\n    return 1\ndef _own():\n    pass\n",
        "gps/read.py": "def read_and_plan_enable(ctx):\n    pass\ndef shared(ctx):\n    pass\n",
        "gps/status.py": "def status_task(ctx):\n    pass\nclass plan_x:\n    pass\n",
        "webui/remote.py": "def status_task(ctx):\n    pass\ndef f():\n    def plan_x():\n        pass\n",
    }
    assert twice_defined(modules) == {"plan_enable": ["gps/plan.py", "gps/service.py"],
                                      "shared": ["gps/plan.py", "gps/read.py"]}


def test_no_planner_of_core_is_defined_twice() -> None:
    files = sorted(CORE.rglob("*.py"))
    assert len(files) > 100  # the whole of core is walked
    modules = {str(path.relative_to(CORE)): path.read_text(encoding="utf-8") for path in files}
    assert any(Path(p).name == "plan.py" for p in modules)
    found = twice_defined(modules)
    assert found == {}, "give the reader its own name (read_and_plan_*), or let the engine call the planner:\n" + \
        "\n".join(f"{name}: {', '.join(paths)}" for name, paths in found.items())


def test_every_feature_that_plans_has_its_plan_module() -> None:
    """The planners the golden tier checks live in each feature's plan.py."""
    for feature in ("config", "driver", "gps", "apply", "manager_ops", "shutdown", "remote/webui"):
        assert (CORE / feature / "plan.py").is_file(), feature
