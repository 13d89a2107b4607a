"""Stand-in of a Teltonika RUTX11's REST API and GNSS NMEA forwarding (panther-ops test lab).

NOT the router. Runs in the lab router's namespaces (tests/lab/router.py):

* HTTPS on :443 with the lab's self-signed certificate; ``POST /api/login`` with
  ``{"username", "password"}`` gives ``data.token`` (expires after TOKEN_TTL seconds: 401
  afterwards); ``GET``/``PUT`` ``/api/gps/global``, ``/api/gps/nmea/config/nmea_forwarding``,
  ``/api/gps/nmea/rules/config`` with a bearer token. Like the real API, every value must be a
  string, switches only "0"/"1" (422 with ``errors`` otherwise).
* An NMEA sender at 1 Hz (sentences made with pynmea2 by tests/lab/nmea.py): when the GNSS and
  forwarding are enabled and proto is udp, each enabled sentence goes to hostname:port in a
  datagram of its own, CRLF-terminated. Why one per datagram: the router's forwarding rules are
  per sentence (``forwarding_enabled``/``forwarding_interval`` per ID, husarion/panther_rutx11@a135d67:
  rutx11_manager.py), and Husarion's documented receiver is nmea_navsat_driver's
  nmea_socket_driver (husarion/nmea-gps-docker, panther_ros@2.1.1 ``launch_nmea_gps``), which
  strips a datagram and splits it at "\n" (ros-drivers/nmea_navsat_driver@2.0.1:
  src/libnmea_navsat_driver/nodes/nmea_socket_driver.py): of a CRLF burst every sentence but
  the last keeps its "\r" and fails the parser's checksum regex, so the GGA of a burst would
  never give the fix the manual shows (``ros2 topic echo /panther/gps/fix``). The test
  controls the sender through ``sender.json`` in the router's directory (on, lat, lon, quality).

Usage: rutx11-standin.py DIR REPO_ROOT PORT TOKEN_TTL
"""

from __future__ import annotations

import json
import secrets
import socket
import ssl
import sys
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

