"""The apply pipeline every mutating command goes through, per robot.

read -> plan (pure, with exact diffs) -> [confirm, in the CLI] -> backup on the robot ->
stage every file (temp file beside it, fsynced) -> rename each into place (atomic) ->
``docker compose up -d --force-recreate`` of the affected services as the robot user in a
login shell -> verify (the container runs the planned command and is ready, `readiness`: up and
unrestarted for a short window, ``--settle`` the upper bound) -> on failure restore the backup, recreate, report
``rolled-back``. A plan with nothing to change reports ``ok`` with the reason and writes
nothing.
"""

from __future__ import annotations

import hashlib
import os
import posixpath
import secrets
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from datetime import datetime, timezone
from typing import Any

from panther_ops.core.fleet import readiness
from panther_ops.core.fleet.memo import Memo
from panther_ops.core.fleet.plan import RobotPlan, Verify
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.core.parse.shell_words import has_word
from panther_ops.errors import OpsError, TransportError, UnreachableError
from panther_ops.results import Outcome, RobotResult
from panther_ops.secret import Secret
from panther_ops.transport import scripts_apply, scripts_backup
from panther_ops.transport.base import Command, CommandResult
from panther_ops.transport.session import FileWrite, Session, stage_input

BACKUP_ROOT = scripts_backup.BACKUP_ROOT


@dataclass(frozen=True)
class ApplyOptions:
    dry_run: bool = False
    restart: bool = True
    settle_s: float = 5.0
    command: str = ""
    on_staged: Callable[[str], None] | None = None
    """Called with the robot name after every file is staged and before any rename (tests)."""
    sudo_password: Secret | None = None
    """For steps that run ``sudo`` on a computer beside the robot (the WebUI's User Computer)."""


def _sha(data: bytes | None) -> str | None:
    return None if data is None else hashlib.sha256(data).hexdigest()


def new_backup_id(now: datetime | None = None) -> str:
    stamp = (now or datetime.now(timezone.utc)).strftime("%Y%m%dT%H%M%SZ")
    return f"{stamp}-{secrets.token_hex(2)}"


@dataclass(frozen=True)
class Staged:
    """A robot's write, staged (or being staged) on the robot, waiting for the go-ahead."""

    backup_id: str
    final: bool
    """Nothing follows the write (no recreate): the backup's status is recorded with it."""
    session: Session
    """The write's session on the robot (:mod:`panther_ops.transport.session`)."""


