"""The robot's own shutdown hosts file: which file the manager reads, and plans that change it (pure).

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

``desired.shutdown_hosts`` converged by `apply` (and shown by `config diff`, `desired_hosts`):
the robot's shutdown hosts file lists exactly the inventory's hosts. The file in use is edited
in place (mounted, or the 2.2 config tree's); a robot still on its image's default gets the
default with the hosts converged, pushed as `config push --as shutdown-hosts` pushes it (copied
to ``~/config/<package>/config/<file>``, mounted and pointed at on 2.0/2.1). The whole file as
it would be written passes the hosts file's validator for the robot's stack (SSH entries up to
2.2.0, HTTP entries from 2.2.1). Secrets arrive resolved (the reader resolves the inventory's
``{env: ...}``/``{file: ...}``): the robot's manager needs the value; diffs show ``****``.

Pure functions of compose.yaml as read and the files they ask for (:class:`Reads`); the
reads (and the image's default, through `config pull`) are `read.py`'s.
"""

from __future__ import annotations

import re
import shlex
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.plan import FileEdit, MaskedFileEdit, RobotPlan, Step, Verify
from panther_ops.core.fleet.plan_rollback import plan_rollback
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind, FileKindError, check_file
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S, Edit, HostsFile, Mode, converge_hosts, parse_hosts
from panther_ops.core.robot.edits import compose_plan
from panther_ops.core.robot.files import config_file
from panther_ops.core.robot.launch_args import spec
from panther_ops.core.robot.push import Bundle, push_onto
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.core.stack import Stack
from panther_ops.core.yaml.document import DocumentError, YamlDocument
from panther_ops.errors import InputError, UsageError
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost


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


def hosts_in_use(cfg: RobotConfig, reads: Reads) -> RobotHostsFile | None:
    """The mounted hosts file, else the 2.2 tree's (None: the robot uses its image's default)."""
    robot = reads.robot
    cf = config_file(cfg.stack, FileKind.SHUTDOWN_HOSTS)
    arg = spec("shutdown_hosts_config_path").name_for(cfg.stack)
    current = cfg.compose.args.get(arg)
    if current:
        host = cfg.host_path_of(current)
        if host is not None:
            data = reads.file(host)
            if data is None:
                raise UsageError(f"{arg}:={current} is mounted from {host}, which does not exist on the robot",
                                 hint=f"push a hosts file in its place: panther-ops config push hosts.yaml --as "
                                 f"shutdown-hosts -r {shlex.quote(robot)} (check it first: panther-ops "
                                 "shutdown hosts validate hosts.yaml)")
            return RobotHostsFile(data.decode(errors="replace"), host, f"{host} (mounted, {arg}:={current})",
                                  cfg.stack, cfg)
    if cfg.tree_mounted:
        data = reads.file(cf.robot_path)
        if data is not None:
            return RobotHostsFile(data.decode(errors="replace"), cf.robot_path, f"{cf.robot_path} (config tree)",
                                  cfg.stack, cfg)
    return None


Editor = Callable[[str, Mode], Edit]


def hosts_edit(rf: RobotHostsFile, editor: Editor, power_budget: float = POWER_BUDGET_S, *,
               robot: str = "ROBOT") -> tuple[Edit, list[str]]:
    """The edit of the robot's hosts file and its warnings (refused when the file would have errors;
    the hint is the command that removes the first entry in error from ``robot``)."""
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
                            hint=f"fix or remove the entries named ({_remove_command(robot, after)}); "
                            "nothing was changed")
    return edit, [str(f) for f in after.warnings]


