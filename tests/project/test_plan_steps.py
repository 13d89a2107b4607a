"""Issue 28, a second change path: executors take typed steps, never ``plan.data`` (which only
shows a plan); every step type has its executor; `mutate` takes few parameters."""

from __future__ import annotations

import ast
import importlib
import inspect
from dataclasses import dataclass, replace
from pathlib import Path

from panther_ops.cli.mutate import mutate
from panther_ops.core.fleet.changes import does_something
from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.plan import RobotPlan, Step
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.steps import Write, executes, executor_of
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.local import LocalTransport

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
            found.append(f"line {getattr(node, 'lineno', 0)}: {ast.unparse(node)[:80]}")
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
    kinds = {k for k in _subclasses(Step) if k.__module__.startswith("panther_ops.")}  # not this file's
    assert len(kinds) >= 11, sorted(k.__qualname__ for k in kinds)
    for kind in kinds:
        assert kind.__dataclass_params__.frozen, kind  # type: ignore[attr-defined]
        assert kind.__module__.endswith(".plan"), f"{kind.__qualname__}: a step type lives in its feature's plan.py"
        fn = executor_of(kind)
        assert fn.__module__ == kind.__module__.rpartition(".")[0] + ".apply", (kind, fn.__module__)


def test_mutate_takes_at_most_five_parameters() -> None:
    params = inspect.signature(mutate).parameters
    assert len(params) <= 5, list(params)


@dataclass(frozen=True)
class Marked(Step):
    """A step for the test: its executor notes its name before and after the rest."""

    name: str
    skip_rest: bool = False


NOTES: list[str] = []


@executes(Marked)
def _marked(ctx: RobotContext, plan: RobotPlan, step: Marked, opts: ApplyOptions, write: Write) -> RobotResult:
    NOTES.append(f"{step.name} before")
    if step.skip_rest:
        return RobotResult(ctx.robot.name, Outcome.CHANGED, f"{step.name} did it all")
    result = write(replace(opts, settle_s=opts.settle_s + 1))
    NOTES.append(f"{step.name} after ({result.message})")
    return result


def _ctx(tmp_path: Path) -> RobotContext:
    robot = Robot(name="r", host="localhost", transport="local", root=tmp_path, home="/home/me", source="test")
    inv = Inventory(path=tmp_path / "inventory.yaml", origin="test", robots={"r": robot}, groups={}, forks=1)
    return RobotContext(robot, LocalTransport("r", tmp_path, "me", "/home/me"), inv)


def test_the_pipeline_runs_the_steps_in_order_each_around_the_rest(tmp_path: Path) -> None:
    NOTES.clear()
    plan = RobotPlan("r", "two steps", noop="no file to write", steps=[Marked("a"), Marked("b")])
    result = apply_plan(_ctx(tmp_path), plan, ApplyOptions())
    assert NOTES == ["a before", "b before", "b after (no file to write)", "a after (no file to write)"]
    assert result.outcome is Outcome.OK and result.message == "no file to write"
    assert plan.action and does_something(plan)  # a step is the change: the plan does something without edits


def test_a_step_that_is_the_whole_change_writes_nothing_after_it(tmp_path: Path) -> None:
    NOTES.clear()
    plan = RobotPlan("r", "one step", steps=[Marked("a", skip_rest=True), Marked("never")])
    result = apply_plan(_ctx(tmp_path), plan, ApplyOptions())
    assert NOTES == ["a before"] and result.message == "a did it all"


COMMANDS = Path(__file__).resolve().parents[2] / "panther_ops" / "cli" / "commands"
OWN_CONFIRMATION = {
    "reimage.py": "reimage write/flash: erases a block device of this machine, not a target the runner reaches",
    "sim.py": "sim files and sim charging: a local simulation's file and a call into the running simulation",
    "shutdown_inputs.py": "`shutdown setup` (ask_to_confirm): asks, in the middle of its setup, before recording "
                          "a computer's host key in the robot's known_hosts; not yet a change (left)",
}
"""The commands that still confirm on their own, each with why (a new one must go through `fleet.change`)."""


def confirmations(source: str) -> list[int]:
    """Lines calling ``require(...)`` or ``confirm(...)`` (the CLI's own plan -> confirm -> act)."""
    return [node.lineno for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("require", "confirm")]


def test_every_command_that_changes_something_goes_through_fleet_change() -> None:
    """Issue 28: no command hand-rolls plan -> confirm -> act: `cli/mutate.py` asks, for every
    change (`trust`, `shutdown --hosts`, `estop reset`, `webui set`, `shutdown robot` moved onto it)."""
    found = {p.name: lines for p in sorted(COMMANDS.glob("*.py")) if (lines := confirmations(p.read_text()))}
    assert set(found) <= set(OWN_CONFIRMATION), {n: ls for n, ls in found.items() if n not in OWN_CONFIRMATION}
    assert not {"trust.py", "shutdown.py"} & set(found) and set(OWN_CONFIRMATION) <= set(found), found  # the list is kept exact
