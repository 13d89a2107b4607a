"""Issue 28, a second change path: executors take typed steps, never ``plan.data`` (which only
shows a plan); every step type has its executor; `mutate` takes few parameters."""

from __future__ import annotations

import ast
import importlib
import inspect
from pathlib import Path

from panther_ops.cli.mutate import mutate
from panther_ops.core.fleet.plan import Step
from panther_ops.core.fleet.steps import executor_of

CORE = Path(__file__).resolve().parents[2] / "panther_ops" / "core"
APPLY_MODULES = sorted(CORE.rglob("apply.py"))


def data_reads(source: str) -> list[str]:
    """Where ``<x>.data`` of a plan is read by key: ``plan.data[...]``, ``plan.data.get(...)``,
    ``"key" in plan.data`` (a whole copy for a result's display, ``dict(plan.data)``, is not a read)."""
    found: list[str] = []
    for node in ast.walk(ast.parse(source)):
        target: ast.expr | None = None
        if isinstance(node, ast.Subscript):
            target = node.value
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in ("get", "pop"):
            target = node.func.value
        elif isinstance(node, ast.Compare) and any(isinstance(op, (ast.In, ast.NotIn)) for op in node.ops):
            target = node.comparators[0]
        if (isinstance(target, ast.Attribute) and target.attr == "data" and isinstance(target.value, ast.Name)
                and "plan" in target.value.id):
            found.append(f"line {node.lineno}: {ast.unparse(node)[:80]}")
    return found


def test_the_check_sees_a_read_of_plan_data() -> None:
    """The check itself: the reads the appliers made before the steps (issue 28) are found."""
    old = ('def apply(ctx, plan, opts):\n    service = plan.data.get("remove_service")\n'
           '    tree = str(plan.data["config_dir"])\n    if "backup" in plan.data:\n        pass\n'
           '    return RobotResult(ctx.robot.name, "", data=dict(plan.data))\n')
    assert sorted(r.split(":")[0] for r in data_reads(old)) == ["line 2", "line 3", "line 4"]


def test_no_executor_reads_plan_data() -> None:
    assert len(APPLY_MODULES) >= 7
    reads = {str(p.relative_to(CORE)): data_reads(p.read_text()) for p in APPLY_MODULES}
    assert {p: r for p, r in reads.items() if r} == {}, "an executor takes its step's fields, not plan.data"


def _subclasses(kind: type[Step]) -> set[type[Step]]:
    out: set[type[Step]] = set()
    for sub in kind.__subclasses__():
        out |= {sub} | _subclasses(sub)
    return out


def test_every_step_type_has_its_executor_beside_its_planner() -> None:
    for path in sorted(CORE.rglob("plan.py")):  # every feature's step types defined
        importlib.import_module(".".join(("panther_ops", *path.relative_to(CORE.parent).with_suffix("").parts)))
    kinds = _subclasses(Step)
    assert len(kinds) >= 11, sorted(k.__qualname__ for k in kinds)
    for kind in kinds:
        assert kind.__dataclass_params__.frozen, kind  # type: ignore[attr-defined]
        assert kind.__module__.endswith(".plan"), f"{kind.__qualname__}: a step type lives in its feature's plan.py"
        fn = executor_of(kind)
        assert fn.__module__ == kind.__module__.rpartition(".")[0] + ".apply", (kind, fn.__module__)


def test_mutate_takes_at_most_five_parameters() -> None:
    params = inspect.signature(mutate).parameters
    assert len(params) <= 5, list(params)
