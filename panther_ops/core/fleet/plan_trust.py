"""The planner of `panther-ops trust ROBOT`: a change whose subject is the robot's host key in
the operator's known_hosts file. A pure function of what was read: the key the robot offers
with the keys known for it (the fact ``host key``, read by `trust.py` without trusting the
robot), and the known_hosts file's content; the plan is that file's exact edit (one line
added, or the robot's old lines replaced with ``--replace``), written by the pipeline as any
local file (backup, staged, renamed only if unchanged)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import PurePosixPath

from panther_ops.core.fleet.plan import FileEdit, RobotPlan
from panther_ops.core.fleet.reads import Reads
from panther_ops.errors import HostKeyError, UsageError

HOST_KEY = "host key"
"""The fact a trust plan asks for: the key a robot offers and the ones known for it."""


@dataclass(frozen=True)
class OfferedKey:
    """The key a robot offers (read through the transport, without authenticating)."""

    hostname: str
    port: int
    address: str
    """How known_hosts names the host (``host`` or ``[host]:port``)."""
    key_type: str
    key_base64: str
    fingerprint: str
    known: tuple[tuple[str, str], ...]
    """(type, fingerprint) of every key the known_hosts files hold for the host."""
    known_hosts_file: str
    """The file the key is recorded in (the first known_hosts file of the inventory)."""


def trust_state(key_type: str, fingerprint: str, known: Sequence[tuple[str, str]]) -> str:
    """``known`` (that key is recorded), ``changed`` (another key of its type is) or ``new``;
    ``known``: (type, fingerprint) of every key recorded for the host."""
    if any(fp == fingerprint for _t, fp in known):
        return "known"
    if any(t == key_type for t, _fp in known):
        return "changed"
    return "new"


def known_hosts_after(text: str, offered: OfferedKey, replace: bool) -> str:
    """known_hosts with the offered key recorded: appended, or (``replace``) the host's plain
    lines dropped first (hashed lines and comments are kept as they are)."""
    line = f"{offered.address} {offered.key_type} {offered.key_base64}\n"
    lines = text.splitlines(keepends=True)
    if replace:
        lines = [ln for ln in lines
                 if ln.lstrip().startswith("#") or not ln.split() or offered.address not in ln.split()[0].split(",")]
    if lines and not lines[-1].endswith("\n"):
        lines[-1] += "\n"
    return "".join(lines) + line


def plan_trust(reads: Reads, robot: str, replace: bool) -> RobotPlan:
    """The plan recording ``robot``'s offered key (nothing when it is known; a changed key is
    refused unless ``replace``: the operator checked it on the robot)."""
    offered: OfferedKey = reads.fact(HOST_KEY, robot)
    state = trust_state(offered.key_type, offered.fingerprint, offered.known)
    known_fps = [fp for _t, fp in offered.known]
    data = {"robot": robot, "address": offered.address, "key_type": offered.key_type,
            "fingerprint": offered.fingerprint, "state": state, "known_hosts_file": offered.known_hosts_file,
            "known_fingerprints": known_fps}
    said = f"{robot} ({offered.address}) offers {offered.key_type} {offered.fingerprint}"
    if state == "known":
        return RobotPlan(reads.robot, said, noop=f"{said}: already trusted in {offered.known_hosts_file}",
                         data=data)
    if state == "changed" and not replace:
        raise HostKeyError(robot, f"host key changed: refused ({offered.known_hosts_file} has "
                           f"{', '.join(known_fps)})", offered=offered.fingerprint, expected=", ".join(known_fps),
                           hint="if you reinstalled the robot and checked the fingerprint on it: "
                           f"panther-ops trust {robot} --replace")
    before = reads.file(offered.known_hosts_file)
    try:
        text = (before or b"").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UsageError(f"{offered.known_hosts_file} is not UTF-8 text ({exc.reason} at byte {exc.start})",
                         hint="nothing was recorded") from exc
    after = known_hosts_after(text, offered, replace=state == "changed").encode()
    verb = "replace the changed key with" if state == "changed" else "record"
    return RobotPlan(reads.robot, f"{verb} {offered.key_type} {offered.fingerprint} in {offered.known_hosts_file}",
                     [FileEdit(offered.known_hosts_file, before, after, 0o600)], data=data,
                     home=str(PurePosixPath(offered.known_hosts_file).parent))
