"""A configuration file pushed onto a robot (`config push`, `lights deploy`, the shutdown hosts
file): the local bundle, read and checked before any robot is contacted (`read_bundle`), and
the edits that put it in place on one robot (`push_onto`: the file, its mount, its launch
argument; `push_plan`: those as the plan that writes compose.yaml). What the robot has in use
is `pull.py`'s."""

from __future__ import annotations

import posixpath
import re
from dataclasses import dataclass, field
from pathlib import Path

from panther_ops.core.fleet.memo import Memo
from panther_ops.core.fleet.plan import FileEdit, RobotPlan, Verify
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.kinds import PUSHABLE, FileKind, Target, check_file
from panther_ops.core.robot.edits import compose_plan, edit_args
from panther_ops.core.robot.files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR, ConfigFile, config_file
from panther_ops.core.robot.launch_args import spec
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import InputError, UsageError

BT_ARGS = {FileKind.BT_LIGHTS: "lights_bt_project_path", FileKind.BT_SAFETY: "safety_bt_project_path"}


@dataclass
class Bundle:
    """The local files of a push: the main file and what it brings along."""

    main: Path
    data: bytes
    extra: dict[str, bytes] = field(default_factory=dict)
    """name (relative to the main file's robot directory) -> content"""



_IMAGE = re.compile(r"^(\s*image:\s*)(['\"]?)([^'\"\n#]+?)\2(\s*(#.*)?)$", re.MULTILINE)


def _rewrite_images(text: str, target_dir: str) -> str:
    def sub(m: re.Match[str]) -> str:
        ref = m.group(3).strip()
        if ref.startswith("$(find"):
            return m.group(0)
        return f"{m.group(1)}{m.group(2)}{target_dir}/animations/{posixpath.basename(ref)}{m.group(2)}{m.group(4)}"

    return _IMAGE.sub(sub, text)


def robot_wheel(reads: Reads, cfg: RobotConfig) -> str:
    """The robot's ``wheel_type`` (``custom`` included; its model's default when the command
    sets none: WH05 on a Lynx)."""
    from panther_ops.core.robot.robot_model import wheel_type_of

    return wheel_type_of(reads, cfg)


def wheel_of(reads: Reads, cfg: RobotConfig) -> str:
    """The wheel type whose stock files name the robot's (``WH01``'s for custom wheels)."""
    wheel = robot_wheel(reads, cfg)
    return "WH01" if wheel == "custom" else wheel


def robot_file(reads: Reads, cfg: RobotConfig, kind: FileKind) -> ConfigFile:
    """The configuration file of ``kind`` (not a BT project, not joy2twist) on this robot: of its
    stack, wheel type and model (a Lynx has its own animations)."""
    from panther_ops.core.robot.robot_model import robot_model_of

    return config_file(cfg.stack, kind, wheel_type=wheel_of(reads, cfg), robot_model=robot_model_of(reads, cfg))


def _stock_named(kind: FileKind, data: bytes, reads: Reads, cfg: RobotConfig) -> bool:
    """The file may take the name of the robot wheel type's stock file (``WH01_controller.yaml``
    in the 2.2 tree): it describes those wheels, or states no kinematics. A custom wheel's file
    (the manual's procedure) or another stock wheel's keeps its own name, pointed at by its
    launch argument (what ``wheel_type:=custom`` needs)."""
    if kind not in (FileKind.CONTROLLER, FileKind.WHEEL):
        return True
    from panther_ops.core.kinds.stock_wheels import limits_wheel, wheels_in

    wheel = wheel_of(reads, cfg)
    return limits_wheel(wheels_in(kind is FileKind.CONTROLLER, data, cfg.stack), wheel) == wheel


_CHECKED: Memo[list[str]] = Memo()


@dataclass
class Pushed:
    """What a push does to a robot: its files, and (in ``cfg``) the mount and the argument."""

    edits: list[FileEdit]
    warnings: list[str]
    verify: Verify
    summary: str
    robot_path: str



