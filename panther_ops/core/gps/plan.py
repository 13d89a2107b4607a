"""`gps enable|disable`: the NMEA GPS driver on a robot, as its stack runs it.

- panther_ros 2.0.x-2.1.0 (and any stack with ``--container``): the manual's ``nmea-gps``
  service in ``~/compose.yaml`` (GNSS API, "Use Docker Compose"): image
  ``husarion/nmea-gps:humble-2.0.1-20240617``, ``network_mode: host``, ``restart: always``,
  command ``ros2 launch /husarion_utils/nmea_navsat.launch.py robot_namespace:=<ns>``. With a
  port other than 5000 the service runs the image's ``nmea_socket_driver`` node with ``ip``
  and ``port`` parameters instead (the image's own demo form). Only that service is
  recreated and checked. One addition to the manual's service: it merges the driver's
  ``x-common-config`` (``<<: *common-config``; with no anchor, the driver's ``env_file`` and
  ``environment`` are copied), so the GPS node runs on the driver's ``ROS_DOMAIN_ID`` and
  ``RMW_IMPLEMENTATION`` (panther-docker@2.1.1:demo/compose.minimal-setup.yaml sets
  ``rmw_cyclonedds_cpp``, which the nmea-gps image's base husarnet/ros installs:
  husarnet/ros-docker:Dockerfile.ros). The manual's service alone publishes ``/<ns>/gps/fix``
  on domain 0 with the image's default RMW, which a robot with another ``ROS_DOMAIN_ID``
  never sees.
- panther_ros 2.1.1+ and husarion_ugv 2.2: ``launch_nmea_gps:=True`` on the driver. A port
  other than 5000 needs the NMEA parameters file, passed by the argument the NMEA launch file
  (included by localization) declares: panther_ros 2.1.1's ``params_file``
  (panther_ros@2.1.1:panther_localization/launch/nmea_navsat.launch.py; panther-ops writes
  ``~/config/panther_localization/config/nmea_navsat_params.yaml`` and mounts it read-only at
  ``/config/...``), husarion_ugv 2.2's ``nmea_params_path``
  (husarion_ugv_ros@2.2.2:husarion_ugv_localization/launch/nmea_navsat.launch.py; the file
  ``~/config/husarion_ugv_localization/config/nmea_navsat.yaml`` in the mounted config tree).

``disable`` takes back exactly what ``enable`` adds: the service (its container is stopped
and removed), or the argument, the parameters path and the file -- an enable followed by a
disable leaves compose.yaml byte-identical.

The planners, pure functions of what was read (compose.yaml, and on 2.2 the params file,
through :class:`Reads`); the reads are `read.py`'s, the executor `apply.py`'s.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from panther_ops.core.fleet.inventory_desired import IP_RULE, nmea_ip, nmea_namespace
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Step, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.gps.fix_topic import service_topic
from panther_ops.core.gps.udp_address import check_port
from panther_ops.core.parse.ros_names import RosNameError, namespace
from panther_ops.core.robot.edits import edit_args
from panther_ops.core.robot.launch_args import bool_word, spec
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.core.stack import Family
from panther_ops.core.yaml.render import Block
from panther_ops.errors import UsageError

SERVICE = "nmea-gps"


@dataclass(frozen=True)
class RemoveService(Step):
    """`gps disable` dropped ``service`` from compose.yaml: after the write its container is
    stopped and removed (compose would leave it running as an orphan)."""

    action: ClassVar[bool] = False
    service: str
DDS_KEYS = ("env_file", "environment")
"""The driver's settings the nmea-gps service shares when the driver merges no anchor."""
IMAGE = "husarion/nmea-gps:humble-2.0.1-20240617"
DEFAULT_PORT = 5000
DEFAULT_IP = "10.15.20.2"
"""The Built-in Computer's address the router forwards to (panther-stack.md section 4)."""
LAUNCH_FILE = "/husarion_utils/nmea_navsat.launch.py"
PARAMS_FILES = {False: ("panther_localization", "nmea_navsat_params.yaml"),
                True: ("husarion_ugv_localization", "nmea_navsat.yaml")}
