"""Benchmark: `config set wheel_type WH02` on N robots at several round-trip times.

    sudo .venv/bin/python bench/config_bench.py [--sizes 10,30] [--rtts 0,50,150] [--repeat 3] [--json]

The change: ` wheel_type:=WH02` appended to the `command:` line of the driver service in
`/home/husarion/compose.yaml` of every robot. Made, on the same simulated lab (tests/lab,
docker on; robots behind delay relays for RTT > 0, docs/lab.md), by:

- panther-ops on its default path: `config set wheel_type WH02 --all --yes` (backup, write,
  the driver recreated and verified for the default `--settle` of 5 s);
- panther-ops `--no-restart` (backup and write only: what the other tools do);
- the floor: one OpenSSH connection per robot, all robots at once, each running
  `grep -q ... || sed -i -E ... compose.yaml` (no backup, no plan, no check);
- pyinfra: `files.line` (sed, `backup=True`), the new line computed from a `FindInFile` fact;
- Ansible: `ansible.builtin.replace` (Python regex, `backup: true`), pipelining on, forks=N,
  no fact gathering, ControlMaster/ControlPersist as Ansible's default `ssh_args`.

All verify host keys strictly against the lab's known_hosts and use the lab's key.

Each timed run is a fresh process; before it every robot's compose.yaml is reset to what
the lab wrote and everything the tools left in the home directory (backups, panther-ops'
~/.panther-ops, ~/.ansible) is removed, so every run really changes every file; after it
every file is checked against the expected bytes. The order of the tools rotates between
repeats. Before the timed runs each tool does one untimed run (warm-up and check) and a
second one that must leave the files untouched (idempotence: same inode and mtime).

Besides wall time (and, for RTT > 0, wall / RTT: the run in round trips) it reports the CPU
time of the tool's process tree ("CPU tool"; Ansible's ControlPersist ssh masters are
daemons and not in it) and the CPU the robots spent on the run ("CPU robots": each robot's
sshd plus what its init reaped, i.e. every session command, plus each robot's dockerd and
containers). The relays that make the round trips are the network, not the robots: their
CPU is reported apart. All robots of the lab share the machine's cores with the tool, so
robot-side work adds up here, where on a real fleet each robot does its own in parallel.
The connections and exec sessions each tool opened per robot are counted from the robots'
sshd logs. A timed run during which the machine spent more than --max-other-cpu CPU seconds
(default 0.5) on neither the tool, the robots nor the relays is discarded and repeated (up
to --retries times). A lab is brought up per size and RTT and always torn down.

Fleets of hundreds (issue 29): sizes up to the lab's 960; without the default path the lab
runs no dockerd. Ansible runs with forks = N (--ansible-forks caps it), pyinfra --parallel N,
panther-ops at its default --forks and at each of --po-forks. Each timed run also reports the
peak memory of the tool's process tree (a memory cgroup of its own) and its CPU per robot
(bench/README.md).

Needs root (the lab). Ansible and pyinfra come from bench/requirements.txt, installed into
their own venv (default /root/.cache/panther-ops-bench-venv, created or reused); panther-ops
is this checkout installed as users install it, from a wheel, into a venv of its own
(default /root/.cache/panther-ops-bench-po-venv; --panther-ops names another executable).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
REQUIREMENTS = Path(__file__).resolve().parent / "requirements.txt"
DEFAULT_VENV = Path(os.environ.get("PANTHER_OPS_BENCH_VENV", "/root/.cache/panther-ops-bench-venv"))
DEFAULT_PO_VENV = Path(os.environ.get("PANTHER_OPS_BENCH_PO_VENV", "/root/.cache/panther-ops-bench-po-venv"))
COMPOSE = "/home/husarion/compose.yaml"
USER = "husarion"
# issue #12: --no-restart at 150 ms <= 0.8x the floor and <= 0.6x pyinfra; at 0 ms <= 0.7x
# pyinfra and <= 0.15x Ansible.
TARGETS = {150.0: {"floor": 0.8, "pyinfra": 0.6}, 0.0: {"pyinfra": 0.7, "ansible": 0.15}}
# issue #29: at 100 robots and more, 150 ms: <= 0.6x pyinfra and <= 0.15x Ansible (10 robots: <= 0.8x the floor)
TARGETS_HUNDREDS = {150.0: {"pyinfra": 0.6, "ansible": 0.15}}


def targets(robots: int, rtt_ms: float) -> dict[str, float]:
    return (TARGETS_HUNDREDS if robots >= 100 else TARGETS).get(rtt_ms, {})
ALL_TOOLS = "panther-ops,panther-ops-no-restart,floor,pyinfra,ansible"
RUN_TIMEOUT = 180.0
DEFAULT_FORKS = 32  # panther-ops' default --forks (docs/inventory.md)
MAX_ROBOTS = 960  # the lab's limit (docs/lab.md, "A lab of hundreds")

# The driver's launch line: `    command: ros2 launch panther_bringup bringup.launch.py ...` (2.0/2.1)
# or `... husarion_ugv_bringup ...` (2.2). Ansible's regexp (Python re, MULTILINE): appends
# ` wheel_type:=WH02`, replaces another wheel_type value in place, leaves WH02 alone.
ANSIBLE_REGEXP = (
    r"^([ \t]+command:[ \t]+ros2 launch \S+_bringup bringup\.launch\.py(?:(?! wheel_type:=)[^\n])*)"
    r"(?: wheel_type:=(?!WH02(?:\s|$))\S+)?((?:(?! wheel_type:=)[^\n])*)$"
)
# pyinfra greps/seds with this (ERE); the replacement line is computed in the deploy file.
DRIVER_ERE = r"^\s+command:\s+ros2 launch [a-z_]+_bringup bringup\.launch\.py.*$"
# The floor: GNU sed -E, the same edit (WH02 left alone, another value replaced, else appended),
# after a grep that leaves an already changed file untouched (idempotent).
FLOOR_DRIVER = r"^[[:space:]]+command:[[:space:]]+ros2 launch [a-z_]+_bringup bringup\.launch\.py"
FLOOR_SED = (FLOOR_DRIVER + r"/{/ wheel_type:=WH02( |$)/b;s/ wheel_type:=[^ ]+/ wheel_type:=WH02/;t;"
             r"s/$/ wheel_type:=WH02/}")
FLOOR_REMOTE = (f"grep -qE '{FLOOR_DRIVER}.* wheel_type:=WH02( |$)' {COMPOSE} || "
                f"sed -i -E '/{FLOOR_SED}' {COMPOSE}")

PLAYBOOK = f"""\
- name: Driver wheel type
  hosts: robots
  gather_facts: false
  tasks:
    - name: Driver launches with wheel_type:=WH02
      ansible.builtin.replace:
        path: {COMPOSE}
        regexp: '{ANSIBLE_REGEXP}'
        replace: '\\1 wheel_type:=WH02\\2'
        backup: true