def checked_for(reads: Reads, cfg: RobotConfig, kind: FileKind, main: Path, data: bytes, force: bool) -> list[str]:
    """The file (``data``, as it will be written) through its kind's one validator, for this
    robot's stack, wheel and namespace (once each)."""
    namespace = None
    if kind is FileKind.CONTROLLER:  # its IMU broadcaster must read the IMU under the driver's namespace
        from panther_ops.core.robot.namespace import driver_namespace

        namespace = driver_namespace(reads, cfg)[0]
    target = Target(cfg.stack, robot_wheel(reads, cfg), namespace)
    return list(_CHECKED.get((kind, str(main), data, target, force),
                             lambda: check_file(kind, str(main), data, local=main, target=target, force=force)))



def push_onto(reads: Reads, cfg: RobotConfig, kind: FileKind, bundle: Bundle, *, force: bool = False) -> Pushed:
    """Push ``bundle`` as ``kind`` (not joy2twist) onto the robot ``cfg`` describes: the files
    to write, checked by their kind's validator; the mount and the launch argument are made in
    ``cfg`` (the caller's plan writes compose.yaml)."""
    main_data, translated = bundle.data, list[str]()
    if kind in (FileKind.USER_ANIMATIONS, FileKind.LED):  # animation types of this stack, then its check
        from panther_ops.core.robot.animation_types import for_stack

        text, translated = for_stack(bundle.data.decode(), cfg.stack)
        main_data = text.encode()
    warnings = checked_for(reads, cfg, kind, bundle.main, main_data, force)
    warnings += [f"{bundle.main.name}: {t} for {cfg.stack.label()}" for t in translated]
    forced = [w for w in warnings if w.endswith("(forced)")]
    if kind in BT_ARGS:
        pkg = f"{cfg.stack.package_prefix}_manager"
        robot_dir = f"{ROBOT_CONFIG_DIR}/{pkg}/behavior_trees"
        container_dir = f"{CONTAINER_CONFIG_DIR}/{pkg}/behavior_trees"
        arg = BT_ARGS[kind]
        name = bundle.main.name
        main_data = bundle.data
        extra = bundle.extra
    else:
        cf = robot_file(reads, cfg, kind)
        if cf.launch_arg is None:  # written, it would change nothing (husarion_ugv 2.2's simulated battery)
            raise UsageError(f"--as {kind.value}: {cf.filename} is not the driver's on {cfg.stack.label()}: {cf.note}",
                             hint="pass the file to the simulation's launch command instead")
        arg = cf.launch_arg
        robot_dir, container_dir = posixpath.dirname(cf.robot_path), posixpath.dirname(cf.container_path)
        name = bundle.main.name
        in_tree = cfg.reads_from_tree(cf) and reads.file(cf.robot_path) is not None
        if in_tree and _stock_named(kind, main_data, reads, cfg):
            name = cf.filename  # the tree's own file: read through common_dir_path, no argument needed
            arg = ""
        extra = {}
        if kind is FileKind.USER_ANIMATIONS and bundle.extra:
            main_data = _rewrite_images(main_data.decode(), posixpath.dirname(container_dir)).encode()
            extra = {f"../{k}": v for k, v in bundle.extra.items()}
    edits: list[FileEdit] = []
    files = {name: main_data, **extra}
    inside = posixpath.dirname(robot_dir) if kind is FileKind.USER_ANIMATIONS else robot_dir
    for rel, content in files.items():
        path = posixpath.normpath(posixpath.join(robot_dir, rel))
        if not path.startswith(inside + "/"):
            raise InputError(f"{rel} would be written to {path}, outside {inside}", path=str(bundle.main),
                             hint="the files a push brings stay in the robot's config directory")
        before = reads.file(path)
        if before != content:
            edits.append(FileEdit(path, before, content))
    main_container = f"{container_dir}/{name}"
    contains: tuple[str, ...] = ()
    if not cfg.tree_mounted:
        mount_src = robot_dir if (extra or kind in BT_ARGS) else f"{robot_dir}/{name}"
        mount_dst = container_dir if (extra or kind in BT_ARGS) else main_container
        if kind is FileKind.USER_ANIMATIONS and extra:
            mount_src, mount_dst = posixpath.dirname(robot_dir), posixpath.dirname(container_dir)
        if cfg.host_path_of(mount_dst) != mount_src:
            cfg.compose.add_volume(mount_src, mount_dst, ro=True)
    if arg:
        arg = spec(arg).name_for(cfg.stack)  # the name this stack declares (2.2: animations_config_path)
        w, v = edit_args(cfg, {arg: main_container}, [], force)
        warnings += w
        contains = v.cmd_contains
    summary = f"{kind.value}: {bundle.main.name} -> {robot_dir}/{name}" + (f" ({arg}:={main_container})" if arg else "")
    if forced:
        summary += " [--force: " + "; ".join(forced) + "]"
    return Pushed(edits, warnings, Verify(cfg.service, contains), summary, f"{robot_dir}/{name}")



