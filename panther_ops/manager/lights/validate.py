"""`validate_animations`: every rule violation of an animations file, each with its own code.

Rules: IDs 0-19 reserved (user files), unique IDs (also against the led_config's),
user priority 2-3 only, priority 1-3, duration x repeat <= 10 s, positive duration and
repeat, brightness in [0, 1], image paths absolute or ``$(find pkg)`` and existing, hex
colours, known animation types, segments groups in segments_map, segments_map names
defined segments, segment channels present in panels, led_range inside its panel.
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
from panther_ops.manager.paths import default_led_config
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


def _check(path: str | Path, led_config: str | Path | None) -> tuple[LedConfig, list[Finding]]:
    doc, findings = _read(path)
    if doc is None:
        return LedConfig({}, {}, {}), findings
    source = str(path)
    if "user_animations" in doc:
        base, base_findings = check_led_config(led_config or default_led_config())
        findings += [f for f in base_findings if f.where.startswith(source)]
        taken = {i: f"{d.name} in {base.source}" for i, d in base.animations.items()}
        user, more = parse_animations(doc.get("user_animations") or [], base, source,
                                      user=True, taken=taken)
        animations = {**base.animations, **user}
        return LedConfig(base.panels, base.segments, base.segments_map, animations,
                         source), findings + more
    if "led_animations" in doc:
        if "panels" in doc or "segments" in doc:
            layout, findings = parse_layout(doc, source)
        else:
            layout, _ = check_led_config(led_config or default_led_config())
        descs, more = parse_animations(doc.get("led_animations") or [], layout, source, user=False)
        return LedConfig(layout.panels, layout.segments, layout.segments_map, descs,
                         source), findings + more
    return LedConfig({}, {}, {}), [error("anim-list-missing", "no 'user_animations' or "
                                         "'led_animations' list", source)]


def validate_animations(path: str | Path, led_config: str | Path | None = None) -> list[Finding]:
    """Check an animations file; one finding per rule violation (empty when valid).

    Args:
        path: a user animations file (``user_animations:``) or a whole led_config
            (``panels``, ``segments``, ``segments_map``, ``led_animations``).
        led_config: panels, segments and system animations a user file builds on
            (default: the shipped templates/lights/led_config.yaml).
    """
    return _check(path, led_config)[1]


def animations_with_layout(path: str | Path, led_config: str | Path | None = None) -> LedConfig:
    """The animations of `path` with the panels and segments they play on; raise on errors."""
    config, findings = _check(path, led_config)
    if has_errors(findings):
        raise LightsConfigError("\n".join(str(f) for f in findings if f.severity.value == "error"))
    return config
