"""Times as a robot's docker engine gives them: RFC 3339 stamps, its own clock, uptimes."""

from __future__ import annotations

import re
from datetime import datetime, timezone
from typing import Any

_TS = re.compile(r"^(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d)(?:\.(\d+))?(Z|[+-]\d\d:\d\d)?$")


def parse_timestamp(text: Any) -> datetime | None:
    """Docker's RFC 3339 times (nanoseconds, ``Z`` or an offset); None for the zero time."""
    if not isinstance(text, str) or not text or text.startswith("0001-"):
        return None
    m = _TS.match(text.strip())
    if not m:
        return None
    frac = ((m[2] or "") + "000000")[:6]
    tz = "+00:00" if m[3] in (None, "Z") else m[3]
    return datetime.fromisoformat(f"{m[1]}.{frac}{tz}")


def human_duration(seconds: float | None) -> str:
    """``3725`` -> ``1h 2m``: the two largest units."""
    if seconds is None:
        return "-"
    s = int(max(seconds, 0))
    parts = [(s // 86400, "d"), (s % 86400 // 3600, "h"), (s % 3600 // 60, "m"), (s % 60, "s")]
    shown = [f"{n}{u}" for n, u in parts if n]
    return " ".join(shown[:2]) if shown else "0s"


def engine_now(client: Any) -> datetime:
    """The robot engine's clock (uptimes do not depend on this machine's clock)."""
    try:
        now = parse_timestamp(client.info().get("SystemTime"))
    except Exception:  # the engine's clock is a nicety: fall back to this machine's
        now = None
    return now or datetime.now(timezone.utc)
