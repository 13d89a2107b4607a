"""`gps enable|disable`: the NMEA GPS driver on a robot, as its stack runs it.

- panther_ros 2.0.x-2.1.0 (and any stack with ``--container``): the manual's ``nmea-gps``
  service in ``~/compose.yaml`` (GNSS API, "Use Docker Compose"): image
  ``husarion/nmea-gps:humble-2.0.1-20240617``, ``network_mode: host``, ``restart: always``,
  command ``ros2 launch /husarion_utils/nmea_navsat.launch.py robot_namespace:=<ns>``. With a
  port other than 5000 the service runs the image's ``nmea_socket_driver`` node with ``ip``
  and ``port`` parameters instead (the image's own demo form). Only that service is
  recreated and checked.
- panther_ros 2.1.1+ and husarion_ugv 2.2: ``launch_nmea_gps:=True`` on the driver. A port
  other than 5000 needs the NMEA parameters file: on 2.2 panther-ops writes
  ``~/config/husarion_ugv_localization/config/nmea_navsat.yaml`` (in the mounted config tree)
  and passes ``nmea_params_path:=/config/...``; panther_ros 2.1.1 has no argument for that
  file (use ``--container``).

``disable`` takes back exactly what ``enable`` adds: the service (its container is stopped
and removed), or the argument, the parameters path and the file -- an enable followed by a
disable leaves compose.yaml byte-identical.

The planners, pure functions of what was read (compose.yaml, and on 2.2 the params file,
through :class:`Reads`); the reads and the apply are `service.py`'s.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from panther_ops.core.config.launch_args import bool_word
from panther_ops.core.config.planners import edit_args
from panther_ops.core.config.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.core.fleet.inventory_desired import IP_RULE, NAMESPACE_RULE, nmea_ip, nmea_namespace
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.gps.fix_topic import service_topic
from panther_ops.core.gps.udp_address import check_port
from panther_ops.core.stack import Family
from panther_ops.core.yaml.render import Folded
from panther_ops.errors import UsageError

SERVICE = "nmea-gps"
IMAGE = "husarion/nmea-gps:humble-2.0.1-20240617"
DEFAULT_PORT = 5000
DEFAULT_IP = "10.15.20.2"
"""The Built-in Computer's address the router forwards to (panther-stack.md section 4)."""
LAUNCH_FILE = "/husarion_utils/nmea_navsat.launch.py"
PARAMS_PACKAGE = "husarion_ugv_localization"
PARAMS_NAME = "nmea_navsat.yaml"


@dataclass(frozen=True)
class GpsOptions:
    """What the operator asked for (checked before any robot is contacted)."""

    port: int = DEFAULT_PORT
    ip: str = DEFAULT_IP
    namespace: str | None = None
    container: bool = False

    def __post_init__(self) -> None:
        check_port(self.port, "--port")
        if not nmea_ip(self.ip):
            raise UsageError(f"--ip {self.ip!r}: {IP_RULE}")
        if self.namespace is not None and not nmea_namespace(self.namespace):
            raise UsageError(f"--namespace {self.namespace!r}: {NAMESPACE_RULE}")

    @property
    def default_socket(self) -> bool:
        return self.port == DEFAULT_PORT and self.ip == DEFAULT_IP


def robot_namespace(reads: Reads, cfg: RobotConfig, asked: str | None) -> str:
    """--namespace, else the inventory's, else the driver's namespace:= or ROBOT_NAMESPACE, else panther."""
    if asked:
        return asked
    env = cfg.compose.environment(cfg.service).get("ROBOT_NAMESPACE")
    found = reads.namespace or cfg.compose.args.get("namespace") or env or "panther"
    if not nmea_namespace(found):
        raise UsageError(f"the robot's namespace {found!r} is not a plain ROS namespace", hint="pass --namespace")
    return found


