#!/usr/bin/python3
"""`snap` stand-in of the panther-ops test lab's User Computers (tests/lab). NOT snapd.

Knows one snap, husarion-webui, with the behaviour panther-ops relies on:

  snap install husarion-webui [--channel=C]   root; "already installed" when it is
  snap list husarion-webui                     Name Version Rev Tracking Publisher Notes
  snap get [-d] husarion-webui [KEY]           -d: the configuration as JSON
  snap set husarion-webui KEY=VALUE...         root; the configure hook's rules
                                               (husarion-snap-common 0.5.0): a refused
                                               value refuses the whole set, nothing changes
  snap services husarion-webui                 Service Startup Current Notes
  husarion-webui.start / husarion-webui.stop   root; a real HTTP server answering /ui on
                                               webui.port while started

State: /var/lib/snapd-standin/husarion-webui.json; common directory
/var/snap/husarion-webui/common (custom DDS profiles `<name>.xml` there).
"""

from __future__ import annotations

import contextlib
import http.server
import json
import os
import re
import signal
import socket
import subprocess
import sys
import time

SNAP = "husarion-webui"
STATE = "/var/lib/snapd-standin/husarion-webui.json"
COMMON = "/var/snap/husarion-webui/common"
PIDFILE = "/run/husarion-webui-standin.pid"
DEFAULTS = {"ros": {"domain-id": "0", "localhost-only": "0", "transport": "udp"},
            "webui": {"layout": "default", "port": "8080"}}
BUILTIN = ("udp", "udp-lo", "shm", "builtin", "rmw_fastrtps_cpp", "rmw_cyclonedds_cpp")


def fail(msg: str, code: int = 1) -> None:
    sys.stderr.write(msg + "\n")
    sys.exit(code)


def need_root() -> None:
    if os.geteuid() != 0:
        fail("error: access denied (try with sudo)")


def load() -> dict | None:
    try:
        with open(STATE) as f:
            return json.load(f)
    except FileNotFoundError:
        return None


def save(state: dict) -> None:
    os.makedirs(os.path.dirname(STATE), exist_ok=True)
    tmp = STATE + ".tmp"
    with open(tmp, "w") as f:
        json.dump(state, f, indent=1)
    os.replace(tmp, STATE)


def installed() -> dict:
    state = load()
    if state is None:
        fail(f'error: snap "{SNAP}" is not installed')
    return state  # type: ignore[return-value]


def hook(config: dict) -> str | None:
    """The configure hook's checks of the ROS keys; None when accepted."""
    ros = config.get("ros", {})
    ns = ros.get("namespace")
    if ns not in (None, "") and not re.fullmatch(r"[0-9a-z_-]{1,20}", ns):
        return f"Invalid namespace '{ns}'. Allowed: 1-20 characters of a-z, 0-9, '_' and '-'."
    dom = ros.get("domain-id", "0")
    if not re.fullmatch(r"\d+", dom) or not 0 <= int(dom) <= 232:
        return f"Invalid ROS_DOMAIN_ID '{dom}'. Allowed: 0-232."
    lo = ros.get("localhost-only", "0")
    if lo not in ("0", "1"):
        return f"Invalid ROS_LOCALHOST_ONLY '{lo}'. Allowed: 0 or 1."
    tr = ros.get("transport", "udp")
    if tr not in BUILTIN and not os.path.isfile(os.path.join(COMMON, f"{tr}.xml")):
        return f"'{tr}' is not a supported value for ros.transport. Possible values are: {', '.join(BUILTIN)}, " \
               f"or a DDS profile {COMMON}/<name>.xml."
    port = config.get("webui", {}).get("port", "8080")
    if not re.fullmatch(r"\d+", port) or not 1 <= int(port) <= 65535:
        return f"Invalid webui.port '{port}'."
    return None


def running() -> int | None:
    try:
        with open(PIDFILE) as f:
            pid = int(f.read())
    except (OSError, ValueError):
        return None
    try:
        os.kill(pid, 0)
    except PermissionError:  # root's server, asked by a user: it runs
        return pid
    except OSError:
        return None
    return pid


