"""The simulated robot lab: real Linux hosts (netns + mount/UTS/PID namespaces, OpenSSH sshd,
optionally a dockerd running the robot's compose stack) on one machine.

See docs/lab.md. Facts this follows: /work/shared/reference/fleet-lab-notes.md.
"""

from __future__ import annotations

import contextlib
import glob
import json
import os
import posixpath
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from . import files as F
from ._sys import (
    LabError,
    alive,
    children,
    clean_env,
    run,
    signal_recorded,
    start_time,
    terminate,
    wait_child,
    wait_for,
    wait_gone,
)
from .image import IMPORT_CHANGES, VERSION_LABEL, build_rootfs, find_static_busybox, import_changes, with_version
from .state import DEFAULT_BASE, LabState, Proc, RobotState, all_states, base_lock
from .teardown import (
    CGROUP_ROOT,
    PREFIX_RE,
    host_links,
    lab_processes,
    netns_list,
    rmtree_lab,
    teardown,
)

SUBNET_BASE = "10.200"
JUMP_BRIDGE = "jbr0"
ROBOTS_PER_24 = 240
"""Robots of one /24 of the lab LAN: .11 to .250 (the host's side is .1)."""
MAX_ROBOTS = 4 * ROBOTS_PER_24
"""A lab's LAN is at most a /22 (4 consecutive /24s)."""
RELAY_ROBOTS = 100
"""Robots per delay relay process (one event loop carries about this many at 150 ms)."""
BUILD_WORKERS = 16
BUILD_BATCH = 32
"""Robots built in parallel (threads), and per save of the state file."""
SSHD = "/usr/sbin/sshd"
INNER_SSHD = ("127.0.0.1", 2222)
"""Where a robot's sshd listens inside its namespace when a delay relay is in front of it."""
RELAY = Path(__file__).with_name("relay.py")

#: robot path -> path relative to the robot directory (the bind mounts of robot-init.sh)
_BIND_DIRS = {
    "/home": "home",
    "/run": "run",
    "/var/run": "run",
    "/var/log": "var/log",
    "/tmp": "tmp",
    "/etc/ssh": "etc/ssh",
    "/etc/sudoers.d": "etc/sudoers.d",
    "/etc/docker": "etc/docker",
}
_BIND_FILES = {f"/etc/{f}": f"etc/{f}" for f in ("passwd", "group", "shadow", "hostname", "hosts")}

REQUIRED_BINARIES = ("ip", "unshare", "nsenter", "setpriv", SSHD, "ssh", "mount", "bash")
DOCKER_BINARIES = ("dockerd", "containerd", "runc")


def missing_requirements(docker: bool = False) -> list[str]:
    """Why the lab cannot run here (empty list: it can)."""
    why = []
    if os.geteuid() != 0:
        why.append("the lab needs root (network, mount and PID namespaces)")
    for b in REQUIRED_BINARIES + (DOCKER_BINARIES if docker else ()):
        if not (os.path.isabs(b) and os.access(b, os.X_OK)) and shutil.which(b, path=_path()) is None:
            why.append(f"missing binary {b}")
    if docker and compose_plugin() is None:
        why.append("missing docker compose v2 CLI plugin (scripts/install-test-deps.sh)")
    if docker and docker_cli() is None:
        why.append("missing binary docker")
    if docker:
        try:
            find_static_busybox()
        except LabError as exc:
            why.append(str(exc))
    return why


def _path() -> str:
    return os.environ.get("PATH", "") + ":" + clean_env()["PATH"]


def docker_cli() -> str | None:
    """The docker CLI talking to the robots' engines (Debian's, matching engine 20.10)."""
    if os.access("/usr/bin/docker", os.X_OK):
        return "/usr/bin/docker"
    return shutil.which("docker", path=_path())


def compose_plugin() -> str | None:
    dirs = [
        os.path.expanduser("~/.docker/cli-plugins"),
        "/usr/local/lib/docker/cli-plugins",
        "/usr/local/libexec/docker/cli-plugins",
        "/usr/lib/docker/cli-plugins",
        "/usr/libexec/docker/cli-plugins",
    ]
    for d in dirs:
        p = os.path.join(d, "docker-compose")
        if os.access(p, os.X_OK):
            return p
    return None


def can_raise_rlimits() -> bool:
    """Can root raise RLIMIT_RTPRIO to 99 and RLIMIT_MEMLOCK to unlimited (compose ulimits)?

    Not on machines whose root lacks CAP_SYS_RESOURCE (as on the lab's reference machine).
    """
    cp = run(["prlimit", "--rtprio=99:99", "--memlock=unlimited:unlimited", "true"], check=False)
    return cp.returncode == 0


def faketime_library() -> str | None:
    found = sorted(glob.glob("/usr/lib/*/faketime/libfaketime.so.1"))
    return found[0] if found else None


def _in_lab_dir(name: str) -> property:
    """A `Lab` property: the path of the lab directory's file ``name``."""
    return property(lambda lab: lab.dir / name, doc=f"The lab directory's {name}.")


def robot_name(i: int, n: int) -> str:
    """Name of robot `i` of a lab of `n`: r01..r99, or r001..r960 in a lab of 100 or more."""
    return f"r{i:02d}" if n < 100 else f"r{i:03d}"