def service_mapping(namespace: str, opts: GpsOptions) -> dict[str, Any]:
    """The ``nmea-gps`` service: the manual's, or the socket-driver form for another ip/port."""
    if opts.default_socket:
        command = f"ros2 launch {LAUNCH_FILE}\nrobot_namespace:={namespace}"
    else:
        command = (f"ros2 run nmea_navsat_driver nmea_socket_driver --ros-args\n-p ip:={opts.ip} -p port:={opts.port}"
                   f"\n-r __ns:=/{namespace}")
    return {"image": IMAGE, "network_mode": "host", "restart": "always", "command": Folded(command)}


def service_check(namespace: str, opts: GpsOptions) -> Verify:
    words = (f"robot_namespace:={namespace}",) if opts.default_socket else (f"port:={opts.port}", f"__ns:=/{namespace}")
    return Verify(SERVICE, words)


def params_text(opts: GpsOptions) -> str:
    """The NMEA driver's parameters file (husarion_ugv 2.2's nmea_navsat.yaml keys)."""
    return (
        "# NMEA GPS driver parameters (written by panther-ops gps enable)\n"
        "/**:\n"
        "  ros__parameters:\n"
        f"    ip: {opts.ip}\n"
        f"    port: {opts.port}\n"
        "    buffer_size: 4096\n"
        "    timeout_sec: 2.0\n"
    )


def _params_paths(cfg: RobotConfig) -> tuple[str, str]:
    """(robot path, container path) of the params file in 2.2's config tree."""
    rel = f"{PARAMS_PACKAGE}/config/{PARAMS_NAME}"
    return cfg.resolve(f"~/config/{rel}"), f"/config/{rel}"


def uses_container(cfg: RobotConfig, opts: GpsOptions) -> bool:
    return opts.container or cfg.stack.version < (2, 1, 1)


def _driver_enabled(cfg: RobotConfig) -> bool:
    return cfg.compose.args.get("launch_nmea_gps", "").lower() == "true"


@dataclass
class Change:
    """What enabling does to one robot's files (compose.yaml is edited in ``cfg`` itself)."""

    summary: str
    noop: str
    recreate: tuple[str, ...]
    verify: list[Verify]
    extra: list[FileEdit]
    warnings: list[str]
    data: dict[str, Any]


def enable_change(reads: Reads, cfg: RobotConfig, opts: GpsOptions) -> Change:
    """Edit ``cfg.compose`` (and plan the params file) so the NMEA driver runs as asked."""
    namespace = robot_namespace(reads, cfg, opts.namespace)
    if uses_container(cfg, opts):
        return _enable_service(cfg, namespace, opts)
    return _enable_argument(reads, cfg, opts)


def plan_enable(raw: ComposeRead, reads: Reads, opts: GpsOptions) -> RobotPlan:
    """`gps enable`: the NMEA driver as this robot's stack runs it."""
    cfg = parse_config(raw, reads.stack)
    c = enable_change(reads, cfg, opts)
    return _plan(reads.robot, cfg, c.summary, c.noop, c.recreate, c.verify, c.extra, c.warnings, c.data)


def _plan(robot: str, cfg: RobotConfig, summary: str, noop: str, recreate: tuple[str, ...],
          verify: list[Verify], extra: list[FileEdit], warnings: list[str], data: dict[str, Any]) -> RobotPlan:
    edits = list(extra)
    after = cfg.compose.text().encode()
    if after != cfg.before:
        edits.insert(0, FileEdit(cfg.compose_path, cfg.before, after, cfg.mode))
    plan = RobotPlan(robot, summary, edits, recreate if edits else (), cfg.compose_path, verify,
                     None if edits else noop, [*warnings, *cfg.compose.notes])
    plan.data.update({"stack": cfg.stack.label(), **data})
    plan.home = cfg.home
    return plan


