"""User computers for the lab: the hosts a robot shuts down with itself (shutdown tests).

A computer is built like a robot (own network, mount, UTS and PID namespaces, robot-init.sh
as PID 1, a real OpenSSH sshd with its own host key, the user `husarion`, the power-off
stand-ins over /sbin/shutdown, /sbin/poweroff, /sbin/reboot) but without docker, compose or
the robot's key pair, and:

* `behind="r01"`: it sits on a LAN that only robot r01 reaches (a bridge inside r01's
  network namespace, as `Lab.behind_jump` builds it; the host has only an `unreachable`
  route to it), as user computers sit on the robot's LAN. `behind=None`: on the lab bridge,
  reachable from the operator (this machine).
* sudo: nothing in /etc/sudoers.d unless `sudo_rule=True` (the manual's NOPASSWD rule for
  /sbin/poweroff, /sbin/reboot, /sbin/shutdown in /etc/sudoers.d/husarion).
* `password`: husarion's password (sshd accepts it; sudo asks for it).
* `admin`: husarion's sudo rights besides the shutdown rule: None (none); "group" (member of
  group `sudo`: `%sudo ALL=(ALL:ALL) ALL` with the password, as the first user of an Ubuntu
  install); "limited" (with the password, only install, visudo, cmp, cp, mv and rm as root --
  what `shutdown setup` runs -- and no shell, so that `sudo -n -l /bin/sh` stays refused after
  the setup); "nopasswd" (`NOPASSWD: ALL`, as on cloud images).
* authorized keys: the operator's key (`operator_key`) and/or the lab robots' `~/.ssh/id_rsa`
  public key (`robot_key`).
* `http`: a stand-in of the husarion-shutdown service (data/shutdown-service.py) on that
  port, as root in the computer's namespaces: checks the HMAC, then runs /sbin/poweroff.
* `poweroff_delay`: seconds the power-off stand-in waits after answering before the
  computer goes silent (all its interfaces down). The robots' stand-in waits 0.3 s.
* `webui`: the `snap` stand-in for husarion-webui (data/snap-standin.py: `snap install|list|
  get|set|services`, `husarion-webui.start|stop`, the configure hook's rules, a real HTTP
  server answering /ui on webui.port while started) in /usr/local/bin, seen through an
  overlay of /usr/local and /var (robot-init.sh); nothing of the host is written.

Computers are recorded in the lab's state.json like robots (`kind: computer`), so `down`
tears them down with everything else; they are left out of inventory.yaml, ssh_config and
known_hosts, and out of `Lab.names`/`Lab.robots`. Their host keys are in
`<labdir>/computers_known_hosts`.
"""

from __future__ import annotations

import os
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from . import files as F
from ._sys import LabError, run
from .state import RobotState, base_lock

if TYPE_CHECKING:
    from .lab import Lab

KIND = "computer"
FIRST_HOST = 100  # computers get .101, .102, ... on their subnet
SERVICE_LOG = "/var/log/shutdown-service.log"
SECRET_PATH = "/run/husarion-shutdown/password"
_STANDIN_SLEEP = 'setsid sh -c "sleep 0.3; $links_down"'
ADMIN_RULES: dict[str | None, str] = {
    None: "",
    "group": "",
    "limited": (f"# panther-ops lab: {F.USER} administers with a password, without a shell\n"
                f"{F.USER} ALL=(root) /usr/bin/install, /usr/sbin/visudo, /usr/bin/cmp, /usr/bin/cp, /usr/bin/mv, "
                "/usr/bin/rm\n"),
    "nopasswd": f"# panther-ops lab: passwordless sudo (cloud-image style)\n{F.USER} ALL=(ALL) NOPASSWD: ALL\n",
}


@dataclass(frozen=True)
class HttpService:
    """The husarion-shutdown stand-in: port and shared secret."""

    port: int = 3003
    secret: str = "husarion"


@dataclass(frozen=True)
class ComputerSpec:
    name: str
    behind: str | None = None
    sudo_rule: bool = False
    operator_key: bool = True
    robot_key: bool = False
    password: str | None = None
    admin: str | None = None
    http: HttpService | None = None
    poweroff_delay: float = 0.3
    webui: bool = False


