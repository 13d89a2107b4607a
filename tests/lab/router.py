"""A RUTX11 on a lab robot's LAN: a namespace behind the robot (as the router sits behind the
Built-in Computer's 10.15.20.2 at 10.15.20.1) running the stand-in of the router's REST API
and GNSS NMEA forwarding (data/rutx11-standin.py).

Built as a lab computer (tests/lab/computers.py: own namespaces, reachable only through the
robot, torn down with the lab); its certificate is a self-signed one made here. The sender's
target follows the stand-in's forwarding settings; `Router.sender()` switches the GNSS
"antenna" on or off and sets the position it reports.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import json
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .computers import ComputerSpec, add_computers
from .files import DATA
from .nmea import wait_until

if TYPE_CHECKING:
    from .lab import Lab

REPO_ROOT = Path(__file__).resolve().parents[2]
SENTENCES = ("GPGSV", "GPGGA", "GPVTG", "GPRMC", "GPGSA", "GLGSV", "GNGSA", "GNGNS", "GAGSV", "PQGSV", "PQGSA")


@dataclass(frozen=True)
class Router:
    name: str
    ip: str
    dir: Path
    robot: str
    robot_lan_ip: str
    """The robot's address on its LAN (where the router forwards NMEA, 10.15.20.2's role)."""

    def state(self) -> dict[str, Any]:
        return dict(json.loads((self.dir / "rutx-state.json").read_text()))

    def sender(self, *, on: bool = True, lat: float = 53.1978, lon: float = 18.3732, quality: int = 1) -> None:
        tmp = self.dir / "sender.tmp"
        tmp.write_text(json.dumps({"on": on, "lat": lat, "lon": lon, "quality": quality}))
        tmp.replace(self.dir / "sender.json")

    def set_password(self, password: str) -> None:
        (self.dir / "rutx-password").write_text(password + "\n")

    def events(self) -> list[dict[str, Any]]:
        path = self.dir / "rutx-standin.log"
        return [json.loads(x) for x in path.read_text().splitlines() if x.strip()] if path.exists() else []


def _self_signed(dest: Path, name: str) -> None:
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import NameOID

    key = ec.generate_private_key(ec.SECP256R1())
    subject = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, name)])
    now = dt.datetime.now(dt.timezone.utc)
    cert = (x509.CertificateBuilder().subject_name(subject).issuer_name(subject).public_key(key.public_key())
            .serial_number(x509.random_serial_number()).not_valid_before(now - dt.timedelta(minutes=5))
            .not_valid_after(now + dt.timedelta(days=2)).sign(key, hashes.SHA256()))
    (dest / "cert.pem").write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    fd = os.open(dest / "key.pem", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                  serialization.NoEncryption()))


def renew_certificate(lab: Lab, router: Router) -> None:
    """A new self-signed certificate (a reset router): the stand-in restarts with it."""
    _self_signed(router.dir, "RUTX11 (new)")
    _start(lab, lab._rs(router.name), router.dir)


def initial_state(robot_lan_ip: str) -> dict[str, Any]:
    """A router as delivered: GNSS on, forwarding off (to the Built-in Computer's port 5000)."""
    return {
        "global": {"enabled": "1", "galileo_sup": "0", "glonass_sup": "0", "beidou_sup": "0"},
        "forwarding": {"id": "nmea_forwarding", "enabled": "0", "hostname": robot_lan_ip, "port": "5000",
                       "proto": "udp"},
        "rules": [{"id": s, "forwarding_enabled": "1" if s in ("GPGGA", "GPRMC", "GPGSA", "GPGSV") else "0",
                   "forwarding_interval": "1"} for s in SENTENCES],
    }


def add_router(lab: Lab, robot: str, *, name: str = "rtx", password: str = "Husarion1", token_ttl: float = 300.0
               ) -> Router:
    (c,) = add_computers(lab, [ComputerSpec(name, behind=robot, operator_key=False)])
    w = lab.st.jump_subnets[robot]
    lan_ip = f"10.200.{w}.1"
    d = c.dir
    _self_signed(d, "RUTX11")
    (d / "rutx-state.json").write_text(json.dumps(initial_state(lan_ip), indent=2))
    router = Router(name, c.ip, d, robot, lan_ip)
    router.set_password(password)
    router.sender(on=True)
    (d / "token-ttl").write_text(f"{token_ttl}\n")
    _start(lab, lab._rs(name), d)
    return router


def _start(lab: Lab, r: Any, d: Path) -> None:
    old = r.proc("rutx11")
    if old is not None:
        with contextlib.suppress(ProcessLookupError):
            os.kill(old.pid, 15)
    log = d / "rutx-standin.log"
    before = log.read_text().count('"listening"') if log.exists() else 0
    ttl = (d / "token-ttl").read_text().strip()
    # the router's network only: the stand-in runs this checkout's interpreter and imports from
    # it (pynmea2, tests.lab.nmea), which a computer's own mount namespace may hide (its /tmp)
    argv = ["nsenter", "-t", str(lab._init_pid(r)), "-n", "--", sys.executable, str(DATA / "rutx11-standin.py"),
            str(d), str(REPO_ROOT), "443", ttl]
    # nsenter without a PID namespace execs it itself: one process
    lab._start_until(r, argv, d / "rutx-standin.out", ("rutx11",), "RUTX11 stand-in",
                     lambda: log.exists() and log.read_text().count('"listening"') > before, timeout=15.0)


__all__ = ["Router", "add_router", "renew_certificate", "wait_until"]
