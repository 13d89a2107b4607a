"""Which Panther ROS 2 stack a robot runs, from the driver image tag in its compose.yaml.

The stack changes launch arguments, config file locations and shutdown behaviour at the
patch level (reference: panther-stack.md sections 0 and 1), so the version is kept to the
patch and grouped into the generations that behave alike.

Two release lines are supported (`LINES`): ROS 2 Humble, panther_ros 2.0-2.1 and
husarion_ugv 2.2.x (``husarion/husarion-ugv:humble-2.2.2-20250702``), and ROS 2 Jazzy,
husarion_ugv 2.3.0-2.3.2 (``husarion/husarion-ugv:jazzy-2.3.2-20260622``; the image tags of
husarion_ugv_ros@2.3.0/2.3.1/2.3.2:docker/demo/compose.hardware.yaml). The Jazzy line is a
branch of its own: 2.3.0 branched off after 2.2.1 and lacks 2.2.2's changes (2.3.1 has them;
`has_changes_of`), and its patches differ among themselves, so only the three known releases
are taken. Any other line (2.4, another distro such as kilted or rolling, a crossed pair such
as ``humble-2.3.x``) is refused, naming what is supported.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from enum import Enum

from panther_ops.errors import RemoteStateError

PANTHER_REPO = "husarion/panther"
UGV_REPO = "husarion/husarion-ugv"

_TAG = re.compile(
    r"^(?P<distro>[a-z]+)-(?P<major>\d+)\.(?P<minor>\d+)\.(?P<patch>\d+)"
    r"(?:-(?P<date>\d{8}))?(?:-(?P<suffix>[A-Za-z0-9._-]+))?$", re.ASCII  # \d: 0-9, not other scripts' digits
)


class Family(str, Enum):
    """The repository (and package prefix) a version belongs to."""

    PANTHER_ROS = "panther_ros"
    HUSARION_UGV = "husarion_ugv"


class Generation(str, Enum):
    """Version ranges that behave alike (arguments, file locations, shutdown)."""

    G2_0_0 = "2.0.0-2.0.1"
    G2_0_2 = "2.0.2-2.0.4"
    G2_1_0 = "2.1.0"
    G2_1_1 = "2.1.1-2.1.2"
    G2_2_0 = "2.2.0"
    G2_2_1 = "2.2.1+"
    G2_3_0 = "2.3.0"
    """Jazzy; the gamepad is its own compose service, the animations are the image's (as 2.2.0)."""
    G2_3_1 = "2.3.1"
    """Jazzy; bringup's launch_gamepad and the animations in ~/config (as 2.2.2)."""
    G2_3_2 = "2.3.2"
    """Jazzy; husarion_ugv_teleop runs the gamepad, twist_mux_controller, use_madgwick_filter."""


@dataclass(frozen=True)
class Line:
    """A release line panther-ops supports: a ROS 2 distro and the versions its images carry."""

    distro: str
    first: tuple[int, int, int]
    last: tuple[int, int, int]
    """Inclusive; ``(2, 2, 999)``: every patch of 2.2."""
    text: str

    def holds(self, version: tuple[int, int, int]) -> bool:
        return self.first <= version <= self.last


LINES = (
    Line("humble", (2, 0, 0), (2, 2, 999), "humble: panther_ros 2.0.x-2.1.x, husarion_ugv 2.2.x"),
    Line("jazzy", (2, 3, 0), (2, 3, 2), "jazzy: husarion_ugv 2.3.0, 2.3.1, 2.3.2"),
)
"""The supported lines (husarion_ugv_ros@2.2.2/2.3.x:docker/Dockerfile.hardware `ARG ROS_DISTRO`)."""
SUPPORTED_TEXT = "; ".join(line.text for line in LINES)

