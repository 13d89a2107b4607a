"""`shutdown setup`: the manual's procedure for a user computer, end to end, through the robot.

SSH era (panther_ros 2.0 - husarion_ugv 2.2.0), for user U on the computer at IP:

1. ``robot-key``: the Built-in Computer has the key pair the driver container mounts
   (``~/.ssh/id_rsa``); created with ssh-keygen when missing.
2. ``reach``: IP answers ping from the robot.
3. ``host-key``: the computer's host key, shown by fingerprint and recorded in the robot's
   ``~/.ssh/known_hosts`` only after confirmation (``--yes``); a changed key is refused.
4. ``authorized-key``: the robot's public key in U's ``~/.ssh/authorized_keys``, once. The
   login for that uses the robot's key (already set up), the operator's key, or U's password.
5. ``login``: the robot's key logs in as U (batch: no password), as the manager will.
6. ``sudoers``: ``/etc/sudoers.d/panther-shutdown`` = ``U ALL=(root) NOPASSWD: /sbin/poweroff,
   /sbin/reboot, /sbin/shutdown``, written to a temp file, checked with ``visudo -cf``, mode
   0440 root:root, then moved into place and the whole configuration checked with
   ``visudo -c`` (restored when that fails). Never an append to /etc/sudoers. Needs root on
   the computer: U's sudo with U's password (``--ask-password``) or a passwordless sudo.
   Skipped when ``sudo -n -l`` already allows the three commands.
7. ``hosts-file``: the host added to the robot's hosts file through the pipeline.

HTTP era (2.2.1+): ``reach``, ``service`` (husarion-shutdown answers; how to install it
when not), ``secret`` (accepted, without shutting down), then ``hosts-file``.

Re-running changes nothing.
"""

from __future__ import annotations

import shlex
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S, Mode, add_host, new_entry
from panther_ops.core.shutdown.check import install_hint, probe_secret, sudo_without_password
from panther_ops.core.shutdown.links import http_get, ping, robot_ip_towards
from panther_ops.core.shutdown.read import plan_hosts_edit
from panther_ops.core.stack import Stack
from panther_ops.errors import OpsError
from panther_ops.manager.shutdown_executor import ShutdownHost
from panther_ops.results import Diff, Outcome, RobotResult
from panther_ops.secret import Secret
from panther_ops.transport.base import Command
from panther_ops.transport.hostkeys import fingerprint, known_hosts_name
from panther_ops.transport.lan import Key, LanSession, RobotLink, TargetError, exec_on

SUDOERS_PATH = "/etc/sudoers.d/panther-shutdown"
CONTAINER_KEY = "/root/.ssh/id_rsa"
"""Where the compose files of every version mount the robot's ~/.ssh/id_rsa (panther-stack.md §1.8)."""
POWER_COMMANDS = ("/sbin/poweroff", "/sbin/reboot", "/sbin/shutdown")

ENSURE_KEY = (
    'k="$HOME/.ssh/id_rsa"; '
    'if [ -d "$k" ]; then echo "$k is a directory (docker creates one when the file is missing at start)" >&2; '
    'exit 3; fi; '
    'if [ -f "$k" ]; then echo present; exit 0; fi; '
    'umask 077; mkdir -p "$HOME/.ssh" && ssh-keygen -q -t rsa -b 4096 -N "" -C "$1" -f "$k" >/dev/null && echo created'
)

AUTHORIZE = (
    'set -eu; key=$1; blob=$(printf "%s\\n" "$key" | awk "{print \\$2}"); umask 077; '
    'mkdir -p "$HOME/.ssh"; chmod 700 "$HOME/.ssh"; f="$HOME/.ssh/authorized_keys"; touch "$f"; chmod 600 "$f"; '
    'if awk -v b="$blob" "{for(i=1;i<=NF;i++) if(\\$i==b) f=1} END{exit !f}" "$f"; then echo present; exit 0; fi; '
    'if [ -s "$f" ] && [ -n "$(tail -c 1 "$f")" ]; then printf "\\n" >> "$f"; fi; '
    'printf "%s\\n" "$key" >> "$f"; echo added'
)

