"""A local shutdown hosts file (`shutdown hosts add|remove FILE`) as a target of the change
pipeline, as a robot's file is.

The file's directory is a local target (the local transport, as a demo robot's directory):
the plan reads the file through it, checks the whole file as it would be written with the
hosts file kind's one validator, and carries a masked exact diff; the pipeline then backs
the old content up in ``<directory>/.panther-ops/backups/<id>/`` (``files/0`` and a
``manifest.json``), stages the new file beside it and renames it into place only if the file
is still what was read. Nothing is recreated.

``config history --file FILE`` lists those backups (``history.list_history`` with ``only``:
the ones of that file; a directory may hold several hosts files) and ``config rollback --file
FILE`` restores one through the same planner and pipeline as a robot's rollback
(`fleet/plan_rollback.py`, through `plan.py`'s ``plan_local_restore``): masked exact diff,
backup of the current file first, staged write renamed only if the file is unchanged; the
content restored goes through the hosts file validator as every write of the file does.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from panther_ops.core.fleet.confine import local_file
from panther_ops.core.fleet.history import ROLLBACK_FACTS
from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.hostsfile import Edit
from panther_ops.core.shutdown.plan import plan_local_edit, plan_local_restore


def local_target(file: Path, option: str | None = None) -> tuple[Inventory, Robot]:
    """The file's directory as a one-target inventory (named as the operator gave the file);
    ``option``: the file was given with it (``--file``) and is checked first (exit 2)."""
    full = Path(local_file(str(file), option)) if option else file.resolve()
    robot = Robot(name=str(file), host="localhost", transport="local", root=Path("/"), home=str(full.parent),
                  source=str(file))
    return Inventory(path=full, origin=str(file), robots={robot.name: robot}, groups={}, forks=1,
                     subject="file"), robot


def plan_local_hosts_edit(ctx: RobotContext, file: Path, change: Callable[[str], Edit]) -> RobotPlan:
    """The plan of one change to a local hosts file (``change`` maps its text to the new one)."""
    return read_and_plan(ctx, lambda reads: plan_local_edit(reads, file, change))


def plan_local_rollback(ctx: RobotContext, file: Path, to: str | None) -> RobotPlan:
    """The plan restoring the local file as it was before backup ``to`` (default: the newest)."""
    return read_and_plan(ctx, lambda reads: plan_local_restore(reads, file, to), ROLLBACK_FACTS)


def hosts_as_targets(file: Path, hosts: list[str], via: tuple[Inventory, Robot] | None = None
                     ) -> tuple[Inventory, list[Robot]]:
    """`shutdown --hosts FILE`: the hosts of the file as the change's targets (subject ``host``),
    named as the file describes them, all at once (side by side, as the manager's tree). From
    here each is a local target (nothing is connected to but the host itself, by its step);
    through ``via`` each target's connection is the robot's (its endpoint, its jump hosts)."""
    from dataclasses import replace

    if via is None:
        targets = [Robot(name=h, host="localhost", transport="local", root=Path("/"), home=str(file.resolve().parent),
                         source=str(file)) for h in hosts]
        return Inventory(path=file.resolve(), origin=str(file), robots={r.name: r for r in targets}, groups={},
                         forks=max(1, len(targets)), subject="host"), targets
    inv, robot = via
    targets = [replace(robot, name=h) for h in hosts]
    return replace(inv, robots={**inv.robots, **{r.name: r for r in targets}}, forks=max(1, len(targets)),
                   subject="host"), targets