_GENERATION_FROM: tuple[tuple[tuple[int, int, int], Generation], ...] = (
    ((2, 0, 0), Generation.G2_0_0), ((2, 0, 2), Generation.G2_0_2), ((2, 1, 0), Generation.G2_1_0),
    ((2, 1, 1), Generation.G2_1_1), ((2, 2, 0), Generation.G2_2_0), ((2, 2, 1), Generation.G2_2_1),
    ((2, 3, 0), Generation.G2_3_0), ((2, 3, 1), Generation.G2_3_1), ((2, 3, 2), Generation.G2_3_2),
)
"""Each generation from its first version on (`Stack.generation`: the last one a version reaches;
older than them all: the first)."""
_LACKS: dict[tuple[int, int, int], tuple[tuple[int, int, int], ...]] = {(2, 3, 0): ((2, 2, 2),)}
"""Releases that a higher version lacks: husarion_ugv_ros 2.3.0 branched off after 2.2.1 (2.2.1 is an
ancestor of the tag 2.3.0, 2.2.2 is not; 2.3.1 carries 2.2.2's changes: launch_gamepad in bringup,
the animations read from ~/config)."""


@dataclass(frozen=True)
class Stack:
    """The stack a robot runs, derived from its driver image."""

    image: str
    distro: str
    version: tuple[int, int, int]
    build_date: str | None

    @property
    def version_str(self) -> str:
        return ".".join(str(p) for p in self.version)

    @property
    def family(self) -> Family:
        return Family.HUSARION_UGV if self.version >= (2, 2, 0) else Family.PANTHER_ROS

    @property
    def generation(self) -> Generation:
        reached = [gen for first, gen in _GENERATION_FROM if self.version >= first]
        return reached[-1] if reached else Generation.G2_0_0

    @property
    def driver_service(self) -> str:
        """Compose service (and container name) of the driver."""
        return "husarion_ugv_ros" if self.family is Family.HUSARION_UGV else "panther_ros"

    @property
    def package_prefix(self) -> str:
        return "husarion_ugv" if self.family is Family.HUSARION_UGV else "panther"

    @property
    def controller_key(self) -> str:
        """Name of the drive controller in the controller YAML."""
        return "drive_controller" if self.version >= (2, 1, 0) else "panther_base_controller"

    @property
    def shutdown_over_http(self) -> bool:
        """2.2.1+ shut user computers down with husarion-shutdown over HTTP, not SSH."""
        return self.version >= (2, 2, 1)

    @property
    def has_config_tree(self) -> bool:
        """2.2+ keeps configuration in /home/husarion/config (common_dir_path)."""
        return self.family is Family.HUSARION_UGV

    @property
    def robot_env_file(self) -> str:
        return DRIVER_ENV_FILES[0] if self.family is Family.HUSARION_UGV else DRIVER_ENV_FILES[1]

    @property
    def jazzy(self) -> bool:
        """husarion_ugv 2.3 on ROS 2 Jazzy."""
        return self.distro == "jazzy"

    def label(self) -> str:
        return f"{self.family.value} {self.version_str}"


def has_changes_of(stack: Stack, release: tuple[int, int, int]) -> bool:
    """True when ``stack`` has what ``release`` brought: the version order, but for the branches of
    `_LACKS` (husarion_ugv 2.3.0 lacks 2.2.2's changes)."""
    return stack.version >= release and release not in _LACKS.get(stack.version, ())


def lacking(release: tuple[int, int, int]) -> tuple[str, ...]:
    """The later releases that lack what ``release`` brought (`_LACKS`): ``("2.3.0",)`` for 2.2.2."""
    return tuple(".".join(map(str, v)) for v, lacks in _LACKS.items() if release in lacks)