"""(package, file) of the NMEA parameters file by family (husarion_ugv: True), as the image names it."""
PARAMS_ARG = "params_file"
"""Its launch argument's catalogue key (2.2: ``nmea_params_path``)."""


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
        if self.namespace is not None:
            gps_namespace(self.namespace, "--namespace")

    @property
    def default_socket(self) -> bool:
        return self.port == DEFAULT_PORT and self.ip == DEFAULT_IP


def gps_namespace(value: str, what: str, hint: str | None = None) -> str:
    """A namespace the NMEA service takes: a ROS namespace (core/parse/ros_names) of one token,
    since the service writes it as ``robot_namespace:=<ns>`` and ``__ns:=/<ns>``."""
    try:
        namespace(value)
    except RosNameError as exc:
        raise UsageError(f"{what} {value!r}: {exc}", hint=hint) from None
    if not nmea_namespace(value):
        raise UsageError(f"{what} {value!r}: one namespace token for the NMEA driver (letters, digits and _, "
                         "e.g. panther), without '/'", hint=hint)
    return value


def _robot_namespace(reads: Reads, cfg: RobotConfig, asked: str | None) -> str:
    """--namespace, else the inventory's, else the driver's namespace:= or ROBOT_NAMESPACE, else panther."""
    if asked:
        return asked
    env = cfg.compose.environment(cfg.service).get("ROBOT_NAMESPACE")
    found = reads.namespace or cfg.compose.args.get("namespace") or env or "panther"
    return gps_namespace(found, "the robot's namespace", hint="pass --namespace")


def service_mapping(namespace: str, opts: GpsOptions) -> dict[str, Any]:
    """The ``nmea-gps`` service: the manual's, or the socket-driver form for another ip/port."""
    if opts.default_socket:
        command = f"ros2 launch {LAUNCH_FILE}\nrobot_namespace:={namespace}"
    else:
        command = (f"ros2 run nmea_navsat_driver nmea_socket_driver --ros-args\n-p ip:={opts.ip} -p port:={opts.port}"
                   f"\n-r __ns:=/{namespace}")
    return {"image": IMAGE, "network_mode": "host", "restart": "always", "command": Block(command, ">")}


def service_check(namespace: str, opts: GpsOptions) -> Verify:
    words = (f"robot_namespace:={namespace}",) if opts.default_socket else (f"port:={opts.port}", f"__ns:=/{namespace}")
    return Verify(SERVICE, words)


def params_text(opts: GpsOptions) -> str:
    """The NMEA driver's parameters file: the keys and types of the image's own
    (panther_ros@2.1.1:panther_localization/config/nmea_navsat_params.yaml,
    husarion_ugv_ros@2.2.0:husarion_ugv_localization/config/nmea_navsat.yaml) with ip and port
    as asked. ``timeout_sec`` stays an integer: nmea_socket_driver declares it with the
    default 2, and rclpy refuses a double for an integer parameter."""
    return (
        "# NMEA GPS driver parameters (written by panther-ops gps enable)\n"
        "/**:\n"
        "  nmea_navsat_driver:\n"
        "    ros__parameters:\n"
        f"      ip: {opts.ip}\n"
        f"      port: {opts.port}\n"
        "      buffer_size: 4096\n"
        "      timeout_sec: 2\n"
    )


def _params_paths(cfg: RobotConfig) -> tuple[str, str]:
    """(robot path, container path) of the params file: ``~/config/<package>/config/<file>``, seen
    at ``/config/...`` (2.2: the mounted tree; 2.1.1: the file's own read-only mount)."""
    package, name = PARAMS_FILES[cfg.stack.family is Family.HUSARION_UGV]
    rel = f"{package}/config/{name}"
    return cfg.resolve(f"~/config/{rel}"), f"/config/{rel}"