def lan_span(n: int) -> int:
    """/24s a lab of `n` robots needs on its LAN (1, 2 or 4: a /24, /23 or /22)."""
    need = -(-n // ROBOTS_PER_24)
    return 1 if need <= 1 else 2 if need == 2 else 4


def lan_prefixlen(span: int) -> int:
    return {1: 24, 2: 23, 4: 22}[span]


def robot_ip(w: int, i: int) -> str:
    """Address of robot `i` on the LAN starting at 10.200.w.0: 10.200.w.(10+i) for the first 240
    robots, then the next /24 (.11 to .250 again)."""
    block, host = divmod(i - 1, ROBOTS_PER_24)
    return f"{SUBNET_BASE}.{w + block}.{11 + host}"


@dataclass(frozen=True)
class Robot:
    """Read-only view of one robot (names and addresses as the operator sees them)."""

    name: str
    index: int
    ip: str
    port: int
    ns: str
    dir: Path
    stack: F.StackImage
    docker: bool
    jump: str | None
    serial: str

    @property
    def host(self) -> str:
        return self.ip

    @property
    def driver_container(self) -> str:
        return "husarion_ugv_ros" if self.stack.ugv else "panther_ros"

    @property
    def image(self) -> str:
        """Driver image of the robot's compose template (e.g. husarion/panther:humble-2.1.1-…)."""
        return self.stack.images()[0]


class Lab:
    """A lab of `n` simulated robots named r01..rNN.

    Args:
        n: number of robots (1..99).
        docker: run a dockerd in each robot and bring its compose stack up.
        images: stack versions cycled over the robots ("2.0", "2.1.1", "2.2").
        prefix: names of namespaces/bridge/lab dir; default: the first free `plN`.
        jumps: robot -> jump robot, for robots reachable only through another robot.
        base: directory holding the labs (default /root/.cache/panther-ops-lab).
        ephemeral: the lab belongs to this process (pytest); a later auto-prefixed `up`
            may reclaim it once this process is gone. CLI labs are persistent.
        rtt_ms: > 0: a realistic network: each robot's sshd moves to an inner address of its
            namespace and a delay relay (tests/lab/relay.py) takes its public address:22,
            delaying each direction by rtt_ms / 2 (same address and host key for the client).
        jitter_ms: with rtt_ms, each chunk's one-way delay varies by up to ± this much.
        rate: a `tc tbf` rate limit on each robot's eth0 (e.g. "20mbit"); None: none.
        relay_trace: each relay writes `<robot dir>/relay.trace` (see tests/lab/relay.py).
    """

    def __init__(
        self,
        n: int = 5,
        *,
        docker: bool = False,
        images: Sequence[str] = ("2.1.1",),
        prefix: str | None = None,
        jumps: Mapping[str, str] | None = None,
        base: Path | str = DEFAULT_BASE,
        ephemeral: bool = False,
        log: Callable[[str], None] | None = None,
        rtt_ms: float = 0.0,
        jitter_ms: float = 0.0,
        rate: str | None = None,
        relay_trace: bool = False,
        first_subnet: int = 1,
    ) -> None:
        if not 1 <= n <= MAX_ROBOTS:
            raise ValueError(f"n must be within 1..{MAX_ROBOTS}")
        if prefix is not None and not PREFIX_RE.match(prefix):
            raise ValueError("prefix: 1-8 characters, a-z then a-z0-9")
        if rtt_ms < 0 or jitter_ms < 0 or (jitter_ms and jitter_ms > rtt_ms / 2):
            raise ValueError("rtt_ms and jitter_ms: >= 0, and the jitter at most half the round trip")
        if rate is not None and not re.fullmatch(r"[0-9]+(\.[0-9]+)?[kmg]?(bit|bps)", rate):
            raise ValueError(f"rate {rate!r}: a tc rate such as 20mbit or 512kbit")
        self.n = n
        self.rtt_ms, self.jitter_ms, self.rate = float(rtt_ms), float(jitter_ms), rate
        self.relay_trace = relay_trace
        self.docker_enabled = docker
        self.images = [F.stack(i).key for i in images] or ["2.1.1"]
        self.prefix = prefix
        self.jumps = dict(jumps or {})
        self.first_subnet = first_subnet  # subnets from 10.200.<first_subnet>.0 up (tests/ux/doclab.py: 100)
        self.base = Path(base)
        self.ephemeral = ephemeral
        self._log_cb = log
        self.state: LabState | None = None
        self.timings: dict[str, float] = {}
        self._lock = threading.RLock()
        self._popen: dict[int, subprocess.Popen] = {}  # type: ignore[type-arg]
        self._batching = False
        names = [self._name(i) for i in range(1, n + 1)]
        for hidden, jump in self.jumps.items():
            if hidden not in names or jump not in names or hidden == jump:
                raise ValueError(f"jump {hidden} -> {jump}: both must be robots of the lab")
            if names.index(hidden) >= ROBOTS_PER_24:  # a jump robot's LAN is one /24
                raise ValueError(f"jump {hidden} -> {jump}: only the first {ROBOTS_PER_24} robots can be hidden")
            if jump in self.jumps:
                raise ValueError(f"jump robot {jump} cannot itself be behind a jump host")

    def _name(self, i: int) -> str:
        return robot_name(i, self.n)

    # ===================================================================================
    # attach / context manager
    # ===================================================================================
    @classmethod
    def attach(cls, prefix: str, base: Path | str = DEFAULT_BASE) -> Lab:
        """The lab `prefix` brought up earlier (by another process, e.g. the CLI)."""
        path = Path(base) / prefix / "state.json"
        if not path.is_file():
            raise LabError(f"no lab {prefix!r} under {base}")
        st = LabState.load(path)
        lab = cls(len(st.robots) or 1, docker=st.docker, prefix=st.prefix, base=base,
                  rtt_ms=st.rtt_ms, jitter_ms=st.jitter_ms, rate=st.rate)
        lab.images = sorted({r.image for r in st.robots.values()})
        lab.jumps = {r.name: r.jump for r in st.robots.values() if r.jump}
        lab.state = st
        return lab

    def __enter__(self) -> Lab:
        if self.state is None:
            self.up()
        return self

    def __exit__(self, *exc: object) -> None:
        self.down()

    # ===================================================================================
    # paths and robots
    # ===================================================================================
    @property
    def st(self) -> LabState:
        if self.state is None:
            raise LabError("the lab is not up")
        return self.state

    @property
    def dir(self) -> Path:
        return Path(self.st.dir)

    inventory_path = _in_lab_dir("inventory.yaml")
    ssh_config_path = _in_lab_dir("ssh_config")
    known_hosts_path = _in_lab_dir("known_hosts")
    identity_file = _in_lab_dir("id_ed25519")
    identity_path = identity_file
    """Alias of identity_file."""

    @property
    def jump_robot(self) -> Robot | None:
        """The first robot reachable only through a jump host (None if there is none)."""
        hidden = [r for r in self.robots if r.jump]
        return hidden[0] if hidden else None

    @property
    def names(self) -> list[str]:
        return sorted(n for n, r in self.st.robots.items() if r.kind == "robot")

    @property
    def robots(self) -> list[Robot]:
        return [self.robot(n) for n in self.names]

    def robot(self, name: str) -> Robot:
        r = self._rs(name)
        return Robot(
            name=r.name,
            index=r.index,
            ip=r.ip,
            port=22,
            ns=r.ns,
            dir=Path(r.dir),
            stack=F.stack(r.image),
            docker=r.docker,
            jump=r.jump,
            serial=r.serial,
        )

    def _rs(self, name: str) -> RobotState:
        try:
            return self.st.robots[name]
        except KeyError:
            raise LabError(f"no robot {name!r} in lab {self.st.prefix}") from None

    def _log(self, msg: str) -> None:
        line = f"{time.strftime('%H:%M:%S')} {msg}"
        if self._log_cb:
            self._log_cb(line)
        if self.state is not None:
            with contextlib.suppress(OSError), open(self.dir / "lab.log", "a") as f:
                f.write(line + "\n")

    def _save(self) -> None:
        with self._lock:
            self.st.save()

    def _record(self, r: RobotState, role: str, pid: int) -> Proc:
        """Record a started process in the state file (during `up`: at the end of its batch,
        as teardown also finds it in the robot's network namespace)."""
        p = Proc(role, pid, start_time(pid))
        with self._lock:
            r.drop(role)
            r.procs.append(p)
            if not self._batching:
                self.st.save()
        return p

    def _init_pid(self, r: RobotState) -> int:
        p = r.proc("init")
        if p is None or not alive(p.pid, p.start):
            raise LabError(f"robot {r.name} is not running (no init process)")
        return p.pid

    # ===================================================================================
    # up
    # ===================================================================================
    def up(self) -> Lab:
        """Create every robot (tearing down leftovers of a crashed run of the same prefix)."""
        why = missing_requirements(self.docker_enabled)
        if why:
            raise LabError("; ".join(why))
        t0 = time.monotonic()
        self._plan()
        try:
            self._create()
        except BaseException:
            self._log("up failed: tearing down")
            with contextlib.suppress(Exception):
                self.down()
            raise
        self.timings["up"] = time.monotonic() - t0
        self._log(f"up: {self.n} robots in {self.timings['up']:.2f} s")
        return self

    def _plan(self) -> None:
        """Choose prefix and subnets and write the state file, before creating anything."""
        with base_lock(self.base):
            prefix = self.prefix or self._free_prefix()
            labdir = self.base / prefix
            old = labdir / "state.json"
            if old.is_file():
                teardown(LabState.load(old), log=self._log_cb)
            elif labdir.exists():
                rmtree_lab(labdir, self.base)
            used = _used_subnets(self.base)
            span = lan_span(self.n)
            subnet = _free_subnet(used, span, self.first_subnet)
            used.update(range(subnet, subnet + span))
            st = LabState(
                prefix=prefix,
                dir=str(labdir),
                subnet=subnet,
                bridge=f"{prefix}-br",
                cgroup_parent=f"{CGROUP_ROOT}/{prefix}",
                docker=self.docker_enabled,
                created=time.time(),
                rtt_ms=self.rtt_ms,
                jitter_ms=self.jitter_ms,
                rate=self.rate,
                span=span,
            )
            if self.ephemeral:
                st.owner = Proc("owner", os.getpid(), start_time(os.getpid()))
            for jump in sorted(set(self.jumps.values())):
                w = _free_subnet(used, 1, self.first_subnet)
                used.add(w)
                st.jump_subnets[jump] = w
                st.routes.append(f"unreachable {SUBNET_BASE}.{w}.0/24")
            for i in range(1, self.n + 1):
                name = self._name(i)
                jump = self.jumps.get(name)
                w = st.jump_subnets[jump] if jump else subnet
                st.robots[name] = RobotState(
                    name=name,
                    index=i,
                    ns=f"{prefix}-{name}",
                    ip=robot_ip(w, i),
                    dir=str(labdir / name),
                    image=self.images[(i - 1) % len(self.images)],
                    serial=f"{1000 + i:04d}",
                    docker=self.docker_enabled,
                    jump=jump,
                    link=f"v-{name}" if jump else f"{prefix}-{name}",
                )
            self.state = st
            self.prefix = prefix
            st.save()  # claims prefix and subnets for other lab processes

    def _free_prefix(self) -> str:
        netns = set(netns_list())
        links = set(host_links())
        for i in range(1, 1000):
            p = f"pl{i}"
            labdir = self.base / p
            if labdir.exists():
                st = None
                with contextlib.suppress(Exception):
                    st = LabState.load(labdir / "state.json")
                if st is None or st.owner is None or alive(st.owner.pid, st.owner.start):
                    continue  # persistent (CLI) lab, or one whose process still runs
                teardown(st, log=self._log_cb)  # ephemeral lab whose process is gone
                netns, links = set(netns_list()), set(host_links())
            if not any(n.startswith(p + "-") for n in netns) and f"{p}-br" not in links:
                return p
        raise LabError("no free lab prefix")

    def _create(self) -> None:
        st = self.st
        d = self.dir
        d.mkdir(parents=True, exist_ok=True, mode=0o700)
        (d / "bin").mkdir(exist_ok=True)
        if os.path.exists("/etc/ssh/moduli"):
            shutil.copy("/etc/ssh/moduli", d / "etc-ssh-moduli")
        shutil.copy(F.DATA / "robot-init.sh", d / "bin" / "robot-init.sh")
        os.chmod(d / "bin" / "robot-init.sh", 0o755)
        priv, pub = F.ed25519_keypair(f"panther-ops-lab-{st.prefix}")
        _write(self.identity_file, priv, 0o600)
        _write(d / "id_ed25519.pub", (pub + "\n").encode(), 0o644)
        self._operator_pub = pub
        self._id_rsa = F.rsa_keypair(f"husarion@panther-ops-lab-{st.prefix}")
        self._cgroups = _cgroup_mounts()
        self._rlimits_ok = can_raise_rlimits()
        if self.docker_enabled:
            self._rootfs = build_rootfs(d / "image" / "rootfs.tar", self.base / ".images").read_bytes()

        # network: bridge, host routes, namespaces, jump bridges
        run(["ip", "link", "add", st.bridge, "type", "bridge"])
        run(["ip", "addr", "add", f"{SUBNET_BASE}.{st.subnet}.1/{lan_prefixlen(st.span)}", "dev", st.bridge])
        run(["ip", "link", "set", st.bridge, "up"])
        for route in st.routes:
            run(["ip", "route", "add", *route.split()])
        run(["ip", "-batch", "-"], input="".join(f"netns add {r.ns}\n" for r in st.robots.values()))
        for jump, w in st.jump_subnets.items():
            self._jump_bridge(st.robots[jump], w)

        # robots in batches: the state file is saved once per batch, not once per process
        # (each save writes every robot: per process it would grow with the square of N)
        robots = list(st.robots.values())
        workers = min(len(robots), BUILD_WORKERS)
        self._batching = True
        try:
            with ThreadPoolExecutor(max_workers=workers) as ex:
                for k in range(0, len(robots), BUILD_BATCH):
                    list(ex.map(self._build_robot, robots[k : k + BUILD_BATCH]))
                    self._save()
        finally:
            self._batching = False
            self._save()
        if st.rtt_ms > 0:
            self._start_relays(robots)
        self._write_operator_files()

    def _build_robot(self, r: RobotState) -> None:
        t0 = time.monotonic()
        self._write_robot_files(r)
        self._wire(r)
        self._start_init(r)
        self._start_sshd(r)
        if self.st.rate:
            run(["ip", "netns", "exec", r.ns, "tc", "qdisc", "add", "dev", "eth0", "root", "tbf",
                 "rate", self.st.rate, "burst", "32kbit", "latency", "400ms"])
        if r.docker:
            self._start_dockerd(r)
            self._import_images(r)
            cp = self.compose(r.name, "up", "-d")
            if cp.returncode != 0:
                raise LabError(f"{r.name}: docker compose up -d failed:\n{cp.stderr.strip()}")
        self._log(f"{r.name}: up in {time.monotonic() - t0:.2f} s ({r.ip}, {r.image})")

    # -- files -------------------------------------------------------------------------
    def _write_robot_files(self, r: RobotState) -> None:
        d = Path(r.dir)
        st_img = F.stack(r.image)
        for sub, mode in (
            ("etc/ssh/ssh_config.d", 0o755),
            ("etc/ssh/sshd_config.d", 0o755),
            ("etc/sudoers.d", 0o755),
            ("etc/docker", 0o755),
            ("var/log", 0o755),
            ("home", 0o755),
            ("run/sshd", 0o755),
            ("run/husarion", 0o755),
            ("tmp", 0o1777),
        ):
            (d / sub).mkdir(parents=True, exist_ok=True)
            os.chmod(d / sub, mode)
        passwd = F.robot_passwd(Path("/etc/passwd").read_text())
        _write(d / "etc/passwd", passwd.encode(), 0o644)
        _write(d / "etc/group", F.robot_group(Path("/etc/group").read_text()).encode(), 0o644)
        _write(d / "etc/shadow", F.robot_shadow(passwd).encode(), 0o640)
        _write(d / "etc/hostname", f"{r.name}\n".encode(), 0o644)
        _write(d / "etc/hosts", F.etc_hosts(r.name, r.ip).encode(), 0o644)
        _write(d / "etc/sudoers.d/husarion", F.SUDOERS.encode(), 0o440)
        if os.path.exists("/etc/ssh/ssh_config"):
            shutil.copy("/etc/ssh/ssh_config", d / "etc/ssh/ssh_config")
        moduli = self.dir / "etc-ssh-moduli"  # 0.6 MB: one copy per lab, hard-linked
        if moduli.exists():
            with contextlib.suppress(FileNotFoundError):
                (d / "etc/ssh/moduli").unlink()
            os.link(moduli, d / "etc/ssh/moduli")
        priv, pub = F.ed25519_keypair(f"root@{r.name}")
        _write(d / "etc/ssh/ssh_host_ed25519_key", priv, 0o600)
        _write(d / "etc/ssh/ssh_host_ed25519_key.pub", (pub + "\n").encode(), 0o644)
        self._known_key(r, set_to=pub)
        _write(d / "etc/ssh/sshd_config", self._sshd_config(r).encode(), 0o644)
        _write(d / "var/log/power-standin.log", b"", 0o622)
        shutil.copy(F.DATA / "poweroff-standin.sh", d / "poweroff-standin")
        os.chmod(d / "poweroff-standin", 0o755)
        _write(d / "cgroups", (self._cgroups if r.docker else "").encode(), 0o644)
        with contextlib.suppress(FileNotFoundError):
            (d / "ready").unlink()

        env_path, env_text, yml_path, yml_text = F.robot_env(st_img, r.serial)
        _write(d / env_path.lstrip("/"), env_text.encode(), 0o644)
        _write(d / yml_path.lstrip("/"), yml_text.encode(), 0o644)

        home = d / "home" / F.USER
        files: dict[str, tuple[bytes, int]] = {}
        skel = Path("/etc/skel")
        for f in (".bashrc", ".bash_logout"):
            if (skel / f).is_file():
                files[f] = ((skel / f).read_bytes(), 0o644)
        skel_profile = (skel / ".profile").read_text() if (skel / ".profile").is_file() else ""
        files[".profile"] = (F.login_profile(st_img, skel_profile).encode(), 0o644)
        files[".ssh/authorized_keys"] = ((self._operator_pub + "\n").encode(), 0o600)
        files[".ssh/id_rsa"] = (self._id_rsa[0], 0o600)
        files[".ssh/id_rsa.pub"] = ((self._id_rsa[1] + "\n").encode(), 0o644)
        files["compose.yaml"] = (
            F.lab_compose(st_img.template_text(), drop_ulimits=not self._rlimits_ok).encode(),
            0o644,
        )
        if st_img.ugv:
            for rel, text in F.ugv_config_tree(st=st_img).items():
                files[f"config/{rel}"] = (text.encode(), 0o644)
        home.mkdir(mode=0o750, exist_ok=True)
        os.chmod(home, 0o750)
        os.chown(home, F.UID, F.GID)
        for rel, (data, mode) in files.items():
            p = home / rel
            _mkdirs_owned(p.parent, home, 0o700 if rel.startswith(".ssh/") else 0o755)
            _write(p, data, mode)
            os.chown(p, F.UID, F.GID)

    def _sshd_config(self, r: RobotState) -> str:
        setenv = None
        if r.clock_offset:
            lib = faketime_library()
            if lib is None:
                raise LabError("libfaketime not found: apt-get install faketime")
            setenv = {
                "LD_PRELOAD": lib,
                "FAKETIME": f"{r.clock_offset:+d}",
                "FAKETIME_DONT_FAKE_MONOTONIC": "1",
            }
        if self.st.rtt_ms > 0:  # the delay relay takes the public address (see _start_relay)
            return F.sshd_config(INNER_SSHD[0], password=r.password, setenv=setenv, port=INNER_SSHD[1])
        return F.sshd_config(r.ip, password=r.password, setenv=setenv)

    def _known_key(self, r: RobotState, set_to: str | None = None) -> str:
        path = Path(r.dir) / "known_host_key"
        if set_to is not None:
            path.write_text(set_to + "\n")
            return set_to
        return path.read_text().strip()

    # -- network -----------------------------------------------------------------------
    def _jump_lan(self, jump: RobotState) -> None:
        """A subnet of the robot's own behind its bridge, once; the host only has an `unreachable`
        route to it. The caller holds the base lock and the lab's lock."""
        st = self.st
        if jump.name in st.jump_subnets:
            return
        w = _free_subnet(_used_subnets(self.base), 1, self.first_subnet)
        st.jump_subnets[jump.name] = w
        st.routes.append(f"unreachable {SUBNET_BASE}.{w}.0/24")
        st.save()
        run(["ip", "route", "add", "unreachable", f"{SUBNET_BASE}.{w}.0/24"])
        self._jump_bridge(jump, w)

    def _jump_bridge(self, jump: RobotState, w: int) -> None:
        cmds = (
            f"link add {JUMP_BRIDGE} type bridge\n"
            f"addr add {SUBNET_BASE}.{w}.1/24 dev {JUMP_BRIDGE}\n"
            f"link set {JUMP_BRIDGE} up\n"
        )
        run(["ip", "-n", jump.ns, "-batch", "-"], input=cmds)

    def _wire(self, r: RobotState) -> None:
        """Connect the robot's eth0: to the lab bridge, or to its jump robot's bridge."""
        if r.jump:
            jump = self.st.robots[r.jump]
            run(
                ["ip", "-n", jump.ns, "-batch", "-"],
                input=(
                    f"link add {r.link} type veth peer name eth0 netns {r.ns}\n"
                    f"link set {r.link} master {JUMP_BRIDGE} up\n"
                ),
            )
        else:
            run(
                ["ip", "-batch", "-"],
                input=(
                    f"link add {r.link} type veth peer name eth0 netns {r.ns}\n"
                    f"link set {r.link} master {self.st.bridge} up\n"
                ),
            )
        run(
            ["ip", "-n", r.ns, "-batch", "-"],
            input=(f"addr add {r.ip}/{24 if r.jump else lan_prefixlen(self.st.span)} dev eth0\n"
                   "link set eth0 up\nlink set lo up\n"),
        )

    # -- processes ---------------------------------------------------------------------
    def _spawn(self, argv: list[str], logfile: Path) -> subprocess.Popen:  # type: ignore[type-arg]
        with open(logfile, "ab") as out:
            p = subprocess.Popen(
                argv,
                stdin=subprocess.DEVNULL,
                stdout=out,
                stderr=subprocess.STDOUT,
                start_new_session=True,
                env=clean_env(),
                close_fds=True,
            )
        self._popen[p.pid] = p
        return p

    def _start_until(self, r: RobotState, argv: list[str], out: Path, roles: tuple[str, ...], what: str,
                     ready: Callable[[], bool], *, log: Path | None = None, timeout: float = 10.0) -> None:
        """Start `argv` for robot `r` (its output to `out`) and wait until `ready()`.

        ``roles``: the name the started process is recorded under, then, where it is an nsenter
        or unshare that forks the program, the name of that child. A LabError naming `what` with
        the end of `log` (default `out`) if the process ends first; on timeout, one naming it.
        The fork gets the same `timeout` as the readiness: under load (CI runs two suites side by
        side) an nsenter once had not forked dockerd after 5 s, and the lab failed to build."""
        p = self._spawn(argv, out)
        self._record(r, roles[0], p.pid)
        if len(roles) > 1:
            self._record(r, roles[1], wait_child(p.pid, timeout))  # a start as slow as the budget allows

        def up() -> bool:
            if p.poll() is not None:
                raise LabError(f"{r.name}: {what} exited:\n{_tail(log or out)}")
            return ready()

        wait_for(up, timeout, f"{what} of {r.name}")

    def _nsenter(self, r: RobotState) -> list[str]:
        return ["nsenter", "-t", str(self._init_pid(r)), "-n", "-m", "-u", "-p", "--"]

    def _start_init(self, r: RobotState) -> None:
        d = Path(r.dir)
        argv = [
            "ip",
            "netns",
            "exec",
            r.ns,
            "unshare",
            "--mount",
            "--uts",
            "--pid",
            "--fork",
            "--propagation",
            "private",
            str(self.dir / "bin" / "robot-init.sh"),
            str(d),
            r.name,
        ]
        self._start_until(r, argv, d / "init.log", ("unshare", "init"), "robot-init.sh",
                          (d / "ready").exists)

    def _sshd_listening(self, r: RobotState) -> int:
        return _count(Path(r.dir) / "var/log/sshd.log", "Server listening on")

    def _start_sshd(self, r: RobotState) -> None:
        before = self._sshd_listening(r)
        argv = [*self._nsenter(r), SSHD, "-D", "-f", "/etc/ssh/sshd_config", "-E", "/var/log/sshd.log"]
        self._start_until(r, argv, Path(r.dir) / "sshd.out", ("sshd-nsenter", "sshd"), "sshd",
                          lambda: self._sshd_listening(r) > before, log=Path(r.dir) / "var/log/sshd.log")

    def _start_relays(self, robots: list[RobotState]) -> None:
        """The delay relays: one process per RELAY_ROBOTS robots, each listening on its robots'
        public address:22 in their namespaces, in front of their inner sshd (tests/lab/relay.py).
        Each robot records its relay under the role `relay` (the same PID for its group)."""
        groups = [robots[k : k + RELAY_ROBOTS] for k in range(0, len(robots), RELAY_ROBOTS)]

        def start(k: int, group: list[RobotState]) -> None:
            conf = self.dir / f"relay-{k}.json"
            log = self.dir / f"relay-{k}.log"
            routes = [{"netns": f"/run/netns/{r.ns}", "listen": f"{r.ip}:22",
                       "to": f"{INNER_SSHD[0]}:{INNER_SSHD[1]}",
                       "trace": str(Path(r.dir) / "relay.trace") if self.relay_trace else None} for r in group]
            _write(conf, json.dumps(routes, indent=1).encode(), 0o600)
            argv = [sys.executable, "-I", str(RELAY), "--robots", str(conf),
                    "--delay-ms", f"{self.st.rtt_ms / 2:g}", "--jitter-ms", f"{self.st.jitter_ms:g}"]
            p = self._spawn(argv, log)
            proc = Proc("relay", p.pid, start_time(p.pid))
            with self._lock:  # recorded before it is waited for: teardown finds it
                for r in group:
                    r.drop("relay")
                    r.procs.append(proc)
                self.st.save()

            def ready() -> bool:
                if p.poll() is not None:
                    raise LabError(f"the delay relay of {group[0].name}..{group[-1].name} exited:\n{_tail(log)}")
                return "ready" in log.read_text(errors="replace")

            wait_for(ready, 30.0, f"the delay relay of {group[0].name}..{group[-1].name}")

        with ThreadPoolExecutor(max_workers=len(groups)) as ex:
            list(ex.map(start, range(1, len(groups) + 1), groups))

    def _reload_sshd(self, r: RobotState) -> None:
        """SIGHUP: sshd re-executes itself (same PID) and reads its configuration again."""
        p = r.proc("sshd")
        if p is None or not alive(p.pid, p.start):
            return  # not running: the new configuration applies at the next start
        before = self._sshd_listening(r)
        signal_recorded(p.pid, p.start, signal.SIGHUP)
        wait_for(lambda: self._sshd_listening(r) > before, 10.0, f"sshd of {r.name} to reload")

    def _stop_sshd(self, r: RobotState) -> None:
        sshd, wrapper = r.proc("sshd"), r.proc("sshd-nsenter")
        if sshd is not None:
            terminate([sshd.key()], timeout=5.0)
        if wrapper is not None:  # exits by itself once sshd is reaped
            self._reap()
            terminate(wait_gone([wrapper.key()], 2.0), timeout=2.0)
        self._reap()
        with self._lock:
            r.drop("sshd")
            r.drop("sshd-nsenter")
            self.st.save()

    def _reap(self) -> None:
        for pid, p in list(self._popen.items()):
            if p.poll() is not None:
                del self._popen[pid]

    # -- docker ------------------------------------------------------------------------
    def docker_socket(self, name: str) -> Path:
        """Host path of the robot's /run/docker.sock."""
        return Path(self._rs(name).dir) / "run" / "docker.sock"

    def _start_dockerd(self, r: RobotState) -> None:
        d = Path(r.dir)
        argv = [
            *self._nsenter(r),
            "dockerd",
            "--data-root",
            str(d / "docker"),
            "--exec-root",
            str(d / "dx"),
            "--pidfile",
            str(d / "dockerd.pid"),
            "-H",
            "unix:///run/docker.sock",
            "--group",
            "docker",
            "--iptables=false",
            "--ip-forward=false",
            "--ip-masq=false",
            "--bridge=none",
            "--cgroup-parent",
            f"{self.st.cgroup_parent}/{r.name}",
            "--log-level",
            "warn",
        ]
        sock = d / "run" / "docker.sock"

        def ready() -> bool:
            if not sock.exists():
                return False
            try:
                return self.docker_client(r.name, timeout=2).ping()
            except Exception:
                return False

        self._start_until(r, argv, d / "var/log/dockerd.log", ("dockerd-nsenter", "dockerd"), "dockerd", ready,
                          timeout=30.0)

    def docker_client(self, name: str, timeout: float = 30) -> Any:
        """docker SDK client for the robot's engine, through its socket from the host."""
        import docker

        return docker.DockerClient(base_url=f"unix://{self.docker_socket(name)}", version="1.41", timeout=timeout)

    def _import_images(self, r: RobotState) -> None:
        """Each stack's driver image with its release's /version.txt, the others without."""
        client = self.docker_client(r.name, timeout=60)
        try:
            drivers: set[str] = set()
            for st in F.STACKS.values():
                driver = st.images()[0]
                repo, tag = driver.rsplit(":", 1)
                client.api.import_image_from_data(
                    with_version(self._rootfs, st.key, st.distro), repository=repo, tag=tag,
                    changes=[*import_changes(st.distro), f"LABEL {VERSION_LABEL}={st.key}"],
                )
                drivers.add(driver)
            others = [t for t in F.all_image_tags() if t not in drivers]
            if others:
                first_repo, first_tag = others[0].rsplit(":", 1)
                client.api.import_image_from_data(
                    self._rootfs, repository=first_repo, tag=first_tag, changes=list(IMPORT_CHANGES)
                )
                for t in others[1:]:
                    repo, tag = t.rsplit(":", 1)
                    client.api.tag(others[0], repo, tag)
        finally:
            client.close()

    def docker(self, name: str, *args: str, check: bool = False, timeout: float = 60) -> subprocess.CompletedProcess:  # type: ignore[type-arg]
        """`docker ARGS` against the robot's engine, from the host (through its socket)."""
        cli = docker_cli()
        if cli is None:
            raise LabError("docker CLI not found")
        return run([cli, "-H", f"unix://{self.docker_socket(name)}", *args], check=check, timeout=timeout)

    def compose(self, name: str, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:  # type: ignore[type-arg]
        """`docker compose ARGS` as the real robot runs it: user husarion, login shell, in ~."""
        cmd = "docker compose " + " ".join(shlex.quote(a) for a in args)
        return self.exec(name, ["bash", "-lc", cmd], user=F.USER, timeout=timeout)

    # ===================================================================================
    # operator files
    # ===================================================================================
    def _write_operator_files(self) -> None:
        with self._lock:
            states = [r for r in sorted(self.st.robots.values(), key=lambda x: x.index) if r.kind == "robot"]
            robots = [self.robot(r.name) for r in states]
            host_keys = {r.name: " ".join(self._known_key(r).split()[:2]) for r in states}
            _write(self.known_hosts_path, F.known_hosts(robots, host_keys).encode(), 0o644)
            _write(
                self.ssh_config_path, F.ssh_config(robots, self.identity_file, self.known_hosts_path).encode(), 0o644
            )
            _write(self.inventory_path, F.inventory_yaml(robots).encode(), 0o644)

    # ===================================================================================
    # down
    # ===================================================================================
    def down(self) -> None:
        """Tear down everything the lab owns (the state file says what)."""
        if self.state is None:
            return
        t0 = time.monotonic()
        teardown(self.state, log=self._log_cb)
        for p in self._popen.values():
            with contextlib.suppress(Exception):
                p.wait(timeout=2)
        self._popen.clear()
        self.timings["down"] = time.monotonic() - t0
        self.state = None

    # ===================================================================================
    # inside a robot
    # ===================================================================================
    def exec(
        self,
        name: str,
        argv: Sequence[str],
        user: str | None = None,
        *,
        input: str | bytes | None = None,
        timeout: float = 60.0,
        check: bool = False,
        env: Mapping[str, str] | None = None,
        text: bool = True,
    ) -> subprocess.CompletedProcess:  # type: ignore[type-arg]
        """Run `argv` inside the robot's namespaces (as root, or as `user` in its home).

        A `user` gets a fresh environment from the robot's passwd (setpriv --reset-env) and
        the robot's clock offset, if one is set (see clock_offset).
        """
        r = self._rs(name)
        cmd = self._nsenter(r)
        if user is not None and user != "root":
            extra = dict(self._clock_env(r))
            extra.update(env or {})
            cmd += [
                "setpriv",
                f"--reuid={user}",
                f"--regid={_robot_gid(r, user)}",
                "--init-groups",
                "--reset-env",
                "--",
                "env",
                *(f"{k}={v}" for k, v in extra.items()),
                "sh",
                "-c",
                'cd "$HOME" 2>/dev/null; exec "$@"',
                "sh",
                *argv,
            ]
            return run(cmd, check=check, input=input, timeout=timeout, text=text)
        return run(
            [*cmd, *argv], check=check, input=input, timeout=timeout, text=text, env=clean_env(**dict(env or {}))
        )

    def sh(self, name: str, script: str, user: str | None = None, **kw: Any) -> subprocess.CompletedProcess:  # type: ignore[type-arg]
        """`exec(name, ["sh", "-c", script], user)`."""
        return self.exec(name, ["sh", "-c", script], user, **kw)

    def _host_path(self, r: RobotState, path: str) -> Path | None:
        """Host path of a robot path when it lies in one of the robot's own bind mounts."""
        p = posixpath.normpath("/" + path.lstrip("/"))
        d = Path(r.dir)
        if p in _BIND_FILES:
            return d / _BIND_FILES[p]
        for mnt, rel in _BIND_DIRS.items():
            if p == mnt or p.startswith(mnt + "/"):
                host = d / rel / p[len(mnt) :].lstrip("/")
                # symlinks are resolved by the host: only accept what stays in the robot dir
                real = os.path.realpath(host)
                if real == str(d / rel) or real.startswith(str(d / rel) + "/"):
                    return host
                return None
        return None

    def read_bytes(self, name: str, path: str) -> bytes:
        r = self._rs(name)
        host = self._host_path(r, path)
        if host is not None:
            return host.read_bytes()
        cp = self.exec(name, ["cat", "--", path], text=False)
        if cp.returncode != 0:
            raise FileNotFoundError(f"{name}:{path}: {cp.stderr.decode(errors='replace').strip()}")
        return cp.stdout  # type: ignore[no-any-return]

    def read(self, name: str, path: str) -> str:
        """Content of a file of the robot (robot path)."""
        return self.read_bytes(name, path).decode()

    def write(self, name: str, path: str, data: str | bytes, *, mode: int | None = None) -> None:
        """Write a robot file in place (its inode is kept: bind mounts see the new content).

        New files under /home/husarion belong to husarion, others to root.
        """
        r = self._rs(name)
        raw = data.encode() if isinstance(data, str) else data
        host = self._host_path(r, path)
        if host is None:
            script = 'cat > "$1"' + (f' && chmod {mode:o} "$1"' if mode is not None else "")
            self.exec(name, ["sh", "-c", script, "sh", path], input=raw, check=True, text=False)
            return
        owned = posixpath.normpath(path).startswith(F.HOME + "/")
        if host.exists():
            with open(host, "r+b") as f:
                f.truncate(0)
                f.write(raw)
        else:
            top = Path(r.dir) / "home" / F.USER if owned else host.parent
            _mkdirs_owned(host.parent, top, 0o755, owned)
            _write(host, raw, 0o644)
            if owned:
                os.chown(host, F.UID, F.GID)
        if mode is not None:
            os.chmod(host, mode)

    # ===================================================================================
    # edge features
    # ===================================================================================
    def link_down(self, name: str) -> None:
        """The robot's eth0 goes down: no ping, ssh connects time out."""
        run(["ip", "-n", self._rs(name).ns, "link", "set", "eth0", "down"])

    def link_up(self, name: str) -> None:
        run(["ip", "-n", self._rs(name).ns, "link", "set", "eth0", "up"])

    def power_on(self, name: str) -> None:
        """Undo the power-off stand-in: every interface of the robot up again."""
        r = self._rs(name)
        out = run(["ip", "-n", r.ns, "-o", "link", "show"]).stdout
        for m in re.finditer(r"^\d+: ([^:@]+)", out, flags=re.M):
            run(["ip", "-n", r.ns, "link", "set", m.group(1), "up"])

    def power_calls(self, name: str) -> list[dict[str, Any]]:
        """Calls of shutdown/poweroff/reboot (and systemctl) recorded by the stand-in."""
        text = (Path(self._rs(name).dir) / "var/log/power-standin.log").read_text()
        return [json.loads(line) for line in text.splitlines() if line.strip()]

    def standins(self, name: str) -> dict[str, str]:
        """Paths covered by the power-off stand-in in this robot: command -> mounted target."""
        text = (Path(self._rs(name).dir) / "standin-targets").read_text()
        return dict(line.split(" ", 1) for line in text.splitlines() if line.strip())

    def kill_sshd(self, name: str) -> None:
        """Stop the robot's sshd (open sessions stay, as on a real host)."""
        self._stop_sshd(self._rs(name))

    def kill_sshd_and_sessions(self, name: str) -> None:
        """Stop the robot's sshd and end its open sessions (by the PIDs of its children):
        from the operator's side the connection drops, as when the daemon dies with them."""
        r = self._rs(name)
        p = r.proc("sshd")
        sessions: list[int] = []
        todo = children(p.pid) if p is not None and alive(p.pid, p.start) else []
        while todo:  # each session's monitor, its unprivileged child and what runs under them
            pid = todo.pop()
            sessions.append(pid)
            todo.extend(children(pid))
        self._stop_sshd(r)
        for pid in sessions:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)

    def start_sshd(self, name: str) -> None:
        r = self._rs(name)
        p = r.proc("sshd")
        if p is not None and alive(p.pid, p.start):
            return
        self._start_sshd(r)

    def sshd_accepts(self, name: str) -> int:
        """Accepted logins in the robot's sshd log ("Accepted publickey for husarion", ...)."""
        path = Path(self._rs(name).dir) / "var/log/sshd.log"
        return len(re.findall(r"Accepted \S+ for husarion", _read(path)))

    def sshd_connections(self, name: str) -> int:
        """TCP connections the robot's sshd accepted ("Connection from ..." in its log)."""
        path = Path(self._rs(name).dir) / "var/log/sshd.log"
        return len(re.findall(r"^Connection from ", _read(path), re.M))

    def host_fingerprint(self, name: str) -> str:
        """SHA256 fingerprint of the host key the robot's sshd currently uses (`SHA256:…`)."""
        pub = (Path(self._rs(name).dir) / "etc/ssh/ssh_host_ed25519_key.pub").read_text()
        return F.fingerprint(pub)

    def rotate_host_key(self, name: str) -> str:
        """New host key, sshd restarted; known_hosts is NOT updated. Returns the new key."""
        r = self._rs(name)
        d = Path(r.dir) / "etc/ssh"
        key = d / "ssh_host_ed25519_key"
        saved = d / "known_ssh_host_ed25519_key"  # the key known_hosts still names
        if not saved.exists():
            shutil.copy2(key, saved)
        priv, pub = F.ed25519_keypair(f"root@{r.name}")
        _write(key, priv, 0o600)
        _write(d / "ssh_host_ed25519_key.pub", (pub + "\n").encode(), 0o644)
        self._stop_sshd(r)
        self._start_sshd(r)
        return pub

    def restore_host_key(self, name: str) -> None:
        """Undo rotate_host_key: the robot uses the key in known_hosts again (sshd restarted)."""
        r = self._rs(name)
        d = Path(r.dir) / "etc/ssh"
        saved = d / "known_ssh_host_ed25519_key"
        if not saved.exists():
            return
        priv = saved.read_bytes()
        _write(d / "ssh_host_ed25519_key", priv, 0o600)
        pub = F.public_key_of(priv) + f" root@{r.name}\n"
        _write(d / "ssh_host_ed25519_key.pub", pub.encode(), 0o644)
        saved.unlink()
        self._stop_sshd(r)
        self._start_sshd(r)

    def accept_host_key(self, name: str) -> None:
        """Put the robot's current host key into known_hosts (the other way to undo a rotation)."""
        r = self._rs(name)
        pub = (Path(r.dir) / "etc/ssh/ssh_host_ed25519_key.pub").read_text().strip()
        self._known_key(r, set_to=pub)
        with contextlib.suppress(FileNotFoundError):
            (Path(r.dir) / "etc/ssh/known_ssh_host_ed25519_key").unlink()
        self._write_operator_files()

    def clock_offset(self, name: str, seconds: int) -> None:
        """Shift the clock of the robot's login environment (ssh sessions, exec as a user).

        libfaketime via sshd `SetEnv LD_PRELOAD=... FAKETIME=+N` (0 removes it); the kernel
        clock is shared with the host and is not changed. Static binaries (Go: docker) are
        not affected.
        """
        r = self._rs(name)
        r.clock_offset = int(seconds)
        self._save()
        _write_in_place(Path(r.dir) / "etc/ssh/sshd_config", self._sshd_config(r).encode())
        self._reload_sshd(r)

    def _clock_env(self, r: RobotState) -> dict[str, str]:
        if not r.clock_offset:
            return {}
        lib = faketime_library()
        return (
            {}
            if lib is None
            else {
                "LD_PRELOAD": lib,
                "FAKETIME": f"{r.clock_offset:+d}",
                "FAKETIME_DONT_FAKE_MONOTONIC": "1",
            }
        )

    def password_login(self, name: str, password: str | None = "husarion", *, enabled: bool = True) -> None:
        """sshd of the robot also accepts `password` for husarion.

        `password=None` or `enabled=False`: key-only again (the account's password is `*`).
        """
        if not enabled:
            password = None
        r = self._rs(name)
        shadow = Path(r.dir) / "etc/shadow"
        pw_hash = "*" if password is None else _sha512_crypt(password)
        lines = []
        for line in shadow.read_text().splitlines():
            f = line.split(":")
            if f[0] == F.USER:
                f[1] = pw_hash
            lines.append(":".join(f))
        _write_in_place(shadow, ("\n".join(lines) + "\n").encode())
        r.password = password is not None
        self._save()
        _write_in_place(Path(r.dir) / "etc/ssh/sshd_config", self._sshd_config(r).encode())
        self._reload_sshd(r)

    def behind_jump(self, name: str, jump: str) -> None:
        """Move `name` onto a subnet that only `jump` also sits on (ProxyJump needed).

        The robot gets 10.200.<w2>.(10+i) behind a bridge inside the jump robot; the host
        has only an `unreachable` route to that subnet (so probes never leave the machine).
        Inventory, ssh_config and known_hosts are rewritten (same host key, new address).
        """
        st = self.st
        r, j = self._rs(name), self._rs(jump)
        if r.jump == jump:
            return
        if j.jump or any(x.jump == name for x in st.robots.values()) or name == jump:
            raise LabError("a jump robot cannot be behind a jump robot itself")
        with base_lock(self.base), self._lock:
            self._jump_lan(j)
        w = st.jump_subnets[jump]
        # unwire: deleting eth0 in the robot deletes its peer too
        run(["ip", "-n", r.ns, "link", "del", "eth0"], check=False)
        r.jump = jump
        r.link = f"v-{name}"
        if r.index > ROBOTS_PER_24:
            raise LabError(f"only the first {ROBOTS_PER_24} robots can be moved behind a jump robot")
        r.ip = robot_ip(w, r.index)
        self._save()
        self._wire(r)
        _write_in_place(Path(r.dir) / "etc/hosts", F.etc_hosts(r.name, r.ip).encode())
        _write_in_place(Path(r.dir) / "etc/ssh/sshd_config", self._sshd_config(r).encode())
        self._stop_sshd(r)
        self._start_sshd(r)
        self._write_operator_files()

    # ===================================================================================
    # user computers (tests/lab/computers.py)
    # ===================================================================================
    def add_computers(self, specs: Sequence[Any]) -> list[Any]:
        """User computers (`computers.ComputerSpec`), on the lab bridge or behind a robot."""
        from . import computers

        return computers.add_computers(self, list(specs))

    @property
    def computer_names(self) -> list[str]:
        from . import computers

        return computers.computer_names(self)

    def computer(self, name: str) -> Any:
        from . import computers

        return computers.computer(self, name)

    @property
    def computers_known_hosts_path(self) -> Path:
        """known_hosts with every computer's host key (for the operator's side)."""
        return self.dir / "computers_known_hosts"

    # ===================================================================================
    # ssh helpers (operator side)
    # ===================================================================================
    def connect(self, name: str, *, timeout: float = 5.0, password: str | None = None) -> Any:
        """paramiko SSHClient logged in as husarion (RejectPolicy + the lab's known_hosts).

        Robots behind a jump host are reached through a direct-tcpip channel of the jump
        robot (the jump client is closed with the returned client).
        """
        import paramiko

        r = self._rs(name)
        sock = None
        jump_client = None
        if r.jump:
            jump_client = self.connect(r.jump, timeout=timeout)
            sock = jump_client.get_transport().open_channel(
                "direct-tcpip", (r.ip, 22), ("127.0.0.1", 0), timeout=timeout
            )
        client = _LabSSHClient(jump_client)
        client.load_host_keys(str(self.known_hosts_path))
        client.set_missing_host_key_policy(paramiko.RejectPolicy())
        auth: dict[str, Any] = {"look_for_keys": False, "allow_agent": False}
        if password is not None:
            auth["password"] = password
        else:
            auth["key_filename"] = str(self.identity_file)
        try:
            client.connect(
                r.ip,
                22,
                username=F.USER,
                sock=sock,
                timeout=timeout,
                banner_timeout=timeout,
                auth_timeout=timeout,
                **auth,
            )
        except BaseException:
            client.close()
            raise
        return client

    def ssh_argv(self, name: str, *command: str) -> list[str]:
        """OpenSSH command line for the robot (`ssh -F <lab>/ssh_config NAME ...`)."""
        return ["ssh", "-F", str(self.ssh_config_path), "-o", "BatchMode=yes", name, *command]

    def ssh(self, name: str, command: str, *, timeout: float = 30) -> subprocess.CompletedProcess:  # type: ignore[type-arg]
        """Run `command` on the robot over OpenSSH (as an operator would)."""
        return run(self.ssh_argv(name, command), check=False, timeout=timeout, env=dict(os.environ))

    # ===================================================================================
    # status
    # ===================================================================================
    def status(self) -> dict[str, Any]:
        return lab_status(self.st)


class _LabSSHClient:
    """Built lazily so that importing the lab does not import paramiko."""

    def __new__(cls, jump: Any) -> Any:  # type: ignore[misc]
        import paramiko

        class LabSSHClient(paramiko.SSHClient):
            def __init__(self) -> None:
                super().__init__()
                self.jump_client = jump

            def close(self) -> None:
                super().close()
                if self.jump_client is not None:
                    self.jump_client.close()

        return LabSSHClient()


# =======================================================================================
# status and teardown (work from a state file alone: usable after a crash)
# =======================================================================================
def lab_status(st: LabState) -> dict[str, Any]:
    robots = {}
    for r in sorted(st.robots.values(), key=lambda x: x.index):
        procs = {p.role: alive(p.pid, p.start) for p in r.procs}
        robots[r.name] = {
            "ip": r.ip,
            "image": r.image,
            "jump": r.jump,
            "running": procs.get("init", False),
            "sshd": procs.get("sshd", False),
            "dockerd": procs.get("dockerd", False) if r.docker else None,
        }
    owner_alive = st.owner is not None and alive(st.owner.pid, st.owner.start)
    return {
        "prefix": st.prefix,
        "dir": st.dir,
        "subnet": f"{SUBNET_BASE}.{st.subnet}.0/{lan_prefixlen(st.span)}",
        "docker": st.docker,
        "rtt_ms": st.rtt_ms,
        "jitter_ms": st.jitter_ms,
        "rate": st.rate,
        "owner": None if st.owner is None else st.owner.pid,
        "owner_alive": owner_alive,
        "inventory": str(Path(st.dir) / "inventory.yaml"),
        "ssh_config": str(Path(st.dir) / "ssh_config"),
        "robots": robots,
    }


def lab_memory(st: LabState) -> dict[str, Any]:
    """Memory of the lab's processes now: count, summed RSS and PSS (shared pages split), MB."""
    procs = {pid for r in st.robots.values() for pid, s in (p.key() for p in r.procs) if alive(pid, s)}
    procs |= {pid for pid, _ in lab_processes(st.prefix, Path(st.dir))}
    rss = pss = 0
    for pid in procs:
        with contextlib.suppress(OSError, ValueError, IndexError):
            with open(f"/proc/{pid}/smaps_rollup") as f:
                fields = {line.split(":")[0]: int(line.split()[1]) for line in f if line.endswith("kB\n")}
            rss += fields.get("Rss", 0)
            pss += fields.get("Pss", 0)
    return {"processes": len(procs), "rss_mb": rss / 1024, "pss_mb": pss / 1024}


# =======================================================================================
# small helpers
# =======================================================================================


def _used_subnets(base: Path) -> set[int]:
    """Third octets of 10.200.x.y in use: host addresses and routes (a /22 covers 4), labs."""
    used: set[int] = set()
    pat = re.compile(r"\b10\.200\.(\d+)\.\d+(?:/(\d+))?")
    for cmd in (["ip", "-4", "-o", "addr", "show"], ["ip", "-4", "route", "show", "table", "all"]):
        for third, plen in pat.findall(run(cmd, check=False).stdout):
            w, bits = int(third), int(plen or 32)
            size = 1 << (24 - bits) if 16 <= bits < 24 else 1
            used.update(range(w - w % size, w - w % size + size))
    for st in all_states(base):
        used |= st.all_subnets()
    return used


def _free_subnet(used: Iterable[int], span: int = 1, first: int = 1) -> int:
    """First free 10.200.w.0/24 (`span` consecutive ones, w a multiple of span; w >= first >= 1)."""
    taken = set(used)
    for w in range(-(-max(first, 1) // span) * span, 255 - span + 1, span):
        if not taken & set(range(w, w + span)):
            return w
    raise LabError(f"no free 10.200.x.0/{lan_prefixlen(span)} subnet")



def _cgroup_mounts() -> str:
    """The host's cgroup hierarchies as "fstype options subdir" lines for robot-init.sh."""
    lines = []
    with open("/proc/self/mounts") as f:
        for line in f:
            _dev, mnt, fstype, opts = line.split()[:4]
            if fstype in ("cgroup", "cgroup2") and mnt.startswith("/sys/fs/cgroup"):
                sub = mnt[len("/sys/fs/cgroup") :].lstrip("/") or "."
                keep = [o for o in opts.split(",") if o not in ("rw", "relatime", "ro")]
                lines.append(f"{fstype} {','.join(['rw', *keep])} {sub}")
    return "\n".join(lines) + ("\n" if lines else "")


def _write(path: Path, data: bytes, mode: int) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, mode)
    with os.fdopen(fd, "wb") as f:
        f.write(data)
    os.chmod(path, mode)


def _write_in_place(path: Path, data: bytes) -> None:
    """Rewrite keeping the inode (the file is bind-mounted on its own into a robot)."""
    with open(path, "r+b") as f:
        f.truncate(0)
        f.write(data)


def _mkdirs_owned(path: Path, top: Path, mode: int, owned: bool = True) -> None:
    """mkdir -p up from `top`; new directories belong to husarion when `owned`."""
    missing = []
    p = path
    while not p.exists() and p != top and top in p.parents:
        missing.append(p)
        p = p.parent
    for m in reversed(missing):
        m.mkdir(mode=mode)
        os.chmod(m, mode)
        if owned:
            os.chown(m, F.UID, F.GID)
    path.mkdir(parents=True, exist_ok=True)


def _robot_gid(r: RobotState, user: str) -> int:
    for line in (Path(r.dir) / "etc/passwd").read_text().splitlines():
        f = line.split(":")
        if f[0] == user:
            return int(f[3])
    raise LabError(f"{r.name}: no user {user!r}")


def _sha512_crypt(password: str) -> str:
    cp = run(["openssl", "passwd", "-6", "-stdin"], input=password + "\n", check=False)
    if cp.returncode == 0 and cp.stdout.startswith("$6$"):
        return cp.stdout.strip()
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        import crypt  # removed in 3.13; only a fallback when openssl is missing

        return crypt.crypt(password, crypt.mksalt(crypt.METHOD_SHA512))


def _read(path: Path) -> str:
    try:
        return path.read_text(errors="replace")
    except FileNotFoundError:
        return ""


def _count(path: Path, needle: str) -> int:
    return _read(path).count(needle)


def _tail(path: Path, n: int = 20) -> str:
    return "\n".join(_read(path).splitlines()[-n:])
