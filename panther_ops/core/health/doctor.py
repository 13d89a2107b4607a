"""`panther-ops doctor`: checks each robot (and the fleet) and says how to fix what is off.

Checks: clock offset against this machine and the spread across the fleet (the manual asks
for time sync before installing anything; warn above 1 s), key authentication, docker and
compose v2 present, free disk, the stack supported (a driver image of a release panther-ops
does not know fails), whether its release has the two safety fixes of husarion_ugv 2.3.2
(`safety_fixes`), and whether the default password ``husarion`` is still accepted over SSH.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.facts import signed_seconds
from panther_ops.core.fleet.runner import RobotContext, Task
from panther_ops.core.health.safety_fixes import missing_text
from panther_ops.core.health.status import detect_stack, gather_facts
from panther_ops.results import FleetResult, Outcome, RobotResult

CLOCK_LIMIT_S = 1.0
# Room for what panther-ops itself puts on the robot's disk: `driver update` pulls the next
# husarion/husarion-ugv (or panther) image, layers downloaded and unpacked, while the running
# one stays for a rollback. An absolute amount, not a share: on the Built-in Computer's small
# card the two agree, and on a big disk a share would flag tens of GiB free as low.
DISK_MIN_BYTES = 5 * 1024**3
DEFAULT_PASSWORD = "husarion"  # the factory default we warn about, not a credential of ours


@dataclass(frozen=True)
class Finding:
    check: str
    state: str  # ok | warn | fail
    detail: str
    fix: str | None = None

    def to_json(self) -> dict[str, Any]:
        return {"check": self.check, "state": self.state, "detail": self.detail, "fix": self.fix}


def make_doctor_task(*, password_check: bool = True, gps: Task | None = None) -> Any:
    """The checks of each robot; ``password_check``: try the default password (a second
    connection); ``gps``: how a robot's `gps status` is read (default: with doctor's window),
    for a robot whose inventory says it has GNSS."""
    def doctor_task(ctx: RobotContext) -> RobotResult:
        findings: list[Finding] = []
        facts, offset = gather_facts(ctx)
        if ctx.robot.transport == "local":
            findings.append(Finding("ssh key auth", "ok", "demo robot: reached as a local directory"))
        else:
            findings.append(Finding("ssh key auth", "ok", f"connected as {ctx.robot.user} with a key"))
        if offset is None:
            findings.append(Finding("clock", "warn", "could not read the robot's clock",
                                    "on the robot: `timedatectl` shows its time and whether NTP syncs it"))
        elif abs(offset) > CLOCK_LIMIT_S:
            findings.append(Finding(
                "clock", "warn", f"robot clock is {signed_seconds(offset)} off this machine",
                "sync time before installing anything: on the robot `sudo timedatectl set-ntp true` "
                "(or point chrony at your NTP server) and check `timedatectl`",
            ))
        else:
            findings.append(Finding("clock", "ok", f"{signed_seconds(offset)} from this machine"))
        stack, _service, problem = detect_stack(ctx, facts)
        if stack:
            findings.append(Finding("stack", "ok", stack.label()))
            lacking = missing_text(stack)
            findings.append(Finding("safety fixes", "warn", *lacking) if lacking else
                            Finding("safety fixes", "ok", f"{stack.label()} has the soft E-stop and "
                                    "battery-dead fixes"))
        elif problem and _service is not None:  # a driver image of a release panther-ops does not know
            findings.append(Finding("stack", "fail", problem, "put a supported driver image in compose.yaml "
                                    "(panther-ops driver versions lists them), or set `stack:` in the inventory"))
        else:
            findings.append(Finding("stack", "warn", problem or "unknown",
                                    "check ~/compose.yaml or set `stack:` in the inventory"))
        local = ctx.robot.transport == "local"
        if local:
            findings.append(Finding("docker", "ok", "demo robot: no docker engine (docker steps are skipped)"))
        elif facts.docker_server is None:
            findings.append(Finding("docker", "fail", facts.docker_error or "docker not found",
                                    "the Built-in Computer image ships docker; reinstall the OS image"))
        else:
            findings.append(Finding("docker", "ok", f"engine {facts.docker_server}"))
            if facts.compose_version and facts.compose_version.split(".")[0] >= "2":
                findings.append(Finding("compose v2", "ok", f"docker compose {facts.compose_version}"))
            else:
                findings.append(Finding("compose v2", "fail", facts.compose_error or "docker compose v2 not found",
                                        "install the docker compose v2 plugin (docker-compose-plugin)"))
        findings.append(_disk(facts.disk_free_bytes, facts.disk_total_bytes))
        if password_check and not local:
            findings.append(_password(ctx))
        from panther_ops.core.health.gps_check import gps_finding, wants_gps

        if wants_gps(ctx.robot.desired):  # an ANT02: NMEA should arrive with a fix
            findings.append(gps_finding(ctx, gps))
        data: dict[str, Any] = {"findings": [f.to_json() for f in findings], "clock_offset_s": offset}
        worst = "fail" if any(f.state == "fail" for f in findings) else (
            "warn" if any(f.state == "warn" for f in findings) else "ok")
        summary = ", ".join(f"{f.check}: {f.state}" for f in findings if f.state != "ok") or "all checks ok"
        outcome = Outcome.FAILED if worst == "fail" else Outcome.OK
        return RobotResult(ctx.robot.name, outcome, summary, data=data)

    return doctor_task


def _disk(free: int | None, total: int | None) -> Finding:
    if free is None or not total:
        return Finding("disk", "warn", "could not read free disk space", "on the robot: `df -h /` shows it")
    share = free / total
    detail = f"{free / 1024**3:.1f} GiB free ({share:.0%})"
    if free < DISK_MIN_BYTES:
        return Finding("disk", "warn", detail, "remove unused images: `docker image prune -a` on the robot")
    return Finding("disk", "ok", detail)


def _password(ctx: RobotContext) -> Finding:
    """Does the robot's sshd still accept the factory password? (one extra connection)"""
    from panther_ops.transport.ssh import default_password_accepted

    try:
        accepted = default_password_accepted(ctx.inventory.endpoint(ctx.robot), DEFAULT_PASSWORD)
    except Exception as exc:  # a check that cannot run is a warning, not a crash
        return Finding("default password", "warn", f"could not check: {exc}",
                       f"check by hand: ssh -o PubkeyAuthentication=no -p {ctx.robot.port or 22} "
                       f"{ctx.robot.user}@{ctx.robot.host} (the default password must not let you in)")
    if accepted:
        return Finding(
            "default password", "warn", f"sshd accepts the default password for {ctx.robot.user}",
            "change it (`passwd` on the robot) or set `PasswordAuthentication no` in /etc/ssh/sshd_config",
        )
    return Finding("default password", "ok", "the default password is not accepted")


