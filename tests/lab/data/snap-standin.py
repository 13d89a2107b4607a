#!/usr/bin/python3
"""`snap` stand-in of the panther-ops test lab's User Computers (tests/lab). NOT snapd.

Knows one snap, husarion-webui, and follows its shared hooks as husarion-snap-common states
them at its latest tag (0.13.0):

  snap install husarion-webui [--channel=C]   root; "already installed" when it is. The install
                                               hook (local-ros/install_hook_ros.sh): ros.transport
                                               udp, ros.domain-id 0, ros.namespace and (humble)
                                               ros.localhost-only unset; the shipped profiles in
                                               <common>/rmw/{fastdds,cyclonedds}/ and the links
                                               <common>/dds-config-{udp,shm,udp-lo,udp-lo-cyclone}.xml
  snap list husarion-webui                     Name Version Rev Tracking Publisher Notes
  snap get [-d] husarion-webui [KEY]           -d: the configuration as JSON
  snap set husarion-webui KEY=VALUE...         root; then the configure hook
                                               (local-ros/configure_hook_ros.sh, utils.sh): a
                                               refused value refuses the whole set, nothing
                                               changes; accepted, it writes <common>/ros.env
  snap services husarion-webui                 Service Startup Current Notes
  husarion-webui.start / husarion-webui.stop   root; a real HTTP server answering /ui on
                                               webui.port while started

The configure hook's rules, as its source states them: ros.* keys only those of humble
(validate_keys); ros.localhost-only 0, 1 or unset; ros.domain-id digits, 0-232
(validate_number); ros.namespace unset or ^[a-z_][0-9a-z_]{0,19}$; ros.transport
rmw_fastrtps_cpp / rmw_cyclonedds_cpp (no profile), udp / shm / udp-lo / udp-lo-cyclone
(rmw/ profiles), fastdds/<X> / cyclonedds/<X> (rmw/<kind>/<X>.xml must exist), zenoh
refused, any other <X> only when <common>/dds-config-<X>.xml exists and
check_xml_profile_type detects it: `yq '. | keys | .[1]'` (key 0 is the XML declaration)
is `profiles` with xmlns http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles or
`CycloneDDS` with xmlns https://cdds.io/config. rmw_fastrtps_cpp and shm need the shm-plug
connected (it is, in this stand-in: the husarion-webui snap's own snapcraft.yaml is not among
the sources). webui.port 1-65535 is the husarion-webui snap's own hook (not in those sources).

State: /var/lib/snapd-standin/husarion-webui.json; common directory /var/snap/husarion-webui/common.
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
DEFAULTS = {"ros": {"domain-id": "0", "localhost-only": "", "namespace": "", "transport": "udp"},
            "webui": {"layout": "default", "port": "8080"}}
ROS_KEYS = ("localhost-only", "domain-id", "transport", "namespace")  # humble
NAMESPACE = r"^[a-z_][0-9a-z_]{0,19}$"
FASTDDS_NS = "http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"
CYCLONE_NS = "https://cdds.io/config"
#: legacy short tokens -> (rmw, profile under <common>/rmw/)
LEGACY = {"udp": ("rmw_fastrtps_cpp", "fastdds/udp.xml"), "shm": ("rmw_fastrtps_cpp", "fastdds/shm.xml"),
          "udp-lo": ("rmw_fastrtps_cpp", "fastdds/udp-lo.xml"),
          "udp-lo-cyclone": ("rmw_cyclonedds_cpp", "cyclonedds/udp-lo.xml")}
#: the shipped profiles (written here for the stand-in, not Husarion's files): name -> (root, xmlns)
SHIPPED = {"fastdds/udp.xml": ("profiles", FASTDDS_NS), "fastdds/shm.xml": ("profiles", FASTDDS_NS),
           "fastdds/udp-lo.xml": ("profiles", FASTDDS_NS), "cyclonedds/udp-lo.xml": ("CycloneDDS", CYCLONE_NS)}


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


def profile_type(path: str) -> str | None:
    """utils.sh check_xml_profile_type: the rmw the file is for, None when not detected."""
    import xml.parsers.expat

    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return None
    keys: list[str] = []  # as yq's XML decoder orders them: processing instructions, then the root
    attrs: dict[str, str] = {}
    parser = xml.parsers.expat.ParserCreate()

    def decl(*_a: object) -> None:
        keys.append("+p_xml")

    def pi(target: str, _data: str) -> None:
        if "<root>" not in keys:
            keys.append(f"+p_{target}")

    def start(tag: str, a: dict[str, str]) -> None:
        if "<root>" not in keys:
            keys.append("<root>")
            attrs.update(a, **{"<tag>": tag})

    parser.XmlDeclHandler, parser.ProcessingInstructionHandler, parser.StartElementHandler = decl, pi, start
    try:
        parser.Parse(data, True)
    except xml.parsers.expat.ExpatError:
        return None
    if len(keys) < 2 or keys[1] != "<root>":  # `keys | .[1]` is not the root element
        return None
    root, ns = attrs.get("<tag>"), attrs.get("xmlns")
    if root == "profiles" and ns == FASTDDS_NS:
        return "rmw_fastrtps_cpp"
    if root == "CycloneDDS" and ns == CYCLONE_NS:
        return "rmw_cyclonedds_cpp"
    return None


def transport(tr: str) -> tuple[str | None, str, str]:
    """The hook's resolution of ros.transport: (why refused or None, the rmw, the profile path)."""
    rmw, profile = "", ""
    if tr in ("rmw_zenoh_cpp", "zenoh") or tr.startswith("zenoh/"):
        return f"'{tr}' (zenoh) is not currently supported by this snap configuration.", "", ""
    if tr in ("rmw_fastrtps_cpp", "rmw_cyclonedds_cpp"):
        rmw = tr
    elif tr.startswith(("fastdds/", "cyclonedds/")):
        kind, _, rest = tr.partition("/")
        rmw = "rmw_fastrtps_cpp" if kind == "fastdds" else "rmw_cyclonedds_cpp"
        profile = os.path.join(COMMON, "rmw", kind, f"{rest}.xml")
    elif tr in LEGACY:
        rmw, rel = LEGACY[tr]
        profile = os.path.join(COMMON, "rmw", rel)
    else:
        legacy = os.path.join(COMMON, f"dds-config-{tr}.xml")
        if not (os.path.isfile(legacy) or os.path.islink(legacy)):
            return f"'{tr}' is not a valid value for 'ros.transport'.", "", ""
        detected = profile_type(legacy)
        if detected is None:
            return f"'{tr}' resolves to {legacy} but the XML profile type couldn't be detected.", "", ""
        rmw, profile = detected, legacy
    if profile and not os.path.exists(profile):
        return f"'{tr}' resolves to '{profile}' which doesn't exist.", "", ""
    return None, rmw, profile