def push_plan(reads: Reads, cfg: RobotConfig, kind: FileKind, bundle: Bundle, *, force: bool = False) -> RobotPlan:
    """The plan of pushing ``bundle`` as ``kind`` (not joy2twist) to the robot ``cfg`` describes."""
    pushed = push_onto(reads, cfg, kind, bundle, force=force)
    plan = compose_plan(reads.robot, cfg, pushed.summary, pushed.warnings, [pushed.verify],
                        f"{pushed.robot_path} already has this content", extra=pushed.edits)
    plan.data["robot_path"] = pushed.robot_path
    return plan


_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.+-]*$")


def push_kind(text: str, option: str = "--as") -> FileKind:
    """The file kind a push or pull names (exit 2 naming what is allowed)."""
    try:
        kind = FileKind(text)
    except ValueError:
        kind = None
    if kind not in PUSHABLE:
        raise UsageError(f"{option} {text!r} is not a config kind",
                         hint="allowed: " + ", ".join(k.value for k in PUSHABLE))
    return kind


def read_bundle(kind: FileKind, path: Path, *, force: bool = False) -> Bundle:
    """Read and check the local files before any robot is contacted (bad input: exit 2).

    The content goes through the kind's one validator (`core.filekinds`) with what needs no
    robot; `plan_push` checks it again against each robot's stack and wheel type.
    """
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", path=str(path)) from None
    if not _NAME.match(path.name):
        raise InputError(f"the file name {path.name!r} becomes a path in the driver's command: use letters, "
                         "digits and _ . + - only", path=str(path))
    bundle = Bundle(path, data)
    if kind in BT_ARGS:
        if path.suffix != ".btproj":
            raise InputError("a BT project is pushed by its .btproj file", path=str(path))
        from panther_ops.core.kinds.bt import project_files

        check_file(kind, str(path), data, local=path, force=force)
        bundle.extra = {rel: src.read_bytes() for rel, src in project_files(path).items()}
        return bundle
    check_file(kind, str(path), data, local=path, force=force)
    if kind is FileKind.USER_ANIMATIONS:
        _animation_images(bundle)
    return bundle


_IMAGE_MAGIC = (b"\x89PNG\r\n\x1a\n", b"\xff\xd8\xff", b"GIF87a", b"GIF89a")


def _animation_images(bundle: Bundle) -> None:
    """Collect local images the animations reference; their paths are rewritten on push."""
    for m in _IMAGE.finditer(bundle.data.decode()):
        ref = m.group(3).strip()
        if ref.startswith("$(find"):
            continue
        src = Path(ref) if ref.startswith("/") else bundle.main.parent / ref
        if src.is_file():
            data = src.read_bytes()
            if not data.startswith(_IMAGE_MAGIC):  # only images travel to the robot, whatever the path names
                raise InputError(f"image {ref} is not a PNG, JPEG or GIF file: not pushed", path=str(bundle.main))
            name = f"animations/{src.name}"
            if bundle.extra.get(name, data) != data:
                raise InputError(f"two different images are named {src.name}: they would land on the same robot "
                                 "path", path=str(bundle.main))
            bundle.extra[name] = data
        elif not ref.startswith("/"):
            raise InputError(f"image {ref} not found next to the file", path=str(bundle.main))