def _remove_command(robot: str, hosts: HostsFile) -> str:
    """``panther-ops shutdown hosts remove`` of the first entry in error, its values filled in
    (as written in the file; ``IP`` where the entry has no ip)."""
    index = next((int(m.group(1)) for f in hosts.errors if (m := re.match(r"hosts\[(\d+)\]", f.where))), None)
    ip: object = None
    if index is not None:
        try:
            doc = YamlDocument.load(hosts.text, hosts.source).to_plain()
            ip = doc["hosts"][index].get("ip")
        except (DocumentError, AttributeError, IndexError, KeyError, TypeError):
            ip = None
    shown = shlex.quote(str(ip)) if isinstance(ip, str | int) and str(ip) else "IP"
    return f"panther-ops shutdown hosts remove -r {shlex.quote(robot)} --ip {shown}"


def plan_in_place(robot: str, rf: RobotHostsFile, edit: Edit, warnings: list[str]) -> RobotPlan | None:
    """The plan of an edit of the file in use (None: the image's default must be pushed instead)."""
    summary = f"shutdown hosts: {edit.message}"
    if not edit.changed:
        plan = compose_plan(robot, rf.cfg, summary, warnings, [], edit.message)
        plan.data["robot_path"] = rf.path
        return plan
    if rf.path is None:
        return None
    edits: list[FileEdit] = [MaskedFileEdit(rf.path, rf.text.encode(), edit.text.encode())]
    plan = compose_plan(robot, rf.cfg, summary, warnings, [Verify(rf.cfg.service)], edit.message, extra=edits)
    plan.data["robot_path"] = rf.path
    return plan


def as_hosts_push(plan: RobotPlan, edit: Edit, warnings: list[str], checked: list[str]) -> RobotPlan:
    """A `config push` plan of the edited default file, masked, summarised as a hosts change. The
    file's findings are the edit's ``warnings`` (weighed against the command's power budget), in
    place of the push's own check of the same file (``checked``: its validator's default budget),
    so that each is said once."""
    plan.edits = [MaskedFileEdit(e.path, e.before, e.after, e.mode) for e in plan.edits]
    plan.summary = f"shutdown hosts: {edit.message} ({plan.summary})"
    rest = list(plan.warnings)
    for finding in checked:
        if finding in rest:
            rest.remove(finding)
    plan.warnings = [*warnings, *rest]
    return plan


def plan_local_edit(reads: Reads, file: Path, change: Callable[[str], Edit]) -> RobotPlan:
    """The plan of one change to a local hosts file (``change`` maps its text to the new one)."""
    path = str(file.resolve())
    where = str(file)
    before = reads.file(path)
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
        return RobotPlan(reads.robot, edit.message, noop=edit.message, warnings=warnings, home=home)
    # a new file may hold a secret (--ask-secret): only its owner reads it
    edits: list[FileEdit] = [MaskedFileEdit(path, before, after, None if before is not None else 0o600)]
    return RobotPlan(reads.robot, edit.message, edits, warnings=warnings, home=home,
                     data={"hosts_file": where})


def plan_local_restore(reads: Reads, file: Path, to: str | None) -> RobotPlan:
    """The plan restoring a local hosts file as it was before backup ``to`` (default: the
    newest): masked diff, the content restored checked as every write of the file is."""
    warnings: list[str] = []

    def edit(path: str, now: bytes | None, old: bytes | None) -> FileEdit:
        if old is not None:
            warnings.extend(check_file(FileKind.SHUTDOWN_HOSTS, str(file), old, local=file))
        return MaskedFileEdit(path, now, old, None if now is not None else 0o600)

    plan = plan_rollback(reads, to, only=str(file.resolve()), edit=edit)
    plan.warnings += warnings
    plan.home = str(file.resolve().parent)
    plan.data["hosts_file"] = str(file)
    return plan


@dataclass
class RobotShutdownPlan:
    robot: str
    hosts_file: RobotHostsFile
    parsed: HostsFile
    hosts: list[ShutdownHost]


def shutdown_plan(robot: str, rf: RobotHostsFile, power_budget: float = POWER_BUDGET_S) -> RobotShutdownPlan:
    """`shutdown robot`: the robot's hosts file, validated (UsageError when it has errors)."""
    parsed = rf.parse(power_budget)
    if parsed.errors:
        raise UsageError(f"its hosts file ({rf.source}) has errors: "
                         + "; ".join(str(f) for f in parsed.errors),
                         hint=f"fix it first (panther-ops shutdown hosts validate -r {robot}); nothing was "
                         "shut down")
    return RobotShutdownPlan(robot, rf, parsed, parsed.hosts())