def _enable_service(cfg: RobotConfig, namespace: str, opts: GpsOptions) -> Change:
    compose = cfg.compose
    if cfg.stack.version >= (2, 1, 1) and _driver_enabled(cfg):
        raise UsageError("the driver already runs the NMEA driver (launch_nmea_gps:=True)",
                         hint="panther-ops gps disable first, or enable without --container")
    want = service_mapping(namespace, opts)
    try:
        compose.add_service(SERVICE, want)  # False: already there as wanted
    except UsageError:  # there with another port or namespace: replaced
        compose.remove_service(SERVICE)
        compose.add_service(SERVICE, want)
    where = f"udp {opts.ip}:{opts.port}"
    topic = service_topic(want)
    data = {"mode": "service", "service": SERVICE, "namespace": namespace, "port": opts.port, "ip": opts.ip}
    return Change(f"add service {SERVICE} ({IMAGE}, {where}, {topic})",
                  f"service {SERVICE} already runs the NMEA driver ({where})", (SERVICE,),
                  [service_check(namespace, opts)], [], [], data)


def _enable_argument(reads: Reads, cfg: RobotConfig, opts: GpsOptions) -> Change:
    if SERVICE in cfg.compose.services():
        raise UsageError(f"compose.yaml already has the {SERVICE} service",
                         hint="panther-ops gps disable first, or pass --container to keep the service")
    sets: dict[str, Any] = {"launch_nmea_gps": bool_word(cfg.stack, True)}
    extra: list[FileEdit] = []
    data: dict[str, Any] = {"mode": "argument", "service": cfg.service, "port": opts.port, "ip": opts.ip}
    if not opts.default_socket:
        if cfg.stack.family is not Family.HUSARION_UGV:
            raise UsageError(
                f"{cfg.stack.label()} has no launch argument for the NMEA parameters file "
                f"(nmea_params_path is husarion_ugv 2.2+): cannot use udp {opts.ip}:{opts.port}",
                hint="pass --container to run the nmea-gps service instead, or keep port 5000")
        if not cfg.tree_mounted:
            raise UsageError("the config tree (~/config at /config) is not mounted in the driver",
                             hint="the NMEA parameters file goes to ~/config/husarion_ugv_localization/config")
        host_path, container_path = _params_paths(cfg)
        before = reads.file(host_path)
        after = params_text(opts).encode()
        if after != before:
            extra.append(FileEdit(host_path, before, after, 0o644))
        sets["nmea_params_path"] = container_path
        data["params_file"] = host_path
    warnings, verify = edit_args(cfg, sets, [], False)
    words = " ".join(f"{k}:={v}" for k, v in sets.items())
    return Change(f"{words} on {cfg.service}", f"{cfg.service} already runs with {words}", (cfg.service,),
                  [verify], extra, warnings, data)


def plan_disable(raw: ComposeRead, reads: Reads) -> RobotPlan:
    """`gps disable`: takes back exactly what enable adds."""
    cfg = parse_config(raw, reads.stack)
    data: dict[str, Any] = {}
    extra: list[FileEdit] = []
    recreate: tuple[str, ...] = ()
    verify: list[Verify] = []
    done: list[str] = []
    if SERVICE in cfg.compose.services():
        cfg.compose.remove_service(SERVICE)
        data["remove_service"] = SERVICE
        done.append(f"remove service {SERVICE}")
    if cfg.stack.version >= (2, 1, 1):
        unsets = [k for k in ("launch_nmea_gps",) if k in cfg.compose.args]
        host_path, container_path = _params_paths(cfg)
        if cfg.compose.args.get("nmea_params_path") == container_path:
            unsets.append("nmea_params_path")
            before = reads.file(host_path)
            if before is not None and before.startswith(params_text(GpsOptions()).splitlines()[0].encode()):
                extra.append(FileEdit(host_path, before, None))
        if unsets:
            _w, check = edit_args(cfg, {}, unsets, False)
            recreate, verify = (cfg.service,), [check]
            done.append(f"unset {', '.join(unsets)} on {cfg.service}")
    return _plan(reads.robot, cfg, "; ".join(done), "the NMEA GPS driver is not enabled", recreate, verify, extra, [],
                 data)
