"""The husarion-webui snap's settings and their validator: the configure hook's rules.

Keys and defaults (snapcraft.io/husarion-webui; `snap set husarion-webui KEY=VALUE`):
``ros.namespace`` (unset), ``ros.transport`` (udp), ``ros.domain-id`` (0),
``ros.localhost-only`` (0), ``webui.layout`` (default), ``webui.port`` (8080).

The ROS keys are checked by the snap's configure hook (husarion-snap-common 0.5.0,
``local-ros/configure_hook_ros.sh``), which refuses the whole ``snap set`` otherwise:
namespace ``^[0-9a-z_-]{1,20}$``, domain id 0-232, localhost-only 0 or 1, a transport that is
``rmw_fastrtps_cpp``, ``rmw_cyclonedds_cpp`` or names a DDS profile shipped with the snap
(udp, udp-lo, shm, builtin) or added to its common directory (``<name>.xml`` there, the
manual's "custom DDS configuration"). The WebUI keys are the built-in server's port
(1-65535) and a layout name (a file ``foxglove-<layout>.json`` in the common directory).
The same rules run here before anything is sent, so a refused value changes nothing.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Mapping

SNAP = "husarion-webui"
COMMON_DIR = "/var/snap/husarion-webui/common"
DEFAULTS = {
    "ros.namespace": "",
    "ros.transport": "udp",
    "ros.domain-id": "0",
    "ros.localhost-only": "0",
    "webui.layout": "default",
    "webui.port": "8080",
}
KEYS = tuple(DEFAULTS)
ALIASES = {
    "namespace": "ros.namespace",
    "transport": "ros.transport",
    "domain_id": "ros.domain-id",
    "localhost_only": "ros.localhost-only",
    "layout": "webui.layout",
    "port": "webui.port",
}
"""The inventory's short names (desired.webui) for the snap's keys."""
BUILTIN_TRANSPORTS = ("udp", "udp-lo", "shm", "builtin", "rmw_cyclonedds_cpp", "rmw_fastrtps_cpp")
NAMESPACE = re.compile(r"^[0-9a-z_-]{1,20}$")
PROFILE = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,63}$")
"""A custom DDS profile or layout name: a plain file name part, nothing a shell or a path reads."""


class SettingError(Exception):
    """A WebUI setting the configure hook would refuse."""

    def __init__(self, key: str, value: str, allowed: str) -> None:
        super().__init__(key, value, allowed)
        self.key = key
        self.value = value
        self.allowed = allowed

    def __str__(self) -> str:
        return f"{self.key}={self.value!r} is not allowed: {self.allowed}"


class SettingConflict(SettingError):
    """Two names given for one key (a snap key and its inventory short name, or a key and the
    option that also sets it): which one was meant is not known, so neither is used."""

    def __init__(self, key: str, first: str, second: str, keep: str = "") -> None:
        super().__init__(key, "", keep)
        self.first = first
        self.second = second

    def __str__(self) -> str:
        keep = self.allowed or "keep one of them"
        return f"{self.first} and {self.second} both set {self.key}: {keep}"


def canonical_key(key: str) -> str:
    """The snap's key for ``key`` (a snap key or an inventory alias)."""
    if key in DEFAULTS:
        return key
    if key in ALIASES:
        return ALIASES[key]
    raise SettingError(key, "", f"unknown key; the snap's keys: {', '.join(KEYS)}")


def validate(settings: Mapping[str, object], dds_profiles: Collection[str] | None = None) -> dict[str, str]:
    """The settings as the snap's keys and string values, every one checked.

    ``dds_profiles``: the custom profile names present in the snap's common directory
    (``<name>.xml``); None when unknown (a custom transport is then checked for its form
    only, its presence when it is applied). Raises :class:`SettingError` on the first bad one,
    :class:`SettingConflict` when two of the given names are the same key (``port`` and
    ``webui.port``).
    """
    out: dict[str, str] = {}
    named: dict[str, str] = {}
    for raw_key, given in settings.items():
        key = canonical_key(str(raw_key))
        if key in named:
            raise SettingConflict(key, named[key], f"{raw_key}={given}")
        named[key] = f"{raw_key}={given}"
        raw = int(given) if isinstance(given, bool) and key == "ros.localhost-only" else given  # YAML true/false
        if isinstance(raw, bool) or raw is None or isinstance(raw, (list, dict)):
            raise SettingError(key, str(raw), "a single value")
        value = str(raw).strip()
        out[key] = _check(key, value, dds_profiles)
    return out


def _check(key: str, value: str, dds_profiles: Collection[str] | None) -> str:
    if key == "ros.namespace":
        if not NAMESPACE.match(value):
            raise SettingError(key, value, "1-20 characters of a-z, 0-9, '_' and '-' (e.g. panther)")
    elif key == "ros.transport":
        if value in BUILTIN_TRANSPORTS:
            return value
        if not PROFILE.match(value):
            raise SettingError(key, value, f"{', '.join(BUILTIN_TRANSPORTS)}, or the name of a DDS profile "
                                           f"<name>.xml in {COMMON_DIR}")
        if dds_profiles is not None and value not in dds_profiles:
            have = ", ".join(sorted(dds_profiles)) or "none"
            raise SettingError(key, value, f"no DDS profile {COMMON_DIR}/{value}.xml (custom profiles there: {have}; "
                                           "upload one with --dds-file)")
    elif key == "ros.domain-id":
        _integer(key, value, 0, 232)
    elif key == "ros.localhost-only":
        if value not in ("0", "1"):
            raise SettingError(key, value, "0 or 1")
    elif key == "webui.port":
        _integer(key, value, 1, 65535)
    elif key == "webui.layout" and not PROFILE.match(value):
        raise SettingError(key, value, "a layout name: letters, digits, '_', '.' and '-' (e.g. panther)")
    return value


def _integer(key: str, value: str, low: int, high: int) -> None:
    from panther_ops.core.parse.numbers import NumberError, int_in_range

    try:
        int_in_range(value, low, high)
    except NumberError:
        raise SettingError(key, value, f"a whole number from {low} to {high} in ASCII digits 0-9") from None


DDS_ROOTS = ("dds", "profiles", "CycloneDDS")
"""Root elements of a DDS profile: Fast DDS (<dds>, <profiles>) or Cyclone DDS (<CycloneDDS>)."""


def dds_profile(name: str, data: bytes) -> tuple[str, bytes]:
    """A DDS XML profile to upload as ``<name>.xml``: its name and content, checked (well-formed
    XML without a DOCTYPE, a Fast DDS or Cyclone DDS root element). Raises SettingError."""
    import xml.etree.ElementTree as ET

    stem = name[:-4] if name.endswith(".xml") else name
    if not PROFILE.match(stem):
        raise SettingError("--dds-file", name, "a file name of letters, digits, '_', '.' and '-' ending in .xml")
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise SettingError("--dds-file", name, "a DDS profile without DOCTYPE or entities")
    try:
        root = ET.fromstring(data)  # noqa: S314 - DOCTYPE and entities refused above: nothing to expand
    except ET.ParseError as exc:
        raise SettingError("--dds-file", name, f"well-formed XML ({exc})") from None
    tag = root.tag.split("}", 1)[-1]
    if tag not in DDS_ROOTS:
        raise SettingError("--dds-file", name, f"a DDS profile: root element {' or '.join(DDS_ROOTS)}, not <{tag}>")
    return stem, data
