"""Where the shipped templates live: ``panther_ops/templates`` when installed from a wheel,
else the repository's ``templates/`` directory (a checkout or an editable install)."""

from __future__ import annotations

from pathlib import Path


def _templates() -> Path:
    package = Path(__file__).resolve().parents[1]  # panther_ops/
    installed = package / "templates"
    return installed if installed.is_dir() else package.parent / "templates"


TEMPLATES = _templates()
BEHAVIOR_TREES = TEMPLATES / "behavior_trees"
LIGHTS = TEMPLATES / "lights"
SCENARIOS = TEMPLATES / "manager" / "scenarios"


def default_led_config() -> Path:
    """The shipped led_config.yaml (panels, segments, default animations)."""
    return LIGHTS / "led_config.yaml"


def default_lights_project() -> Path:
    """The shipped Lights BehaviorTree project."""
    return BEHAVIOR_TREES / "PantherLightsBT.btproj"


def default_safety_project() -> Path:
    """The shipped Safety and Shutdown BehaviorTree project."""
    return BEHAVIOR_TREES / "PantherSafetyBT.btproj"
