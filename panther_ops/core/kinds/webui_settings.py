"""The husarion-webui snap's settings and their validator: the configure hook's rules.

Keys and defaults (snapcraft.io/husarion-webui; `snap set husarion-webui KEY=VALUE`):
``ros.namespace`` (unset), ``ros.transport`` (udp), ``ros.domain-id`` (0),
``ros.localhost-only`` (unset), ``webui.layout`` (default), ``webui.port`` (8080).

The ROS keys are the snap's shared hooks', husarion/husarion-snap-common (its latest tag,
0.13.0; the flat 0.5.0 layout agrees where noted). Sources:

* ``husarion/husarion-snap-common@0.13.0:local-ros/install_hook_ros.sh``: on install
  ``ros.transport=udp``, ``ros.domain-id=0``, ``ros.namespace`` and (humble)
  ``ros.localhost-only`` unset; the shipped profiles under ``<common>/rmw/`` with the
  back-compat links ``<common>/dds-config-{udp,shm,udp-lo,udp-lo-cyclone}.xml``
  (0.5.0 copies files of those names there).
* ``husarion/husarion-snap-common@0.13.0:local-ros/configure_hook_ros.sh``, which refuses the
  whole ``snap set`` otherwise: namespace ``^[a-z_][0-9a-z_]{0,19}$`` (0.5.0 also took '-' and
  a leading digit; ROS names do not); domain id 0-232 (``validate_number``); localhost-only
  0, 1 or unset; ``ros.transport`` one of ``rmw_fastrtps_cpp``, ``rmw_cyclonedds_cpp`` (no
  profile), ``udp``, ``shm``, ``udp-lo``, ``udp-lo-cyclone`` (shipped profiles), zenoh
  refused, and any other ``<X>`` only when ``<common>/dds-config-<X>.xml`` exists and its
  type is detected (the same file name in 0.5.0: the manual's "custom DDS configuration").
  0.6.0+ also takes ``fastdds/<X>`` / ``cyclonedds/<X>`` (files under ``rmw/``); 0.5.0
  does not, so panther-ops does not offer them.
* ``husarion/husarion-snap-common@0.13.0:local-ros/utils.sh`` ``check_xml_profile_type``:
  ``yq '. | keys | .[1]'`` (key 0 is the XML declaration, ``+p_xml``) must be ``profiles``
  with ``xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"`` (Fast DDS) or
  ``CycloneDDS`` with ``xmlns="https://cdds.io/config"``; anything else is refused.

The WebUI keys are the built-in server's port (1-65535) and a layout name (a file
``foxglove-<layout>.json`` in the common directory): the husarion-webui snap's own hook, which
is not among the mirrored sources. The same rules run here before anything is sent, so a
refused value changes nothing.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Mapping

from panther_ops.core.parse.numbers import NumberError, int_in_range
from panther_ops.core.parse.ros_names import RosNameError, namespace

SNAP = "husarion-webui"
COMMON_DIR = "/var/snap/husarion-webui/common"
DEFAULTS = {
    "ros.namespace": "",
    "ros.transport": "udp",
    "ros.domain-id": "0",
    "ros.localhost-only": "",
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
BUILTIN_TRANSPORTS = ("udp", "shm", "udp-lo", "udp-lo-cyclone", "rmw_fastrtps_cpp", "rmw_cyclonedds_cpp")
"""Tokens the configure hook resolves itself (never to ``dds-config-<X>.xml``)."""
ZENOH_TRANSPORTS = ("rmw_zenoh_cpp", "zenoh")
"""Refused by the configure hook (``HSC_ALLOW_ZENOH`` unset)."""
NAMESPACE = re.compile(r"^[a-z_][0-9a-z_]{0,19}$")
PROFILE = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,63}$")
"""A custom DDS profile or layout name: a plain file name part, nothing a shell or a path reads."""
PROFILE_PREFIX = "dds-config-"
"""A custom profile ``<X>`` is the file ``<common>/dds-config-<X>.xml``."""
FASTDDS_NS = "http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"
CYCLONEDDS_NS = "https://cdds.io/config"
PROFILE_ROOTS = {"profiles": FASTDDS_NS, "CycloneDDS": CYCLONEDDS_NS}
"""Root element -> the ``xmlns`` the hook's ``check_xml_profile_type`` needs on it."""


def profile_path(name: str) -> str:
    """Where the configure hook looks for the custom profile ``name``."""
    return f"{COMMON_DIR}/{PROFILE_PREFIX}{name}.xml"


def profile_name(file_name: str) -> str | None:
    """The transport a file of the common directory names (``dds-config-<X>.xml`` -> X)."""
    if file_name.startswith(PROFILE_PREFIX) and file_name.endswith(".xml"):
        return file_name[len(PROFILE_PREFIX):-4] or None
    return None


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

    ``dds_profiles``: the profile names present in the snap's common directory
    (``dds-config-<name>.xml``); None when unknown (a custom transport is then checked for its
    form only, its presence when it is applied). Raises :class:`SettingError` on the first bad one,
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


def _transports() -> str:
    return f"{', '.join(BUILTIN_TRANSPORTS)}, or <name> of a DDS profile {profile_path('<name>')}"


