"""husarion-webui's state on the User Computer as read (`remote.read_state`), and the plan of
a `webui set`: pure functions of that state and what was asked."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.kinds.webui_settings import DEFAULTS, SNAP, profile_name
from panther_ops.core.remote.estop.answers import split
from panther_ops.core.remote.webui.defaults import KEY as NS_KEY


@dataclass
class WebuiState:
    """What the User Computer said about the snap."""

    installed: bool
    channel: str | None = None
    revision: str | None = None
    settings: dict[str, str] = field(default_factory=dict)
    running: bool = False
    profiles: set[str] = field(default_factory=set)
    """Transports with a ``dds-config-<name>.xml`` in the common directory (the install hook's
    links for the shipped ones included)."""

    def value(self, key: str) -> str:
        return self.settings.get(key, DEFAULTS[key])

    def to_json(self) -> dict[str, Any]:
        return {"installed": self.installed, "channel": self.channel, "revision": self.revision,
                "settings": {k: self.value(k) for k in DEFAULTS} if self.installed else {},
                "running": self.running, "dds_profiles": sorted(self.profiles)}


def parse_state(output: str) -> WebuiState:
    got = split(output)
    listed = got.get("list")
    if listed is None or listed.status != 0:
        return WebuiState(False)
    state = WebuiState(True)
    for line in listed.text.splitlines()[1:]:
        cols = line.split()
        if cols and cols[0] == SNAP and len(cols) >= 4:
            state.revision, state.channel = cols[2], cols[3]
    getd = got.get("get")
    if getd is not None and getd.status == 0:
        try:
            doc = json.loads(getd.text or "{}")
        except ValueError:
            doc = {}
        for section, values in doc.items() if isinstance(doc, dict) else ():
            for name, value in values.items() if isinstance(values, dict) else ():
                state.settings[f"{section}.{name}"] = str(value)
    services = got.get("services")
    state.running = services is not None and any(
        SNAP in line and " active" in f" {line}" and "inactive" not in line for line in services.text.splitlines())
    profiles = got.get("profiles")
    if profiles is not None:  # dds-config-<X>.xml: the files the configure hook resolves <X> to
        state.profiles = {name for n in profiles.text.split() if (name := profile_name(n)) is not None}
    return state


def plan_changes(state: WebuiState, wanted: dict[str, str]) -> list[tuple[str, str, str]]:
    """(key, current, new) for every key whose value changes (pure)."""
    return [(k, state.value(k), v) for k, v in wanted.items() if state.value(k) != v]


def plan_text(plan: list[tuple[str, str, str]], note: str) -> str:
    """``key: current -> new, ...``; a ``ros.namespace`` that is the robot's default says so."""
    defaulted = note.startswith(f"{NS_KEY} ") and ": " in note

    def item(k: str, c: str, n: str) -> str:
        why = f" ({note.split(': ', 1)[1]})" if k == NS_KEY and defaulted else ""
        return f"{k}: {c or '(unset)'} -> {n}{why}"

    return ", ".join(item(k, c, n) for k, c, n in plan)