def unreached_findings(fleet: FleetResult) -> None:
    """A robot the doctor could not check (not reached, or its checks failed before any finding)
    gets one finding saying why, with its fix: the hint of the error (the next command, filled
    in), else running the doctor again on it."""
    for r in fleet.results:
        if r.data.get("findings"):
            continue
        check = "ssh connect" if r.outcome is Outcome.UNREACHABLE else "doctor"
        fix = r.data.get("hint") or f"run the checks again on it: panther-ops doctor -r {r.robot}"
        r.data["findings"] = [Finding(check, "fail", r.message, str(fix)).to_json()]


def fleet_findings(fleet: FleetResult) -> list[dict[str, Any]]:
    """Fleet-wide checks: the spread of robot clocks."""
    offsets = {r.robot: r.data.get("clock_offset_s") for r in fleet.results if r.outcome is not Outcome.UNREACHABLE}
    known = {k: v for k, v in offsets.items() if isinstance(v, (int, float))}
    if len(known) < 2:
        return []
    lo = min(known, key=lambda k: known[k])
    hi = max(known, key=lambda k: known[k])
    spread = known[hi] - known[lo]
    if spread > CLOCK_LIMIT_S:
        return [Finding("time sync", "warn", f"robot clocks differ by {spread:.2f} s ({lo} .. {hi})",
                        "sync every robot to one NTP source before installing anything").to_json()]
    return [Finding("time sync", "ok", f"robot clocks within {spread:.2f} s of each other").to_json()]
