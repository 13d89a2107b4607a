"""`config restore-defaults`: the stack's default configuration back (the 2.2 config tree reset)."""

from __future__ import annotations

import json
import re
from datetime import datetime, timezone

from panther_ops.core.config.files import CONTAINER_CONFIG_DIR
from panther_ops.core.config.robot import read_compose
from panther_ops.core.containers.engine import engine
from panther_ops.core.driver import planners
from panther_ops.core.driver.containers import last_line
from panther_ops.core.fleet.pipeline import (
    BACKUP_ROOT,
    ApplyOptions,
    apply_plan,
    mark_backup,
    new_backup_id,
    recreate_and_verify,
)
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import OpsError, TransportError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command

_PATH_ARG = re.compile(r"(_config_path|_file|_path)$")
TAR_SAVE = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; c="$2"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'mkdir -p -- "$r$d" || exit 1; '
    'if [ -d "$r$c" ]; then tar -czf "$r$d/config.tar.gz" -C "$(dirname -- "$r$c")" "$(basename -- "$c")" || exit 1; '
    'fi; cat > "$r$d/manifest.json.tmp" && mv -f -- "$r$d/manifest.json.tmp" "$r$d/manifest.json" && sync'
)
"""$1 = backup dir, $2 = the config directory; stdin = manifest.json. Archive: <backup>/config.tar.gz."""


TAR_RESTORE = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; c="$2"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'rm -rf -- "$r$c" || exit 1; '
    'if [ -f "$r$d/config.tar.gz" ]; then tar -xzf "$r$d/config.tar.gz" -C "$(dirname -- "$r$c")" || exit 1; fi'
)
"""Put the config directory back as it was in the archive (or absent, when it was)."""


CLEAN_TREE = (
    'r="${PANTHER_OPS_ROOT:-}"; c="$1"; [ -d "$r$c" ] || exit 0; '
    'find "$r$c" -mindepth 1 -maxdepth 1 ! -name common -exec rm -rf -- {} +'
)
"""``--hard``: everything in the config directory but ``common/`` goes (it is in the archive)."""


def no_engine(ctx: RobotContext, _key: str) -> str | None:
    """Why the robot's docker engine cannot be asked (None: it can)."""
    return engine(ctx)[1]


def plan_restore_defaults(ctx: RobotContext, *, hard: bool = False) -> RobotPlan:
    """`config restore-defaults`: read compose.yaml (and whether there is an engine); plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_restore_defaults(raw, reads, hard=hard),
                         {planners.ENGINE: no_engine})


def apply_restore(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """2.0/2.1: the pipeline. 2.2: archive ~/config, update_config_directory, recreate, verify, else restore."""
    if plan.data.get("action") != "update_config_directory":
        return apply_plan(ctx, plan, opts)
    name = ctx.robot.name
    result = RobotResult(name, Outcome.CHANGED, plan.summary, warnings=list(plan.warnings), data=dict(plan.data))
    if opts.dry_run:
        result.message = f"would {plan.summary} (dry run)"
        result.data["dry_run"] = True
        return result
    client, why = engine(ctx)
    if client is None:
        result.outcome = Outcome.SKIPPED
        result.message = f"{why}: update_config_directory runs in the driver image"
        return result
    tree = str(plan.data["config_dir"])
    backup_id = new_backup_id()
    bdir = f"{BACKUP_ROOT}/{backup_id}"
    archive = f"{bdir}/config.tar.gz".replace("~", plan.home or ctx.transport.home(), 1)
    manifest = {
        "id": backup_id, "created": datetime.now(timezone.utc).isoformat(timespec="seconds"), "robot": name,
        "command": opts.command, "summary": plan.summary, "compose_file": plan.compose_file,
        "recreate": list(plan.recreate), "files": [], "archive": "config.tar.gz", "config_dir": tree,
    }
    res = ctx.transport.run(Command.sh(TAR_SAVE, bdir, tree), stdin=json.dumps(manifest, indent=2).encode(),
                            timeout=300)
    if not res.ok:
        raise TransportError(name, f"backup of {tree} failed, nothing changed: {res.stderr.strip()[-300:]}")
    result.data.update(backup=backup_id, archive=archive)
    problem: str | None = None
    if plan.data.get("hard"):
        res = ctx.transport.run(Command.sh(CLEAN_TREE, tree))
        if not res.ok:
            problem = f"clearing {tree} failed: {res.stderr.strip()[-300:]}"
    if problem is None:
        mounts = [a for m in plan.data.get("env_mounts", []) for a in ("-v", str(m))]
        res = ctx.transport.run(Command.of("docker", "run", "--rm", "--network", "none",
                                           "-v", f"{tree}:{CONTAINER_CONFIG_DIR}", *mounts,
                                           str(plan.data["image"]), "update_config_directory", login=True),
                                timeout=600)
        if not res.ok:
            problem = f"update_config_directory failed: {last_line(res.stderr) or last_line(res.stdout)}"
    recreated = problem is None and opts.restart
    if recreated:
        problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.message = (f"defaults restored in {tree} from {plan.data['image']}"
                          + ("" if opts.restart else " (driver not recreated: --no-restart)")
                          + f"; previous {tree} in {archive}")
        mark_backup(ctx, backup_id, "applied" + ("" if opts.restart else " (not recreated)"))
        return result
    try:
        res = ctx.transport.run(Command.sh(TAR_RESTORE, bdir, tree), timeout=300)
        if not res.ok:
            raise TransportError(name, res.stderr.strip()[-300:])
        again = (recreate_and_verify(ctx, plan, min(opts.settle_s, 3.0), RobotResult(name, Outcome.OK, ""))
                 if recreated else None)
    except OpsError as exc:
        result.outcome = Outcome.FAILED
        result.message = f"{problem}; RESTORE FAILED: {exc.message} (the previous {tree} is in {archive})"
        return result
    result.outcome = Outcome.ROLLED_BACK
    result.message = (f"{problem}; {tree} restored from {archive}" + (f" (after restore: {again})" if again else "")
                      + ("" if recreated else "; the driver was not touched"))
    mark_backup(ctx, backup_id, f"rolled-back: {problem}")
    return result
