"""Two phases for every mutating command, over one connection per robot.

Phase 1 plans every targeted robot (reads only). A planning error that is the operator's
(a bad key or value for that robot's stack) stops the whole command before anything is
written anywhere (exit 2). Phase 2, after the CLI showed the diffs and got confirmation,
applies the plans through the pipeline on the same connections.

When the command needs no confirmation (``--yes``), phase 1 also makes each robot's write
session as its planning starts (a transport may open it in the background), made to read the
robot's compose file first: the plan takes that read (``ctx.session``, `core/robot/read.py`),
so the read and the write are one command on the robot. The write is staged as soon as the
plan is known: the backup and the new files wait
beside their targets while the rest of the fleet is still being planned, and nothing is
renamed until phase 2 gives the go-ahead (one round trip: the staging only sent, the robot
answers both at once). If phase 2 does not come for a robot (another robot's plan was
refused, or a canary failed), its staging is taken back: the robot is left as it was.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import dataclass, field, replace

from panther_ops.core.fleet.interrupt import FleetInterrupted
from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.memo import Memo
from panther_ops.core.fleet.pipeline import ApplyOptions, Staged, apply_plan, apply_staged, stage_plan, unstage
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import compose_file
from panther_ops.core.fleet.runner import Connections, Progress, RobotContext, RunOptions, run_fleet
from panther_ops.errors import OpsError, UsageError
from panther_ops.results import FleetResult, Outcome, RobotResult

Planner = Callable[[RobotContext], RobotPlan]


def does_something(plan: RobotPlan) -> bool:
    """A plan with file edits, or with an action step (e.g. a reset the image's script carries out)."""
    return bool(plan.edits or plan.action)


@dataclass
class FleetPlan:
    """Every robot's plan (or why it has none)."""

    command: str
    plans: dict[str, RobotPlan] = field(default_factory=dict)
    results: FleetResult = field(default_factory=lambda: FleetResult("plan"))
    usage_errors: dict[str, UsageError] = field(default_factory=dict)
    staged: dict[str, Staged] = field(default_factory=dict)
    """Writes staged during planning, waiting for the go-ahead (see the module's text)."""

    @property
    def to_change(self) -> list[str]:
        return [name for name, p in self.plans.items() if does_something(p)]


_COMPOSE_CHECKED: Memo[list[str]] = Memo()


def check_written(plan: RobotPlan) -> None:
    """The compose file a plan writes, through the compose file kind's validator (once per
    distinct content: the robots of a fleet mostly share one)."""
    from panther_ops.core.kinds import FileKind, check_file

    for e in plan.edits:
        if e.path == plan.compose_file and e.after is not None:
            path, after = e.path, e.after

            def check(path: str = path, after: bytes = after) -> list[str]:
                return check_file(FileKind.COMPOSE, path, after)

            _COMPOSE_CHECKED.get((path, after), check)


def plan_fleet(command: str, inventory: Inventory, robots: list[Robot], planner: Planner, connections: Connections,
               options: RunOptions, progress: Progress | None = None, stage: ApplyOptions | None = None) -> FleetPlan:
    """Plan every robot; with ``stage`` (the options phase 2 will apply with) also stage each
    robot's file edits through the pipeline as soon as its plan is known (see the module's text)."""
    fp = FleetPlan(command)

    def task(ctx: RobotContext) -> RobotResult:
        ctx.phase("plan")
        session = None
        if stage is not None and not stage.dry_run:  # it reads the compose file for the plan (one command)
            try:
                path: str | None = compose_file(ctx)
            except UsageError:  # the planner's read says so, as this robot's error
                path = None
            session = ctx.session = ctx.transport.session(read=path)
        try:
            try:
                plan = planner(ctx)
                check_written(plan)
            except UsageError as exc:
                fp.usage_errors[ctx.robot.name] = exc
                raise
            if session is not None and plan.edits and not plan.steps:  # steps: in phase 2
                assert stage is not None
                fp.staged[ctx.robot.name] = stage_plan(ctx, plan, stage, session)  # gone away: no plan either
                session = None
        finally:
            ctx.session = None
            if session is not None:  # nothing to stage on it
                session.close()
        fp.plans[ctx.robot.name] = plan
        outcome = Outcome.CHANGED if does_something(plan) else Outcome.SKIPPED if plan.skipped else Outcome.OK
        message = plan.summary if does_something(plan) else (plan.skipped or plan.noop or "nothing to change")
        return RobotResult(ctx.robot.name, outcome, message, diffs=plan.diffs, warnings=list(plan.warnings),
                           data=dict(plan.data))

    plan_opts = RunOptions(forks=options.forks)
    try:
        fp.results = run_fleet(command, inventory, robots, task, plan_opts, progress, connections)
    except FleetInterrupted as exc:  # a change planned is not written
        planned = [r.robot for r in exc.where.finished if r.outcome is Outcome.CHANGED]
        raise exc.regrouped([r.name for r in robots], {}, planned) from None
    return fp


def apply_fleet(fp: FleetPlan, inventory: Inventory, robots: list[Robot], connections: Connections,
                options: RunOptions, apply: ApplyOptions, progress: Progress | None = None) -> FleetResult:
    """Apply every plan that does something; the others keep their plan-phase result."""
    by_name = {r.robot: r for r in fp.results.results}
    todo = [r for r in robots if r.name in fp.plans and does_something(fp.plans[r.name])]

    def task(ctx: RobotContext) -> RobotResult:
        plan = fp.plans[ctx.robot.name]
        staged = fp.staged.pop(ctx.robot.name, None)
        return apply_plan(ctx, plan, apply) if staged is None else apply_staged(ctx, plan, apply, staged)

    try:
        applied = run_fleet(fp.command, inventory, todo, task, options, progress, connections) if todo else \
            FleetResult(fp.command, subject=inventory.subject)
    except FleetInterrupted as exc:  # the robots with nothing to apply were finished with their plan
        started = {r.name for r in todo}
        raise exc.regrouped([r.name for r in robots], {n: r for n, r in by_name.items() if n not in started}) \
            from None
    unstage_fleet(fp, inventory, robots, connections, options)  # robots never started (canary, max-fail)
    for r in applied.results:
        by_name[r.robot] = r
    out = FleetResult(fp.command, [by_name[r.name] for r in robots], notes=applied.notes, subject=inventory.subject)
    out.duration_s = fp.results.duration_s + applied.duration_s
    return out


def unstage_fleet(fp: FleetPlan, inventory: Inventory, robots: list[Robot], connections: Connections,
                  options: RunOptions) -> None:
    """Take back every write still staged: those robots are left exactly as they were."""
    waiting = {r.name: staged for r in robots if (staged := fp.staged.pop(r.name, None)) is not None}

    def task(ctx: RobotContext) -> RobotResult:
        with contextlib.suppress(OpsError):  # the session is gone: the robot dropped the staged files itself
            unstage(waiting[ctx.robot.name])
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, "staged write taken back")

    if waiting:
        run_fleet(fp.command, inventory, [r for r in robots if r.name in waiting], task,
                  RunOptions(forks=options.forks), None, connections)


def dry_run_result(fp: FleetPlan, *, read_only: bool = False) -> FleetResult:
    """The plan as a dry run's result: each change is what the robot ``would`` get (a plan
    with an action has a summary that starts with its verb: ``would remove manager ...``).

    ``read_only``: the command never writes (``config diff``, the plan shown before the
    question): no "dry run" note then. The plan's own results are left as they are.
    """
    out = FleetResult(fp.command, notes=[] if read_only else ["dry run: nothing was written"],
                      subject=fp.results.subject)
    for r in fp.results.results:
        if r.outcome is Outcome.CHANGED:
            action = r.robot in fp.plans and fp.plans[r.robot].action
            out.add(replace(r, message=f"would {r.message}" if action else f"would change: {r.message}",
                            data={**r.data, "dry_run": True}))
        else:
            out.add(r)
    out.duration_s = fp.results.duration_s
    return out
