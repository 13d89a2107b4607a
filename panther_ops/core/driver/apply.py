"""The driver's executors: what `driver restart|stop|start`, `driver update` and `config
restore-defaults` plans do on the robot (their planners: `plan.py`; their reads: `read.py`).

restart: ``docker compose up -d --force-recreate <driver>`` through the pipeline, watched for
the settle time. stop/start: ``docker compose stop|start <driver service>`` as the robot user
in a login shell (the same way every compose command runs), in the compose file's directory,
then the container's state is read back: stopped (``exited``) after a stop; after a start,
running and not restarted for the settle time (the watch `driver restart` uses). update: a new
driver image in compose.yaml, pulled, recreated, verified, rolled back on failure. restore:
2.0/2.1 through the pipeline; 2.2's config tree archived, reset by the image's
``update_config_directory``, the driver recreated and verified, else the tree restored.
"""

from __future__ import annotations

import json
import posixpath
import time
from dataclasses import replace
from datetime import datetime, timezone
from typing import Any

from panther_ops.core.containers.engine import engine
from panther_ops.core.driver.containers import last_line
from panther_ops.core.driver.migrate.dirs import RMDIR_EMPTY
from panther_ops.core.driver.plan import RecreateDriver, ResetConfigTree, SetRunState, UpdateDriver
from panther_ops.core.fleet import readiness
from panther_ops.core.fleet.pipeline import (
    BACKUP_ROOT,
    ApplyOptions,
    mark_backup,
    new_backup_id,
    recreate_and_verify,
    roll_back,
    rolled_back,
    watch_services,
)
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.robot.files import CONTAINER_CONFIG_DIR
from panther_ops.errors import OpsError, TransportError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command


@executes(RecreateDriver)
def apply_restart(ctx: RobotContext, plan: RobotPlan, step: RecreateDriver, opts: ApplyOptions,
                  _write: Write) -> RobotResult:
    """``docker compose up -d --force-recreate <driver>`` as the robot user, then watch it for the settle time."""
    name = ctx.robot.name
    client, why = engine(ctx)
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"{why}: nothing to restart", data=dict(plan.data))
    service = plan.recreate[0]
    wd = project_dir(ctx, plan.compose_file, plan.home)
    before = service_containers(client, service, wd, own_only=True)
    result = RobotResult(name, Outcome.CHANGED, "", data=dict(plan.data))
    result.data["previous_container"] = before[0].id[:12] if before else None
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem:
        result.outcome = Outcome.FAILED
        result.message = problem
        result.data["hint"] = "see panther-ops driver logs"
        return result
    after = service_containers(client, service, wd, own_only=True)
    result.data["container"] = after[0].id[:12] if after else None
    result.message = f"recreated {service} ({step.image}); running after {readiness.stable_for(opts.settle_s):g} s"
    return result


STOP_TIMEOUT_S = 30
"""How long a stop waits for the container to exit (docker compose's own default is 10 s; the
driver's shutdown of the motor controllers may take longer)."""


@executes(SetRunState)
def apply_run_state(ctx: RobotContext, plan: RobotPlan, step: SetRunState, opts: ApplyOptions,
                    _write: Write) -> RobotResult:
    """Stop or start the driver's container (``step.verb``) and check its state."""
    name = ctx.robot.name
    action, service = step.verb, step.service
    client, why = engine(ctx)
    if client is None:
        return RobotResult(name, Outcome.SKIPPED, f"{why}: nothing to {action}", data=dict(plan.data))
    wd = project_dir(ctx, plan.compose_file, plan.home)
    found = service_containers(client, service, wd, own_only=True)
    if not found:
        return RobotResult(name, Outcome.FAILED, f"no {service} container of the project in {wd}",
                           data={**plan.data, "hint": f"panther-ops driver restart -r {name}"})
    running = found[0].attrs.get("State", {}).get("Status") == "running"
    if running == (action == "start"):
        return RobotResult(name, Outcome.OK, f"{service} already {'running' if running else 'stopped'}",
                           data=dict(plan.data))
    ctx.phase(action)
    argv = ["docker", "compose", "-f", posixpath.basename(plan.compose_file), action]
    argv += ["-t", str(STOP_TIMEOUT_S)] if action == "stop" else []
    res = ctx.transport.run(Command.of(*argv, service, login=True, cwd=posixpath.dirname(plan.compose_file) or "~"),
                            timeout=STOP_TIMEOUT_S + 60)
    result = RobotResult(name, Outcome.CHANGED, "", data=dict(plan.data))
    if not res.ok:
        result.outcome = Outcome.FAILED
        result.message = f"docker compose {action} failed: {res.stderr.strip()[-400:]}"
        return result
    if action == "start":
        ctx.phase("verify")
        problem = watch_services(client, plan, opts.settle_s, wd)
        if problem:
            result.outcome = Outcome.FAILED
            result.message = problem
            result.data["hint"] = f"panther-ops driver logs -r {name}"
            return result
        result.message = f"started {service}; running after {readiness.stable_for(opts.settle_s):g} s"
        return result
    deadline = time.monotonic() + 5
    while True:
        state = service_containers(client, service, wd, own_only=True)[0].attrs.get("State", {})
        if state.get("Status") == "exited":
            result.message = f"stopped {service} (exit code {state.get('ExitCode')}); `driver start` brings it back"
            return result
        if time.monotonic() >= deadline:
            result.outcome = Outcome.FAILED
            result.message = f"{service} is {state.get('Status')} after docker compose stop"
            return result
        time.sleep(0.2)


