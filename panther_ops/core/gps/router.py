"""`gps router show|set`: the RUTX11's NMEA forwarding, through its REST API.

The router sits on the robot's LAN (10.15.20.1); panther-ops reaches it through the robot's
SSH connection (a direct-tcpip channel), logs in (``POST /api/login``) and reads or writes
three resources, every value a string (the API takes only ``"0"``/``"1"`` for switches):

- ``/api/gps/global``: ``enabled`` (the GNSS receiver);
- ``/api/gps/nmea/config/nmea_forwarding``: ``enabled``, ``hostname``, ``port``, ``proto``;
- ``/api/gps/nmea/rules/config``: per sentence ``id``, ``forwarding_enabled``,
  ``forwarding_interval``.

Reads are ``GET`` on the same paths. Credentials: `core.gps.credentials`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.gps.credentials import Credentials
from panther_ops.core.gps.udp_address import check_port
from panther_ops.errors import UsageError
from panther_ops.results import Outcome, RobotResult

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


def open_router(ctx: RobotContext, address: str, creds: Credentials) -> Any:
    from panther_ops.transport import pins
    from panther_ops.transport.rutx import RouterClient
    from panther_ops.transport.tunnel import open_tcp

    client = getattr(ctx.transport, "client", None)
    if client is None:
        raise NoRouter(f"{ctx.robot.name} is reached without SSH (a demo robot): no router behind it")
    key = f"{ctx.robot.name}/{address}"
    api = RouterClient(lambda: open_tcp(client, ctx.robot.name, address, 443), ctx.robot.name, address,
                       pinned=pins.pinned(key), pin=lambda fp: pins.pin(key, fp))
    username, password = creds.for_robot(ctx.robot.name)
    api.login(username, password)
    return api


class NoRouter(UsageError):
    pass


def read_state(api: Any) -> dict[str, Any]:
    rules = api.call("GET", RULES) or []
    return {"global": dict(api.call("GET", GLOBAL) or {}), "forwarding": dict(api.call("GET", FORWARDING) or {}),
            "rules": {str(r.get("id")): dict(r) for r in rules if isinstance(r, dict)}}


def summary_of(state: dict[str, Any]) -> dict[str, Any]:
    """The state in plain terms (JSON data and tables)."""
    fwd, glob = state["forwarding"], state["global"]
    on = [i for i, r in state["rules"].items() if r.get("forwarding_enabled") == "1"]
    return {"gps_enabled": glob.get("enabled") == "1", "forwarding": fwd.get("enabled") == "1",
            "hostname": fwd.get("hostname"), "port": fwd.get("port"), "proto": fwd.get("proto"), "sentences": on}


def show_task(address: str, creds: Credentials) -> Any:
    def task(ctx: RobotContext) -> RobotResult:
        try:
            api = open_router(ctx, address, creds)
        except NoRouter as exc:
            return RobotResult(ctx.robot.name, Outcome.SKIPPED, exc.message)
        state = summary_of(read_state(api))
        data = {"router": address, **state, "certificate": api.fingerprint}
        warnings = [f"router certificate pinned on first use: {api.fingerprint}"] if api.pinned_now else []
        where = f"{state['hostname']}:{state['port']}/{state['proto']}"
        msg = f"forwarding {'on' if state['forwarding'] else 'off'} to {where}; {len(state['sentences'])} sentences"
        return RobotResult(ctx.robot.name, Outcome.OK, msg, warnings=warnings, data=data)

    return task


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


def describe(state: dict[str, Any], puts: dict[str, Any]) -> str:
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


def plan_router(ctx: RobotContext, address: str, creds: Credentials, req: RouterRequest) -> RobotPlan:
    api = open_router(ctx, address, creds)
    state = read_state(api)
    puts = changes(state, req)
    plan = RobotPlan(ctx.robot.name, f"change router {address}: {describe(state, puts)}" if puts else "",
                     noop=None if puts else f"router {address} already as asked")
    plan.data.update({"router": address, "before": summary_of(state), "certificate": api.fingerprint})
    if puts:
        plan.data["action"] = "router"
        plan.data["puts"] = puts
    if api.pinned_now:
        plan.warnings.append(f"router certificate pinned on first use: {api.fingerprint}")
    return plan


def apply_router(address: str, creds: Credentials, req: RouterRequest) -> Any:
    """Carry out a plan: the PUTs, then the state read back must be as asked (else failed)."""
    def apply(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
        result = RobotResult(ctx.robot.name, Outcome.CHANGED, plan.summary, warnings=list(plan.warnings),
                             data=dict(plan.data))
        api = open_router(ctx, address, creds)
        for path, body in plan.data["puts"].items():
            api.call("PUT", path, {"data": body})
        state = read_state(api)
        result.data["after"] = summary_of(state)
        left = changes(state, req)
        if left:
            result.outcome = Outcome.FAILED
            result.message = f"the router did not keep: {describe(state, left)}"
        return result

    return apply
