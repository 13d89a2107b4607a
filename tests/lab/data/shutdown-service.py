#!/usr/bin/env python3
"""Stand-in of the husarion-shutdown service for the panther-ops test lab (tests/lab).

NOT the real snap. Runs as root inside one lab user computer (its own network, mount and PID
namespaces) and answers what the Panther manager sends from 2.2.1 on
(husarion_ugv_manager/plugins/shutdown_host.hpp):

    GET /shutdown?ts=<unix seconds>&sig=<hex HMAC-SHA256(secret, "/shutdown|<ts>")>

* ts or sig missing or malformed        -> 400 "bad request: ..."
* signature does not match the secret   -> 403 "invalid signature"
* signature matches, ts older/newer than WINDOW seconds -> 401 "expired timestamp"
  (the signature is checked first, so an old request tells a right secret from a wrong one
  without shutting anything down; panther-ops' `shutdown check` relies on that)
* otherwise                             -> 200 "shutting down", then /sbin/poweroff (the
  lab's power-off stand-in, bind-mounted over it in this computer only)

Every request is appended to /var/log/shutdown-service.log as one JSON object.
Usage: shutdown-service.py IP PORT SECRET_FILE
"""

from __future__ import annotations

import hashlib
import hmac
import http.server
import json
import subprocess
import sys
import time
import urllib.parse

WINDOW = 30
LOG = "/var/log/shutdown-service.log"


def log(entry: dict) -> None:
    entry["time"] = time.time()
    with open(LOG, "a") as f:
        f.write(json.dumps(entry) + "\n")


class Handler(http.server.BaseHTTPRequestHandler):
    secret_file = ""

    @property
    def secret(self) -> bytes:
        """Read on every request: the lab may change it (as `snap set ... config.password=`)."""
        with open(self.secret_file, "rb") as f:
            return f.read().strip()

    def answer(self, status: int, text: str) -> None:
        body = (text + "\n").encode()
        self.send_response(status)
        self.send_header("Content-Type", "text/plain")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)
        log({"client": self.client_address[0], "path": self.path.split("?")[0], "status": status, "reason": text})

    def do_GET(self) -> None:
        url = urllib.parse.urlsplit(self.path)
        if url.path != "/shutdown":
            self.answer(404, "not found")
            return
        query = urllib.parse.parse_qs(url.query)
        ts, sig = query.get("ts", [""])[0], query.get("sig", [""])[0]
        if not ts.isdigit() or not sig:
            self.answer(400, "bad request: ts and sig are required")
            return
        want = hmac.new(self.secret, f"/shutdown|{ts}".encode(), hashlib.sha256).hexdigest()
        if not hmac.compare_digest(want, sig.lower()):
            self.answer(403, "invalid signature")
            return
        if abs(time.time() - int(ts)) > WINDOW:
            self.answer(401, "expired timestamp")
            return
        self.answer(200, "shutting down")
        self.wfile.flush()
        subprocess.Popen(["/sbin/poweroff"], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True)

    def log_message(self, format: str, *args: object) -> None:
        return


def main() -> None:
    ip, port, secret_file = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    Handler.secret_file = secret_file
    server = http.server.ThreadingHTTPServer((ip, port), Handler)
    log({"event": "listening", "ip": ip, "port": port})
    server.serve_forever()


if __name__ == "__main__":
    main()