"""

DEPLOY = f"""\
import re

from pyinfra import host
from pyinfra.facts.files import FindInFile
from pyinfra.operations import files

PATH = {COMPOSE!r}
DRIVER = {DRIVER_ERE!r}

# The same fact files.line reads (cached per host): one grep, then one sed if needed.
for old in host.get_fact(FindInFile, path=PATH, pattern=DRIVER, interpolate_variables=False,
                         extended_regex=True) or []:
    if re.search(r" wheel_type:=\\S+", old):
        new = re.sub(r" wheel_type:=\\S+", " wheel_type:=WH02", old, count=1)
    else:
        new = old + " wheel_type:=WH02"
    files.line(name="Driver launches with wheel_type:=WH02", path=PATH, line=DRIVER, replace=new,
               backup=True, extended_regex=True)
"""


def log(msg: str) -> None:
    sys.stderr.write(msg + "\n")
    sys.stderr.flush()


# ---------------------------------------------------------------------------------------
# environment
# ---------------------------------------------------------------------------------------
def ensure_project_python() -> None:
    """Re-run under the project's venv when the lab's dependencies are missing here."""
    try:
        import paramiko  # noqa: F401
        import yaml  # noqa: F401
    except ImportError:
        venv_python = REPO / ".venv" / "bin" / "python"
        if venv_python.exists() and not os.environ.get("PANTHER_OPS_BENCH_REEXEC"):
            os.environ["PANTHER_OPS_BENCH_REEXEC"] = "1"
            os.execv(str(venv_python), [str(venv_python), *sys.argv])
        raise


def ensure_tool_venv(venv: Path) -> Path:
    """Create (or reuse) the venv holding ansible-core and pyinfra; returns its bin dir."""
    stamp = venv / ".requirements.sha256"
    want = hashlib.sha256(REQUIREMENTS.read_bytes()).hexdigest()
    bindir = venv / "bin"
    ok = all((bindir / b).exists() for b in ("ansible-playbook", "pyinfra"))
    if ok and stamp.exists() and stamp.read_text().strip() == want:
        return bindir
    log(f"installing {REQUIREMENTS.name} into {venv} ...")
    if not (bindir / "python").exists():
        base = getattr(sys, "_base_executable", sys.executable)
        subprocess.run([base, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(bindir / "python"), "-m", "pip", "install", "-q", "-r", str(REQUIREMENTS)], check=True)
    stamp.write_text(want + "\n")
    return bindir


def ensure_panther_ops_venv(venv: Path) -> str:
    """Install this checkout into its own venv as users install it (a wheel, not editable);
    returns its panther-ops executable.

    An editable install starts every process with a path finder (site imports pathlib and
    urllib for it: ~10 ms per start here) that no installed package has, and ansible and
    pyinfra are measured from wheels too. The dependencies are installed once per version
    of pyproject.toml; panther_ops itself is reinstalled from the checkout on every run.
    """
    pyproject = REPO / "pyproject.toml"
    stamp = venv / ".pyproject.sha256"
    want = hashlib.sha256(pyproject.read_bytes()).hexdigest()
    python = venv / "bin" / "python"
    if not python.exists():
        base = REPO / ".venv" / "bin" / "python"
        subprocess.run([str(base if base.exists() else sys.executable), "-m", "venv", "--clear", str(venv)],
                       check=True)
    pip = [str(python), "-m", "pip", "install", "-q", "--disable-pip-version-check"]
    if not stamp.exists() or stamp.read_text().strip() != want:
        log(f"installing panther-ops and its dependencies into {venv} ...")
        subprocess.run([*pip, str(REPO)], check=True)
        stamp.write_text(want + "\n")
    subprocess.run([*pip, "--no-deps", "--force-reinstall", str(REPO)], check=True)
    return str(venv / "bin" / "panther-ops")


def version_of(argv: list[str]) -> str:
    try:
        cp = subprocess.run(argv, capture_output=True, text=True, timeout=60, check=False)
    except OSError as exc:
        return f"? ({exc})"
    return (cp.stdout or cp.stderr).strip().splitlines()[0] if (cp.stdout or cp.stderr).strip() else "?"


def git_state() -> str:
    """The commit of this checkout, and whether panther_ops/ differs from it."""
    try:
        head = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--", "panther_ops"],
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "?"
    return head + (" + uncommitted changes in panther_ops/" if dirty else "")


# ---------------------------------------------------------------------------------------
# the change itself (what every tool must produce)
# ---------------------------------------------------------------------------------------
_DRIVER_LINE = re.compile(r"^([ \t]+command:[ \t]+ros2 launch \S+_bringup bringup\.launch\.py)(.*)$", re.M)


def expected_after(before: str) -> str:
    lines = _DRIVER_LINE.findall(before)
    if len(lines) != 1:
        raise SystemExit(f"compose.yaml: expected one driver `command:` line, found {len(lines)}")

    def edit(m: re.Match[str]) -> str:  # a wheel_type already there is set in place, else appended
        if re.search(r" wheel_type:=\S+", m.group(2)):
            return m.group(1) + re.sub(r" wheel_type:=\S+", " wheel_type:=WH02", m.group(2), count=1)
        return f"{m.group(1)}{m.group(2)} wheel_type:=WH02"

    return _DRIVER_LINE.sub(edit, before, count=1)


# ---------------------------------------------------------------------------------------
# tools
# ---------------------------------------------------------------------------------------
@dataclass
class Tool:
    key: str
    label: str
    argv: list[str]
    env: dict[str, str] = field(default_factory=dict)
    ansible_cp_dir: Path | None = None


def make_tools(lab: Any, n: int, work: Path, bindir: Path, panther_ops: str, wanted: list[str],
               also: tuple[tuple[str, str], ...] = (), ansible_forks: int | None = None,
               po_forks: tuple[int, ...] = ()) -> list[Tool]:
    """The tools for a lab of ``n`` robots, each at its best documented settings for that size:
    Ansible forks = n (or ``ansible_forks`` where the machine cannot hold n), pipelining,
    ControlPersist; pyinfra ``--parallel n``; panther-ops at its default ``--forks`` (32) and,
    for each of ``po_forks`` that works on a different number of robots at once at this size,
    ``--forks K`` beside it."""
    inv = str(lab.inventory_path)
    key = str(lab.identity_file)
    known = str(lab.known_hosts_path)
    for r in lab.robots:  # the bench talks to the lab only
        if not str(r.ip).startswith("10.200."):
            raise SystemExit(f"{r.name}: {r.ip} is not a lab address (10.200.x.y)")

    # Ansible: INI inventory with the lab's addresses, cfg with strict host keys and pipelining.
    hosts = ["[robots]"] + [
        f"{r.name} ansible_host={r.ip} ansible_port={r.port} ansible_user={USER} ansible_ssh_private_key_file={key}"
        for r in lab.robots
    ]
    (work / "hosts.ini").write_text("\n".join(hosts) + "\n")
    (work / "play.yml").write_text(PLAYBOOK)
    cp_dir = work / "cp"
    (work / "ansible.cfg").write_text(
        "[defaults]\n"
        f"forks = {min(n, ansible_forks or n)}\n"
        "gathering = explicit\n"
        "host_key_checking = True\n"
        "interpreter_python = /usr/bin/python3\n"
        "retry_files_enabled = False\n"
        "[ssh_connection]\n"
        "pipelining = True\n"
        "ssh_args = -C -o ControlMaster=auto -o ControlPersist=60s"
        f" -o UserKnownHostsFile={known} -o GlobalKnownHostsFile=/dev/null"
        " -o StrictHostKeyChecking=yes -o IdentitiesOnly=yes\n"
        f"control_path_dir = {cp_dir}\n"
    )
    # pyinfra: Python inventory with the same data, strict host keys against the lab's file.
    pyhosts = [
        (r.name, {"ssh_hostname": r.ip, "ssh_port": r.port, "ssh_user": USER, "ssh_key": key,
                  "ssh_known_hosts_file": known, "ssh_strict_host_key_checking": "yes",
                  "ssh_allow_agent": False, "ssh_look_for_keys": False})
        for r in lab.robots
    ]
    (work / "inventory.py").write_text(f"robots = {pyhosts!r}\n")
    (work / "deploy.py").write_text(DEPLOY)

    po = [panther_ops, "-i", inv, "config", "set", "wheel_type", "WH02", "--all", "--yes"]
    # the floor: one OpenSSH client per robot, all started at once, waited for together
    import shlex

    ssh_cfg = str(lab.ssh_config_path)
    floor = " ".join(f"ssh -F {shlex.quote(ssh_cfg)} {r.name} {shlex.quote(FLOOR_REMOTE)} &" for r in lab.robots
                     if not r.jump)
    (work / "floor.sh").write_text(f"{floor} wait\n")  # a file: at 300 robots one argument would exceed 128 KiB
    floor_argv = ["sh", str(work / "floor.sh")]  # each file is checked afterwards
    ansible_env = {"ANSIBLE_CONFIG": str(work / "ansible.cfg"), "ANSIBLE_HOME": str(work / "ansible-home"),
                   "ANSIBLE_NOCOLOR": "1"}
    tools = [
        Tool("panther-ops", "panther-ops (default: recreate + verify)", po),
        Tool("panther-ops-no-restart", "panther-ops --no-restart", [*po, "--no-restart"]),
        Tool("floor", "floor: ssh + sed -i, all at once", floor_argv),
        Tool("pyinfra", "pyinfra", [str(bindir / "pyinfra"), "-y", "--parallel", str(n),
                                    str(work / "inventory.py"), str(work / "deploy.py")]),
        Tool("ansible", f"ansible (pipelining, forks {min(n, ansible_forks or n)})",
             [str(bindir / "ansible-playbook"), "-i", str(work / "hosts.ini"), str(work / "play.yml")],
             ansible_env, cp_dir),
    ]
    for k in po_forks:  # panther-ops at another --forks (the default is 32)
        if min(k, n) != min(DEFAULT_FORKS, n) and "panther-ops-no-restart" in wanted:
            tools.append(Tool(f"panther-ops-no-restart@forks{k}", f"panther-ops --no-restart --forks {k}",
                              [*po, "--no-restart", "--forks", str(k)]))
    for label, exe in also:  # other builds of panther-ops, timed in the same lab, in turn with this one
        alt = [exe, *po[1:]]
        if "panther-ops" in wanted:
            tools.append(Tool(f"panther-ops@{label}", f"panther-ops, {label}", alt))
        if "panther-ops-no-restart" in wanted:
            tools.append(Tool(f"panther-ops-no-restart@{label}", f"panther-ops --no-restart, {label}",
                              [*alt, "--no-restart"]))
    return [t for t in tools if t.key in wanted or "@" in t.key]


def close_control_masters(cp_dir: Path) -> None:
    """End the ControlPersist masters Ansible left (so the next run starts cold)."""
    if not cp_dir.is_dir():
        return
    for sock in cp_dir.iterdir():
        subprocess.run(["ssh", "-o", f"ControlPath={sock}", "-O", "exit", "lab-robot"],
                       capture_output=True, timeout=10, check=False)
    shutil.rmtree(cp_dir, ignore_errors=True)


# ---------------------------------------------------------------------------------------
# the lab side: reset, check, count
# ---------------------------------------------------------------------------------------
class Fleet:
    def __init__(self, lab: Any) -> None:
        self.lab = lab
        self.robots = list(lab.robots)
        self.original = {r.name: lab.read_bytes(r.name, COMPOSE) for r in self.robots}
        self.expected = {k: expected_after(v.decode()).encode() for k, v in self.original.items()}
        self.home = {r.name: Path(r.dir) / "home" / USER for r in self.robots}
        for r in self.robots:  # the host path of the home must be the robot's home
            if (self.home[r.name] / "compose.yaml").read_bytes() != self.original[r.name]:
                raise SystemExit(f"{r.name}: cannot find the robot's home under {r.dir}")
        self.home_entries = {k: set(os.listdir(v)) for k, v in self.home.items()}
        self.sshd_log = {r.name: Path(r.dir) / "var" / "log" / "sshd.log" for r in self.robots}
        self.pids = robot_pids(lab)
        self.extra = {name: (roles.get("dockerd"),) for name, roles in _roles(lab).items()}
        # one relay process carries up to 100 robots: each PID once
        self.relays = sorted({roles["relay"] for roles in _roles(lab).values() if "relay" in roles})
        self.cgroup = Path("/sys/fs/cgroup/cpuacct") / lab.st.cgroup_parent.lstrip("/") / "cpuacct.usage"

    def relay_cpu(self) -> float:
        """CPU seconds the delay relays (the emulated network) used so far."""
        return sum(_proc_cpu(pid) for pid in self.relays) / os.sysconf("SC_CLK_TCK")

    def robot_cpu(self) -> float | None:
        """CPU seconds used so far on the robots by sshd and all it ran (reaped processes)."""
        if not self.pids:
            return None
        total = 0
        for pids in self.pids.values():
            for pid in pids:
                total += _proc_cpu(pid)
        for extra in self.extra.values():  # dockerd and what it reaped
            total += sum(_proc_cpu(pid) for pid in extra if pid is not None)
        containers = 0.0
        if self.cgroup.exists():  # the robots' containers (the lab's docker cgroup parent)
            containers = int(self.cgroup.read_text()) / 1e9
        return total / os.sysconf("SC_CLK_TCK") + containers

    def wait_sessions_closed(self, timeout: float = 5.0) -> None:
        """Wait until every robot's sshd has reaped its connections (their CPU is then counted)."""
        deadline = time.monotonic() + timeout
        for pid, _init in self.pids.values():
            children = Path(f"/proc/{pid}/task/{pid}/children")
            while time.monotonic() < deadline and children.exists() and children.read_text().strip():
                time.sleep(0.02)

    def reset(self) -> None:
        for r in self.robots:
            home = self.home[r.name]
            for entry in set(os.listdir(home)) - self.home_entries[r.name]:
                p = home / entry
                if p.is_dir() and not p.is_symlink():
                    shutil.rmtree(p)
                else:
                    p.unlink()
            self.lab.write(r.name, COMPOSE, self.original[r.name])

    def contents(self) -> dict[str, bytes]:
        return {r.name: (self.home[r.name] / "compose.yaml").read_bytes() for r in self.robots}

    def stats(self) -> dict[str, tuple[int, int]]:
        out = {}
        for r in self.robots:
            st = (self.home[r.name] / "compose.yaml").stat()
            out[r.name] = (st.st_ino, st.st_mtime_ns)
        return out

    def check_changed(self, label: str) -> None:
        bad = [k for k, v in self.contents().items() if v != self.expected[k]]
        if bad:
            got = self.contents()[bad[0]].decode(errors="replace")
            raise RuntimeError(f"{label}: compose.yaml not as expected on {len(bad)} robot(s), e.g. {bad[0]}:\n{got}")

    def log_offsets(self) -> dict[str, int]:
        return {k: p.stat().st_size if p.exists() else 0 for k, p in self.sshd_log.items()}

    def sessions(self, since: dict[str, int]) -> tuple[float, float]:
        """Median per robot of (connections accepted, exec sessions) since the offsets."""
        conns, execs = [], []
        for k, p in self.sshd_log.items():
            with open(p, "rb") as f:
                f.seek(since[k])
                text = f.read().decode(errors="replace")
            conns.append(len(re.findall(r"^Accepted \S+ for ", text, re.M)))
            execs.append(len(re.findall(r"^Starting session: ", text, re.M)))
        return statistics.median(conns), statistics.median(execs)


