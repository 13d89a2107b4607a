"""The lab's state file (`<labdir>/state.json`): everything the lab owns, written before it exists.

`down` (and `up` after a crash) tear down exactly what this file names: network namespaces,
bridges, host routes, every PID started (with its start time, so a reused PID is never
signalled), the docker cgroup parent and the lab directory.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

STATE_VERSION = 1
DEFAULT_BASE = Path(os.environ.get("PANTHER_OPS_LAB_BASE", "/root/.cache/panther-ops-lab"))


@dataclass
class Proc:
    """One process the lab started: `pid` checked against `start` (clock ticks since boot)."""

    role: str
    pid: int
    start: int | None

    def key(self) -> tuple[int, int | None]:
        return (self.pid, self.start)


@dataclass
class RobotState:
    name: str
    index: int
    ns: str
    ip: str
    dir: str
    image: str  # version key: "2.0.4", "2.1.1" or "2.2.2"
    serial: str
    docker: bool
    jump: str | None = None  # robot reachable only through this robot
    link: str = ""  # host-side (or jump-side) end of the robot's veth pair
    clock_offset: int = 0
    password: bool = False
    procs: list[Proc] = field(default_factory=list)
    kind: str = "robot"  # or "computer": a user computer (tests/lab/computers.py)

    def proc(self, role: str) -> Proc | None:
        for p in self.procs:
            if p.role == role:
                return p
        return None

    def drop(self, role: str) -> None:
        self.procs = [p for p in self.procs if p.role != role]


@dataclass
class LabState:
    prefix: str
    dir: str
    subnet: int  # robots on 10.200.<subnet>.0/<24, 23 or 22> (see `span`)
    bridge: str
    cgroup_parent: str
    docker: bool
    robots: dict[str, RobotState] = field(default_factory=dict)
    jump_subnets: dict[str, int] = field(default_factory=dict)  # jump robot -> hidden subnet
    routes: list[str] = field(default_factory=list)  # host routes the lab added
    owner: Proc | None = None  # process whose exit ends the lab (pytest); None: persistent
    version: int = STATE_VERSION
    created: float = 0.0
    rtt_ms: float = 0.0  # > 0: each robot's sshd behind a delay relay (tests/lab/relay.py)
    jitter_ms: float = 0.0
    rate: str | None = None  # `tc tbf` rate on each robot's eth0 (e.g. "20mbit"); None: none
    span: int = 1  # /24s of the lab's LAN, from `subnet` on (1, 2 or 4: over 240 robots)

    # -- persistence ---------------------------------------------------------------------
    def to_json(self) -> str:
        return json.dumps(asdict(self), indent=2, sort_keys=True)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> LabState:
        robots = {}
        for name, r in d.get("robots", {}).items():
            procs = [Proc(**p) for p in r.pop("procs", [])]
            robots[name] = RobotState(**r, procs=procs)
        owner = Proc(**d["owner"]) if d.get("owner") else None
        rest = {k: v for k, v in d.items() if k not in ("robots", "owner")}
        return cls(**rest, robots=robots, owner=owner)

    @classmethod
    def load(cls, path: Path) -> LabState:
        return cls.from_dict(json.loads(path.read_text()))

    def save(self) -> None:
        path = Path(self.dir) / "state.json"
        path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        tmp = path.with_suffix(".json.tmp")
        tmp.write_text(self.to_json())
        os.replace(tmp, path)

    # -- addresses -----------------------------------------------------------------------
    def all_subnets(self) -> set[int]:
        return {*range(self.subnet, self.subnet + self.span), *self.jump_subnets.values()}


@contextlib.contextmanager
def base_lock(base: Path) -> Iterator[None]:
    """Serialise prefix/subnet allocation between lab processes (pytest-xdist workers...)."""
    base.mkdir(parents=True, exist_ok=True, mode=0o700)
    with open(base / ".lock", "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def all_states(base: Path) -> list[LabState]:
    """States of every lab under `base` (unreadable ones skipped)."""
    out = []
    if not base.is_dir():
        return out
    for p in sorted(base.glob("*/state.json")):
        with contextlib.suppress(OSError, ValueError, TypeError, KeyError):
            out.append(LabState.load(p))
    return out