@dataclass(frozen=True)
class ShutdownRobot(Step):
    """`shutdown robot`: the hosts of ``plan`` (side by side, from the robot), then the Built-in
    Computer (`run.shutdown_robot`)."""

    plan: RobotShutdownPlan


def robot_shutdown(sp: RobotShutdownPlan) -> RobotPlan:
    """`shutdown robot`'s change: its hosts named, then the robot itself."""
    names = ", ".join(h.describe() for h in sp.hosts)
    first = f"{len(sp.hosts)} host(s) first ({names}), then " if sp.hosts else "no hosts in its file; "
    return RobotPlan(sp.robot, f"shut down {first}the Built-in Computer", warnings=[str(f) for f in sp.parsed.warnings],
                     data={"hosts_file": sp.hosts_file.source}, steps=[ShutdownRobot(sp)])


DEFAULT_FACT = "shutdown_hosts_default"
"""Fact: the hosts file the robot's image ships (bytes), for a robot that uses it."""


@dataclass
class DesiredHosts:
    edits: list[FileEdit] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    summary: str = ""


def desired_hosts(reads: Reads, cfg: RobotConfig, entries: list[Mapping[str, Any]]) -> DesiredHosts:
    """The edits that make the robot's hosts file list ``entries`` (none: it already does)."""
    rf = hosts_in_use(cfg, reads)
    if rf is None:
        default = reads.fact(DEFAULT_FACT)
        rf = RobotHostsFile(bytes(default).decode(errors="replace"), None, "the image's default", cfg.stack, cfg)
    edit, warnings = hosts_edit(rf, lambda text, _mode: converge_hosts(text, list(entries), rf.path or rf.source),
                                robot=reads.robot)
    if not edit.changed:
        return DesiredHosts(warnings=warnings)
    if rf.path is not None:
        return DesiredHosts([MaskedFileEdit(rf.path, rf.text.encode(), edit.text.encode())], warnings,
                            f"shutdown hosts: {edit.message}")
    cf = config_file(cfg.stack, FileKind.SHUTDOWN_HOSTS)
    pushed = push_onto(reads, cfg, FileKind.SHUTDOWN_HOSTS, Bundle(Path(cf.filename), edit.text.encode()))
    edits: list[FileEdit] = [MaskedFileEdit(e.path, e.before, e.after, e.mode) for e in pushed.edits]
    return DesiredHosts(edits, warnings + pushed.warnings, f"shutdown hosts: {edit.message} ({pushed.summary})")


@dataclass(frozen=True)
class ShutdownFileHost(Step):
    """`shutdown --hosts FILE`: the shutdown order of one host of the file (`apply.py`), from
    this machine (``known_hosts``, ``identity``: for SSH hosts) or through the robot ``via``
    (the target's connection is then the robot's)."""

    host: ShutdownHost
    via: str | None = None
    known_hosts: str | None = None
    identity: str | None = None


def plan_file_host(target: str, row: dict[str, Any], step: ShutdownFileHost, warnings: list[str]) -> RobotPlan:
    """What would be done to one host of a hosts file (a pure function of its entry, ``row``:
    `HostEntry.row`, which never holds the secret)."""
    if row["method"] == "http":
        request, then = f"GET /shutdown?ts=…&sig=… (secret: {row['secret']})", "ping until gone"
    else:
        request = f"ssh: {row['command']}"
        then = "ping until gone" if row["ping_for_success"] else "done at the response"
    where = f"through {step.via}" if step.via else "from here"
    return RobotPlan(target, f"shut down {target} ({request}, {where}; then {then}, timeout {row['timeout']:g} s)",
                     warnings=list(warnings), data={**row, "via": step.via}, steps=[step])