def _proc_cpu(pid: int) -> int:
    """utime + stime + cutime + cstime of ``pid`` in clock ticks (0 once it is gone)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0
    return sum(int(x) for x in fields[11:15])


def _roles(lab: Any) -> dict[str, dict[str, int]]:
    return {name: {p.role: int(p.pid) for p in rs.procs} for name, rs in lab.state.robots.items()}


def robot_pids(lab: Any) -> dict[str, tuple[int, int]]:
    """Each robot's listening sshd and its init (from the lab's state); empty when unknown.

    Between them they reap everything a connection ran: sshd its connection processes, the
    robot's init (PID 1 of the robot) the session commands orphaned when a connection ends.
    """
    out = {}
    try:
        for name, rs in lab.state.robots.items():
            roles = {p.role: int(p.pid) for p in rs.procs}
            pids = (roles["sshd"], roles["init"])
            if all(Path(f"/proc/{pid}/stat").exists() for pid in pids):
                out[name] = pids
    except (AttributeError, KeyError, TypeError, ValueError):
        return {}
    return out


def machine_cpu() -> tuple[float, float]:
    """(busy, steal) CPU seconds of the whole machine so far, from /proc/stat."""
    f = [int(x) for x in Path("/proc/stat").read_text().splitlines()[0].split()[1:]]
    user, nice, system, _idle, _iowait, irq, softirq, steal = f[:8]
    hz = os.sysconf("SC_CLK_TCK")
    return (user + nice + system + irq + softirq) / hz, steal / hz


@dataclass
class Run:
    wall: float
    cpu: float
    robot_cpu: float | None
    conns: float
    execs: float
    other_cpu: float | None = None
    """Machine CPU in the run that neither the tool, the robots nor the relays used (other work, the kernel)."""
    steal: float = 0.0
    relay_cpu: float = 0.0
    mem_peak: int | None = None
    """Peak memory of the tool's process tree in bytes: its own memory cgroup's peak (None without one)."""
    rss_sum: int | None = None
    """Sum over the tree's processes of each one's peak RSS (VmHWM), sampled: shared pages counted in
    every process that maps them, so an upper bound."""


MEMCG_ROOT = Path("/sys/fs/cgroup/memory")


class MemoryCgroup:
    """A fresh cgroup v1 memory group for one timed run: the tool's process enters it before it
    execs, so everything it starts (forks, ssh clients, Ansible's ControlPersist masters) is in
    it. ``memory.max_usage_in_bytes`` is then the run's peak, each page counted once: anonymous
    memory plus the page cache the run itself brought in (files already cached, e.g. the
    interpreter and libraries read by an earlier run, stay charged where they were first read).
    On a cgroup v2 machine ``memory.peak`` means the same. None where neither is writable."""

    def __init__(self, name: str) -> None:
        self.path: Path | None = None
        for root, peak in ((MEMCG_ROOT, "memory.max_usage_in_bytes"), (Path("/sys/fs/cgroup"), "memory.peak")):
            if (root / peak).exists() or (root / "cgroup.controllers").exists():
                try:
                    path = root / name
                    path.mkdir(exist_ok=True)
                except OSError:
                    continue
                if (path / peak).exists():
                    self.path, self.peak_file = path, peak
                    break
                path.rmdir()

    def wrap(self, argv: list[str]) -> list[str]:
        """``argv`` started inside the group: a shell enters it, then execs the tool (no fork)."""
        if self.path is None:
            return argv
        return ["sh", "-c", 'echo $$ > "$0" && exec "$@"', str(self.path / "cgroup.procs"), *argv]

    def peak(self) -> int | None:
        return None if self.path is None else int((self.path / self.peak_file).read_text())

    def sample_hwm(self, stop: threading.Event, interval: float = 0.2) -> dict[int, int]:
        """Until ``stop``: every ``interval`` s, each process's VmHWM (kB) in the group, the last seen per PID."""
        seen: dict[int, int] = {}
        while self.path is not None:
            try:
                pids = [int(x) for x in (self.path / "cgroup.procs").read_text().split()]
            except OSError:
                pids = []
            for pid in pids:
                try:
                    status = Path(f"/proc/{pid}/status").read_text()
                except OSError:
                    continue
                m = re.search(r"^VmHWM:\s+(\d+) kB", status, re.M)
                if m:
                    seen[pid] = max(seen.get(pid, 0), int(m.group(1)))
            if stop.wait(interval):
                break
        return seen

    def remove(self) -> None:
        if self.path is None:
            return
        for _ in range(100):  # the last processes (ssh masters) may still be exiting
            try:
                self.path.rmdir()
                return
            except OSError:
                for pid in (self.path / "cgroup.procs").read_text().split():
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(int(pid), 9)
                time.sleep(0.05)


def run_tool(tool: Tool, fleet: Fleet, work: Path, tag: str) -> Run:
    if tool.ansible_cp_dir is not None:
        close_control_masters(tool.ansible_cp_dir)
    fleet.wait_sessions_closed()
    since = fleet.log_offsets()
    robot_cpu0 = fleet.robot_cpu()
    relay0 = fleet.relay_cpu()
    busy0, steal0 = machine_cpu()
    env = {**os.environ, **tool.env}
    out = work / f"{tool.key}-{tag}.log"
    memcg = MemoryCgroup(f"config-bench-{os.getpid()}-{tool.key.replace('@', '-')}-{tag}")
    stop = threading.Event()
    hwm: dict[int, int] = {}
    sampler = threading.Thread(target=lambda: hwm.update(memcg.sample_hwm(stop)), daemon=True)
    try:
        sampler.start()
        with open(out, "wb") as fo:
            t0 = time.perf_counter()
            p = subprocess.Popen(memcg.wrap(tool.argv), stdin=subprocess.DEVNULL, stdout=fo, stderr=subprocess.STDOUT,
                                 env=env, cwd=work)
            try:
                _, status, ru = os.wait4(p.pid, 0)
            except BaseException:
                p.kill()
                p.wait()
                raise
            wall = time.perf_counter() - t0
            busy1, steal1 = machine_cpu()
            p.returncode = os.waitstatus_to_exitcode(status)
        if tool.ansible_cp_dir is not None:
            close_control_masters(tool.ansible_cp_dir)
        mem_peak = memcg.peak()
    finally:
        stop.set()
        sampler.join()
        memcg.remove()
    rss_sum = sum(hwm.values()) * 1024 if memcg.path is not None else None
    if p.returncode != 0:
        tail = out.read_text(errors="replace")[-3000:]
        raise RuntimeError(f"{tool.label} exited {p.returncode}:\n{tail}")
    fleet.wait_sessions_closed()
    time.sleep(0.05)  # let sshd finish writing its log lines
    robot_cpu1 = fleet.robot_cpu()
    relay = fleet.relay_cpu() - relay0
    robot_cpu = None if robot_cpu0 is None or robot_cpu1 is None else robot_cpu1 - robot_cpu0
    conns, execs = fleet.sessions(since)
    cpu = ru.ru_utime + ru.ru_stime
    other = None if robot_cpu is None else max(0.0, busy1 - busy0 - cpu - robot_cpu - relay)
    return Run(wall, cpu, robot_cpu, conns, execs, other, steal1 - steal0, relay, mem_peak, rss_sum)


def bench_size(n: int, rtt: float, args: argparse.Namespace, bindir: Path, wanted: list[str]) -> dict[str, Any]:
    from tests.lab import Lab

    # docker only where a tool recreates the driver (panther-ops' default path); a lab of hundreds
    # runs without (docs/lab.md), and --no-restart, the floor, pyinfra and Ansible never touch it
    lab = Lab(n, docker="panther-ops" in wanted, images=("2.1.1",), prefix=args.prefix, ephemeral=True,
              rtt_ms=rtt)
    work = Path(tempfile.mkdtemp(prefix=f"panther-ops-config-bench-{n}-"))
    result: dict[str, Any] = {"robots": n, "rtt_ms": rtt, "tools": {}}
    try:
        t = time.perf_counter()
        lab.up()
        log(f"N={n} RTT {rtt:g} ms: lab {lab.prefix} up in {time.perf_counter() - t:.2f} s")
        fleet = Fleet(lab)
        tools = make_tools(lab, n, work, bindir, args.panther_ops, wanted, args.also, args.ansible_forks,
                           args.po_forks)
        for tool in tools:  # untimed: warm-up + correctness + idempotence
            fleet.reset()
            run_tool(tool, fleet, work, "warmup")
            fleet.check_changed(tool.label)
            before = fleet.stats()
            run_tool(tool, fleet, work, "again")
            fleet.check_changed(f"{tool.label} (second run)")
            if fleet.stats() != before:
                raise RuntimeError(f"{tool.label}: a second run rewrote compose.yaml (not idempotent)")
            log(f"N={n}: {tool.label}: changes every robot as expected; a second run changes nothing")
        runs: dict[str, list[Run]] = {t.key: [] for t in tools}
        discarded = 0
        for rep in range(args.repeat):
            order = tools[rep % len(tools):] + tools[: rep % len(tools)]
            for tool in order:
                for attempt in range(args.retries + 1):
                    fleet.reset()
                    r = run_tool(tool, fleet, work, f"run{rep}")
                    fleet.check_changed(tool.label)
                    busy = r.other_cpu is not None and r.other_cpu > args.max_other_cpu
                    if not busy or attempt == args.retries:
                        break
                    discarded += 1
                    log(f"N={n} run {rep + 1}/{args.repeat}: {tool.label}: {r.wall:.2f} s discarded, other "
                        f"processes used {r.other_cpu:.2f} s CPU meanwhile; again")
                runs[tool.key].append(r)
                rcpu = "?" if r.robot_cpu is None else f"{r.robot_cpu:.2f}"
                mem = "?" if r.mem_peak is None else f"{r.mem_peak / 2**20:.0f} MB"
                log(f"N={n} RTT {rtt:g} run {rep + 1}/{args.repeat}: {tool.label:24s} {r.wall:6.2f} s "
                    f"(cpu {r.cpu:.2f} s tool + {rcpu} s robots, {r.conns:g} conn + {r.execs:g} exec per robot, "
                    f"peak memory {mem}, sum of peak RSS {(r.rss_sum or 0) / 2**20:.0f} MB)")
        for tool in tools:
            rs = runs[tool.key]
            walls = [r.wall for r in rs]
            result["tools"][tool.key] = {
                "label": tool.label,
                "argv": [a.replace(str(work), "$WORK") for a in tool.argv],
                "median_s": statistics.median(walls),
                "min_s": min(walls),
                "max_s": max(walls),
                "runs_s": walls,
                "cpu_median_s": statistics.median(r.cpu for r in rs),
                "cpu_per_robot_ms": statistics.median(r.cpu for r in rs) / n * 1000,
                "mem_peak_mb": (None if any(r.mem_peak is None for r in rs)
                                else statistics.median(r.mem_peak for r in rs) / 2**20),
                "rss_sum_mb": (None if any(r.rss_sum is None for r in rs)
                               else statistics.median(r.rss_sum for r in rs) / 2**20),
                "robot_cpu_median_s": (None if any(r.robot_cpu is None for r in rs)
                                       else statistics.median(r.robot_cpu for r in rs)),
                "relay_cpu_median_s": statistics.median(r.relay_cpu for r in rs),
                "round_trips": statistics.median(walls) / (rtt / 1000.0) if rtt else None,
                "connections_per_robot": statistics.median(r.conns for r in rs),
                "exec_sessions_per_robot": statistics.median(r.execs for r in rs),
            }
        others = [r.other_cpu for rs in runs.values() for r in rs if r.other_cpu is not None]
        result["other_cpu_s"] = {"median": statistics.median(others), "max": max(others)} if others else None
        result["discarded_runs"] = discarded
        steals = [r.steal for rs in runs.values() for r in rs]
        result["steal_s"] = {"median": statistics.median(steals), "max": max(steals)}
        return result
    finally:
        t = time.perf_counter()
        try:
            lab.down()
            log(f"N={n}: lab down in {time.perf_counter() - t:.2f} s")
        finally:
            if args.keep_work:
                log(f"N={n}: work files kept in {work}")
            else:
                shutil.rmtree(work, ignore_errors=True)


# ---------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------
def ratios(size: dict[str, Any], key: str = "panther-ops-no-restart") -> dict[str, float]:
    """panther-ops --no-restart's (or the tool ``key``'s) median wall time over the others'."""
    tools = size["tools"]
    out = {}
    if key in tools:
        po = tools[key]["median_s"]
        for other in ("floor", "pyinfra", "ansible"):
            if other in tools:
                out[other] = po / tools[other]["median_s"]
    return out


def table(doc: dict[str, Any]) -> str:
    rows = ["| robots | RTT | tool | median wall | min–max | round trips | CPU tool | CPU tool / robot | peak memory "
            "| sum of peak RSS | CPU robots | CPU relays | conn + exec per robot | × floor | × pyinfra | × Ansible |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for size in doc["sizes"]:
        tools = size["tools"]
        bases = {k: tools.get(k, {}).get("median_s") for k in ("floor", "pyinfra", "ansible")}
        for t in tools.values():
            rel = [f"{t['median_s'] / b:.2f}" if b else "-" for b in bases.values()]
            rcpu = "?" if t["robot_cpu_median_s"] is None else f"{t['robot_cpu_median_s']:.2f} s"
            rt = "-" if t["round_trips"] is None else f"{t['round_trips']:.1f}"
            mem = "?" if t.get("mem_peak_mb") is None else f"{t['mem_peak_mb']:.0f} MB"
            rss = "?" if t.get("rss_sum_mb") is None else f"{t['rss_sum_mb']:.0f} MB"
            rows.append(f"| {size['robots']} | {size['rtt_ms']:g} ms | {t['label']} | {t['median_s']:.2f} s | "
                        f"{t['min_s']:.2f}–{t['max_s']:.2f} s | {rt} | {t['cpu_median_s']:.2f} s | "
                        f"{t['cpu_per_robot_ms']:.1f} ms | {mem} | {rss} | {rcpu} | "
                        f"{t['relay_cpu_median_s']:.2f} s | {t['connections_per_robot']:g} + "
                        f"{t['exec_sessions_per_robot']:g} | {' | '.join(rel)} |")
    lines = ["\n".join(rows), ""]
    for size in doc["sizes"]:
        goals = targets(size["robots"], size["rtt_ms"])
        for key, tool in size["tools"].items():  # panther-ops --no-restart, at each --forks timed
            if not key.startswith("panther-ops-no-restart"):
                continue
            parts = []
            for other, v in ratios(size, key).items():
                goal = goals.get(other)
                verdict = "" if goal is None else f" (target ≤ {goal}: {'met' if v <= goal else 'MISSED'})"
                parts.append(f"{v:.2f}× {other}{verdict}")
            if parts:
                head = f"N={size['robots']} RTT {size['rtt_ms']:g} ms: {tool['label']} = "
                lines.append("- " + head + "; ".join(parts))
    for s in doc["sizes"]:
        o, st = s.get("other_cpu_s"), s["steal_s"]
        if o is not None:
            lines.append(f"- N={s['robots']} RTT {s['rtt_ms']:g} ms: machine CPU used by neither the tool, the robots "
                         f"nor the relays during a timed run: median {o['median']:.2f} s, max {o['max']:.2f} s; "
                         f"steal: median {st['median']:.2f} s, max {st['max']:.2f} s; "
                         f"{s['discarded_runs']} run(s) discarded and repeated for other work")
    return "\n".join(lines)


def compile_bytecode(exe: str) -> None:
    """Compile the checkout's modules for the interpreter of ``exe`` (its shebang), as pip does
    when it installs a package: an editable install run with PYTHONDONTWRITEBYTECODE set would
    otherwise compile panther_ops from source on every run, which the other tools, installed
    from wheels, never do."""
    try:
        first = Path(exe).read_bytes().split(b"\n", 1)[0].decode()
    except (OSError, UnicodeDecodeError):
        return
    if first.startswith("#!") and "python" in first:
        subprocess.run([*first[2:].split(), "-m", "compileall", "-q", str(REPO / "panther_ops")], check=True,
                       stdout=subprocess.DEVNULL)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="10,30", help="robot counts, comma separated (default 10,30)")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per tool and size (default 3)")
    ap.add_argument("--rtts", default="0,50,150", help="round trips in ms, comma separated (default 0,50,150)")
    ap.add_argument("--tools", default=ALL_TOOLS, help=f"subset of {ALL_TOOLS}")
    ap.add_argument("--json", action="store_true", help="print one JSON document instead of the table")
    ap.add_argument("--out", type=Path, default=None,
                    help="also write the JSON document to this file, after each size and RTT (a long run "
                         "keeps what it measured if a later size fails)")
    ap.add_argument("--venv", type=Path, default=DEFAULT_VENV,
                    help=f"venv for ansible/pyinfra (default {DEFAULT_VENV})")
    ap.add_argument("--panther-ops", default=None,
                    help="panther-ops executable (default: this checkout installed into its own venv, "
                         f"{DEFAULT_PO_VENV}, as a wheel)")
    ap.add_argument("--also", action="append", default=[], metavar="LABEL=EXE",
                    help="another panther-ops executable (e.g. a build of main) timed in the same lab, in turn "
                         "with this one: paired runs for a before/after comparison (repeatable)")
    ap.add_argument("--prefix", default=None, help="lab prefix (default: the first free one)")
    ap.add_argument("--keep-work", action="store_true", help="keep the generated files and tool logs")
    ap.add_argument("--max-other-cpu", type=float, default=0.5,
                    help="repeat a timed run during which other processes used more CPU seconds (default 0.5)")
    ap.add_argument("--retries", type=int, default=3, help="how often to repeat such a run (default 3)")
    ap.add_argument("--ansible-forks", type=int, default=None,
                    help="cap Ansible's forks (default: one per robot, its documented best for a fleet this "
                         "size; cap it where the machine cannot hold that many workers)")
    ap.add_argument("--po-forks", default="",
                    help="also time panther-ops --no-restart with these --forks, comma separated (e.g. 100,300), "
                         "beside its default 32, where they change how many robots are worked on at once")
    args = ap.parse_args()
    args.po_forks = tuple(int(k) for k in args.po_forks.split(",") if k.strip())
    args.also = tuple(tuple(a.split("=", 1)) for a in args.also)
    if any(len(a) != 2 or not a[0] or not a[1] for a in args.also):
        log("config_bench: --also takes LABEL=EXE")
        return 2
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    rtts = [float(s) for s in args.rtts.split(",") if s.strip()]
    wanted = [t.strip() for t in args.tools.split(",") if t.strip()]
    if os.geteuid() != 0:
        log("config_bench: the lab needs root")
        return 2
    if args.repeat < 1 or not sizes or any(not 1 <= n <= MAX_ROBOTS for n in sizes):
        log(f"config_bench: --repeat ≥ 1 and sizes within 1..{MAX_ROBOTS}")
        return 2
    ensure_project_python()
    sys.path.insert(0, str(REPO))
    from tests.lab import missing_requirements

    missing = missing_requirements(docker="panther-ops" in wanted)
    if missing:
        log("config_bench: the lab cannot run here: " + "; ".join(missing))
        return 2
    bindir = ensure_tool_venv(args.venv) if {"pyinfra", "ansible"} & set(wanted) else args.venv / "bin"
    if args.panther_ops is None:
        args.panther_ops = ensure_panther_ops_venv(DEFAULT_PO_VENV)
    else:
        compile_bytecode(args.panther_ops)
    for _, exe in args.also:
        compile_bytecode(exe)
    doc: dict[str, Any] = {
        "benchmark": "config set wheel_type WH02 on N robots at RTT 0/50/150 ms",
        "date": time.strftime("%Y-%m-%d"),
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "kernel": platform.release()},
        "versions": {
            "panther-ops": version_of([args.panther_ops, "--version"]),
            "pyinfra": version_of([str(bindir / "pyinfra"), "--version"]),
            "ansible-core": version_of([str(bindir / "ansible-playbook"), "--version"]),
            "openssh": version_of(["ssh", "-V"]),
        },
        "panther_ops_source": git_state(),
        "repeat": args.repeat,
        "sizes": [],
    }
    t0 = time.perf_counter()
    for n in sizes:
        for rtt in rtts:
            doc["sizes"].append(bench_size(n, rtt, args, bindir, wanted))
            if args.out is not None:
                args.out.write_text(json.dumps(doc, indent=2) + "\n")
    doc["total_s"] = time.perf_counter() - t0
    for size in doc["sizes"]:
        size["ratios"] = ratios(size)
    if args.json:
        print(json.dumps(doc, indent=2))
    else:
        v = doc["versions"]
        print(f"config set wheel_type WH02 on N robots — {doc['date']}, {doc['machine']['cpus']} CPUs, "
              f"Python {doc['machine']['python']}; median of {args.repeat} fresh runs")
        print(f"{v['panther-ops']} ({args.panther_ops}; checkout {doc['panther_ops_source']}); {v['pyinfra']}; "
              f"{v['ansible-core']}; {v['openssh']}")
        print(table(doc))
        print(f"total {doc['total_s']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