@dataclass(frozen=True)
class Computer:
    name: str
    ip: str
    ns: str
    dir: Path
    behind: str | None
    spec: ComputerSpec


def add_computers(lab: Lab, specs: list[ComputerSpec]) -> list[Computer]:
    """Create the computers (all recorded in state.json before anything is built)."""
    st = lab.st
    names = set(st.robots)
    for s in specs:
        if s.name in names:
            raise LabError(f"{s.name}: a robot or computer of that name exists")
        if not s.name[:1].isalpha() or len(s.name) > 6:
            raise LabError(f"{s.name}: 1-6 characters starting with a letter")
        if s.behind is not None and s.behind not in st.robots:
            raise LabError(f"{s.name}: behind {s.behind!r}, which is not a robot of the lab")
        names.add(s.name)
    for jump in sorted({s.behind for s in specs if s.behind}):
        _ensure_lan(lab, jump)
    taken = {r.ip for r in st.robots.values()}  # robots of a large lab reach .101 and beyond
    states = []
    with lab._lock:
        for s in specs:
            w = st.jump_subnets[s.behind] if s.behind else st.subnet
            index = next((i for i in range(FIRST_HOST + 1, 251) if f"10.200.{w}.{i}" not in taken), None)
            if index is None:
                raise LabError(f"{s.name}: no free address left on 10.200.{w}.0/24")
            taken.add(f"10.200.{w}.{index}")
            r = RobotState(
                name=s.name, index=index, ns=f"{st.prefix}-{s.name}", ip=f"10.200.{w}.{index}",
                dir=str(lab.dir / s.name), image="2.1.1", serial="", docker=False, jump=s.behind,
                link=f"v-{s.name}" if s.behind else f"{st.prefix}-{s.name}", kind=KIND,
                password=s.password is not None,
            )
            st.robots[s.name] = r
            states.append((r, s))
        st.save()
    run(["ip", "-batch", "-"], input="".join(f"netns add {r.ns}\n" for r, _ in states))
    for r, s in states:
        _build(lab, r, s)
    write_known_hosts(lab)
    return [Computer(r.name, r.ip, r.ns, Path(r.dir), r.jump, s) for r, s in states]


def computer(lab: Lab, name: str) -> Computer:
    r = lab._rs(name)
    if r.kind != KIND:
        raise LabError(f"{name} is a robot, not a computer")
    return Computer(r.name, r.ip, r.ns, Path(r.dir), r.jump, _spec(lab, r))


def computer_names(lab: Lab) -> list[str]:
    return sorted(n for n, r in lab.st.robots.items() if r.kind == KIND)


def known_hosts_path(lab: Lab) -> Path:
    return lab.dir / "computers_known_hosts"


def write_known_hosts(lab: Lab) -> None:
    lines = []
    for name in computer_names(lab):
        r = lab._rs(name)
        pub = (Path(r.dir) / "etc/ssh/ssh_host_ed25519_key.pub").read_text().split()
        lines.append(f"{r.ip} {pub[0]} {pub[1]}\n")
    path = known_hosts_path(lab)
    path.write_text("".join(lines))
    os.chmod(path, 0o644)


def trust_on_robot(lab: Lab, robot: str, name: str) -> None:
    """Record computer `name`'s host key in `robot`'s ~husarion/.ssh/known_hosts (as a first
    `ssh` from the robot would after answering yes)."""
    from .lab import _mkdirs_owned

    r, c = lab._rs(robot), lab._rs(name)
    pub = (Path(c.dir) / "etc/ssh/ssh_host_ed25519_key.pub").read_text().split()
    home = Path(r.dir) / "home" / F.USER
    path = home / ".ssh/known_hosts"
    _mkdirs_owned(path.parent, home, 0o700)
    line = f"{c.ip} {pub[0]} {pub[1]}\n"
    text = path.read_text() if path.exists() else ""
    if line not in text:
        with open(path, "a") as f:
            f.write(line)
    os.chmod(path, 0o600)
    os.chown(path, F.UID, F.GID)


def set_poweroff_delay(lab: Lab, name: str, seconds: float) -> None:
    """Seconds between the stand-in's answer and the computer going silent (kept inode)."""
    path = Path(lab._rs(name).dir) / "poweroff-standin"
    with open(path, "r+b") as f:
        f.truncate(0)
        f.write(_standin(seconds).encode())
    (Path(lab._rs(name).dir) / "poweroff-delay").write_text(f"{seconds}\n")


