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
FILE`` restores one through the same plan and pipeline as a robot's rollback
(``history.plan_rollback``): masked exact diff, backup of the current file first, staged
write renamed only if the file is unchanged; the content restored goes through the hosts
file validator as every write of the file does.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from panther_ops.core.fleet.confine import local_file
from panther_ops.core.fleet.history import plan_rollback
from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.plan import FileEdit, MaskedFileEdit, RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds import FileKind, check_file
from panther_ops.core.kinds.hostsfile import Edit
from panther_ops.errors import UsageError


def local_target(file: Path, option: str | None = None) -> tuple[Inventory, Robot]:
    """The file's directory as a one-target inventory (named as the operator gave the file);
    ``option``: the file was given with it (``--file``) and is checked first (exit 2)."""
    full = Path(local_file(str(file), option)) if option else file.resolve()
    robot = Robot(name=str(file), host="localhost", transport="local", root=Path("/"), home=str(full.parent),
                  source=str(file))
    return Inventory(path=full, origin=str(file), robots={robot.name: robot}, groups={}, forks=1), robot


def plan_local_hosts_edit(ctx: RobotContext, file: Path, change: Callable[[str], Edit]) -> RobotPlan:
    """The plan of one change to a local hosts file (``change`` maps its text to the new one)."""
    path = str(file.resolve())
    where = str(file)
    try:
        before: bytes | None = ctx.transport.read_file(path)
    except FileNotFoundError:
        before = None
    try:
        text = (before or b"").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UsageError(f"{where} is not UTF-8 text ({exc.reason} at byte {exc.start})",
                         hint="nothing was changed") from exc
    edit = change(text)
    after = edit.text.encode()
    warnings = check_file(FileKind.SHUTDOWN_HOSTS, where, after, local=file)
    home = str(Path(path).parent)
    if not edit.changed or after == before:
        return RobotPlan(ctx.robot.name, edit.message, noop=edit.message, warnings=warnings, home=home)
    # a new file may hold a secret (--ask-secret): only its owner reads it
    edits: list[FileEdit] = [MaskedFileEdit(path, before, after, None if before is not None else 0o600)]
    return RobotPlan(ctx.robot.name, edit.message, edits, warnings=warnings, home=home,
                     data={"hosts_file": where})


def plan_local_rollback(ctx: RobotContext, file: Path, to: str | None) -> RobotPlan:
    """The plan restoring the local file as it was before backup ``to`` (default: the newest)."""

    warnings: list[str] = []

    def edit(path: str, now: bytes | None, old: bytes | None) -> FileEdit:
        if old is not None:
            warnings.extend(check_file(FileKind.SHUTDOWN_HOSTS, str(file), old, local=file))
        return MaskedFileEdit(path, now, old, None if now is not None else 0o600)

    plan = plan_rollback(ctx, to, only=str(file.resolve()), edit=edit)
    plan.warnings += warnings
    plan.home = str(file.resolve().parent)
    plan.data["hosts_file"] = str(file)
    return plan