INSTALL_SUDOERS = r"""set -u
user=$1 dst=$2 content=$3 how=$4
d=$(mktemp -d) || exit 1
trap 'rm -rf "$d"' EXIT
cand="$d/panther-shutdown"
new="$dst.panther-ops-new"
old="$dst.panther-ops-old"
printf '%s' "$content" > "$cand" || exit 1
case "$how" in
    root) S= ;;
    password) sudo -S -p '' -v 2>"$d/err" || { cat "$d/err" >&2; exit 5; }; S="sudo -n" ;;
    *) S="sudo -n" ;;
esac
$S install -o root -g root -m 0440 "$cand" "$new" || exit 6
if ! out=$($S visudo -cf "$new" 2>&1); then
    $S rm -f "$new"
    printf 'refused: the candidate fails visudo -cf, nothing installed: %s\n' "$out" >&2
    exit 3
fi
had_old=0
$S cmp -s "$new" "$dst"
case $? in
    0) $S rm -f "$new"; echo unchanged; exit 0 ;;
    1) $S cp -p "$dst" "$old" || exit 6; had_old=1 ;;
esac
$S mv -f "$new" "$dst" || exit 6
if ! out=$($S visudo -c 2>&1); then
    if [ "$had_old" = 1 ]; then $S mv -f "$old" "$dst"; else $S rm -f "$dst"; fi
    printf 'refused: sudo fails visudo -c with the drop-in, previous state restored: %s\n' "$out" >&2
    exit 4
fi
[ "$had_old" = 0 ] || $S rm -f "$old"
echo installed
"""


def sudoers_rule(user: str) -> str:
    """The drop-in's content: exactly the manual's three commands, without a password."""
    return (f"# panther-ops shutdown setup: {user} may power this computer off without a password\n"
            f"{user} ALL=(root) NOPASSWD: {', '.join(POWER_COMMANDS)}\n")


@dataclass
class Step:
    name: str
    outcome: Outcome
    message: str

    def to_json(self) -> dict[str, str]:
        return {"step": self.name, "outcome": self.outcome.value, "message": self.message}


@dataclass
class SetupRequest:
    ip: str
    user: str | None = None
    port: int | None = None
    timeout: float | None = None
    password: Secret | None = None
    secret: Secret | None = None
    operator_keys: tuple[str, ...] = ()
    use_agent: bool = True
    confirm_host_key: Callable[[str, str], bool] = lambda _addr, _fp: False
    """(address, "TYPE SHA256:...") -> record it? (the CLI: --yes, or asks)"""
    settle: float = 5.0
    restart: bool = True
    power_budget: float = POWER_BUDGET_S
    command: str = "shutdown setup"


@dataclass
class SetupReport:
    robot: str
    steps: list[Step] = field(default_factory=list)
    diffs: list[Diff] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    hint: str | None = None

    def add(self, name: str, outcome: Outcome, message: str) -> Step:
        step = Step(name, outcome, message)
        self.steps.append(step)
        return step

    @property
    def failed(self) -> bool:
        return any(s.outcome in (Outcome.FAILED, Outcome.ROLLED_BACK) for s in self.steps)

    def result(self) -> RobotResult:
        changed = [s.name for s in self.steps if s.outcome is Outcome.CHANGED]
        if self.failed:
            bad = next(s for s in self.steps if s.outcome in (Outcome.FAILED, Outcome.ROLLED_BACK))
            outcome, message = Outcome.FAILED, f"{bad.name}: {bad.message}"
        elif changed:
            outcome, message = Outcome.CHANGED, "set up: " + ", ".join(changed) + " changed"
        else:
            outcome, message = Outcome.OK, "already set up: nothing changed"
        res = RobotResult(self.robot, outcome, message, diffs=list(self.diffs), warnings=list(self.warnings),
                          data={"steps": [s.to_json() for s in self.steps]})
        if self.hint:
            res.data["hint"] = self.hint
        return res