def hook(config: dict) -> tuple[str | None, str]:
    """The configure hook: (why refused or None, the ros.env it writes)."""
    ros = config.setdefault("ros", {})
    unknown = [k for k in ros if k not in ROS_KEYS]
    if unknown:
        return f"'ros.{unknown[0]}' is not a supported key. Possible keys are:\n" + "\n".join(ROS_KEYS), ""
    env = []
    lo = ros.get("localhost-only", "")
    if lo not in ("", "''", "0", "1"):
        return f"'{lo}' is not a supported value for 'ros.localhost-only' parameter. Possible values are:\n1\n0", ""
    env.append(f"export ROS_LOCALHOST_ONLY={lo}" if lo not in ("", "''") else "unset ROS_LOCALHOST_ONLY")
    dom = ros.get("domain-id", "")
    if not re.fullmatch(r"[0-9]+", dom, re.ASCII) or not 0 <= int(dom) <= 232:
        return (f"'{dom}' is not a supported value for 'ros.domain-id'. Possible values are integers between "
                "0 and 232. "), ""
    env.append(f"export ROS_DOMAIN_ID={dom}")
    ns = ros.get("namespace", "")
    if ns not in ("", "''") and not re.search(NAMESPACE, ns):
        return f"'{ns}' is not a supported value for 'ros.namespace'. It must match the regex pattern: {NAMESPACE}", ""
    env.append(f"export ROS_NAMESPACE={ns}" if ns not in ("", "''") else "unset ROS_NAMESPACE")
    why, rmw, profile = transport(ros.get("transport", ""))
    if why:
        return why, ""
    env.append(f"export RMW_IMPLEMENTATION={rmw}")
    if profile:
        env.append(f"export {'FASTRTPS_DEFAULT_PROFILES_FILE=' if rmw == 'rmw_fastrtps_cpp' else 'CYCLONEDDS_URI=file://'}"
                   f"{profile}")
    port = config.get("webui", {}).get("port", "8080")
    if not re.fullmatch(r"[0-9]+", port, re.ASCII) or not 1 <= int(port) <= 65535:
        return f"Invalid webui.port '{port}'.", ""
    for key in ("localhost-only", "namespace"):  # `snapctl set ros.<key>=''` when unset
        if ros.get(key, "") in ("", "''"):
            ros[key] = ""
    return None, "\n".join(env) + "\n"


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
    seed_common()
    save({"channel": channel, "revision": "42", "version": "1.4.2", "config": json.loads(json.dumps(DEFAULTS))})
    print(f"{SNAP} ({channel}) 1.4.2 from Husarion installed")


def seed_common() -> None:
    """install_hook_ros.sh: the rmw/ tree (profiles of the stand-in's own making) and the
    back-compat links dds-config-*.xml."""
    for rel, (root, ns) in SHIPPED.items():
        path = os.path.join(COMMON, "rmw", rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(f'<?xml version="1.0" encoding="UTF-8" ?>\n<{root} xmlns="{ns}"/>\n')
    for token, (_rmw, rel) in LEGACY.items():
        link = os.path.join(COMMON, f"dds-config-{token}.xml")
        with contextlib.suppress(FileNotFoundError):
            os.unlink(link)
        os.symlink(f"rmw/{rel}", link)


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
    why, env = hook(config)
    if why:
        fail(f'error: cannot perform the following tasks:\n- Run configure hook of "{SNAP}" snap '
             f'(run hook "configure": {why})')
    state["config"] = config
    save(state)
    with open(os.path.join(COMMON, "ros.env"), "w") as f:
        f.write(env)


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
