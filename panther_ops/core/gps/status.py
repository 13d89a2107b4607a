"""`gps status`: is NMEA arriving at the robot, does it carry a fix, and if not, why.

On the robot, a short Python program listens on the NMEA port for a window (default 3 s)
and hands every datagram back (base64, with its arrival time); it also learns the robot's
address toward the router (a UDP socket connected to it: nothing is sent). The operator side
decodes with pynmea2 (`core.gps.nmea`). With ``--router`` the router's forwarding settings
are read too (REST API, `core.gps.router`), which tells "router not forwarding" and
"forwarding to a wrong host/port" apart from "no data".

Once a listener holds the port nothing can be captured: where gpsd runs, its view decides;
where compose.yaml runs the NMEA driver (the ``nmea-gps`` service or ``launch_nmea_gps``),
the robot's own fix topic does (``ros2 topic echo --once`` in the driver container,
`core.gps.fix_echo`).

Verdicts: ``fix``, ``data but no fix``, ``router not forwarding``, ``forwarding to wrong
host/port``, ``no data``, ``no fix message`` (the NMEA driver holds the port and published
nothing within the window), ``port busy`` (a listener that is neither gpsd nor the NMEA
driver of compose.yaml holds the port: nothing captured). Demo robots answer from a
recorded NMEA file.
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.templates import read_template
from panther_ops.core.gps.credentials import Credentials
from panther_ops.core.gps.nmea import Fix, NmeaDecoder
from panther_ops.core.gps.plan import SERVICE
from panther_ops.core.robot.read import read_config
from panther_ops.errors import OpsError, TransportError, UsageError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command

FIX = "fix"
NO_FIX = "data but no fix"
NOT_FORWARDING = "router not forwarding"
WRONG_TARGET = "forwarding to wrong host/port"
NO_DATA = "no data"
BUSY = "port busy"
NO_MESSAGE = "no fix message"

CAPTURE = r"""
import base64, json, socket, sys, time
port, window, router = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
info = {"lan_ip": None}
try:
    p = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    p.connect((router, 9))
    info["lan_ip"] = p.getsockname()[0]
    p.close()
except OSError:
    pass
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
try:
    s.bind(("0.0.0.0", port))
except OSError as e:
    info["bind"] = e.strerror or str(e)
    print(json.dumps(info))
    sys.exit(0)
info["bind"] = "ok"
print(json.dumps(info), flush=True)
end = time.time() + window
n = 0
while n < 2000:
    left = end - time.time()
    if left <= 0:
        break
    s.settimeout(left)
    try:
        data = s.recv(65535)
    except socket.timeout:
        break
    n += 1
    print(json.dumps({"t": time.time(), "d": base64.b64encode(data).decode()}), flush=True)
print(json.dumps({"end": time.time()}))
"""


@dataclass(frozen=True)
class StatusOptions:
    port: int = 5000
    window_s: float = 3.0
    router: str | None = None
    """The router's address when its settings are to be read (``--router``)."""
    credentials: Credentials | None = None

    def __post_init__(self) -> None:
        """Bad input refused before any robot is contacted (exit 2)."""
        import math

        from panther_ops.core.gps.router.plan import check_address
        from panther_ops.core.gps.udp_address import check_port

        check_port(self.port, "--port")
        if not (math.isfinite(self.window_s) and self.window_s > 0):
            raise UsageError(f"--window {self.window_s}: a finite number of seconds > 0, e.g. 3")
        if self.router is not None:
            check_address(self.router)


def driver_mode(ctx: RobotContext) -> dict[str, Any]:
    """How the NMEA driver runs according to compose.yaml."""
    try:
        cfg = read_config(ctx)
    except OpsError as exc:
        return {"mode": "unknown", "detail": exc.message}
    if SERVICE in cfg.compose.services():
        found = {"mode": "service", "service": SERVICE}
    elif cfg.compose.args.get("launch_nmea_gps", "").lower() == "true":
        found = {"mode": "argument", "service": cfg.service}
    else:
        return {"mode": "off"}
    from panther_ops.core.gps.fix_topic import TopicError, fix_topic

    try:
        found["topic"] = fix_topic(cfg, found["mode"], found["service"])
    except TopicError as exc:
        found["topic_error"] = str(exc)
    return found


Captured = tuple[dict[str, Any], list[tuple[float, bytes]], float]
"""What the robot's listener said (bind, lan_ip), the datagrams with their times, its end time."""


