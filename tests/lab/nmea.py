"""NMEA bursts as the RUTX11 sends them (GGA, GSA, RMC, GSV at 1 Hz), made with pynmea2,
and a UDP sender of them: the GNSS side of the lab (a stand-in for the router's receiver)."""

from __future__ import annotations

import datetime as dt
import socket
import threading
import time
from collections.abc import Callable

import pynmea2


def _ddmm(value: float, width: int) -> tuple[str, float]:
    deg = int(abs(value))
    minutes = (abs(value) - deg) * 60
    return f"{deg:0{width}d}{minutes:09.6f}", minutes


def sentences(lat: float, lon: float, *, when: dt.datetime | None = None, quality: int = 1, satellites: int = 9,
              hdop: float = 0.8, altitude: float = 120.4, talker: str = "GP") -> list[str]:
    """One epoch: GGA, GSA, RMC, GSV with valid checksums (minutes with 6 decimals: 1e-7 degree)."""
    when = when or dt.datetime.now(dt.timezone.utc)
    hhmmss = when.strftime("%H%M%S") + ".00"
    la, _ = _ddmm(lat, 2)
    lo, _ = _ddmm(lon, 3)
    ns, ew = ("N" if lat >= 0 else "S"), ("E" if lon >= 0 else "W")
    if quality == 0:
        la = lo = ns = ew = ""
    gga = pynmea2.GGA(talker, "GGA", (hhmmss, la, ns, lo, ew, str(quality), f"{satellites:02d}", f"{hdop:.1f}",
                                       f"{altitude:.1f}", "M", "34.5", "M", "", ""))
    gsa = pynmea2.GSA(talker, "GSA", ("A", "3" if quality else "1", "02", "05", "12", "15", "", "", "", "", "", "", "",
                                       "", "1.6", f"{hdop:.1f}", "1.2"))
    rmc = pynmea2.RMC(talker, "RMC", (hhmmss, "A" if quality else "V", la, ns, lo, ew, "0.02", "84.4",
                                       when.strftime("%d%m%y"), "", ""))
    gsv = pynmea2.GSV(talker, "GSV", ("1", "1", "04", "02", "40", "083", "45", "05", "22", "150", "38", "12", "61",
                                       "270", "44", "15", "10", "310", "30"))
    return [str(s) for s in (gga, gsa, rmc, gsv)]


def burst(lat: float, lon: float, **kw: object) -> bytes:
    return "".join(s + "\r\n" for s in sentences(lat, lon, **kw)).encode()  # type: ignore[arg-type]


class Sender:
    """Sends a burst every ``period`` seconds to the target ``target()`` answers (None: nothing
    sent), from its own thread, until ``stop()``."""

    def __init__(self, target: Callable[[], tuple[str, int] | None], lat: float, lon: float, *,
                 period: float = 1.0, payload: Callable[[], bytes] | None = None) -> None:
        self.target, self.lat, self.lon, self.period = target, lat, lon, period
        self.payload = payload or (lambda: burst(self.lat, self.lon))
        self.sent = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)

    def start(self) -> Sender:
        self._thread.start()
        return self

    def _run(self) -> None:
        while not self._stop.is_set():
            to = self.target()
            if to is not None:
                try:
                    self._sock.sendto(self.payload(), to)
                    self.sent += 1
                except OSError:
                    pass
            self._stop.wait(self.period)

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5)
        self._sock.close()


def wait_until(pred: Callable[[], bool], timeout: float = 10.0) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.05)
    return pred()
