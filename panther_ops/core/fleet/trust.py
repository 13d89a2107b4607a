"""`panther-ops trust ROBOT`: read the host key a robot offers and the known ones, plan
(`plan_trust.py`, pure), and record the key on request."""

from __future__ import annotations

from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.plan_trust import TrustPlan, trust_state
from panther_ops.errors import UsageError
from panther_ops.transport.hostkeys import (
    append_known_host,
    fingerprint,
    known_hosts_name,
    replace_known_host,
)


def record(plan: TrustPlan) -> None:
    """Record the offered key (replacing the old one when it changed)."""
    if plan.state == "changed":
        replace_known_host(plan.known_hosts_file, plan.hostname, plan.port, plan.key)
    else:
        append_known_host(plan.known_hosts_file, plan.hostname, plan.port, plan.key)


def plan_trust(inventory: Inventory, robot: Robot) -> TrustPlan:
    if robot.transport == "local":
        raise UsageError(f"{robot.name} is a local (demo) robot: it has no host key")
    from panther_ops.transport.ssh import fetch_host_key, known_keys

    hop, key = fetch_host_key(inventory.endpoint(robot))
    known = known_keys(hop)
    fp = fingerprint(key)
    known_fps = tuple(fingerprint(k) for k in known)
    state = trust_state(key.get_name(), fp, [(k.get_name(), f) for k, f in zip(known, known_fps, strict=True)])
    return TrustPlan(
        robot=robot.name, address=known_hosts_name(hop.hostname, hop.port), key_type=key.get_name(),
        fingerprint=fp, state=state, known_fingerprints=known_fps,
        known_hosts_file=hop.known_hosts[0], hostname=hop.hostname, port=hop.port, key=key,
    )
