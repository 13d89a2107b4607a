"""The executors of plans' steps (`plan.Step`): which function carries out which step type.

A feature defines its step types in ``core/<feature>/plan.py`` and registers an executor for
each in ``core/<feature>/apply.py``::

    @executes(RemoveService)
    def remove_service(ctx, plan, step, opts, write):
        result = write(opts)            # the steps after this one, then the pipeline's write
        ...                             # this step's own work
        return result

An executor gets the robot, the whole plan, its step, the apply options and ``write``: the
rest of the plan (the later steps and, innermost, the pipeline's write of the file edits:
backup, stage, compare-and-rename, recreate, verify, roll back). It calls ``write`` once (with
the options it needs) or not at all (a step that is the whole change: a container restarted,
a PUT to the router). The pipeline (`pipeline.apply_plan`) runs the steps; the first time it
meets a step type it imports the ``apply`` module beside the ``plan`` module that defines it.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

from panther_ops.core.fleet.plan import RobotPlan, Step
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError
from panther_ops.results import RobotResult

if TYPE_CHECKING:
    from panther_ops.core.fleet.pipeline import ApplyOptions

Write = Callable[["ApplyOptions"], RobotResult]
"""The rest of the plan after a step: the later steps, then the pipeline's write."""
Executor = Callable[[RobotContext, RobotPlan, Any, "ApplyOptions", Write], RobotResult]
S = TypeVar("S", bound=Step)

_EXECUTORS: dict[type[Step], Executor] = {}


def executes(kind: type[S]) -> Callable[[Callable[[RobotContext, RobotPlan, S, ApplyOptions, Write], RobotResult]],
                                        Callable[[RobotContext, RobotPlan, S, ApplyOptions, Write], RobotResult]]:
    """Register the decorated function as the executor of ``kind`` (one executor a type)."""
    def register(fn: Callable[[RobotContext, RobotPlan, S, ApplyOptions, Write], RobotResult]
                 ) -> Callable[[RobotContext, RobotPlan, S, ApplyOptions, Write], RobotResult]:
        if _EXECUTORS.get(kind, fn) is not fn:
            raise ValueError(f"two executors for {kind.__qualname__}")
        _EXECUTORS[kind] = fn
        return fn
    return register


def executor_of(kind: type[Step]) -> Executor:
    """The executor of a step type (its feature's ``apply`` module imported when it was not yet)."""
    if kind not in _EXECUTORS:
        importlib.import_module(kind.__module__.rpartition(".")[0] + ".apply")
    found = _EXECUTORS.get(kind)
    if found is None:
        raise OpsError(f"no executor for the plan step {kind.__qualname__} (a bug: see --debug)")
    return found


def carry_out(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, write: Write) -> RobotResult:
    """Run the plan's steps in order, each around the rest, ``write`` innermost."""
    def rest(i: int) -> Write:
        if i == len(plan.steps):
            return write
        step = plan.steps[i]
        return lambda o: executor_of(type(step))(ctx, plan, step, o, rest(i + 1))

    return rest(0)(opts)