def capture(ctx: RobotContext, opts: StatusOptions, router: str) -> Captured:
    res = ctx.transport.run(Command.of("python3", "-c", CAPTURE, str(opts.port), str(opts.window_s), router),
                            timeout=opts.window_s + 30)
    if not res.ok:
        why = res.stderr.strip()[-300:]
        raise TransportError(ctx.robot.name, f"capture on the robot failed (needs python3): {why}")
    lines = [json.loads(x) for x in res.stdout.splitlines() if x.strip().startswith("{")]
    if not lines:
        raise TransportError(ctx.robot.name, "capture on the robot printed nothing")
    info, rest = lines[0], lines[1:]
    got = [(float(x["t"]), base64.b64decode(x["d"])) for x in rest if "d" in x]
    end = next((float(x["end"]) for x in rest if "end" in x), got[-1][0] if got else 0.0)
    return info, got, end


def verdict(fix: Fix | None, sentences: int, router: dict[str, Any] | None, expect: tuple[str | None, int]
            ) -> tuple[str, str]:
    """(verdict, why) from what arrived and what the router says."""
    if sentences:
        if fix is not None and fix.has_fix:
            return FIX, f"{fix.lat:.7f} {fix.lon:.7f}, {fix.satellites} satellites, HDOP {fix.hdop}"
        return NO_FIX, "NMEA arrives but without a position fix (antenna's sky view?)"
    if router is not None:
        if not router["gps_enabled"] or not router["forwarding"] or router.get("proto") != "udp":
            return NOT_FORWARDING, (f"GNSS {'on' if router['gps_enabled'] else 'off'}, forwarding "
                                    f"{'on' if router['forwarding'] else 'off'} ({router.get('proto')})")
        host, port = expect
        if (host is not None and router["hostname"] != host) or str(router["port"]) != str(port):
            return WRONG_TARGET, f"router sends to {router['hostname']}:{router['port']}, expected {host}:{port}"
    return NO_DATA, f"nothing arrived on udp :{expect[1]}" + ("" if router else " (router not read: --router)")


def _result(ctx: RobotContext, opts: StatusOptions, data: dict[str, Any], dec: NmeaDecoder, fixes: list[Fix],
            seconds: float, router: dict[str, Any] | None, lan_ip: str | None) -> RobotResult:
    last = fixes[-1] if fixes else None
    v, why = verdict(last, dec.stats.sentences, router, (lan_ip, opts.port))
    data.update({
        "verdict": v, "detail": why, "port": opts.port, "window_s": seconds,
        "sentences_per_s": round(dec.stats.sentences / seconds, 2) if seconds else None,
        "counts": dec.stats.to_json(), "fix": last.to_json() if last else None, "robot_lan_ip": lan_ip,
        "router": router,
    })
    outcome = Outcome.OK if v == FIX else Outcome.FAILED
    return RobotResult(ctx.robot.name, outcome, f"{v}: {why}", data=data)


def status_task(opts: StatusOptions) -> Any:
    def task(ctx: RobotContext) -> RobotResult:
        data: dict[str, Any] = {"driver": driver_mode(ctx), "recorded": False}
        dec = NmeaDecoder()
        if ctx.robot.transport == "local":  # a demo robot: the recorded NMEA of a RUTX11
            data["recorded"] = True
            text = read_template("gps", "demo.nmea")
            recorded = dec.feed("".join(x + "\n" for x in text.splitlines() if not x.startswith("#")).encode())
            result = _result(ctx, opts, data, dec, recorded, 3.0, None, None)
            if opts.router is not None:  # --router asked: said, not silently left out
                result.warnings.append("router not read: demo robot, no router behind it (as `gps router show`)")
            return result
        router = None
        warnings: list[str] = []
        if opts.router is not None and opts.credentials is not None:
            from panther_ops.core.gps.router.plan import summary_of
            from panther_ops.core.gps.router.read import open_router, read_state

            api = open_router(ctx, opts.router, opts.credentials)
            router = summary_of(read_state(api))
            if api.pinned_now:
                warnings.append(f"router certificate pinned on first use: {api.fingerprint}")
        info, got, end = capture(ctx, opts, opts.router or "10.15.20.1")
        from panther_ops.core.gps.gpsd_view import gpsd_view

        data["gpsd"] = view = gpsd_view(ctx)
        if info.get("bind") != "ok":
            if (not view or not view.get("running")) and data["driver"]["mode"] in ("service", "argument"):
                result = _from_topic(ctx, opts, data, router, info)
            else:
                result = _busy(ctx, opts, data, view, router, info)
            result.warnings[:0] = warnings
            return result
        fixes: list[Fix] = []
        for when, payload in got:
            fixes += dec.feed(payload, received_at=when)
        result = _result(ctx, opts, data, dec, fixes, opts.window_s, router, info.get("lan_ip"))
        if fixes and fixes[-1].received_at is not None:
            result.data["age_s"] = round(end - fixes[-1].received_at, 3)
        result.warnings[:0] = warnings
        return result

    return task


