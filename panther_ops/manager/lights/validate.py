"""`validate_animations`: every rule violation of an animations file, each with its own code.

Rules (those of the robot's release, `releases.py`): IDs 0-19 reserved (user files), unique
IDs (also against the stock file's), priorities of the release (1-3 on panther_ros, 0-3 on
husarion_ugv 2.2) and the one user animations may not use (1; on 2.2: 0), duration x repeat
<= 10 s, positive duration and repeat, brightness in [0, 1] (panther_ros), image paths
absolute or ``$(find pkg)``, a stock image one the release ships, hex colours, the release's
animation types, segments groups in segments_map, segments_map names defined segments,
segment channels present in panels, led_range inside its panel.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from panther_ops.manager.errors import LightsConfigError
from panther_ops.manager.findings import Finding, error, has_errors
from panther_ops.manager.lights.config import (
    LedConfig,
    check_led_config,
    parse_animations,
    parse_layout,
)
from panther_ops.manager.lights.releases import LightsRelease, release_of
from panther_ops.manager.yaml_io import read_yaml


def _read(path: str | Path) -> tuple[Mapping[str, Any] | None, list[Finding]]:
    try:
        doc = read_yaml(path, LightsConfigError)
    except LightsConfigError as exc:
        return None, [error("file-unreadable", str(exc), str(path))]
    if not isinstance(doc, Mapping):
        return None, [error("file-not-mapping", "expected a mapping with 'user_animations' or "
                            "'led_animations'", str(path))]
    return doc, []


def _types(doc: Mapping[str, Any]) -> list[str]:
    """Every part's ``type`` in a file (to tell which release it is written for)."""
    out: list[str] = []
    for key in ("led_animations", "user_animations"):
        entries = doc.get(key)
        for entry in entries if isinstance(entries, list) else []:
            parts = entry.get("animations") if isinstance(entry, Mapping) else None
            out += [str(p.get("type", "")) for p in (parts if isinstance(parts, list) else [])
                    if isinstance(p, Mapping)]
    return out


def _check(path: str | Path, led_config: str | Path | None,
           release: LightsRelease | None) -> tuple[LedConfig, list[Finding]]:
    doc, findings = _read(path)
    if doc is None:
        return LedConfig({}, {}, {}), findings
    source = str(path)
    rules = release or release_of(_types(doc))
    if "user_animations" in doc:
        base, base_findings = check_led_config(led_config or rules.default_led_config, release=rules)
        findings += [f for f in base_findings if f.where.startswith(source)]
        taken = {i: f"{d.name} in {base.source}" for i, d in base.animations.items()}
        user, more = parse_animations(doc.get("user_animations") or [], base, source,
                                      user=True, taken=taken, release=rules)
        animations = {**base.animations, **user}
        return LedConfig(base.panels, base.segments, base.segments_map, animations,
                         source), findings + more
    if "led_animations" in doc:
        if "panels" in doc or "segments" in doc:
            layout, findings = parse_layout(doc, source)
        else:
            layout, _ = check_led_config(led_config or rules.default_led_config, release=rules)
        descs, more = parse_animations(doc.get("led_animations") or [], layout, source, user=False,
                                       release=rules)
        return LedConfig(layout.panels, layout.segments, layout.segments_map, descs,
                         source), findings + more
    return LedConfig({}, {}, {}), [error("anim-list-missing", "no 'user_animations' or "
                                         "'led_animations' list", source)]


def validate_animations(path: str | Path, led_config: str | Path | None = None,
                        release: LightsRelease | None = None) -> list[Finding]:
    """Check an animations file; one finding per rule violation (empty when valid).

    Args:
        path: a user animations file (``user_animations:``) or a whole led_config
            (``panels``, ``segments``, ``segments_map``, ``led_animations``).
        led_config: panels, segments and system animations a user file builds on
            (default: the release's stock file, see `releases.py`).
        release: the lights rules of the robot's release (`releases.release_for`); None:
            the release whose lights package the file's animation types name.
    """
    return _check(path, led_config, release)[1]


def animations_with_layout(path: str | Path, led_config: str | Path | None = None,
                           release: LightsRelease | None = None) -> LedConfig:
    """The animations of `path` with the panels and segments they play on; raise on errors."""
    config, findings = _check(path, led_config, release)
    if has_errors(findings):
        raise LightsConfigError("\n".join(str(f) for f in findings if f.severity.value == "error"))
    return config