def set_http_secret(lab: Lab, name: str, secret: str) -> None:
    """The service's shared secret (read on every request, like `snap set ... config.password`)."""
    (Path(lab._rs(name).dir) / SECRET_PATH.lstrip("/")).write_text(secret + "\n")


def service_log(lab: Lab, name: str) -> list[dict[str, object]]:
    import json

    path = Path(lab._rs(name).dir) / "var/log/shutdown-service.log"
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def is_silent(lab: Lab, name: str) -> bool:
    """True when the computer's eth0 is down (what the power-off stand-in leaves)."""
    out = run(["ip", "-n", lab._rs(name).ns, "-o", "link", "show", "eth0"]).stdout
    flags = out.split("<", 1)[1].split(">", 1)[0].split(",") if "<" in out else []
    return "UP" not in flags


# -----------------------------------------------------------------------------------------
def _spec(lab: Lab, r: RobotState) -> ComputerSpec:
    d = Path(r.dir)
    delay = float((d / "poweroff-delay").read_text()) if (d / "poweroff-delay").exists() else 0.3
    http = None
    port_file = d / "http-port"
    if port_file.exists():
        secret = (d / SECRET_PATH.lstrip("/")).read_text().strip()
        http = HttpService(int(port_file.read_text()), secret)
    return ComputerSpec(r.name, behind=r.jump, password=None, http=http, poweroff_delay=delay,
                        sudo_rule=(d / "etc/sudoers.d/husarion").exists())


def _ensure_lan(lab: Lab, robot: str) -> None:
    """The robot's own LAN bridge (as Lab.behind_jump creates it), once."""
    j = lab._rs(robot)
    if j.jump:
        raise LabError(f"{robot} is itself behind {j.jump}: computers go behind a directly reachable robot")
    with base_lock(lab.base), lab._lock:
        lab._jump_lan(j)


def _standin(delay: float) -> str:
    text = (F.DATA / "poweroff-standin.sh").read_text()
    if _STANDIN_SLEEP not in text:
        raise LabError("poweroff-standin.sh changed: cannot set the computer's power-off delay")
    return text.replace(_STANDIN_SLEEP, f'setsid sh -c "sleep {delay:g}; $links_down"')


def _robot_public_key(lab: Lab) -> str:
    for r in lab.st.robots.values():
        if r.kind != KIND:
            pub = Path(r.dir) / "home" / F.USER / ".ssh/id_rsa.pub"
            if pub.exists():
                return pub.read_text().strip()
    raise LabError("no robot key pair in the lab")