def _busy(ctx: RobotContext, opts: StatusOptions, data: dict[str, Any], view: dict[str, Any] | None,
          router: dict[str, Any] | None, info: dict[str, Any]) -> RobotResult:
    """The port is held (gpsd or the NMEA driver): gpsd's view decides where gpsd runs."""
    data.update({"port": opts.port, "router": router, "robot_lan_ip": info.get("lan_ip"), "fix": None})
    if not view or not view.get("running"):
        data.update({"verdict": BUSY, "detail": f"udp :{opts.port}: {info.get('bind')}"})
        return RobotResult(ctx.robot.name, Outcome.SKIPPED,
                           f"{BUSY}: a listener holds udp :{opts.port} ({info.get('bind')}); nothing captured",
                           data=data)
    if view.get("active") and view.get("mode", 0) >= 2:
        v, why = FIX, f"gpsd: {view['lat']:.7f} {view['lon']:.7f}, mode {view['mode']}D, " \
                      f"{view.get('satellites_used')} satellites used"
    elif view.get("active"):
        v, why = NO_FIX, f"gpsd: mode {view.get('mode')}: no position fix"
    else:
        v, why = verdict(None, 0, router, (info.get("lan_ip"), opts.port))
        why = f"gpsd has no data; {why}"
    data.update({"verdict": v, "detail": why, "source": "gpsd"})
    return RobotResult(ctx.robot.name, Outcome.OK if v == FIX else Outcome.FAILED, f"{v}: {why}", data=data)


def _from_topic(ctx: RobotContext, opts: StatusOptions, data: dict[str, Any], router: dict[str, Any] | None,
                info: dict[str, Any]) -> RobotResult:
    """The port is the NMEA driver's (compose.yaml runs it): its fix topic decides."""
    from panther_ops.core.gps import fix_echo
    from panther_ops.core.gps.fix_topic import STATUS

    driver = data["driver"]
    lan_ip = info.get("lan_ip")
    data.update({"port": opts.port, "router": router, "robot_lan_ip": lan_ip, "fix": None})
    if "topic" not in driver:  # compose.yaml names no ROS topic: nothing to ask
        why = f"udp :{opts.port}: {info.get('bind')}; the fix topic cannot be asked: {driver.get('topic_error')}"
        data.update({"verdict": BUSY, "detail": why})
        return RobotResult(ctx.robot.name, Outcome.SKIPPED, f"{BUSY}: {why}", data=data)
    wait = fix_echo.timeout_s(opts.window_s)
    got = fix_echo.ask(ctx, driver["topic"], wait)
    topic, fix, tail = fix_echo.answer(got, driver["topic"])
    where = f"container {got.container}" if got.container else "the driver container"
    data.update({"source": f"ros topic {topic}", "topic": topic, "container": got.container, "window_s": wait,
                 "fix": fix.to_json() if fix else None})
    if fix is not None and fix.has_fix:
        v = FIX
        why = (f"{fix.lat:.7f} {fix.lon:.7f}, alt {fix.altitude_m:.1f} m, "
               f"status {fix.status} ({STATUS.get(fix.status, 'unknown')}) on {topic}")
    elif fix is not None:
        v, why = NO_FIX, f"{topic}: status {fix.status} (no fix): the NMEA driver gets NMEA without a position fix"
    else:
        v, why = verdict(None, 0, router, (lan_ip, opts.port))
        if v == NO_DATA:
            v = NO_MESSAGE
            why = (f"nothing published on {topic} within {wait} s (asked in {where})"
                   + (f": {tail}" if tail else "") + ("" if router else " (router not read: --router)"))
        else:
            why += f"; nothing published on {topic} within {wait} s (asked in {where})"
    data.update({"verdict": v, "detail": why})
    return RobotResult(ctx.robot.name, Outcome.OK if v == FIX else Outcome.FAILED, f"{v}: {why}", data=data)
