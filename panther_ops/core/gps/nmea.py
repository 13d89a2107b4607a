"""NMEA 0183 decoding with pynmea2: fixes from GGA (with RMC of the same epoch), counts of
everything else.

A *fix* is one GGA sentence (any talker: GP, GN, GL, GA, BD): latitude, longitude, fix
quality, satellites in use, HDOP, altitude, UTC time. An RMC sentence of the same UTC time
(before it, or after it in the same datagram) adds the date, validity, speed and course.
GSA and GSV are counted by type; anything that is not NMEA, has a bad or missing checksum or
has unreadable fields is counted, never raised.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Any

COORD_DIGITS = 8
"""Decimal places kept for degrees (1e-8 degree, about 1 mm)."""

FIX_QUALITY = {
    0: "invalid", 1: "gps", 2: "dgps", 3: "pps", 4: "rtk", 5: "float-rtk", 6: "estimated", 7: "manual", 8: "simulation",
}
"""GGA fix quality indicator -> name."""


@dataclass
class Fix:
    """One GGA sentence, decoded."""

    lat: float | None
    lon: float | None
    fix_quality: int
    satellites: int | None
    hdop: float | None
    altitude_m: float | None
    time: str | None
    talker: str
    date: str | None = None
    valid: bool | None = None
    speed_knots: float | None = None
    course_deg: float | None = None
    received_at: float | None = None

    @property
    def has_fix(self) -> bool:
        return self.fix_quality > 0 and self.lat is not None and self.lon is not None

    def to_json(self) -> dict[str, Any]:
        return {
            "lat": self.lat, "lon": self.lon, "fix_quality": self.fix_quality,
            "fix": FIX_QUALITY.get(self.fix_quality, "unknown"), "satellites": self.satellites, "hdop": self.hdop,
            "altitude_m": self.altitude_m, "time": self.time, "date": self.date, "valid": self.valid,
            "speed_knots": self.speed_knots, "course_deg": self.course_deg, "talker": self.talker,
            "received_at": self.received_at,
        }


@dataclass
class NmeaStats:
    """What a decoder has seen."""

    sentences: int = 0
    by_type: Counter[str] = field(default_factory=Counter)
    malformed: int = 0
    bad_checksum: int = 0
    unknown_type: int = 0
    datagrams: int = 0

    def to_json(self) -> dict[str, Any]:
        return {
            "datagrams": self.datagrams, "sentences": self.sentences, "by_type": dict(sorted(self.by_type.items())),
            "malformed": self.malformed, "bad_checksum": self.bad_checksum, "unknown_type": self.unknown_type,
        }


def _float(value: Any) -> float | None:
    try:
        return float(value) if value not in (None, "") else None
    except (TypeError, ValueError):
        return None


def _int(value: Any) -> int | None:
    try:
        return int(value) if value not in (None, "") else None
    except (TypeError, ValueError):
        return None


def _coords(msg: Any) -> tuple[float | None, float | None]:
    """Signed degrees, or None for empty fields (no fix). Raises ValueError on garbage."""
    if not msg.lat or not msg.lon:
        return None, None
    if msg.lat_dir not in ("N", "S") or msg.lon_dir not in ("E", "W"):
        raise ValueError(f"hemisphere {msg.lat_dir!r}/{msg.lon_dir!r}")
    return round(float(msg.latitude), COORD_DIGITS), round(float(msg.longitude), COORD_DIGITS)


def _time(msg: Any) -> str | None:
    """UTC time of day as HH:MM:SS[.ffffff] (pynmea2 makes it timezone-aware: UTC)."""
    return msg.timestamp.replace(tzinfo=None).isoformat() if msg.timestamp else None


class NmeaDecoder:
    """Feed it datagrams (or lines); it returns the fixes they complete."""

    def __init__(self) -> None:
        self.stats = NmeaStats()
        self._rmc: dict[str, Any] = {}
        """The last RMC: its time and what it adds to a GGA of that time."""

    def feed(self, data: bytes, *, received_at: float | None = None) -> list[Fix]:
        self.stats.datagrams += 1
        text = data.decode("ascii", errors="replace")
        fixes = []
        for line in text.splitlines():
            if line.strip():
                fix = self.feed_line(line, received_at=received_at)
                if fix is not None:
                    fixes.append(fix)
        for fix in fixes:  # an RMC after the GGA of its epoch, in the same datagram
            if fix.date is None and fix.time is not None and self._rmc.get("time") == fix.time:
                self._enrich(fix)
        return fixes

    def feed_line(self, line: str, *, received_at: float | None = None) -> Fix | None:
        import pynmea2

        self.stats.sentences += 1
        try:
            msg = pynmea2.parse(line.strip(), check=True)
        except pynmea2.ChecksumError:
            self.stats.bad_checksum += 1
            return None
        except pynmea2.SentenceTypeError:
            self.stats.unknown_type += 1
            return None
        except (pynmea2.ParseError, ValueError, TypeError, AttributeError):
            self.stats.malformed += 1
            return None
        kind = str(getattr(msg, "sentence_type", "") or "")
        try:
            if kind == "GGA":
                fix = self._gga(msg, received_at)
            elif kind == "RMC":
                self._remember_rmc(msg)
                fix = None
            else:
                fix = None
        except (ValueError, TypeError, AttributeError, IndexError):
            self.stats.malformed += 1
            return None
        self.stats.by_type[kind] += 1
        return fix

    def _gga(self, msg: Any, received_at: float | None) -> Fix:
        lat, lon = _coords(msg)
        quality = _int(msg.gps_qual)
        if quality is None:
            raise ValueError("no fix quality")
        when = _time(msg)
        fix = Fix(lat=lat, lon=lon, fix_quality=quality, satellites=_int(msg.num_sats), hdop=_float(msg.horizontal_dil),
                  altitude_m=_float(msg.altitude), time=when, talker=str(msg.talker), received_at=received_at)
        if when is not None and self._rmc.get("time") == when:
            self._enrich(fix)
        return fix

    def _enrich(self, fix: Fix) -> None:
        fix.date, fix.valid = self._rmc["date"], self._rmc["valid"]
        fix.speed_knots, fix.course_deg = self._rmc["speed_knots"], self._rmc["course_deg"]

    def _remember_rmc(self, msg: Any) -> None:
        _coords(msg)  # garbage coordinates make the sentence malformed
        self._rmc = {
            "time": _time(msg),
            "date": msg.datestamp.isoformat() if msg.datestamp else None,
            "valid": msg.status == "A",
            "speed_knots": _float(msg.spd_over_grnd), "course_deg": _float(msg.true_course),
        }
