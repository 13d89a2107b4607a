"""LED configuration: panels, segments, segments_map and animation descriptions, with checks.

The checks are the manual's rules ("LED Animations" section) and the lights controller's of
the robot's release (`releases.py`: plugin types, priorities, stock images, each with its
source): each rule has its own finding code and message. `load_led_config` raises on the
first error; `validate_animations` (in `validate.py`) reports them all.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.manager.errors import LightsConfigError
from panther_ops.manager.findings import Finding, error, has_errors, warning
from panther_ops.manager.lights.releases import PACKAGES, PANTHER_ROS, RELEASES, LightsRelease
from panther_ops.manager.yaml_io import read_yaml

IMAGE_TYPES = {r.plugin(t) for r in RELEASES for t in r.types if t != "ChargingAnimation"}
CHARGING_TYPES = {r.plugin("ChargingAnimation") for r in RELEASES if "ChargingAnimation" in r.types}
MOVING_TYPES = {r.plugin("MovingImageAnimation") for r in RELEASES if "MovingImageAnimation" in r.types}
OWN_PACKAGES = set(PACKAGES)
MAX_DISPLAY_SECONDS = 10.0
FIRST_USER_ID = 20
DEFAULT_PRIORITY = 3
DEFAULT_TIMEOUT = 120.0
CONTROLLER_FREQUENCY = 50.0
_RANGE = re.compile(r"^\s*(\d+)\s*-\s*(\d+)\s*$")
_FIND = re.compile(r"^\$\(find\s+([A-Za-z0-9_]+)\)(/.*)$")
_PLUGIN = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)::[A-Za-z_][A-Za-z0-9_]*$")
_HEX = re.compile(r"^(0x|#)?[0-9a-fA-F]{1,6}$")
_MOVING_PARAMS: dict[str, str] = {"center_offset": "int16", "object_width": "int16", "start_offset": "float",
                                  "splash_duration": "float", "default_image_position": "float",
                                  "image_mirrored": "bool", "position_mirrored": "bool"}
"""MovingImageAnimation's optional parameters and the type it reads them as
(husarion_ugv_ros@2.2.0:husarion_ugv_lights/src/animation/moving_image_animation.cpp)."""


@dataclass(frozen=True)
class Panel:
    """A physical LED panel (one bumper)."""

    channel: int
    number_of_leds: int


@dataclass(frozen=True)
class Segment:
    """A virtual segment: LEDs ``first``..``last`` of a panel (reversed when first > last)."""

    name: str
    channel: int
    first: int
    last: int

    @property
    def num_leds(self) -> int:
        return abs(self.last - self.first) + 1

    @property
    def inverted(self) -> bool:
        return self.first > self.last

    @property
    def offset(self) -> int:
        return min(self.first, self.last)


@dataclass(frozen=True)
class AnimationPart:
    """One animation of an ID, on one segments group.

    ``image`` is None for an image that is only in the robot's image (a stock image of a
    release whose images panther-ops does not ship): checked by name, not drawable here.
    """

    type: str
    segments: tuple[str, ...]
    params: Mapping[str, Any]
    image: Path | None = None
    image_ref: str = ""

    @property
    def is_charging(self) -> bool:
        return self.type in CHARGING_TYPES

    @property
    def is_moving(self) -> bool:
        return self.type in MOVING_TYPES


@dataclass(frozen=True)
class AnimationDesc:
    """An animation ID: name, queue priority and timeout, and its parts."""

    id: int
    name: str
    priority: int
    timeout: float
    parts: tuple[AnimationPart, ...]


@dataclass(frozen=True)
class LedConfig:
    """A whole LED configuration."""

    panels: Mapping[int, Panel]
    segments: Mapping[str, Segment]
    segments_map: Mapping[str, tuple[str, ...]]
    animations: Mapping[int, AnimationDesc] = field(default_factory=dict)
    source: str = ""


def _where(source: str, path: str) -> str:
    return f"{source}: {path}" if path else source


def resolve_image(text: str, release: LightsRelease = PANTHER_ROS) -> tuple[Path | None, Finding | None]:
    """An image path: absolute, or ``$(find pkg)/...``.

    ``$(find <lights package>)/...`` must name the release's own package and one of the images
    it ships (`releases.py`); such an image resolves to panther-ops' drawing of the same name
    where it has one (panther_lights' names, in templates/lights), else to None: it is in the
    robot's image. Other packages are looked up in AMENT_PREFIX_PATH; a package that is not
    installed here is the robot's (its image or workspace): the finding is then a warning that
    the image was not checked, with the reason.
    """
    match = _FIND.match(text)
    if match:
        package, rest = match.groups()
        if package in OWN_PACKAGES:
            if package != release.package:
                return None, error("anim-image-package",
                                   f"image {text}: there is no package {package} on {release.name} "
                                   f"(its lights package is {release.package})")
            rel = rest.lstrip("/")
            if rel not in release.images:
                model = "animations/panther/" if "animations/panther/" in release.image_dirs() else "animations/"
                names = sorted(i.rsplit("/", 1)[1] for i in release.images if i.startswith(model))
                return None, error("anim-image-not-found",
                                   f"image {text} is not one of the images {package} ships on {release.name} "
                                   f"({release.image_dirs()}; {model}: {', '.join(names)})")
            local = release.local_images / rel if release.local_images is not None else None
            return (local if local is not None and local.is_file() else None), None
        for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
            share = Path(prefix) / "share" / package
            if share.is_dir():
                return share / rest.lstrip("/"), None
        return None, warning("anim-image-unchecked",
                             f"image {text} not checked: $(find {package}) is resolved on the robot "
                             "(the package is not installed here)")
    if not Path(text).is_absolute():
        return None, error("anim-image-path",
                           f"image path '{text}' must be absolute or start with $(find <package>)")
    return Path(text), None


def _or(values: tuple[int, ...]) -> str:
    """``1, 2 or 3``."""
    text = [str(v) for v in values]
    return text[0] if len(text) == 1 else f"{', '.join(text[:-1])} or {text[-1]}"


def parse_color(value: Any) -> int | None:
    """A hex RGB colour (YAML ``0xff0000`` or the string ``"0xff0000"``), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return value if 0 <= value <= 0xFFFFFF else None
    if isinstance(value, str) and _HEX.match(value.strip()):
        return int(value.strip().lstrip("#").removeprefix("0x").removeprefix("0X"), 16)
    return None


def parse_layout(doc: Mapping[str, Any], source: str) -> tuple[LedConfig, list[Finding]]:
    """Panels, segments and segments_map, with their rules."""
    findings: list[Finding] = []
    panels: dict[int, Panel] = {}
    for i, raw in enumerate(doc.get("panels") or []):
        where = _where(source, f"panels[{i}]")
        try:
            panel = Panel(int(raw["channel"]), int(raw["number_of_leds"]))
        except (KeyError, TypeError, ValueError):
            findings.append(error("panel-invalid", "a panel needs integer 'channel' and "
                                  "'number_of_leds'", where))
            continue
        if panel.channel in panels:
            findings.append(error("panel-duplicate", f"channel {panel.channel} is defined twice",
                                  where))
        panels[panel.channel] = panel
    segments: dict[str, Segment] = {}
    declared: set[str] = set()
    for i, raw in enumerate(doc.get("segments") or []):
        where = _where(source, f"segments[{i}]")
        if not isinstance(raw, Mapping) or "name" not in raw:
            findings.append(error("segment-invalid", "a segment needs a 'name'", where))
            continue
        name = str(raw["name"])
        declared.add(name)
        match = _RANGE.match(str(raw.get("led_range", "")))
        if match is None:
            findings.append(error("segment-range-invalid", f"segment '{name}': led_range "
                                  f"{raw.get('led_range')!r} is not a 'first-last' pair such as "
                                  "0-45 or 45-0", where))
            continue
        try:
            channel = int(raw["channel"])
        except (KeyError, TypeError, ValueError):
            findings.append(error("segment-channel-invalid",
                                  f"segment '{name}': channel must be an integer", where))
            continue
        segment = Segment(name, channel, int(match.group(1)), int(match.group(2)))
        owner = panels.get(channel)
        if owner is None:
            findings.append(error("segment-channel-unknown", f"segment '{name}' uses channel "
                                  f"{channel}, which no panel defines", where))
        elif max(segment.first, segment.last) >= owner.number_of_leds:
            findings.append(error("segment-range-outside", f"segment '{name}': led_range "
                                  f"{segment.first}-{segment.last} is outside panel {channel} "
                                  f"(LEDs 0-{owner.number_of_leds - 1})", where))
        if name in segments:
            findings.append(error("segment-duplicate", f"segment '{name}' is defined twice", where))
        segments[name] = segment
    segments_map: dict[str, tuple[str, ...]] = {}
    for group, members in (doc.get("segments_map") or {}).items():
        names = tuple(str(m) for m in (members or []))
        for name in names:
            if name not in declared:
                findings.append(error("segments-map-unknown-segment", f"segments_map '{group}' "
                                      f"names segment '{name}', which is not defined",
                                      _where(source, f"segments_map.{group}")))
        segments_map[str(group)] = names
    return LedConfig(panels, segments, segments_map, {}, source), findings


def _check_timing(params: Mapping[str, Any], where: str, findings: list[Finding]) -> bool | None:
    """Duration and repeat rules; None when the part cannot be used at all."""
    try:
        duration = float(params["duration"])
        if duration <= 0:
            raise ValueError
    except (KeyError, TypeError, ValueError):
        findings.append(error("anim-duration-invalid", "duration must be a positive number of "
                              "seconds", where))
        return None
    try:
        repeat = int(params.get("repeat", 1))
        if repeat < 1 or isinstance(params.get("repeat", 1), bool):
            raise ValueError
    except (TypeError, ValueError):
        findings.append(error("anim-repeat-invalid", "repeat must be a positive integer", where))
        return None
    ok = True
    if duration * repeat > MAX_DISPLAY_SECONDS:
        findings.append(error("anim-too-long", f"duration x repeat = {duration * repeat:g} s "
                              f"exceeds {MAX_DISPLAY_SECONDS:g} s", where))
        ok = False
    if round(duration * CONTROLLER_FREQUENCY) < 1:
        findings.append(error("anim-too-short", f"duration {duration:g} s is shorter than one "
                              f"frame at {CONTROLLER_FREQUENCY:g} Hz", where))
        ok = False
    return ok


def _check_looks(params: Mapping[str, Any], where: str, findings: list[Finding],
                 release: LightsRelease = PANTHER_ROS) -> bool:
    """Brightness and colour rules."""
    ok = True
    if "brightness" in params and not release.reads_brightness:
        findings.append(warning("anim-brightness-ignored", f"brightness is not read on {release.name} "
                                "(removed in husarion_ugv_lights 2.2.0): give the image's colours, or color", where))
    elif "brightness" in params:
        try:
            brightness = float(params["brightness"])
        except (TypeError, ValueError):
            brightness = -1.0
        if not 0.0 <= brightness <= 1.0:
            findings.append(error("anim-brightness-range", f"brightness {params['brightness']!r} "
                                  "is outside [0, 1]", where))
            ok = False
    if "color" in params and parse_color(params["color"]) is None:
        findings.append(error("anim-color-invalid", f"color {params['color']!r} is not a hex RGB "
                              "value such as 0xff0000", where))
        ok = False
    return ok


def _check_image(params: Mapping[str, Any], where: str, findings: list[Finding],
                 release: LightsRelease = PANTHER_ROS, kind: str = "ImageAnimation") -> tuple[bool, Path | None]:
    """Image path rules: present, absolute or $(find pkg), existing."""
    if not params.get("image"):
        findings.append(error("anim-image-missing-key", f"an {kind.rsplit(':', 1)[-1]} needs 'image'", where))
        return False, None
    image, problem = resolve_image(str(params["image"]), release)
    if problem is not None:
        findings.append(Finding(problem.severity, problem.code, problem.message, where))
        return problem.severity.value != "error", None
    if image is not None and not image.is_file():
        if not _FIND.match(str(params["image"])):  # an absolute path: the robot's (or its image's) file
            findings.append(warning("anim-image-unchecked", f"image {image} not checked: it is not on this "
                                    "computer (a path on the robot or in its image)", where))
            return True, image
        findings.append(error("anim-image-not-found", f"image {image} does not exist", where))
        return False, image
    return True, image


def _check_moving(params: Mapping[str, Any], where: str, findings: list[Finding]) -> None:
    """MovingImageAnimation's optional parameters: a value of another type is ignored on the robot."""
    for name, kind in _MOVING_PARAMS.items():
        if name not in params:
            continue
        value = params[name]
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        fits = {"int16": isinstance(value, int) and not isinstance(value, bool) and -32768 <= value <= 32767,
                "float": number, "bool": isinstance(value, bool)}[kind]
        if not fits:
            findings.append(warning("anim-param-ignored", f"{name}={value!r} is not a{'n' if kind[0] == 'i' else ''} "
                                    f"{kind}: MovingImageAnimation ignores it and uses its default", where))


def _type_rule(kind: str, release: LightsRelease, where: str, findings: list[Finding]) -> str:
    """'stock', 'custom' (another package's plugin) or 'bad' (an error was added)."""
    if kind in release.plugins:
        return "stock"
    plugin = _PLUGIN.match(kind)
    if plugin and plugin.group(1) not in OWN_PACKAGES:  # the manual allows animation plugins
        findings.append(warning("anim-type-custom", f"custom animation type '{kind}': played by its "
                                "plugin on the robot, not checked here (and not drawn by a preview)", where))
        return "custom"
    findings.append(error("anim-type-unknown", f"unknown animation type '{kind}' on {release.name} (known: "
                          f"{', '.join(release.plugins)} [{release.source}], or a plugin's <package>::<Class>)",
                          where))
    return "bad"


def _part(raw: Any, layout: LedConfig, where: str, findings: list[Finding],
          release: LightsRelease = PANTHER_ROS) -> AnimationPart | None:
    if not isinstance(raw, Mapping) or not isinstance(raw.get("animation"), Mapping):
        findings.append(error("anim-part-invalid", "each entry of 'animations' needs 'type', "
                              "'segments' and an 'animation' mapping", where))
        return None
    kind, group, params = str(raw.get("type", "")), str(raw.get("segments", "")), raw["animation"]
    rule = _type_rule(kind, release, where, findings)
    ok = rule != "bad"
    if group not in layout.segments_map:
        findings.append(error("anim-segments-unknown", f"segments '{group}' is not a group of "
                              f"segments_map ({', '.join(layout.segments_map) or 'none'})", where))
        ok = False
    timing = _check_timing(params, where, findings)
    if timing is None:
        return None
    ok = _check_looks(params, where, findings, release) and timing and ok
    image: Path | None = None
    if kind in IMAGE_TYPES | MOVING_TYPES and rule == "stock":
        image_ok, image = _check_image(params, where, findings, release, kind)
        ok = ok and image_ok
    if kind in MOVING_TYPES and rule == "stock":
        _check_moving(params, where, findings)
    if not ok or rule == "custom":  # a plugin's animation is played by the robot's lights controller only
        return None
    return AnimationPart(kind, layout.segments_map[group], dict(params), image, str(params.get("image", "")))


def parse_animations(entries: Any, layout: LedConfig, source: str, *, user: bool,
                     taken: Mapping[int, str] | None = None, release: LightsRelease = PANTHER_ROS,
                     ) -> tuple[dict[int, AnimationDesc], list[Finding]]:
    """Animation descriptions (``led_animations`` or ``user_animations``) with the rules of
    ``release``'s lights controller."""
    findings: list[Finding] = []
    descs: dict[int, AnimationDesc] = {}
    seen: dict[int, str] = dict(taken or {})
    key = "user_animations" if user else "led_animations"
    if not isinstance(entries, list):
        return descs, [error("anim-list-missing", f"'{key}' must be a list", source)]
    for i, raw in enumerate(entries):
        where = _where(source, f"{key}[{i}]")
        if not isinstance(raw, Mapping):
            findings.append(error("anim-invalid", "an animation must be a mapping", where))
            continue
        try:
            anim_id = int(raw["id"])
            if anim_id < 0 or isinstance(raw["id"], bool):
                raise ValueError
        except (KeyError, TypeError, ValueError):
            findings.append(error("anim-id-invalid", "an animation needs a non-negative integer "
                                  "'id'", where))
            continue
        name = str(raw.get("name") or f"ANIMATION_{anim_id}")
        where = _where(source, f"{key}[{i}] (id {anim_id})")
        if user and anim_id < FIRST_USER_ID:
            findings.append(error("anim-id-reserved", f"ID {anim_id} is reserved for system "
                                  f"animations (0-19); user animations use {FIRST_USER_ID} or more",
                                  where))
        if anim_id in seen:
            findings.append(error("anim-id-duplicate", f"ID {anim_id} is already used by "
                                  f"{seen[anim_id]}; IDs must be unique", where))
        seen.setdefault(anim_id, name)
        priority = raw.get("priority", DEFAULT_PRIORITY)
        allowed = release.user_priorities() if user else release.priorities
        if user and priority == release.user_forbidden_priority and not isinstance(priority, bool):
            findings.append(error("anim-priority-reserved", f"priority {priority} is reserved for system "
                                  f"animations on {release.name}; user animations use priority "
                                  f"{_or(allowed)}", where))
        elif priority not in release.priorities or isinstance(priority, bool):
            findings.append(error("anim-priority-invalid", f"priority {priority!r} is not "
                                  f"{_or(release.priorities)} ({release.name})", where))
        try:
            timeout = float(raw.get("timeout", DEFAULT_TIMEOUT))
        except (TypeError, ValueError):
            findings.append(error("anim-timeout-invalid", "timeout must be a number of seconds",
                                  where))
            timeout = DEFAULT_TIMEOUT
        parts_raw = raw.get("animations")
        if not isinstance(parts_raw, list) or not parts_raw:
            findings.append(error("anim-parts-missing", "an animation needs a non-empty "
                                  "'animations' list", where))
            continue
        count = len(findings)
        parts = [_part(p, layout, f"{where} animations[{j}]", findings, release)
                 for j, p in enumerate(parts_raw)]
        if not has_errors(findings[count:]) and all(p is not None for p in parts):
            descs[anim_id] = AnimationDesc(anim_id, name, int(priority), timeout,
                                           tuple(p for p in parts if p is not None))
    return descs, findings


def check_led_config(path: str | Path | None = None, user_animations: str | Path | None = None,
                     release: LightsRelease = PANTHER_ROS) -> tuple[LedConfig, list[Finding]]:
    """Parse and check a led_config (default: the shipped one) and an optional user file."""
    source = str(path or release.default_led_config)
    doc = read_yaml(source, LightsConfigError) or {}
    if not isinstance(doc, Mapping):
        raise LightsConfigError(f"{source}: expected a mapping")
    layout, findings = parse_layout(doc, source)
    descs, more = parse_animations(doc.get("led_animations") or [], layout, source, user=False,
                                   release=release)
    findings += more
    if user_animations is not None:
        user_doc = read_yaml(user_animations, LightsConfigError) or {}
        if not isinstance(user_doc, Mapping):
            raise LightsConfigError(f"{user_animations}: expected a mapping with 'user_animations'")
        taken = {i: f"{d.name} in {source}" for i, d in descs.items()}
        user, more = parse_animations(user_doc.get("user_animations") or [], layout,
                                      str(user_animations), user=True, taken=taken, release=release)
        findings += more
        descs = {**descs, **user}
    config = LedConfig(layout.panels, layout.segments, layout.segments_map, descs, source)
    return config, findings


def load_led_config(path: str | Path | None = None, user_animations: str | Path | None = None,
                    release: LightsRelease = PANTHER_ROS) -> LedConfig:
    """A checked LedConfig; raise LightsConfigError with every error found."""
    config, findings = check_led_config(path, user_animations, release)
    if has_errors(findings):
        raise LightsConfigError("\n".join(str(f) for f in findings))
    return config
