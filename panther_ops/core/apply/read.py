"""The reads of `panther-ops apply` and `config diff`: the inventory's desired state (launch
arguments, controller, image, GPS, shutdown hosts, the WebUI on the User Computer) converged
in one plan per robot.

Reading here: compose.yaml (kept for the write when there is a desired state to converge),
the files the planner (`plan.py`, pure) asks for, the secrets ``desired.shutdown_hosts``
refers to, and the WebUI's state on the User Computer when it asks for it. The plan is
carried out by `apply.py`.
"""

from __future__ import annotations

from typing import Any

from panther_ops.core.apply import plan as planner
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.robot.read import read_compose
from panther_ops.errors import UsageError


def read_and_plan_desired(ctx: RobotContext, *, force: bool = False) -> RobotPlan:
    """Converge the robot to the inventory's ``desired:`` launch_args, controller, image, GPS,
    shutdown hosts and WebUI."""
    from panther_ops.core.remote.webui.plan import FACT
    from panther_ops.core.remote.webui.read import read_desired_webui
    from panther_ops.core.shutdown.plan import DEFAULT_FACT

    desired = ctx.robot.desired
    if desired.get("shutdown_hosts") is not None:
        desired = {**desired, "shutdown_hosts": _resolved_hosts(ctx, desired["shutdown_hosts"])}
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planner.plan_desired(raw, reads, desired, force=force),
                         {FACT: read_desired_webui, DEFAULT_FACT: _image_hosts})


def _image_hosts(ctx: RobotContext, _key: str) -> bytes:
    """The shutdown hosts file the robot's image ships (or panther-ops' template of its release)."""
    from panther_ops.core.kinds import FileKind
    from panther_ops.core.robot.pull import pull

    return pull(ctx, FileKind.SHUTDOWN_HOSTS)[0]


def _resolved_hosts(ctx: RobotContext, entries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """``desired.shutdown_hosts`` with each ``secret: {env|file: ...}`` read (a relative file is
    relative to the inventory): the robot's manager needs the value itself."""
    from panther_ops.core.kinds.hostsfile import SecretRef

    out = []
    for i, entry in enumerate(entries):
        ref = entry.get("secret")
        if isinstance(ref, dict) and len(ref) == 1:
            (kind, where), = ref.items()
            try:
                secret = SecretRef(str(kind), str(where)).resolve(ctx.inventory.path.parent)
            except UsageError as exc:
                raise UsageError(f"{ctx.inventory.path}: desired.shutdown_hosts[{i}].{exc.message}",
                                 hint="set it, or change the inventory's reference") from None
            out.append({**entry, "secret": secret.reveal()})
        else:
            out.append(entry)
    return out
