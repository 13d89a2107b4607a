"""`panther-ops trust ROBOT`: show a robot's host key and record it on request."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.errors import UsageError
from panther_ops.transport.hostkeys import (
    append_known_host,
    fingerprint,
    known_hosts_name,
    replace_known_host,
)


@dataclass(frozen=True)
class TrustPlan:
    robot: str
    address: str
    key_type: str
    fingerprint: str
    state: str  # "known" | "new" | "changed"
    known_fingerprints: tuple[str, ...]
    known_hosts_file: str
    hostname: str
    port: int
    key: Any

    def record(self) -> None:
        """Record the offered key (replacing the old one when it changed)."""
        if self.state == "changed":
            replace_known_host(self.known_hosts_file, self.hostname, self.port, self.key)
        else:
            append_known_host(self.known_hosts_file, self.hostname, self.port, self.key)


def plan_trust(inventory: Inventory, robot: Robot) -> TrustPlan:
    if robot.transport == "local":
        raise UsageError(f"{robot.name} is a local (demo) robot: it has no host key")
    from panther_ops.transport.ssh import fetch_host_key, known_keys

    hop, key = fetch_host_key(inventory.endpoint(robot))
    known = known_keys(hop)
    fp = fingerprint(key)
    known_fps = tuple(fingerprint(k) for k in known)
    same_type = [k for k in known if k.get_name() == key.get_name()]
    if any(fingerprint(k) == fp for k in known):
        state = "known"
    elif same_type:
        state = "changed"
    else:
        state = "new"
    return TrustPlan(
        robot=robot.name, address=known_hosts_name(hop.hostname, hop.port), key_type=key.get_name(),
        fingerprint=fp, state=state, known_fingerprints=known_fps,
        known_hosts_file=hop.known_hosts[0], hostname=hop.hostname, port=hop.port, key=key,
    )
