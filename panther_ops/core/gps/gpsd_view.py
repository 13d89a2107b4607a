"""gpsd's view of the GNSS on a robot (where gpsd runs: ``gpsd -N udp://…:5000``), through
gpsd-py3 and a forwarded port of the robot's SSH connection (gpsd listens on the robot's
127.0.0.1:2947)."""

from __future__ import annotations

import threading
import time
from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.errors import TransportError

GPSD_PORT = 2947
_LOCK = threading.Lock()
"""gpsd-py3 keeps its one connection in module globals: one robot at a time."""


def gpsd_view(ctx: RobotContext, *, wait_s: float = 3.0) -> dict[str, Any] | None:
    """``{"running": False}`` when nothing listens on the robot's 2947; else gpsd's current
    TPV (mode, lat, lon, satellites); None for robots without SSH (demo)."""
    from panther_ops.transport.tunnel import forward_local

    client = getattr(ctx.transport, "client", None)
    if client is None:
        return None
    with _LOCK:
        try:
            local, close = forward_local(client, ctx.robot.name, "127.0.0.1", GPSD_PORT)
        except TransportError:
            return {"running": False}
        try:
            return _poll(local, wait_s)
        finally:
            close()


def _poll(local: int, wait_s: float) -> dict[str, Any]:
    import gpsd

    try:
        gpsd.connect("127.0.0.1", local)
        deadline = time.monotonic() + wait_s
        while True:
            try:
                r = gpsd.get_current()
                break
            except UserWarning:  # "GPS not active": no TPV yet
                if time.monotonic() >= deadline:
                    return {"running": True, "active": False}
                time.sleep(0.2)
    except Exception as exc:  # gpsd-py3 raises bare Exception on protocol surprises
        return {"running": True, "error": str(exc)}
    finally:
        sock = getattr(gpsd, "gpsd_socket", None)
        if sock is not None:
            sock.close()
    out: dict[str, Any] = {"running": True, "active": True, "mode": r.mode, "satellites": r.sats,
                           "satellites_used": r.sats_valid}
    if r.mode >= 2:
        out.update({"lat": r.lat, "lon": r.lon, "time": r.time})
    return out