class _Stop(Exception):
    """A step failed: the report says which."""


def install_sudoers(client: LanSession, user: str, *, login_user: str, password: Secret | None,
                    content: str | None = None) -> tuple[bool, str]:
    """Install the drop-in on the computer: (changed, message). Raises TargetError.

    Root comes from being root, a passwordless sudo, or sudo with `password` (validated once
    with ``sudo -S -v``, then the cached credentials). Only install, visudo, cmp, cp, mv and
    rm run as root; no shell. `content` replaces the generated rule (tests of a candidate
    visudo refuses)."""
    if login_user == "root":
        how = "root"
    elif exec_on(client, shlex.join(["sudo", "-n", "true"]), timeout=15)[0] == 0:
        how = "nopasswd"
    elif password is not None:
        how = "password"
    else:
        raise TargetError(f"installing {SUDOERS_PATH} needs root on the computer and {login_user}'s sudo asks "
                          "for a password", hint="add --ask-password (asked once, never logged), or install "
                          f"the rule by hand: {sudoers_rule(user).splitlines()[1]}")
    argv = ["sh", "-c", INSTALL_SUDOERS, "sh", user, SUDOERS_PATH, content or sudoers_rule(user), how]
    stdin = (password.reveal() + "\n").encode() if how == "password" and password is not None else None
    status, out, err = exec_on(client, shlex.join(argv), timeout=60, stdin=stdin)
    text = err.strip() or out.strip()
    if password is not None:
        text = text.replace(password.reveal(), "****")
    if status == 5:
        said = text.splitlines()[-1] if text else "no detail"
        raise TargetError(f"sudo on the computer refused {login_user}'s password ({said})")
    if status != 0:
        raise TargetError(text or f"installing {SUDOERS_PATH} failed (exit {status})")
    last = out.strip().splitlines()[-1] if out.strip() else ""
    return last == "installed", last


def run_setup(ctx: RobotContext, req: SetupRequest) -> RobotResult:
    """The procedure on one robot (see the module docstring); every failure is a step."""
    from panther_ops.core.robot.read import read_config

    report = SetupReport(ctx.robot.name)
    try:
        link = RobotLink(ctx.transport, ctx.robot.name)
        cfg = read_config(ctx)
        stack = cfg.stack
        if stack.shutdown_over_http:
            entry = _setup_http(link, req, report, stack)
        else:
            mounted = cfg.host_path_of(CONTAINER_KEY)
            if mounted != f"{cfg.home}/.ssh/id_rsa":
                report.warnings.append(f"the driver container does not mount ~/.ssh/id_rsa at {CONTAINER_KEY} "
                                       f"({mounted or 'not mounted'}): its manager cannot log in with the robot's key")
            entry = _setup_ssh(link, req, report, stack)
        _hosts_file(ctx, req, report, entry)
    except _Stop:
        pass
    except OpsError as exc:
        report.add("error", Outcome.FAILED, exc.message)
        report.hint = report.hint or exc.hint
    return report.result()


def _fail(report: SetupReport, name: str, message: str, hint: str | None = None) -> _Stop:
    report.add(name, Outcome.FAILED, message)
    report.hint = hint
    return _Stop(message)


def _reach(link: RobotLink, req: SetupRequest, report: SetupReport) -> None:
    if not ping(link, req.ip):
        raise _fail(report, "reach", f"{req.ip} does not answer ping from {link.name}",
                    "is the computer on, and on the robot's LAN?")
    report.add("reach", Outcome.OK, f"{req.ip} answers ping from {link.name}")


