"""The robot's own shutdown hosts file: which file the manager reads, and plans that change it.

Where the file is (panther-stack.md §1.8): ``panther_bringup/config/shutdown_hosts.yaml``
(2.0.0-2.1.0), ``panther_manager/config/shutdown_hosts_config.yaml`` (2.1.1+),
``husarion_ugv_manager/config/shutdown_hosts.yaml`` (2.2). The file in use is, in order:
the file ``shutdown_hosts_config_path`` points at when it is mounted from the robot; the 2.2
config tree's file (``~/config/...``, read through ``common_dir_path``); else the default
inside the driver image (or panther-ops' template of that version).

Changes go through the configuration pipeline (diff, confirm, backup, atomic write,
recreate, verify, roll back): a mounted file or the tree's file is edited in place; the
image's default is copied to ``~/config/<package>/config/<file>``, edited, mounted and
pointed at with ``shutdown_hosts_config_path`` (2.0/2.1), as `config push` does.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from panther_ops.core.config.files import ConfigKind, config_file
from panther_ops.core.config.launch_args import spec
from panther_ops.core.config.plans import compose_plan
from panther_ops.core.config.push import Bundle, plan_push, pull
from panther_ops.core.config.robot import RobotConfig, read_config
from panther_ops.core.fleet.plan import FileEdit, MaskedFileEdit, RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds import FileKind, FileKindError
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S, Edit, HostsFile, Mode, parse_hosts
from panther_ops.core.stack import Stack
from panther_ops.errors import InputError, UsageError


@dataclass
class RobotHostsFile:
    """The hosts file a robot's manager reads."""

    text: str
    path: str | None
    """Robot path of the file in use; None while the robot uses the image's default."""
    source: str
    stack: Stack
    cfg: RobotConfig

    @property
    def mode(self) -> Mode:
        return Mode.HTTP if self.stack.shutdown_over_http else Mode.SSH

    def parse(self, power_budget: float = POWER_BUDGET_S) -> HostsFile:
        return parse_hosts(self.text, self.path or self.source, mode=self.mode, power_budget=power_budget,
                           allow_refs=False)


def read_robot_hosts(ctx: RobotContext) -> RobotHostsFile:
    """The hosts file in use on the robot (see the module docstring for the order)."""
    cfg = read_config(ctx)
    cf = config_file(cfg.stack, ConfigKind.SHUTDOWN_HOSTS)
    arg = spec("shutdown_hosts_config_path").name_for(cfg.stack)
    current = cfg.compose.args.get(arg)
    if current:
        host = cfg.host_path_of(current)
        if host is not None:
            try:
                data = ctx.transport.read_file(host)
                return RobotHostsFile(data.decode(errors="replace"), host, f"{host} (mounted, {arg}:={current})",
                                      cfg.stack, cfg)
            except FileNotFoundError:
                raise UsageError(f"{arg}:={current} is mounted from {host}, which does not exist on the robot",
                                 hint="push a hosts file: panther-ops shutdown hosts add -r ROBOT ...") from None
    if cfg.tree_mounted:
        try:
            data = ctx.transport.read_file(cf.robot_path)
            return RobotHostsFile(data.decode(errors="replace"), cf.robot_path, f"{cf.robot_path} (config tree)",
                                  cfg.stack, cfg)
        except FileNotFoundError:
            pass
    data, source = pull(ctx, FileKind.SHUTDOWN_HOSTS)
    return RobotHostsFile(data.decode(errors="replace"), None, source, cfg.stack, cfg)


Editor = Callable[[str, Mode], Edit]


def plan_hosts_edit(ctx: RobotContext, editor: Editor, *, power_budget: float = POWER_BUDGET_S) -> RobotPlan:
    """A pipeline plan for an edit of the robot's hosts file (refused when it adds errors)."""
    rf = read_robot_hosts(ctx)
    where = rf.path or rf.source
    try:
        edit = editor(rf.text, rf.mode)
    except InputError as exc:  # the editors name the text they were given: name the robot's file
        if exc.path in (None, "<hosts>"):
            raise InputError(exc.message.removeprefix(f"{exc.path}: ").replace("<hosts>", where), path=where,
                             hint=exc.hint) from None
        raise
    after = parse_hosts(edit.text, where, mode=rf.mode, power_budget=power_budget, allow_refs=False)
    if after.errors:  # the whole file as it would be written: an invalid entry already there is refused too
        raise FileKindError(where, "shutdown hosts file", [str(f) for f in after.errors],
                            hint="fix or remove the entries named (panther-ops shutdown hosts remove -r ROBOT "
                            "--ip IP); nothing was changed")
    warnings = [str(f) for f in after.warnings]
    summary = f"shutdown hosts: {edit.message}"
    if not edit.changed:
        plan = compose_plan(ctx, rf.cfg, summary, warnings, [], edit.message)
        plan.data["robot_path"] = rf.path
        return plan
    if rf.path is not None:
        edits: list[FileEdit] = [MaskedFileEdit(rf.path, rf.text.encode(), edit.text.encode())]
        plan = compose_plan(ctx, rf.cfg, summary, warnings, [Verify(rf.cfg.service)], edit.message, extra=edits)
        plan.data["robot_path"] = rf.path
        return plan
    cf = config_file(rf.stack, ConfigKind.SHUTDOWN_HOSTS)
    plan = plan_push(ctx, FileKind.SHUTDOWN_HOSTS, Bundle(Path(cf.filename), edit.text.encode()))
    plan.edits = [MaskedFileEdit(e.path, e.before, e.after, e.mode) for e in plan.edits]
    plan.summary = f"{summary} ({plan.summary})"
    plan.warnings[:0] = warnings
    return plan