def _build(lab: Lab, r: RobotState, s: ComputerSpec) -> None:
    from .lab import _mkdirs_owned, _sha512_crypt, _write

    t0 = time.monotonic()
    d = Path(r.dir)
    for sub, mode in (("etc/ssh", 0o755), ("etc/sudoers.d", 0o755), ("etc/docker", 0o755), ("var/log", 0o755),
                      ("home", 0o755), ("run/sshd", 0o755), ("run/husarion-shutdown", 0o700), ("tmp", 0o1777)):
        (d / sub).mkdir(parents=True, exist_ok=True)
        os.chmod(d / sub, mode)
    passwd = F.robot_passwd(Path("/etc/passwd").read_text())
    group = F.robot_group(Path("/etc/group").read_text())
    if s.admin not in ADMIN_RULES:
        raise LabError(f"{s.name}: admin must be one of {', '.join(map(str, ADMIN_RULES))}")
    if s.admin == "group":  # the first user of an Ubuntu install
        group = "\n".join(_add_member(line, "sudo", F.USER) for line in group.splitlines()) + "\n"
    _write(d / "etc/passwd", passwd.encode(), 0o644)
    _write(d / "etc/group", group.encode(), 0o644)
    pw_hash = "*" if s.password is None else _sha512_crypt(s.password)
    _write(d / "etc/shadow", F.robot_shadow(passwd, pw_hash).encode(), 0o640)
    _write(d / "etc/hostname", f"{r.name}\n".encode(), 0o644)
    _write(d / "etc/hosts", F.etc_hosts(r.name, r.ip).encode(), 0o644)
    if s.sudo_rule:
        _write(d / "etc/sudoers.d/husarion", F.SUDOERS.encode(), 0o440)
    if ADMIN_RULES[s.admin]:
        _write(d / "etc/sudoers.d/lab-admin", ADMIN_RULES[s.admin].encode(), 0o440)
    priv, pub = F.ed25519_keypair(f"root@{r.name}")
    _write(d / "etc/ssh/ssh_host_ed25519_key", priv, 0o600)
    _write(d / "etc/ssh/ssh_host_ed25519_key.pub", (pub + "\n").encode(), 0o644)
    lab._known_key(r, set_to=pub)
    _write(d / "etc/ssh/sshd_config", F.sshd_config(r.ip, password=s.password is not None).encode(), 0o644)
    if os.path.exists("/etc/ssh/moduli"):
        shutil.copy("/etc/ssh/moduli", d / "etc/ssh/moduli")
    _write(d / "var/log/power-standin.log", b"", 0o622)
    _write(d / "poweroff-standin", _standin(s.poweroff_delay).encode(), 0o755)
    (d / "poweroff-delay").write_text(f"{s.poweroff_delay}\n")
    _write(d / "cgroups", b"", 0o644)

    home = d / "home" / F.USER
    home.mkdir(mode=0o750, exist_ok=True)
    os.chmod(home, 0o750)
    os.chown(home, F.UID, F.GID)
    keys = []
    if s.operator_key:
        keys.append((lab.dir / "id_ed25519.pub").read_text().strip())
    if s.robot_key:
        keys.append(_robot_public_key(lab))
    skel = Path("/etc/skel")
    files: dict[str, tuple[bytes, int]] = {
        f: ((skel / f).read_bytes(), 0o644) for f in (".bashrc", ".bash_logout", ".profile") if (skel / f).is_file()
    }
    if keys:
        files[".ssh/authorized_keys"] = ("".join(k + "\n" for k in keys).encode(), 0o600)
    for rel, (data, mode) in files.items():
        p = home / rel
        _mkdirs_owned(p.parent, home, 0o700 if rel.startswith(".ssh") else 0o755)
        _write(p, data, mode)
        os.chown(p, F.UID, F.GID)

    if s.webui:
        bindir = d / "overlay/usr/local/upper/bin"
        bindir.mkdir(parents=True, exist_ok=True)
        _write(bindir / "snap", (F.DATA / "snap-standin.py").read_bytes(), 0o755)
        for app in ("husarion-webui.start", "husarion-webui.stop"):
            (bindir / app).symlink_to("snap")

    lab._wire(r)
    lab._start_init(r)
    lab._start_sshd(r)
    if s.http is not None:
        _start_service(lab, r, s.http)
    lab._log(f"{r.name}: computer up in {time.monotonic() - t0:.2f} s ({r.ip}, behind {r.jump or 'the host'})")


def _add_member(line: str, group: str, user: str) -> str:
    f = line.split(":")
    if len(f) >= 4 and f[0] == group:
        members = [m for m in f[3].split(",") if m]
        f[3] = ",".join([*members, user])
    return ":".join(f)


def _start_service(lab: Lab, r: RobotState, http: HttpService) -> None:
    d = Path(r.dir)
    secret = d / SECRET_PATH.lstrip("/")
    secret.write_text(http.secret + "\n")
    os.chmod(secret, 0o600)
    (d / "http-port").write_text(f"{http.port}\n")
    shutil.copy(F.DATA / "shutdown-service.py", d / "shutdown-service.py")
    python = "/usr/bin/python3" if os.access("/usr/bin/python3", os.X_OK) else shutil.which("python3")
    if python is None:
        raise LabError("python3 not found for the husarion-shutdown stand-in")
    log = d / "var/log/shutdown-service.log"
    before = log.read_text().count('"listening"') if log.exists() else 0
    argv = [*lab._nsenter(r), python, str(d / "shutdown-service.py"), r.ip, str(http.port), SECRET_PATH]
    lab._start_until(r, argv, d / "shutdown-service.out", ("http-nsenter", "shutdown-http"), "shutdown service",
                     lambda: log.exists() and log.read_text().count('"listening"') > before)
