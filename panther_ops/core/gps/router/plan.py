"""The planner of `gps router set` (and of the router half of `gps enable --router`): a pure
function of the router's state as read (`read.read_state`) and what was asked.

The request types and checks are here too (what the operator asked, checked before any
robot is contacted); the reads (the router's REST API through the robot's SSH connection)
are `read.py`'s, the writes `apply.py`'s.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from panther_ops.core.fleet.plan import RobotPlan, Step
from panther_ops.core.gps.udp_address import check_port
from panther_ops.errors import UsageError

if TYPE_CHECKING:
    from panther_ops.core.gps.credentials import Credentials

DEFAULT_ROUTER = "10.15.20.1"
GLOBAL = "/api/gps/global"
FORWARDING = "/api/gps/nmea/config/nmea_forwarding"
RULES = "/api/gps/nmea/rules/config"
SENTENCES = ("GPGSV", "GPGGA", "GPVTG", "GPRMC", "GPGSA", "GLGSV", "GNGSA", "GNGNS", "GAGSV", "PQGSV", "PQGSA")
"""The sentences Husarion's router setup forwards (panther_rutx11)."""


def check_address(address: str, option: str = "--address") -> str:
    """``address`` if it is an IPv4/IPv6 address or an RFC 1123 host name, else UsageError."""
    from panther_ops.core.fleet.hostspec import HostSpecError, check_host

    try:
        return check_host(address)
    except HostSpecError as exc:
        raise UsageError(f"{option} {address!r}: {exc}; an IPv4/IPv6 address or host name, "
                         f"e.g. {DEFAULT_ROUTER}") from None


@dataclass(frozen=True)
class RouterRequest:
    """What `gps router set` asks for (None: leave as it is)."""

    enabled: bool | None = None
    hostname: str | None = None
    port: int | None = None
    sentences: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        if self.hostname is not None:
            check_address(self.hostname, "--hostname")
        if self.port is not None:
            check_port(self.port, "--port")
        for s in self.sentences or ():
            if s not in SENTENCES:
                raise UsageError(f"--sentences: unknown sentence id {s!r}", hint="known: " + ", ".join(SENTENCES))

    @property
    def empty(self) -> bool:
        return self.enabled is None and self.hostname is None and self.port is None and self.sentences is None


def parse_sentences(text: str | None) -> tuple[str, ...] | None:
    if text is None:
        return None
    ids = tuple(s.strip().upper() for s in text.split(",") if s.strip())
    if not ids:
        raise UsageError("--sentences: a comma-separated list of sentence ids, e.g. GPGGA,GPRMC")
    return ids


def summary_of(state: dict[str, Any]) -> dict[str, Any]:
    """The state in plain terms (JSON data and tables)."""
    fwd, glob = state["forwarding"], state["global"]
    on = [i for i, r in state["rules"].items() if r.get("forwarding_enabled") == "1"]
    return {"gps_enabled": glob.get("enabled") == "1", "forwarding": fwd.get("enabled") == "1",
            "hostname": fwd.get("hostname"), "port": fwd.get("port"), "proto": fwd.get("proto"), "sentences": on}


def changes(state: dict[str, Any], req: RouterRequest) -> dict[str, Any]:
    """The PUT bodies that take ``state`` to ``req`` (only the resources that change)."""
    out: dict[str, Any] = {}
    if req.enabled and state["global"].get("enabled") != "1":
        out[GLOBAL] = {"enabled": "1"}
    fwd: dict[str, str] = {}
    if req.enabled is not None:
        fwd["enabled"] = "1" if req.enabled else "0"
    if req.hostname is not None:
        fwd["hostname"] = req.hostname
    if req.port is not None:
        fwd["port"] = str(req.port)
    if req.enabled:
        fwd["proto"] = "udp"
    fwd = {k: v for k, v in fwd.items() if state["forwarding"].get(k) != v}
    if fwd:
        out[FORWARDING] = fwd
    if req.sentences is not None:
        rules = []
        for sid in sorted(set(state["rules"]) | set(req.sentences)):
            want = "1" if sid in req.sentences else "0"
            have = state["rules"].get(sid, {})
            if have.get("forwarding_enabled") != want or (want == "1" and have.get("forwarding_interval") != "1"):
                rule = {"id": sid, "forwarding_enabled": want}
                if want == "1":
                    rule["forwarding_interval"] = "1"
                rules.append(rule)
        if rules:
            out[RULES] = rules
    return out


def describe_puts(state: dict[str, Any], puts: dict[str, Any]) -> str:
    bits = []
    for path, body in puts.items():
        if path == RULES:
            on = [r["id"] for r in body if r["forwarding_enabled"] == "1"]
            off = [r["id"] for r in body if r["forwarding_enabled"] == "0"]
            bits += [f"forward {','.join(on)}"] if on else []
            bits += [f"stop {','.join(off)}"] if off else []
        else:
            name = "gps" if path == GLOBAL else "forwarding"
            cur = state["global"] if path == GLOBAL else state["forwarding"]
            bits += [f"{name}.{k}: {cur.get(k, '-')} -> {v}" for k, v in body.items()]
    return "; ".join(bits)


@dataclass(frozen=True)
class RouterPuts(Step):
    """The router's PUTs (path -> body) through the robot's connection, then its state read back
    must be as asked (``request``). ``after_driver``: `gps enable --router`, the PUTs follow
    the driver's write (only when it went well); else `gps router set`, the PUTs are the change."""

    address: str
    puts: Mapping[str, Any]
    request: RouterRequest
    creds: Credentials | None
    after_driver: bool = False


def router_plan(robot: str, address: str, state: dict[str, Any], req: RouterRequest, fingerprint: str | None,
                pinned_now: bool, creds: Credentials | None = None) -> RobotPlan:
    """`gps router set`: the PUTs that take ``state`` to ``req`` (``creds``: for the executor)."""
    puts = changes(state, req)
    plan = RobotPlan(robot, f"change router {address}: {describe_puts(state, puts)}" if puts else "",
                     noop=None if puts else f"router {address} already as asked")
    plan.data.update({"router": address, "before": summary_of(state), "certificate": fingerprint})
    if puts:
        plan.data["action"] = "router"
        plan.data["puts"] = puts
        plan.steps.append(RouterPuts(address, puts, req, creds))
    if pinned_now:
        plan.warnings.append(f"router certificate pinned on first use: {fingerprint}")
    return plan


def with_router(plan: RobotPlan, address: str, state: dict[str, Any], req: RouterRequest, fingerprint: str | None,
                pinned_now: bool, creds: Credentials | None = None) -> RobotPlan:
    """`gps enable --router`: the driver's plan, then the router's PUTs toward ``req``."""
    puts = changes(state, req)
    plan.data.update({"router": address, "router_before": summary_of(state)})
    if pinned_now:
        plan.warnings.append(f"router certificate pinned on first use: {fingerprint}")
    if puts:
        text = f"router {address}: {describe_puts(state, puts)}"
        plan.data["router_puts"] = puts
        plan.data["action"] = "router"
        plan.steps.append(RouterPuts(address, puts, req, creds, after_driver=True))
        plan.summary = f"{plan.summary}; {text}" if plan.edits else text
        plan.noop = None
    elif plan.noop:
        plan.noop += f"; router {address} already forwards to {req.hostname}:{req.port}"
    return plan
