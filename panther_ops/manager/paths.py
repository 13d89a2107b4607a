"""Where the shipped templates live (the repository's ``templates/`` directory)."""

from __future__ import annotations

from pathlib import Path

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"
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