def parse_image(image: str) -> Stack:
    """Parse a driver image reference such as ``husarion/panther:humble-2.1.1-20240828``.

    Raises:
        RemoteStateError: not a Panther driver image, a tag without a version, or a
            stack panther-ops does not know (a line or distro not in `LINES`: 2.4, kilted, rolling).
    """
    ref = image.strip()
    name, _, tag = ref.rpartition(":")
    if not name or "/" in tag:
        raise RemoteStateError(f"driver image {ref!r} has no tag; cannot tell the stack version")
    repo = name.split("/", 1)[-1] if name.count("/") > 1 else name
    if repo.endswith(("husarion/panther", "husarion/husarion-ugv")) is False:
        raise RemoteStateError(
            f"image {ref!r} is not a Panther driver image",
            hint=f"expected {PANTHER_REPO}:<tag> or {UGV_REPO}:<tag>",
        )
    m = _TAG.match(tag)
    if not m:
        raise RemoteStateError(
            f"image tag {tag!r} does not follow <distro>-<X.Y.Z>-<YYYYMMDD>",
            hint="set `stack:` for this robot in the inventory",
        )
    version = (int(m["major"]), int(m["minor"]), int(m["patch"]))
    distro = m["distro"]
    if version < (2, 0, 0):
        raise RemoteStateError(f"{ref}: ROS 1 stacks (1.x) are not supported")
    line = next((ln for ln in LINES if ln.holds(version)), None)
    if line is None or line.distro != distro:
        text = ".".join(map(str, version))
        what = f"{distro} {text}" + ("" if line is None else f": {text} is a {line.distro} release")
        raise RemoteStateError(
            f"stack {what} ({ref}) is not a release panther-ops knows",
            hint=f"panther-ops supports {SUPPORTED_TEXT}",
        )
    return Stack(image=ref, distro=distro, version=version, build_date=m["date"])


def parse_version(text: str) -> tuple[int, int, int]:
    """Parse ``2.1.1`` (as written in an inventory's ``stack:``)."""
    m = re.fullmatch(r"([0-9]+)\.([0-9]+)\.([0-9]+)", text.strip())
    if not m:
        raise ValueError(f"{text!r} is not a version X.Y.Z")
    return (int(m[1]), int(m[2]), int(m[3]))


def stack_from_version(text: str) -> Stack:
    """A Stack for an inventory's explicit ``stack: X.Y.Z`` (no image known; the distro is its line's).

    Raises:
        ValueError: not X.Y.Z.
        RemoteStateError: a version of no supported line (2.4.0, 2.3.3, 1.x).
    """
    version = parse_version(text)
    repo = UGV_REPO if version >= (2, 2, 0) else PANTHER_REPO
    line = next((ln for ln in LINES if ln.holds(version)), None)
    if line is None:
        if version < (2, 0, 0):
            raise RemoteStateError(f"stack {text.strip()}: ROS 1 stacks (1.x) are not supported")
        raise RemoteStateError(f"stack {text.strip()} is not a release panther-ops knows",
                               hint=f"panther-ops supports {SUPPORTED_TEXT}")
    return parse_image(f"{repo}:{line.distro}-{text.strip()}")


def stack_option(text: str, option: str = "--stack") -> Stack:
    """A Stack for a version typed on the command line; bad input is a UsageError (exit 2).

    Raises:
        UsageError: not a version X.Y.Z, or a version panther-ops does not support.
    """
    from panther_ops.errors import UsageError

    try:
        return stack_from_version(text)
    except ValueError:
        raise UsageError(f"{option} {text!r} is not a version X.Y.Z",
                         hint="a stack version such as 2.0.4, 2.1.1, 2.2.2 or 2.3.2") from None
    except RemoteStateError as exc:
        raise UsageError(f"{option} {text}: {exc.message}", hint=exc.hint) from None


DRIVER_SERVICES = ("husarion_ugv_ros", "panther_ros")
"""The driver's compose service and container name: husarion_ugv 2.2+, panther_ros up to 2.1."""
DRIVER_ENV_FILES = ("/run/husarion/robot_config.env", "/run/husarion/panther_config.env")
"""The environment file the Built-in Computer's OS writes for each stack of :data:`DRIVER_SERVICES`."""


def find_driver(compose: object) -> tuple[str, str] | None:
    """(service, image) of the driver in a parsed compose document, or None.

    The driver is the ``panther_ros`` / ``husarion_ugv_ros`` service, else the first
    service whose image is a Panther driver image.
    """
    if not isinstance(compose, dict):
        return None
    services = compose.get("services")
    if not isinstance(services, dict):
        return None
    for name in DRIVER_SERVICES:
        svc = services.get(name)
        if isinstance(svc, dict) and isinstance(svc.get("image"), str):
            return name, svc["image"]
    for name, svc in services.items():
        image = svc.get("image") if isinstance(svc, dict) else None
        if isinstance(image, str) and image.split(":")[0].endswith((PANTHER_REPO, UGV_REPO)):
            return str(name), image
    return None