def _check(key: str, value: str, dds_profiles: Collection[str] | None) -> str:
    if key == "ros.namespace":
        if not NAMESPACE.match(value):
            hook = "1-20 characters of a-z, 0-9 and '_', not starting with a digit"
            try:  # say what ROS says of it first, where it says anything
                namespace(value)
            except RosNameError as exc:
                raise SettingError(key, value, f"{exc} (the snap's hook takes {hook})") from None
            raise SettingError(key, value, f"{hook} (e.g. panther)")
    elif key == "ros.transport":
        if value in BUILTIN_TRANSPORTS:
            return value
        if value in ZENOH_TRANSPORTS or value.startswith("zenoh/"):
            raise SettingError(key, value, f"zenoh is refused by the snap's configure hook; use {_transports()}")
        if not PROFILE.match(value):
            raise SettingError(key, value, _transports())
        if dds_profiles is not None and value not in dds_profiles:
            have = ", ".join(sorted(set(dds_profiles) - set(BUILTIN_TRANSPORTS))) or "none"
            raise SettingError(key, value, f"no DDS profile {profile_path(value)} (custom profiles there: {have}; "
                                           "upload one with --dds-file)")
    elif key == "ros.domain-id":
        _integer(key, value, 0, 232)
    elif key == "ros.localhost-only":
        if value not in ("0", "1", ""):
            raise SettingError(key, value, "0 or 1 (or empty: unset)")
    elif key == "webui.port":
        _integer(key, value, 1, 65535)
    elif key == "webui.layout" and not PROFILE.match(value):
        raise SettingError(key, value, "a layout name: letters, digits, '_', '.' and '-' (e.g. panther)")
    return value


def _integer(key: str, value: str, low: int, high: int) -> None:
    try:
        int_in_range(value, low, high)
    except NumberError as exc:
        raise SettingError(key, value, str(exc)) from None


def dds_profile(name: str, data: bytes) -> tuple[str, bytes]:
    """A DDS XML profile to upload as ``dds-config-<name>.xml``: its name (the file's, without
    ``.xml`` and a leading ``dds-config-``) and content, checked as the configure hook checks it
    (see the module): an XML declaration, then the root ``<profiles>`` (Fast DDS) or
    ``<CycloneDDS>`` with its ``xmlns``; no DOCTYPE. Raises SettingError."""
    stem = name[:-4] if name.endswith(".xml") else name
    stem = stem[len(PROFILE_PREFIX):] if stem.startswith(PROFILE_PREFIX) else stem
    if not PROFILE.match(stem):
        raise SettingError("--dds-file", name, "a file name of letters, digits, '_', '.' and '-' ending in .xml")
    if stem in BUILTIN_TRANSPORTS or stem in ZENOH_TRANSPORTS:
        raise SettingError("--dds-file", name, f"a name other than the snap's own transports "
                                               f"({', '.join(BUILTIN_TRANSPORTS + ZENOH_TRANSPORTS)}): "
                                               "the hook resolves those itself and would ignore the file")
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise SettingError("--dds-file", name, "a DDS profile without DOCTYPE or entities")
    root, attrs, declared = _prolog(name, data)
    if root not in PROFILE_ROOTS:
        raise SettingError("--dds-file", name, "a DDS profile the snap detects: root element <profiles> (Fast DDS) "
                                               f"or <CycloneDDS> (Cyclone DDS), not <{root}>")
    if attrs.get("xmlns") != PROFILE_ROOTS[root]:
        raise SettingError("--dds-file", name, f"<{root} xmlns=\"{PROFILE_ROOTS[root]}\"> (the snap detects the "
                                               f"profile type by it), not xmlns={attrs.get('xmlns')!r}")
    if not declared:
        raise SettingError("--dds-file", name, "a first line <?xml version=\"1.0\" encoding=\"UTF-8\"?> (the snap "
                                               "reads the root element as the document's second entry)")
    return stem, data


def _prolog(name: str, data: bytes) -> tuple[str, dict[str, str], bool]:
    """The root element's literal name and attributes, and whether an XML declaration (and no
    other processing instruction) precedes it. Raises SettingError when not well-formed."""
    import xml.parsers.expat

    seen: dict[str, object] = {"declared": False, "other_pi": False}
    found: list[tuple[str, dict[str, str]]] = []
    parser = xml.parsers.expat.ParserCreate()  # no namespace processing: names as written

    def decl(*_args: object) -> None:
        seen["declared"] = True

    def pi(_target: str, _data: str) -> None:
        if not found:
            seen["other_pi"] = True

    def start(tag: str, attrs: dict[str, str]) -> None:
        if not found:
            found.append((tag, dict(attrs)))

    def doctype(*_args: object) -> None:  # also when the bytes check above missed it (UTF-16)
        raise SettingError("--dds-file", name, "a DDS profile without DOCTYPE or entities")

    parser.XmlDeclHandler = decl
    parser.StartDoctypeDeclHandler = doctype
    parser.EntityDeclHandler = doctype
    parser.ProcessingInstructionHandler = pi
    parser.StartElementHandler = start
    try:
        parser.Parse(data, True)
    except xml.parsers.expat.ExpatError as exc:
        raise SettingError("--dds-file", name, f"well-formed XML ({exc})") from None
    if not found:
        raise SettingError("--dds-file", name, "well-formed XML (no root element)")
    return found[0][0], found[0][1], bool(seen["declared"]) and not seen["other_pi"]