@executes(UpdateDriver)
def apply_update(ctx: RobotContext, plan: RobotPlan, step: UpdateDriver, opts: ApplyOptions,
                 write: Write) -> RobotResult:
    """Apply a `driver update` plan: the pipeline, plus pull / orphan removal when the plan needs them;
    then the directories a migration created, once its way back is applied or it is rolled back,
    removed if empty (`migrate.dirs`)."""
    result = _apply_update(ctx, plan, step, opts, write)
    done = Outcome.CHANGED if step.way_back else Outcome.ROLLED_BACK
    if step.remove_if_empty and not opts.dry_run and result.outcome is done:
        try:
            ctx.transport.run(Command.sh(RMDIR_EMPTY, *step.remove_if_empty))
        except OpsError as exc:
            result.warnings.append(f"empty directories not removed ({', '.join(step.remove_if_empty)}): {exc}")
    return result


def _apply_update(ctx: RobotContext, plan: RobotPlan, step: UpdateDriver, opts: ApplyOptions,
                  write: Write) -> RobotResult:
    renamed_from, pull = step.renamed_from, step.pull
    if not (renamed_from or pull) or not plan.edits or opts.dry_run or not opts.restart:
        result = write(opts)
        if renamed_from and result.outcome is Outcome.CHANGED and not opts.restart and not opts.dry_run:
            result.warnings.append(
                f"the {renamed_from} container keeps running until the driver is recreated: then remove it "
                f"(docker compose up -d --remove-orphans {plan.recreate[0]}) or two drivers hold the hardware")
        return result
    client, _why = engine(ctx)
    if client is None:
        return write(opts)
    result = write(replace(opts, restart=False))
    if result.outcome is not Outcome.CHANGED:
        return result
    backup_id = str(result.data["backup"])
    result.message = plan.summary
    cdir = posixpath.dirname(plan.compose_file) or "~"
    if pull:
        res = ctx.transport.run(Command.of("docker", "compose", "-f", posixpath.basename(plan.compose_file), "pull",
                                           *plan.recreate, login=True, cwd=cdir), timeout=1800)
        if not res.ok:
            failed = f"docker compose pull failed: {last_line(res.stderr)}"
            return _roll_back_update(ctx, plan, opts, result, failed, backup_id, client, None)
    if renamed_from:
        for c in service_containers(client, renamed_from, project_dir(ctx, plan.compose_file, plan.home),
                                    own_only=True):
            c.remove(force=True)
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.outcome = Outcome.CHANGED
        mark_backup(ctx, backup_id, "applied")
        return result
    return _roll_back_update(ctx, plan, opts, result, problem, backup_id, client, step)


def _roll_back_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, result: RobotResult, problem: str,
                      backup_id: str, client: Any, recreated: UpdateDriver | None) -> RobotResult:
    """The pipeline's rollback; when containers were touched (``recreated``: the step that
    touched them) the old driver comes back up (a renamed service: the new service's
    containers removed first, the old one recreated)."""
    if recreated is None:
        return roll_back(ctx, plan, opts, result, problem, backup_id, recreate=(),
                         note="; the driver was not touched")
    renamed_from = recreated.renamed_from
    if not renamed_from:
        return roll_back(ctx, plan, opts, result, problem, backup_id)
    wd = project_dir(ctx, plan.compose_file, plan.home)

    def remove_new_containers() -> None:
        for svc in plan.recreate:
            for c in service_containers(client, svc, wd, own_only=True):
                c.remove(force=True)

    return roll_back(ctx, plan, opts, result, problem, backup_id, recreate=(renamed_from,),
                     before_recreate=remove_new_containers)


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


@executes(ResetConfigTree)
def apply_restore(ctx: RobotContext, plan: RobotPlan, step: ResetConfigTree, opts: ApplyOptions,
                  _write: Write) -> RobotResult:
    """2.2: archive ~/config, update_config_directory, recreate, verify, else restore (2.0/2.1:
    a plain pipeline plan, no step)."""
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
    tree = step.config_dir
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
    if step.hard:
        res = ctx.transport.run(Command.sh(CLEAN_TREE, tree))
        if not res.ok:
            problem = f"clearing {tree} failed: {res.stderr.strip()[-300:]}"
    if problem is None:
        mounts = [a for m in step.env_mounts for a in ("-v", m)]
        res = ctx.transport.run(Command.of("docker", "run", "--rm", "--network", "none",
                                           "-v", f"{tree}:{CONTAINER_CONFIG_DIR}", *mounts,
                                           step.image, "update_config_directory", login=True),
                                timeout=600)
        if not res.ok:
            problem = f"update_config_directory failed: {last_line(res.stderr) or last_line(res.stdout)}"
    recreated = problem is None and opts.restart
    if recreated:
        problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.message = (f"defaults restored in {tree} from {step.image}"
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
    return rolled_back(ctx, result, problem, backup_id, f"{tree} restored from {archive}", again,
                       "" if recreated else "; the driver was not touched")