def cmd_install(args: list[str]) -> None:
    need_root()
    channel = "humble/stable"
    for a in args:
        if a.startswith("--channel="):
            channel = a.split("=", 1)[1]
            channel = channel if "/" in channel else f"{channel}/stable"
    state = load()
    if state is not None:
        if state["channel"] == channel:
            print(f'snap "{SNAP}" is already installed, see \'snap help refresh\'')
            return
        state["channel"] = channel
        state["revision"] = str(int(state["revision"]) + 1)
        save(state)
        print(f"{SNAP} ({channel}) 1.{state['revision']} from Husarion refreshed")
        return
    os.makedirs(COMMON, exist_ok=True)
    save({"channel": channel, "revision": "42", "version": "1.4.2", "config": json.loads(json.dumps(DEFAULTS))})
    print(f"{SNAP} ({channel}) 1.4.2 from Husarion installed")


def cmd_list() -> None:
    state = installed()
    print("Name            Version  Rev  Tracking       Publisher  Notes")
    print(f"{SNAP:<15} {state['version']:<8} {state['revision']:<4} {state['channel']:<14} husarion   -")


def cmd_get(args: list[str]) -> None:
    state = installed()
    as_json = "-d" in args
    keys = [a for a in args if not a.startswith("-") and a != SNAP]
    config = state["config"]
    if as_json and not keys:
        print(json.dumps(config, indent=1))
        return
    for key in keys:
        node = config
        for part in key.split("."):
            if not isinstance(node, dict) or part not in node:
                fail(f'error: snap "{SNAP}" has no "{key}" configuration option')
            node = node[part]
        print(json.dumps(node) if isinstance(node, dict) else node)


def cmd_set(args: list[str]) -> None:
    need_root()
    state = installed()
    config = json.loads(json.dumps(state["config"]))
    for a in args:
        if a == SNAP:
            continue
        if "=" not in a:
            fail(f'error: invalid configuration: "{a}" (want key=value)')
        key, value = a.split("=", 1)
        section, _, name = key.partition(".")
        if not name:
            fail(f'error: invalid option name: "{key}"')
        config.setdefault(section, {})[name] = value
    why = hook(config)
    if why:
        fail(f'error: cannot perform the following tasks:\n- Run configure hook of "{SNAP}" snap '
             f'(run hook "configure": {why})')
    state["config"] = config
    save(state)


def cmd_services() -> None:
    installed()
    print("Service                 Startup  Current   Notes")
    print(f"{SNAP}.daemon   disabled {'active' if running() else 'inactive'}  -")


def start() -> None:
    need_root()
    state = installed()
    if running():
        return
    port = int(state["config"]["webui"]["port"])
    p = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--serve", str(port)], start_new_session=True,
                         stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(PIDFILE, "w") as f:
        f.write(str(p.pid))
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            if p.poll() is not None:
                fail(f"husarion-webui: the web server did not start (port {port})")
            time.sleep(0.05)
    fail(f"husarion-webui: the web server did not start (port {port})")


def stop() -> None:
    need_root()
    installed()
    pid = running()
    if pid:
        os.kill(pid, signal.SIGTERM)
        for _ in range(50):
            try:
                os.kill(pid, 0)
            except OSError:
                break
            time.sleep(0.05)
    with contextlib.suppress(FileNotFoundError):
        os.unlink(PIDFILE)


def serve(port: int) -> None:
    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            if self.path.rstrip("/") == "/ui":
                body = b"<!doctype html><title>husarion-webui (lab stand-in)</title>\n"
                self.send_response(200)
                self.send_header("Content-Type", "text/html")
            else:
                body = b"not found\n"
                self.send_response(404)
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: object) -> None:
            pass

    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    http.server.ThreadingHTTPServer(("0.0.0.0", port), Handler).serve_forever()


def main() -> None:
    prog = os.path.basename(sys.argv[0])
    args = sys.argv[1:]
    if args[:1] == ["--serve"]:
        serve(int(args[1]))
    elif prog == f"{SNAP}.start":
        start()
    elif prog == f"{SNAP}.stop":
        stop()
    elif not args:
        fail("usage: snap install|list|get|set|services husarion-webui ...")
    elif SNAP not in args[1:]:
        fail(f'error: snap "{" ".join(a for a in args[1:] if not a.startswith("-")) or "?"}" not known to the '
             "lab stand-in (husarion-webui only)")
    else:
        verb, rest = args[0], args[1:]
        {"install": lambda: cmd_install(rest), "list": cmd_list, "get": lambda: cmd_get(rest),
         "set": lambda: cmd_set(rest), "services": cmd_services}.get(verb, lambda: fail(f"unknown command {verb}"))()


if __name__ == "__main__":
    main()
