"""``desired.shutdown_hosts`` converged by `apply` (and shown by `config diff`): the robot's
shutdown hosts file lists exactly the inventory's hosts (pure).

The file in use is edited in place (mounted, or the 2.2 config tree's); a robot still on its
image's default gets the default with the hosts converged, pushed as `config push --as
shutdown-hosts` pushes it (copied to ``~/config/<package>/config/<file>``, mounted and pointed
at on 2.0/2.1). The whole file as it would be written passes the hosts file's validator for the
robot's stack (SSH entries up to 2.2.0, HTTP entries from 2.2.1). Secrets arrive resolved (the
reader resolves the inventory's ``{env: ...}``/``{file: ...}``): the robot's manager needs the
value; diffs show ``****``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.config.files import config_file
from panther_ops.core.config.plan_push import Bundle, push_onto
from panther_ops.core.config.robot_config import RobotConfig
from panther_ops.core.fleet.plan import FileEdit, MaskedFileEdit
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import FileKind
from panther_ops.core.kinds.hostsfile import converge_hosts
from panther_ops.core.shutdown.plan_hosts import RobotHostsFile, hosts_edit, hosts_in_use

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
    edit, warnings = hosts_edit(rf, lambda text, _mode: converge_hosts(text, list(entries), rf.path or rf.source))
    if not edit.changed:
        return DesiredHosts(warnings=warnings)
    if rf.path is not None:
        return DesiredHosts([MaskedFileEdit(rf.path, rf.text.encode(), edit.text.encode())], warnings,
                            f"shutdown hosts: {edit.message}")
    cf = config_file(cfg.stack, FileKind.SHUTDOWN_HOSTS)
    pushed = push_onto(reads, cfg, FileKind.SHUTDOWN_HOSTS, Bundle(Path(cf.filename), edit.text.encode()))
    edits: list[FileEdit] = [MaskedFileEdit(e.path, e.before, e.after, e.mode) for e in pushed.edits]
    return DesiredHosts(edits, warnings + pushed.warnings, f"shutdown hosts: {edit.message} ({pushed.summary})")
