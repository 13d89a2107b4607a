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


SAMPLE = {
    "gps/plan.py": "def plan_enable(raw, reads):\n    pass\ndef shared(cfg):\n    pass\ndef _own():\n    pass\n",
    "gps/service.py": "def plan_enable(ctx: RobotContext):\n    return 1\ndef _own():\n    pass\n",
    "gps/read.py": "def read_and_plan_enable(ctx):\n    pass\ndef shared(ctx):\n    pass\n"
                   "def plan_task(ctx: RobotContext) -> None:\n    pass\n",
    "gps/extra.py": "def plan_more(reads: Reads) -> None:\n    pass\ndef _plan_own():\n    pass\n",
    "gps/status.py": "def status_task(ctx):\n    pass\nclass plan_x:\n    pass\n",
    "webui/remote.py": "def status_task(ctx):\n    pass\ndef f():\n    def plan_x():\n        pass\n",
    "sim/charging.py": "def plan_charge(action: str) -> int:\n    return 1\n",
    "sim/__init__.py": "",
    "fleet/changes.py": "def plan_fleet(command: str) -> None:\n    pass\n",
    "fleet/plan.py": "",
}
"""A made-up core (path relative to core -> source) for both walks: a reader named as the
planner it wraps (gps/service.py), a plan.py helper defined again (gps/read.py `shared`), a
reader of its own name and one reading a robot (gps/read.py), a pure planner outside plan.py
(gps/extra.py), a class and a nested function named plan_x, a function two modules define that
is not a planner (status_task), a package that plans without a plan.py (sim), the engine's
own planning piece (fleet/changes.py) and private functions."""


def test_the_walk_finds_a_wrapper_named_as_its_planner_and_only_that() -> None:
    assert twice_defined(SAMPLE) == {"plan_enable": ["gps/plan.py", "gps/service.py"],
                                     "shared": ["gps/plan.py", "gps/read.py"]}


def test_no_planner_of_core_is_defined_twice() -> None:
    files = sorted(CORE.rglob("*.py"))
    assert len(files) > 100  # the whole of core is walked
    modules = {str(path.relative_to(CORE)): path.read_text(encoding="utf-8") for path in files}
    assert any(Path(p).name == "plan.py" for p in modules)
    found = twice_defined(modules)
    assert found == {}, "give the reader its own name (read_and_plan_*), or let the engine call the planner:\n" + \
        "\n".join(f"{name}: {', '.join(paths)}" for name, paths in found.items())


ENGINE = {"fleet", "robot", "kinds", "containers", "yaml", "parse"}
"""The engine's packages (docs/develop.md): their own planning pieces are shared, not a feature's."""
ELSEWHERE = {"remote/webui/state.py"}
"""Declared: `webui set`'s own plan -> confirm -> act loop (issue #28: it becomes an ordinary
change, its planners then in remote/webui/plan.py)."""


def plan_functions(source: str) -> dict[str, bool]:
    """The top-level ``plan*`` functions of ``source``, each with whether it reads a robot
    itself (a parameter annotated as a ``RobotContext``: a reader, not a pure planner)."""
    found = {}
    for node in ast.parse(source).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("plan"):
            params = [*node.args.posonlyargs, *node.args.args, *node.args.kwonlyargs]
            found[node.name] = any(a.annotation is not None and "RobotContext" in ast.unparse(a.annotation)
                                   for a in params)
    return found


def misplaced(modules: dict[str, str]) -> tuple[list[str], list[str]]:
    """(packages with a ``plan*`` function but no plan.py, pure planners of a feature outside
    its plan.py) of ``modules`` (path relative to core -> source)."""
    packages: dict[str, list[str]] = defaultdict(list)
    for path in modules:
        packages[str(Path(path).parent)].append(Path(path).name)
    no_plan_module, outside = [], []
    for path, source in sorted(modules.items()):
        package = str(Path(path).parent)
        found = plan_functions(source)
        if found and "plan.py" not in packages[package] and package not in no_plan_module:
            no_plan_module.append(package)
        feature = package.split("/", 1)[0] not in ENGINE and package != "."
        if feature and Path(path).name != "plan.py" and path not in ELSEWHERE:
            outside += [f"{path}: {name}" for name, reads in found.items() if not reads]
    return no_plan_module, outside


def test_the_plan_module_walk_finds_what_it_should() -> None:
    assert misplaced(SAMPLE) == (["sim"], ["gps/extra.py: plan_more", "sim/charging.py: plan_charge"])


def test_every_core_package_that_plans_has_its_plan_module() -> None:
    """A package with a planner has its plan.py (the module the golden tier imports), and a
    feature's pure planners live there; a ``plan*`` function that reads a robot (a
    ``RobotContext`` parameter) is a reader and may live in read.py or its own module."""
    modules = {str(p.relative_to(CORE)): p.read_text(encoding="utf-8") for p in sorted(CORE.rglob("*.py"))}
    no_plan_module, outside = misplaced(modules)
    assert no_plan_module == [], "give each a plan.py with its pure planners"
    assert outside == [], "move each pure planner into its feature's plan.py"
    for package in ("config", "driver", "gps", "apply", "manager_ops", "shutdown", "remote/webui", "reimage", "sim"):
        assert (CORE / package / "plan.py").is_file(), package