def apply_plan(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """Carry out one robot's plan, its steps by their executors around the write of its file
    edits (`steps.py`); every outcome is a RobotResult."""
    if plan.steps:
        from panther_ops.core.fleet.steps import carry_out

        return carry_out(ctx, plan, opts, lambda o: write_plan(ctx, plan, o))
    return write_plan(ctx, plan, opts)


def write_plan(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """The plan's file edits written (its steps left to their executors): backup, stage,
    go-ahead, recreate, verify, roll back."""
    if not plan.edits or opts.dry_run:
        return _unwritten(ctx.robot.name, plan, opts)
    return apply_staged(ctx, plan, opts, stage_plan(ctx, plan, opts))


def _result(name: str, plan: RobotPlan) -> RobotResult:
    return RobotResult(name, Outcome.OK, plan.noop or plan.summary, diffs=plan.diffs,
                       warnings=list(plan.warnings), data=dict(plan.data))


def _unwritten(name: str, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """The result of a plan with nothing to write, or of a dry run."""
    result = _result(name, plan)
    if not plan.edits:
        result.message = plan.noop or "nothing to change"
    else:
        result.outcome = Outcome.CHANGED
        result.message = f"would change (dry run): {plan.summary}"
        result.data["dry_run"] = True
    return result


def stage_plan(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, session: Session | None = None) -> Staged:
    """Back up and stage the plan's files on the robot through one write session (``session``,
    one already opened for it, else a new one); it then waits for :func:`apply_staged` (or
    :func:`unstage`, or the end of the connection): until then no file is replaced. Staging
    only sends: what the robot says of it is read with the go-ahead. Raises the transport's
    errors (the robot went away: nothing was renamed).
    """
    ctx.phase("write")
    now = datetime.now(timezone.utc)
    backup_id = new_backup_id(now)
    manifest = {
        "id": backup_id,
        "created": now.isoformat(timespec="milliseconds"),  # orders backups of the same second
        "robot": ctx.robot.name,
        "command": opts.command,
        "summary": plan.summary,
        "compose_file": plan.compose_file,
        "recreate": list(plan.recreate),
        "files": [
            {"path": e.path, "backup": f"files/{i}" if e.before is not None else None,
             "sha256_before": _sha(e.before), "sha256_after": _sha(e.after), "diff": d.unified}
            for i, (e, d) in enumerate(zip(plan.edits, plan.diffs, strict=True))
        ],
    }
    final = not plan.recreate or not opts.restart
    status = ("applied" + (" (not recreated)" if plan.recreate else "")) if final else ""
    data = _write_input(ctx, plan, f"{BACKUP_ROOT}/{backup_id}", manifest, status)
    session = session if session is not None else ctx.transport.session()
    session.stage(data)
    return Staged(backup_id, final, session)


def unstage(staged: Staged) -> None:
    """Tell a staged write not to go ahead: the robot removes all it staged, backup included."""
    staged.session.stop()


def apply_staged(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, staged: Staged) -> RobotResult:
    """Give a staged write its go-ahead, then recreate, verify and roll back as needed."""
    result = _result(ctx.robot.name, plan)
    ctx.phase("write")
    problem = _commit(ctx, plan, opts, staged.session)
    if problem is not None:
        result.outcome = Outcome.FAILED
        result.message = problem
        return result
    backup_id = staged.backup_id
    result.data["backup"] = backup_id
    if staged.final:
        result.outcome = Outcome.CHANGED
        result.message = plan.summary + ("; not recreated (--no-restart)" if plan.recreate else "")
        return result
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.outcome = Outcome.CHANGED
        result.message = plan.summary
        mark_backup(ctx, backup_id, "applied")
        return result
    return roll_back(ctx, plan, opts, result, problem, backup_id)


_VALUES_ONLY: Memo[bool] = Memo()


def _values_only(before: bytes | None, after: bytes | None) -> bool:
    """True when the two compose files differ only in services' ``command`` or ``image`` values.

    Those are free-form strings to docker compose (any text passes its schema), and the YAML
    editor has already re-parsed the result, so asking the robot's compose adds nothing.
    Robots with the same files share one answer (computed once).
    """
    if before is None or after is None:
        return False
    return _VALUES_ONLY.get((before, after), lambda: _compare_values(before, after))


def _compare_values(before: bytes, after: bytes) -> bool:
    """Both files' values compared (safe load with ruamel, which the plan already loaded:
    ~1.5 ms a file, where PyYAML would first cost ~10 ms to import). Anything it cannot
    load counts as different: the robot's compose then judges."""
    from ruamel.yaml import YAML

    loader = YAML(typ="safe", pure=True)
    try:
        old, new = loader.load(before), loader.load(after)
    except Exception:  # any failure to load: not provably the same
        return False
    if not (isinstance(old, dict) and isinstance(new, dict)):
        return False

    def strip(doc: dict[str, Any]) -> dict[str, Any]:
        services = doc.get("services")
        if not isinstance(services, dict):
            return doc
        cleaned = {n: {k: v for k, v in svc.items() if k not in ("command", "image")} if isinstance(svc, dict)
                   else svc for n, svc in services.items()}
        return {**doc, "services": cleaned}

    return strip(old) == strip(new)


def _write_input(ctx: RobotContext, plan: RobotPlan, backup_dir: str, manifest: dict[str, Any], status: str) -> bytes:
    """What the write session is sent: the backup and the staged files (validated by the robot's
    docker compose where the compose file changes more than values)."""
    name = ctx.robot.name
    home = plan.home or ctx.transport.home()

    def absolute(path: str) -> str:
        path = posixpath.join(home, path[2:]) if path.startswith("~/") else path
        if not path.startswith("/") or "\n" in path or "\t" in path:
            raise TransportError(name, f"refusing a path that is not absolute or holds a newline or tab: {path!r}")
        return posixpath.normpath(path)

    files = [FileWrite(absolute(e.path), e.before, e.after, e.mode,
                       validate=e.path == plan.compose_file and not _values_only(e.before, e.after))
             for e in plan.edits]
    return stage_input(absolute(backup_dir), manifest, status, files, f"{os.getpid()}.{secrets.token_hex(4)}")


def _commit(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, session: Session) -> str | None:
    """The go-ahead for a staged write. Returns why nothing was written, or None when it was."""
    name = ctx.robot.name
    if opts.on_staged:
        ended = session.wait_staged()
        if ended is not None:
            return _write_problem(name, plan, ended) or f"the write ended before staging (exit {ended.exit_status})"
        opts.on_staged(name)
    return _write_problem(name, plan, session.go())


def _write_problem(name: str, plan: RobotPlan, res: CommandResult) -> str | None:
    """What a finished write session says went wrong (None: all renamed); raises when the
    connection died or the robot failed."""
    if res.exit_status == scripts_apply.CHANGED_EXIT:
        what = res.stderr.strip().splitlines()[-1:] or ["a file changed on the robot since it was read"]
        return f"{what[0]}; nothing written: re-run to apply on top"
    if res.exit_status == scripts_apply.REFUSED_EXIT:
        return f"nothing written: docker compose refuses the new {plan.compose_file}: {res.stderr.strip()[-300:]}"
    if res.exit_status == -1:
        raise UnreachableError(name, "connection lost while writing; the staged files were not renamed")
    if not res.ok:
        raise TransportError(name, f"writing failed (exit {res.exit_status}): {res.stderr.strip()}")
    return None


def roll_back(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, result: RobotResult, problem: str,
              backup_id: str, *, recreate: tuple[str, ...] | None = None,
              before_recreate: Callable[[], None] | None = None, note: str = "") -> RobotResult:
    """Every file of ``plan`` back as it was read (new files removed), the services recreated
    and verified, the backup marked: the one rollback of every change.

    ``recreate``: the services to bring back (default the plan's; ``()``: none were touched);
    ``before_recreate``: a step the change needs undone first (e.g. a renamed service's new
    containers removed); ``note`` ends the message.
    """
    ctx.phase("roll back")
    services = plan.recreate if recreate is None else recreate
    restored = _restored_services(plan)
    added = tuple(s for s in services if restored is not None and s not in restored)
    services = tuple(s for s in services if s not in added)
    again: str | None = None
    logs = ""
    try:
        refused = _restore_files(ctx, plan, backup_id)
        if refused is not None:
            result.outcome = Outcome.FAILED
            result.message = (f"{problem}; ROLLBACK REFUSED: {refused}: another change wrote it after this one; "
                              f"nothing restored (backup {backup_id} on the robot: config rollback --to {backup_id})")
            mark_backup(ctx, backup_id, f"failed: {problem}; not rolled back: {refused}")
            return result
        if added:  # a service the change added is gone from the restored file: its containers too
            logs = _remove_containers(ctx, plan, added)
        if services:
            if before_recreate is not None:
                before_recreate()
            restore = RobotPlan(plan.robot, "restore", [], services, plan.compose_file, [], home=plan.home)
            again = recreate_and_verify(ctx, restore, min(opts.settle_s, 3.0),
                                        RobotResult(plan.robot, Outcome.OK, ""))
    except OpsError as exc:
        result.outcome = Outcome.FAILED
        result.message = f"{problem}; ROLLBACK FAILED: {exc.message} (backup {backup_id} on the robot)"
        return result
    return rolled_back(ctx, result, problem, backup_id, f"restored backup {backup_id}", again, logs + note)


def _restore_files(ctx: RobotContext, plan: RobotPlan, backup_id: str) -> str | None:
    """Put every file of ``plan`` back as it was read, through the same locked compare-and-rename
    as the write: only where each file is still what this change wrote (another change made
    since is never overwritten). The files being replaced are kept beside the change's backup
    (``<backup>/rollback``). Returns what changed meanwhile (nothing restored), or None."""
    undo = RobotPlan(plan.robot, f"roll back {backup_id}", [replace(e, before=e.after, after=e.before)
                                                          for e in plan.edits],
                     (), plan.compose_file, [], home=plan.home)
    manifest = {"id": f"{backup_id}/rollback", "robot": ctx.robot.name, "summary": undo.summary,
                "files": [{"path": e.path, "backup": f"files/{i}" if e.before is not None else None}
                          for i, e in enumerate(undo.edits)]}
    data = _write_input(ctx, undo, f"{BACKUP_ROOT}/{backup_id}/rollback", manifest, "")
    session = ctx.transport.session()
    session.stage(data)
    res = session.go()
    if res.exit_status == scripts_apply.CHANGED_EXIT:
        return (res.stderr.strip().splitlines() or ["a file"])[-1].replace(" since it was read", " since")
    problem = _write_problem(ctx.robot.name, undo, res)
    if problem is not None:
        raise TransportError(ctx.robot.name, problem)
    return None


def _restored_services(plan: RobotPlan) -> set[str] | None:
    """The services of the compose file as the rollback puts it back (None: the plan does not
    touch it, or it cannot be read: every service is brought back as planned)."""
    from panther_ops.core.kinds.common import load_mapping
    from panther_ops.core.kinds.compose import WHAT
    from panther_ops.core.kinds.registry import FileKindError

    before = next((e.before for e in plan.edits if e.path == plan.compose_file), None)
    if before is None:
        return None
    try:
        services = load_mapping(plan.compose_file, before, WHAT).get("services")
    except FileKindError:
        return None
    return {str(k) for k in services} if isinstance(services, dict) else None


def _remove_containers(ctx: RobotContext, plan: RobotPlan, services: tuple[str, ...]) -> str:
    """Remove the project's containers of services no longer in its compose file (what ``docker
    compose up --remove-orphans`` would remove; another project's containers of the same name
    stay), so a crash-looping new service does not outlive the rollback; returns their last log
    lines for the message (``; nmea-gps log: ...``)."""
    client = ctx.transport.docker()
    if client is None:
        return ""
    logs = ""
    wd = project_dir(ctx, plan.compose_file, plan.home)
    for service in services:
        for c in service_containers(client, service, wd, own_only=True):
            log = _last_log(c)
            logs += f"; {service} log: {log}" if log else ""
            c.remove(force=True)
    return logs


def _last_log(container: Any, lines: int = 3) -> str:
    """A container's last log lines, each once, joined with `` | `` (at most 400 characters)."""
    try:
        text = container.logs(tail=lines).decode(errors="replace").strip()
    except Exception:  # a log is a courtesy here
        return ""
    unique = list(dict.fromkeys(t.strip() for t in text.splitlines() if t.strip()))
    return " | ".join(unique)[-400:]


def mark_backup(ctx: RobotContext, backup_id: str, status: str) -> None:
    """Record beside the backup how the attempt ended (best effort: one short command)."""
    try:
        ctx.transport.run(Command.sh(scripts_backup.MARK, f"{BACKUP_ROOT}/{backup_id}", status))
    except OpsError:
        return


def rolled_back(ctx: RobotContext, result: RobotResult, problem: str, backup_id: str, restored: str,
                again: str | None, tail: str = "") -> RobotResult:
    """The end of every rollback that went through: ROLLED_BACK, ``<problem>; <restored>`` (then
    what the services recreated after the restore said, ``again``, and ``tail``), the backup
    marked ``rolled-back``."""
    result.outcome = Outcome.ROLLED_BACK
    result.message = f"{problem}; {restored}" + (f" (after restore: {again})" if again else "") + tail
    mark_backup(ctx, backup_id, f"rolled-back: {problem}")
    return result


def recreate_and_verify(ctx: RobotContext, plan: RobotPlan, settle_s: float, result: RobotResult) -> str | None:
    """Recreate the plan's services and watch them; returns a problem, or None when all is well."""
    client = ctx.transport.docker()
    if client is None:
        result.warnings.append("no docker engine on this robot: services not recreated")
        return None
    compose = plan.compose_file
    cdir = posixpath.dirname(compose) or "~"
    ctx.phase("recreate")
    res = ctx.transport.run(
        Command.of("docker", "compose", "-f", posixpath.basename(compose), "up", "-d", "--force-recreate",
                   *plan.recreate, login=True, cwd=cdir),
        timeout=300,
    )
    if not res.ok:
        return f"docker compose up failed: {res.stderr.strip()[-400:]}"
    ctx.phase("verify")
    return watch_services(client, plan, settle_s, project_dir(ctx, compose, plan.home))


def watch_services(client: Any, plan: RobotPlan, settle_s: float, working_dir: str) -> str | None:
    """Watch the plan's services (its verify checks, else its recreated services) until each is
    ready (`readiness.judge`: running, unrestarted, for ``readiness.MIN_STABLE_S``) or for at
    most ``settle_s``: a problem, or None when each runs the planned command and none failed."""
    start = time.monotonic()
    deadline = start + settle_s
    checks = plan.verify or [Verify(s) for s in plan.recreate]
    samples: dict[str, list[readiness.Sample]] = {v.service: [] for v in checks}
    while True:
        ready = 0
        for v in checks:
            ctrs = service_containers(client, v.service, working_dir, own_only=True)
            if not ctrs:
                return f"service {v.service}: no container of the project in {working_dir} after recreate"
            c = ctrs[0]
            cmd = [str(x) for x in c.attrs.get("Config", {}).get("Cmd") or []]
            missing = [x for x in v.cmd_contains if not has_word(cmd, x)]
            if missing:
                return f"service {v.service}: container command lacks {', '.join(missing)}"
            present = [x for x in v.cmd_lacks if has_word(cmd, x)]
            if present:
                return f"service {v.service}: container command still has {', '.join(present)}"
            samples[v.service].append(readiness.sample_of(c.attrs, time.monotonic() - start))
            verdict, problem = readiness.judge(samples[v.service], readiness.MIN_STABLE_S)
            if verdict == readiness.FAILED:
                return f"service {v.service}: {problem}"
            ready += verdict == readiness.READY
        if ready == len(checks) or time.monotonic() >= deadline:
            return None
        time.sleep(min(readiness.POLL_S, max(0.0, deadline - time.monotonic())))