def _params_arg(cfg: RobotConfig) -> str:
    """The name the robot's stack declares for the params file (params_file, nmea_params_path)."""
    return spec(PARAMS_ARG).name_for(cfg.stack)


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
    namespace = _robot_namespace(reads, cfg, opts.namespace)
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
    merge = compose.merged_anchor(cfg.service)
    if merge is None:  # no anchor: the driver's DDS settings, copied
        driver = compose.service(cfg.service)
        want.update({key: driver[key] for key in DDS_KEYS if key in driver})
    try:
        compose.add_service(SERVICE, want, merge=merge)  # False: already there as wanted
    except UsageError:  # there with another port or namespace: replaced
        compose.remove_service(SERVICE)
        compose.add_service(SERVICE, want, merge=merge)
    where = f"udp {opts.ip}:{opts.port}"
    topic = service_topic(want)
    data = {"mode": "service", "service": SERVICE, "namespace": namespace, "port": opts.port, "ip": opts.ip}
    return Change(f"add service {SERVICE} ({IMAGE}, {where}, {topic})",
                  f"service {SERVICE} already runs the NMEA driver ({where})", (SERVICE,),
                  [service_check(namespace, opts)], [], [], data)


def _take_back_params(reads: Reads, cfg: RobotConfig) -> tuple[list[str], list[FileEdit]]:
    """The params argument, mount and file `gps enable` wrote (edits ``cfg.compose``): what to unset
    and the file to delete (only panther-ops' own, recognised by its first line)."""
    host_path, container_path = _params_paths(cfg)
    if cfg.compose.args.get(_params_arg(cfg)) != container_path:
        return [], []
    extra: list[FileEdit] = []
    before = reads.file(host_path)
    if before is not None and before.startswith(params_text(GpsOptions()).splitlines()[0].encode()):
        extra.append(FileEdit(host_path, before, None))
    if cfg.stack.family is not Family.HUSARION_UGV and cfg.host_path_of(container_path) == host_path:
        cfg.compose.remove_volume(container_path)
    return [_params_arg(cfg)], extra


def _enable_argument(reads: Reads, cfg: RobotConfig, opts: GpsOptions) -> Change:
    if SERVICE in cfg.compose.services():
        raise UsageError(f"compose.yaml already has the {SERVICE} service",
                         hint="panther-ops gps disable first, or pass --container to keep the service")
    sets: dict[str, Any] = {"launch_nmea_gps": bool_word(cfg.stack, True)}
    extra: list[FileEdit] = []
    unsets: list[str] = []
    data: dict[str, Any] = {"mode": "argument", "service": cfg.service, "port": opts.port, "ip": opts.ip}
    if opts.default_socket:  # the image's own params (port 5000): a params file of an earlier enable goes
        unsets, extra = _take_back_params(reads, cfg)
    else:
        ugv = cfg.stack.family is Family.HUSARION_UGV
        if ugv and not cfg.tree_mounted:
            raise UsageError("the config tree (~/config at /config) is not mounted in the driver",
                             hint="the NMEA parameters file goes to ~/config/husarion_ugv_localization/config")
        host_path, container_path = _params_paths(cfg)
        before = reads.file(host_path)
        after = params_text(opts).encode()
        if after != before:
            extra.append(FileEdit(host_path, before, after, 0o644))
        if not ugv and cfg.host_path_of(container_path) != host_path:
            cfg.compose.add_volume(host_path, container_path, ro=True)
        sets[_params_arg(cfg)] = container_path
        data["params_file"] = host_path
    warnings, verify = edit_args(cfg, sets, unsets, False)
    words = " ".join([*(f"{k}:={v}" for k, v in sets.items()), *(f"unset {k}" for k in unsets)])
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
        params, extra = _take_back_params(reads, cfg)
        unsets += params
        if unsets:
            _w, check = edit_args(cfg, {}, unsets, False)
            recreate, verify = (cfg.service,), [check]
            done.append(f"unset {', '.join(unsets)} on {cfg.service}")
    plan = _plan(reads.robot, cfg, "; ".join(done), "the NMEA GPS driver is not enabled", recreate, verify, extra,
                 [], data)
    if "remove_service" in data:
        plan.steps.append(RemoveService(SERVICE))
    return plan
