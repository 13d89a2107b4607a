"""`reimage plan` and `reimage backup`: read what makes a robot itself over its one connection.

One probe (facts and the compose file), then one tar stream of every path to carry
(``carry.candidates``); the files, their modes, owners, sha256 and secrecy go into a manifest.
"""

from __future__ import annotations

import hashlib
import io
import posixpath
import tarfile
import time
from dataclasses import dataclass, field
from typing import Any

from panther_ops import __version__
from panther_ops.core.fleet.facts import RobotFacts, parse_probe, probe_command
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.reimage.carry import Candidate, candidates, is_secret, role_of
from panther_ops.core.reimage.manifest import MANIFEST_VERSION
from panther_ops.errors import OpsError, TransportError
from panther_ops.transport.base import Command
from panther_ops.transport.scripts_reimage import TAR


@dataclass
class CarriedFile:
    path: str
    role: str
    kind: str
    """file or symlink."""
    mode: str
    owner: str
    size: int
    sha256: str | None
    secret: bool
    link: str | None = None
    data: bytes = field(default=b"", repr=False)
    info: tarfile.TarInfo | None = field(default=None, repr=False)

    def to_json(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"path": self.path, "role": self.role, "kind": self.kind, "mode": self.mode,
                               "owner": self.owner, "size": self.size, "sha256": self.sha256, "secret": self.secret}
        if self.link is not None:
            doc["link"] = self.link
        return doc


@dataclass
class Carried:
    """Everything read from one robot for its backup."""

    identity: dict[str, Any]
    files: list[CarriedFile]
    missing: list[str]
    unreadable: list[str]
    desired: dict[str, Any]

    def manifest(self) -> dict[str, Any]:
        return {
            "version": MANIFEST_VERSION,
            "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "panther_ops": __version__,
            "robot": self.identity,
            "desired": self.desired,
            "files": [f.to_json() for f in self.files],
            "missing": self.missing,
            "unreadable": self.unreadable,
        }

    @property
    def total_bytes(self) -> int:
        return sum(f.size for f in self.files)


def _driver_mounts(facts: RobotFacts) -> tuple[list[str], dict[str, Any]]:
    """(host paths the driver service mounts, stack facts) from the robot's compose file."""
    if facts.compose_text is None:
        return [], {}
    from panther_ops.core.robot.compose import ComposeFile

    compose = ComposeFile.parse(facts.compose_text)
    try:
        service = compose.driver_service()
    except OpsError:
        return [], {}
    mounts = [v.source for v in compose.list_volumes(service)
              if v.source and v.source.startswith(("/", "~", "."))]
    info: dict[str, Any] = {"driver_service": service, "driver_image": compose.image(service)}
    try:
        stack = compose.stack()
        info.update(stack=stack.label(), stack_version=stack.version_str)
    except OpsError:
        pass
    return mounts, info


def _identity(ctx: RobotContext, facts: RobotFacts, home: str, stack: dict[str, Any]) -> dict[str, Any]:
    fp = getattr(ctx.transport, "host_key_fingerprint", None)
    return {
        "name": ctx.robot.name, "host": ctx.robot.host, "hostname": facts.hostname,
        "model": facts.robot_model, "serial": facts.serial, "robot_version": facts.robot_version,
        "stack": stack.get("stack"), "stack_version": stack.get("stack_version"),
        "driver_service": stack.get("driver_service"), "driver_image": stack.get("driver_image"),
        "os_build": facts.system_build_version, "os": facts.os_name,
        "host_key": fp() if callable(fp) else None, "home": home,
    }


def _files(raw: bytes, chosen: list[Candidate]) -> list[CarriedFile]:
    out = []
    with tarfile.open(fileobj=io.BytesIO(raw), mode="r:") as tar:
        for info in tar:
            name = info.name[2:] if info.name.startswith("./") else info.name
            path = "/" + posixpath.normpath(name).lstrip("/")
            owner = f"{info.uname or info.uid}:{info.gname or info.gid}"
            mode = f"{info.mode & 0o7777:04o}"
            if info.issym():
                out.append(CarriedFile(path, role_of(path, chosen), "symlink", mode, owner, 0, None, False,
                                       link=info.linkname, info=info))
            elif info.isfile():
                fh = tar.extractfile(info)
                data = fh.read() if fh is not None else b""
                out.append(CarriedFile(path, role_of(path, chosen), "file", mode, owner, len(data),
                                       hashlib.sha256(data).hexdigest(), is_secret(path, data), data=data, info=info))
    return out


def collect(ctx: RobotContext, also: tuple[str, ...] = ()) -> Carried:
    """Read the robot: one probe, one tar stream of every path to carry (and of ``also``: the
    paths a restore will write, so their current content is read too)."""
    res = ctx.transport.run(probe_command(ctx.robot.compose_file), timeout=30)
    if "@@end" not in res.stdout:
        raise TransportError(ctx.robot.name, f"probe failed (exit {res.exit_status}): {res.stderr.strip()[:200]}")
    facts = parse_probe(res.stdout)
    home = facts.home or ctx.transport.home()
    mounts, stack = _driver_mounts(facts)
    chosen = candidates(ctx.robot, home, mounts)
    chosen += [Candidate(p, "restored") for p in also
               if not any(p == c.path or p.startswith(c.path + "/") for c in chosen)]
    tar = ctx.transport.run(Command.sh(TAR, *[c.path for c in chosen]), timeout=600)
    if tar.exit_status not in (0, 2) or (tar.exit_status == 2 and not tar.raw_stdout):
        raise TransportError(ctx.robot.name, f"reading the files failed (exit {tar.exit_status}): "
                                             f"{tar.stderr.strip()[-300:]}")
    files = _files(tar.raw_stdout, chosen) if tar.raw_stdout else []
    found = [f.path for f in files]
    missing = [c.path for c in chosen if not any(p == c.path or p.startswith(c.path + "/") for p in found)]
    unreadable = [ln.strip() for ln in tar.stderr.splitlines() if "Cannot" in ln or "Permission denied" in ln]
    return Carried(_identity(ctx, facts, home, stack), files, missing, unreadable, dict(ctx.robot.desired))