DIR, ROOT, PORT, TTL = Path(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
sys.path.insert(0, ROOT)
from tests.lab.nmea import sentences  # noqa: E402

STATE = DIR / "rutx-state.json"
LOG = DIR / "rutx-standin.log"
LOCK = threading.Lock()
TOKENS: dict[str, float] = {}
SWITCH = {"0", "1"}


def log(event: str, **kw: object) -> None:
    with open(LOG, "a") as f:
        f.write(json.dumps({"t": round(time.time(), 3), "event": event, **kw}) + "\n")


def state() -> dict:
    return json.loads(STATE.read_text())


def save(st: dict) -> None:
    tmp = STATE.with_suffix(".tmp")
    tmp.write_text(json.dumps(st, indent=2))
    tmp.replace(STATE)


def check_section(body: object, schema: dict) -> list[dict]:
    errors = []
    if not isinstance(body, dict):
        return [{"source": "data", "error": "must be an object"}]
    for k, v in body.items():
        if k not in schema:
            errors.append({"source": k, "error": "unknown option"})
        elif not isinstance(v, str):
            errors.append({"source": k, "error": f"must be a string, got {type(v).__name__}"})
        elif not schema[k](v):
            errors.append({"source": k, "error": f"invalid value {v!r}"})
    return errors


def _port(v: str) -> bool:
    return v.isdigit() and 1 <= int(v) <= 65535


def _host(v: str) -> bool:
    return bool(v) and not any(c.isspace() for c in v) and len(v) < 254


GLOBAL = {k: SWITCH.__contains__ for k in ("enabled", "galileo_sup", "glonass_sup", "beidou_sup")}
FORWARD = {"enabled": SWITCH.__contains__, "hostname": _host, "port": _port, "proto": {"udp", "tcp"}.__contains__}
RULE = {"id": lambda v: True, "forwarding_enabled": SWITCH.__contains__,
        "forwarding_interval": lambda v: v.isdigit() and 1 <= int(v) <= 3600}


class Handler(BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"

    def log_message(self, fmt: str, *args: object) -> None:
        pass

    def answer(self, status: int, doc: dict) -> None:
        raw = json.dumps(doc).encode()
        self.send_response(status)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(raw)))
        self.end_headers()
        self.wfile.write(raw)

    def body(self) -> object:
        n = int(self.headers.get("Content-Length") or 0)
        try:
            return json.loads(self.rfile.read(n) or b"null")
        except ValueError:
            return None

    def authorised(self) -> bool:
        auth = self.headers.get("Authorization", "")
        token = auth[7:] if auth.startswith("Bearer ") else ""
        with LOCK:
            expires = TOKENS.get(token)
        if expires is None or expires < time.time():
            log("unauthorised", path=self.path, expired=expires is not None)
            self.answer(401, {"success": False, "errors": [{"code": 120, "error": "Unauthorized access"}]})
            return False
        return True

    def do_POST(self) -> None:
        if self.path != "/api/login":
            self.answer(404, {"success": False, "errors": [{"error": "not found"}]})
            return
        body = self.body()
        password = (DIR / "rutx-password").read_text().strip()
        if not isinstance(body, dict) or body.get("username") != "admin" or body.get("password") != password:
            log("login-refused", username=body.get("username") if isinstance(body, dict) else None)
            self.answer(401, {"success": False, "errors": [{"code": 121, "error": "Authentication failed"}]})
            return
        token = secrets.token_hex(16)
        with LOCK:
            TOKENS[token] = time.time() + TTL
        log("login")
        self.answer(200, {"success": True, "data": {"username": "admin", "token": token, "expires": TTL}})

    def do_GET(self) -> None:
        if not self.authorised():
            return
        st = state()
        data = {"/api/gps/global": st["global"], "/api/gps/nmea/config/nmea_forwarding": st["forwarding"],
                "/api/gps/nmea/rules/config": st["rules"]}.get(self.path)
        if data is None:
            self.answer(404, {"success": False, "errors": [{"error": "not found"}]})
        else:
            self.answer(200, {"success": True, "data": data})

    def do_PUT(self) -> None:
        if not self.authorised():
            return
        body = self.body()
        data = body.get("data") if isinstance(body, dict) else None
        with LOCK:
            st = state()
            if self.path in ("/api/gps/global", "/api/gps/nmea/config/nmea_forwarding"):
                key, schema = ("global", GLOBAL) if self.path == "/api/gps/global" else ("forwarding", FORWARD)
                errors = check_section(data, schema)
                if not errors:
                    st[key].update(data)
            elif self.path == "/api/gps/nmea/rules/config":
                errors = [] if isinstance(data, list) else [{"source": "data", "error": "must be a list"}]
                known = {r["id"]: r for r in st["rules"]}
                for rule in data if isinstance(data, list) else []:
                    errors += check_section(rule, RULE)
                    if isinstance(rule, dict) and rule.get("id") not in known:
                        errors.append({"source": "id", "error": f"unknown sentence {rule.get('id')!r}"})
                if not errors:
                    for rule in data:
                        known[rule["id"]].update(rule)
            else:
                self.answer(404, {"success": False, "errors": [{"error": "not found"}]})
                return
            if errors:
                log("put-refused", path=self.path, errors=errors)
                self.answer(422, {"success": False, "errors": errors})
                return
            save(st)
        log("put", path=self.path, data=data)
        self.answer(200, {"success": True, "data": data})


def sender() -> None:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    while True:
        time.sleep(1.0 - (time.time() % 1.0))
        try:
            ctl = json.loads((DIR / "sender.json").read_text())
            st = state()
        except (OSError, ValueError):
            continue
        fwd = st["forwarding"]
        if not ctl.get("on") or st["global"].get("enabled") != "1" or fwd.get("enabled") != "1" \
                or fwd.get("proto") != "udp":
            continue
        on = {r["id"] for r in st["rules"] if r.get("forwarding_enabled") == "1"}
        lines = [s for s in sentences(ctl["lat"], ctl["lon"], quality=int(ctl.get("quality", 1)))
                 if s[1:6] in on]
        if not lines:
            continue
        for line in lines:  # one sentence per datagram (see the module's docstring)
            try:
                sock.sendto((line + "\r\n").encode(), (fwd["hostname"], int(fwd["port"])))
            except OSError as exc:
                log("send-failed", error=str(exc))


def main() -> None:
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    ctx.load_cert_chain(DIR / "cert.pem", DIR / "key.pem")
    server = ThreadingHTTPServer(("0.0.0.0", PORT), Handler)
    server.socket = ctx.wrap_socket(server.socket, server_side=True)
    threading.Thread(target=sender, daemon=True).start()
    log("listening", port=PORT)
    server.serve_forever()


if __name__ == "__main__":
    main()