def _setup_http(link: RobotLink, req: SetupRequest, report: SetupReport, stack: Stack) -> dict[str, Any]:
    port = req.port or 3003
    _reach(link, req, report)
    status, _, error = http_get(link, req.ip, port, "/shutdown", 10)
    if status is None:
        raise _fail(report, "service", f"husarion-shutdown does not answer on {req.ip}:{port} ({error})",
                    install_hint(req.ip, port, robot_ip_towards(link, req.ip)))
    if status == 200:
        raise _fail(report, "service", f"{req.ip}:{port} accepted an UNSIGNED shutdown request: not husarion-shutdown "
                    "or it does not check signatures")
    report.add("service", Outcome.OK, f"husarion-shutdown answers on {req.ip}:{port} (HTTP {status} to an "
               "unsigned request)")
    secret = req.secret.reveal() if req.secret else "husarion"
    probe = ShutdownHost(req.ip, port=port, timeout=req.timeout or 5.0, secret=secret)
    ok, said = probe_secret(link, probe)
    if not ok:
        raise _fail(report, "secret", said, "use the same secret on both sides: --secret-env/--secret-file here and "
                    "`sudo snap set husarion-shutdown config.password=...` on the computer")
    report.add("secret", Outcome.OK, said)
    if req.secret is None:
        report.warnings.append("the default secret 'husarion' is in use: set your own on the computer and pass it "
                               "with --secret-env/--secret-file")
    return new_entry(req.ip, port=port, timeout=req.timeout, secret=req.secret.reveal() if req.secret else None)


def _setup_ssh(link: RobotLink, req: SetupRequest, report: SetupReport, stack: Stack) -> dict[str, Any]:
    user = req.user or "husarion"
    port = req.port or 22
    res = link.run(Command.sh(ENSURE_KEY, f"husarion@{link.name} (panther-ops shutdown)"), timeout=120)
    if not res.ok:
        raise _fail(report, "robot-key", res.stderr.strip() or "cannot create ~/.ssh/id_rsa on the robot",
                    "remove the directory ~/.ssh/id_rsa on the robot, then run setup again (the driver container "
                    "must be recreated to see the key)")
    created = res.stdout.strip().endswith("created")
    key = link.key()
    pub = f"{key.get_name()} {key.get_base64()} husarion@{link.name}"
    report.add("robot-key", Outcome.CHANGED if created else Outcome.OK,
               f"~/.ssh/id_rsa {'created' if created else 'present'} ({key.get_name()} {fingerprint(key)})")
    if created:
        report.warnings.append("a new ~/.ssh/id_rsa was created: the driver container sees it after it is recreated")
    _reach(link, req, report)

    # host key: shown, confirmed, recorded in the robot's known_hosts
    address = known_hosts_name(req.ip, port)
    offered = link.fetch_host_key(req.ip, port)
    fp = f"{offered.get_name()} {fingerprint(offered)}"
    known: dict[str, Any] = dict(link.known_hosts().lookup(address) or {})
    same = [k for k in known.values() if k.get_name() == offered.get_name()]
    if any(k.asbytes() == offered.asbytes() for k in same):
        report.add("host-key", Outcome.OK, f"{address} {fp} already in the robot's known_hosts")
    elif same:
        raise _fail(report, "host-key", f"HOST KEY CHANGED: {address} offers {fp}, the robot's known_hosts has "
                    f"{', '.join(fingerprint(k) for k in same)}: refused",
                    "check the key on the computer (ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub); if it is "
                    f"right, remove the old one on the robot (ssh-keygen -R {req.ip}) and run setup again")
    elif not req.confirm_host_key(address, fp):
        raise _fail(report, "host-key", f"{address} offers {fp}: not trusted, nothing recorded",
                    "compare the fingerprint with the computer's (ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub), "
                    "then run again with --yes")
    else:
        link.record_host_key(req.ip, port, offered)
        report.add("host-key", Outcome.CHANGED, f"{address} {fp} recorded in the robot's ~/.ssh/known_hosts")

    # log in: the robot's key (set up already), else the operator's key, else U's password
    client, how = _login(link, req, user, port, key)
    try:
        status, out, err = exec_on(client, shlex.join(["sh", "-c", AUTHORIZE, "sh", pub]), timeout=30)
        if status != 0:
            raise _fail(report, "authorized-key", f"cannot update ~{user}/.ssh/authorized_keys: {err.strip()}")
        added = out.strip().endswith("added")
        report.add("authorized-key", Outcome.CHANGED if added else Outcome.OK,
                   f"the robot's key {'added to' if added else 'already in'} {user}@{req.ip}:~/.ssh/authorized_keys"
                   f" (logged in with {how})")
    finally:
        client.close()

    robot_client = _login_robot_key(link, report, user, req.ip, port, key)
    try:
        _sudoers(robot_client, req, report, user)
    finally:
        robot_client.close()
    return new_entry(req.ip, username=user, port=port, timeout=req.timeout)


