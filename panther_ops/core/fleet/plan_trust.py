"""The planner of `panther-ops trust ROBOT`: whether the key a robot offers is known, new or
changed, a pure function of the offered key's type and fingerprint and the known keys'
(the reads, the key itself and the write are `trust.py`'s)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class TrustPlan:
    robot: str
    address: str
    key_type: str
    fingerprint: str
    state: str  # "known" | "new" | "changed"
    known_fingerprints: tuple[str, ...]
    known_hosts_file: str
    hostname: str
    port: int
    key: Any
    """The offered key as read (what `trust.record` writes)."""


def trust_state(key_type: str, fingerprint: str, known: Sequence[tuple[str, str]]) -> str:
    """``known`` (that key is recorded), ``changed`` (another key of its type is) or ``new``;
    ``known``: (type, fingerprint) of every key recorded for the host."""
    if any(fp == fingerprint for _t, fp in known):
        return "known"
    if any(t == key_type for t, _fp in known):
        return "changed"
    return "new"