def _missing(client: LanSession) -> list[str]:
    return [c for c in POWER_COMMANDS if not sudo_without_password(client, [c])[0]]


def _sudoers(client: LanSession, req: SetupRequest, report: SetupReport, user: str) -> None:
    if user == "root":
        report.add("sudoers", Outcome.OK, "root needs no sudo rule")
        return
    if not _missing(client):
        report.add("sudoers", Outcome.OK, f"{user} may already run {', '.join(POWER_COMMANDS)} without a password")
        return
    try:
        changed, said = install_sudoers(client, user, login_user=user, password=req.password)
    except TargetError as exc:
        raise _fail(report, "sudoers", exc.message, exc.hint) from None
    still = _missing(client)
    if still:
        raise _fail(report, "sudoers", f"{SUDOERS_PATH} {said} but sudo still asks a password for {', '.join(still)}",
                    "an earlier sudoers entry for this user may override it (the last matching entry wins)")
    report.add("sudoers", Outcome.CHANGED if changed else Outcome.OK,
               f"{SUDOERS_PATH} {said} (visudo -cf ok, 0440 root:root): {user} may run {', '.join(POWER_COMMANDS)} "
               "without a password")


def _login(link: RobotLink, req: SetupRequest, user: str, port: int,
           key: Key) -> tuple[LanSession, str]:
    tried = []
    for how, kwargs in (("the robot's key", {"pkey": key}),
                        ("the operator's key", {"key_files": req.operator_keys, "agent": req.use_agent}),
                        (f"{user}'s password", {"password": req.password})):
        if how == "the operator's key" and not (req.operator_keys or req.use_agent):
            continue
        if "password" in kwargs and req.password is None:
            continue
        try:
            return link.open_ssh(req.ip, port, user, timeout=15, **kwargs), how
        except TargetError as exc:
            if "refused" not in exc.message and "Authentication" not in exc.message:
                raise
            tried.append(how)
    raise TargetError(f"cannot log in as {user}@{req.ip} with {', '.join(tried) or 'any key'}",
                      hint="add --ask-password to log in with the user's password once")


def _login_robot_key(link: RobotLink, report: SetupReport, user: str, ip: str, port: int,
                     key: Key) -> LanSession:
    try:
        client = link.open_ssh(ip, port, user, pkey=key, timeout=15)
    except TargetError as exc:
        raise _fail(report, "login", f"the robot's key does not log in as {user}@{ip}: {exc.message}") from None
    report.add("login", Outcome.OK, f"the robot's key logs in as {user}@{ip} without a password")
    return client


def _hosts_file(ctx: RobotContext, req: SetupRequest, report: SetupReport, entry: dict[str, Any]) -> None:
    def editor(text: str, mode: Mode) -> Any:
        return add_host(text, entry)

    plan = plan_hosts_edit(ctx, editor, power_budget=req.power_budget)
    report.warnings.extend(plan.warnings)
    if not plan.edits:
        report.add("hosts-file", Outcome.OK, plan.noop or "already listed")
        return
    result = apply_plan(ctx, plan, ApplyOptions(restart=req.restart, settle_s=req.settle, command=req.command))
    report.diffs.extend(result.diffs)
    report.warnings.extend(w for w in result.warnings if w not in report.warnings)
    report.add("hosts-file", result.outcome, result.message)
    if "backup" in result.data:
        report.steps[-1].message += f" (backup {result.data['backup']})"
