"""Issue-13 acceptance, the router: `gps router show|set` against the lab's RUTX11 stand-in on
a robot's LAN (tests/lab/router.py), reached through the robot's SSH connection; the router's
NMEA sender follows the forwarding settings, so `router set` changes whether data arrives at
the robot's UDP port."""

from __future__ import annotations

import os
import signal
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.clirun import run_cli
from tests.lab._sys import wait_child
from tests.lab.router import Router, add_router, renew_certificate

pytestmark = pytest.mark.lab
PASSWORD = "lab-router-pass"
CAPTURE = (  # an epoch: the first datagram within 2.5 s, then the rest of its sentences (one per datagram)
    "import socket,sys\n"
    "s=socket.socket(socket.AF_INET,socket.SOCK_DGRAM);s.bind(('0.0.0.0',int(sys.argv[1])));s.settimeout(2.5)\n"
    "got=[]\n"
    "try:\n  got.append(s.recv(65535).decode())\n  s.settimeout(0.3)\n"
    "  while True:\n    got.append(s.recv(65535).decode())\n"
    "except socket.timeout:\n  pass\n"
    "print(''.join(got) or 'NOTHING')\n"
)

SYSTEM_PYTHON = "/usr/bin/python3"
"""Seen inside a robot's namespaces wherever this checkout lives (what the lab's stand-ins run)."""


@pytest.fixture(scope="module")
def router_lab(lab_factory: Any) -> tuple[Any, Router]:
    lab = lab_factory(1, docker=False, images=("2.1.1",))
    return lab, add_router(lab, "r01", password=PASSWORD, token_ttl=3.0)


@pytest.fixture(scope="module")
def jazzy_router_lab(lab_factory: Any) -> tuple[Any, Router]:
    """One husarion_ugv 2.3.2 (Jazzy) robot with its RUTX11: the NMEA setup is unchanged from 2.2."""
    lab = lab_factory(1, docker=False, images=("2.3.2",))
    return lab, add_router(lab, "r01", password=PASSWORD, token_ttl=3.0)


@pytest.fixture
def env(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    pins = tmp_path / "pins"
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PINS", str(pins))
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PASSWORD", PASSWORD)
    monkeypatch.delenv("PANTHER_OPS_ROUTER_USER", raising=False)
    return pins


def cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any], str]:
    code, doc, out, err = run_cli(capsys, *argv)
    return code, doc, out + err


def arrives(lab: Any, port: int = 5000) -> str:
    # the system's python3: the robot's mount namespace may hide this checkout's venv (its /tmp)
    return str(lab.exec("r01", [SYSTEM_PYTHON, "-c", CAPTURE, str(port)], timeout=20).stdout)


@pytest.fixture
def reset(router_lab: tuple[Any, Router]) -> Iterator[None]:
    _lab, router = router_lab
    saved = (router.dir / "rutx-state.json").read_text()
    yield
    (router.dir / "rutx-state.json").write_text(saved)
    router.set_password(PASSWORD)
    router.sender(on=True)


def test_show_set_and_forwarding(router_lab: tuple[Any, Router], env: Path, reset: None,
                                 capsys: pytest.CaptureFixture[str]) -> None:
    lab, router = router_lab
    inv = str(lab.inventory_path)
    base = ["-i", inv]
    code, doc, text = cli(capsys, *base, "gps", "router", "show", "-r", "r01", "--address", router.ip, "--json")
    assert code == 0, text
    d = doc["robots"][0]["data"]
    assert (d["forwarding"], d["hostname"], d["port"], d["proto"]) == (False, router.robot_lan_ip, "5000", "udp")
    assert d["sentences"] == ["GPGSV", "GPGGA", "GPRMC", "GPGSA"]
    assert PASSWORD not in text
    # pinned on first use, 0600
    pin = env.read_text().split()
    assert pin == [f"r01/{router.ip}", d["certificate"]] and stat.S_IMODE(os.stat(env).st_mode) == 0o600
    assert "NOTHING" in arrives(lab)

    code, doc, text = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip, "--enable",
                          "--sentences", "GPGGA,GPRMC", "--dry-run", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed" and router.state()["forwarding"]["enabled"] == "0"

    code, doc, text = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip, "--enable",
                          "--sentences", "GPGGA,GPRMC", "--yes", "--json")
    assert code == 0, text
    st = router.state()
    assert st["forwarding"] == {"id": "nmea_forwarding", "enabled": "1", "hostname": router.robot_lan_ip,
                                "port": "5000", "proto": "udp"}
    assert {r["id"] for r in st["rules"] if r["forwarding_enabled"] == "1"} == {"GPGGA", "GPRMC"}
    got = arrives(lab)
    assert "$GPGGA," in got and "$GPRMC," in got and "$GPGSA" not in got
    code, doc, _ = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip, "--enable",
                       "--sentences", "GPGGA,GPRMC", "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok"

    code, doc, text = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip, "--port",
                          "5009", "--yes", "--json")
    assert code == 0, text
    assert router.state()["forwarding"]["port"] == "5009" and "NOTHING" in arrives(lab, 5000)
    assert "$GPGGA," in arrives(lab, 5009)
    code, doc, text = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip, "--disable",
                          "--port", "5000", "--yes", "--json")
    assert code == 0 and router.state()["forwarding"]["enabled"] == "0" and "NOTHING" in arrives(lab)
    assert not [e for e in router.events() if e["event"] == "put-refused"]


def test_bad_input_and_wrong_password(router_lab: tuple[Any, Router], env: Path, reset: None,
                                      capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    lab, router = router_lab
    base = ["-i", str(lab.inventory_path), "gps", "router", "set", "-r", "r01", "--address", router.ip, "--yes"]
    before = router.state()
    for argv, says in ((["--port", "70000"], "'--port': '70000' is not a port"), (["--hostname", "bad host"], "--hostname"),
                       (["--sentences", "GPGGA,GPXYZ"], "unknown sentence id 'GPXYZ'"), ([], "nothing to set")):
        code, _doc, text = cli(capsys, *base, *argv)
        assert code == 2 and says in text, (argv, text)
    monkeypatch.setenv("PANTHER_OPS_ROUTER_PASSWORD", "wrong-secret")
    code, _doc, text = cli(capsys, *base, "--enable")
    assert code == 2 and "refused the login" in text and "wrong-secret" not in text
    assert router.state() == before


def test_credentials_file_mode_and_pin_mismatch(router_lab: tuple[Any, Router], env: Path, reset: None,
                                                tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    lab, router = router_lab
    base = ["-i", str(lab.inventory_path), "gps", "router", "show", "-r", "r01", "--address", router.ip, "--json"]
    monkeypatch.delenv("PANTHER_OPS_ROUTER_PASSWORD")
    creds = tmp_path / "creds"
    creds.write_text(f"default:\n  username: admin\n  password: {PASSWORD}\n")
    os.chmod(creds, 0o644)
    monkeypatch.setenv("PANTHER_OPS_ROUTER_CREDENTIALS", str(creds))
    code, _doc, text = cli(capsys, *base)
    assert code == 2 and "chmod 600" in text
    os.chmod(creds, 0o600)
    code, doc, text = cli(capsys, *base)
    assert code == 0 and doc["robots"][0]["outcome"] == "ok", text
    renew_certificate(lab, router)
    code, doc, text = cli(capsys, *base)
    assert code == 3 and doc["robots"][0]["outcome"] == "failed"
    assert "not the pinned" in doc["robots"][0]["message"]


def test_expired_token_logs_in_again(router_lab: tuple[Any, Router], env: Path) -> None:
    """One client kept past the token's 3 s: its next call is refused (401), it logs in again."""
    import time

    from panther_ops.core.fleet.inventory_file import load_inventory
    from panther_ops.core.fleet.runner import Connections
    from panther_ops.secret import Secret
    from panther_ops.transport import pins
    from panther_ops.transport.rutx import RouterClient
    from panther_ops.transport.tunnel import open_tcp

    lab, router = router_lab
    inv = load_inventory(str(lab.inventory_path))
    with Connections(inv) as conns:
        ssh = conns.get(inv.robots["r01"]).client  # type: ignore[attr-defined]
        api = RouterClient(lambda: open_tcp(ssh, "r01", router.ip, 443), "r01", router.ip, pinned=None,
                           pin=lambda fp: pins.pin("r01/x", fp))
        api.login("admin", Secret(PASSWORD))
        logins = sum(e["event"] == "login" for e in router.events())
        assert api.call("GET", "/api/gps/global")["enabled"] == "1"
        time.sleep(3.3)
        assert api.call("GET", "/api/gps/nmea/config/nmea_forwarding")["proto"] == "udp"
    events = router.events()
    assert any(e["event"] == "unauthorised" and e["expired"] for e in events)
    assert sum(e["event"] == "login" for e in events) == logins + 1


def test_status_verdicts_follow_the_router(router_lab: tuple[Any, Router], env: Path, reset: None,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    lab, router = router_lab
    base = ["-i", str(lab.inventory_path), "gps"]
    at = ["-r", "r01", "--address", router.ip]

    def status(*extra: str) -> dict[str, Any]:
        code, doc, text = cli(capsys, *base, "status", *at, "--window", "2.5", "--json", *extra)
        assert code in (0, 3), text
        res = doc["robots"][0]
        assert (code == 0) == (res["outcome"] == "ok")
        return dict(res["data"])

    lat, lon = 52.2297123, 21.0122456
    router.sender(on=True, lat=lat, lon=lon)
    d = status("--router")
    assert d["verdict"] == "router not forwarding" and d["router"]["forwarding"] is False
    assert d["robot_lan_ip"] == router.robot_lan_ip
    assert status()["verdict"] == "no data"  # without --router: nothing arrived, cause unknown

    assert cli(capsys, *base, "router", "set", *at, "--enable", "--yes")[0] == 0
    d = status("--router")
    assert d["verdict"] == "fix", d
    assert abs(d["fix"]["lat"] - lat) < 1e-6 and abs(d["fix"]["lon"] - lon) < 1e-6
    assert d["fix"]["fix_quality"] == 1 and d["fix"]["satellites"] == 9 and d["fix"]["hdop"] == 0.8
    assert d["sentences_per_s"] > 0 and d["counts"]["bad_checksum"] == 0 and 0 <= d["age_s"] < 2.6
    assert d["counts"]["by_type"]["GGA"] >= 2

    code, doc, text = cli(capsys, *base, "watch", *at, "--window", "1.5", "--count", "2", "--json")
    assert code == 0, text
    assert [r["robots"][0]["data"]["verdict"] for r in doc["rounds"]] == ["fix", "fix"]

    router.sender(on=True, lat=lat, lon=lon, quality=0)
    assert status()["verdict"] == "data but no fix"

    router.sender(on=False)
    d = status("--router")
    assert d["verdict"] == "no data" and d["counts"]["sentences"] == 0

    router.sender(on=True, lat=lat, lon=lon)
    assert cli(capsys, *base, "router", "set", *at, "--port", "5009", "--yes")[0] == 0
    d = status("--router")
    assert d["verdict"] == "forwarding to wrong host/port" and "5009" in d["detail"]
    assert cli(capsys, *base, "router", "set", *at, "--hostname", "10.200.250.7", "--port", "5000", "--yes")[0] == 0
    d = status("--router")
    assert d["verdict"] == "forwarding to wrong host/port" and "10.200.250.7:5000" in d["detail"]


def test_status_port_busy(router_lab: tuple[Any, Router], env: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A listener already holds the port (the NMEA driver, gpsd): nothing captured, said so."""
    import subprocess

    lab, _router = router_lab
    holder = "import socket,time\ns=socket.socket(socket.AF_INET,socket.SOCK_DGRAM);s.bind(('0.0.0.0',5000))\n" \
             "print('bound',flush=True);time.sleep(30)\n"
    p = subprocess.Popen([*lab._nsenter(lab._rs("r01")), SYSTEM_PYTHON, "-c", holder], stdout=subprocess.PIPE,
                         text=True)
    child = wait_child(p.pid)  # nsenter forks: the holder is its child
    try:
        assert p.stdout is not None and p.stdout.readline().strip() == "bound"
        code, doc, _ = cli(capsys, "-i", str(lab.inventory_path), "gps", "status", "-r", "r01", "--json")
        res = doc["robots"][0]
        assert code == 0 and res["outcome"] == "skipped" and res["data"]["verdict"] == "port busy"
        assert res["data"]["gpsd"] == {"running": False}
    finally:
        os.kill(child, signal.SIGKILL)
        p.wait(timeout=10)
        if p.stdout is not None:
            p.stdout.close()


def test_status_through_a_real_gpsd(router_lab: tuple[Any, Router], env: Path, reset: None,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    """gpsd on the robot takes the router's NMEA (`gpsd -N udp://<robot>:5000`, as the manual
    says): the port is gpsd's, and status reads gpsd's fix through gpsd-py3."""
    import shutil
    import subprocess
    import time

    lab, router = router_lab
    gpsd = shutil.which("gpsd") or "/usr/sbin/gpsd"
    lat, lon = 50.0614123, 19.9365456
    router.sender(on=True, lat=lat, lon=lon)
    at = ["-r", "r01", "--address", router.ip]
    assert cli(capsys, "-i", str(lab.inventory_path), "gps", "router", "set", *at, "--enable", "--yes")[0] == 0
    p = subprocess.Popen([*lab._nsenter(lab._rs("r01")), gpsd, "-N", "-n", "-S", "2947",
                          f"udp://{router.robot_lan_ip}:5000"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    child = wait_child(p.pid)
    try:
        time.sleep(2.5)  # gpsd binds, the next 1 Hz bursts give it a fix
        code, doc, text = cli(capsys, "-i", str(lab.inventory_path), "gps", "status", *at, "--router", "--json")
        res = doc["robots"][0]
        assert code == 0 and res["outcome"] == "ok", text
        d = res["data"]
        assert d["source"] == "gpsd" and d["verdict"] == "fix" and d["gpsd"]["mode"] >= 2
        assert abs(d["gpsd"]["lat"] - lat) < 1e-6 and abs(d["gpsd"]["lon"] - lon) < 1e-6
    finally:
        os.kill(child, signal.SIGTERM)
        p.wait(timeout=10)


def test_enable_with_router_in_one_plan(router_lab: tuple[Any, Router], env: Path, reset: None,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    """`gps enable --router`: the driver (here the nmea-gps service, --container, listening on
    the robot's LAN address) and the router's forwarding to it, one plan; then a fix."""
    lab, router = router_lab
    compose = "/home/husarion/compose.yaml"
    before = lab.read("r01", compose)
    argv = ["-i", str(lab.inventory_path), "gps", "enable", "-r", "r01", "--router", "--address", router.ip,
            "--container", "--ip", router.robot_lan_ip]
    router.sender(on=True, lat=47.3769123, lon=8.5417456)
    code, doc, text = cli(capsys, *argv, "--dry-run", "--json")
    assert code == 0 and router.state()["forwarding"]["enabled"] == "0" and lab.read("r01", compose) == before
    msg = doc["robots"][0]["message"]
    assert "add service nmea-gps" in msg and "forwarding.enabled: 0 -> 1" in msg, msg
    code, doc, text = cli(capsys, *argv, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "changed", text
    assert f"-p ip:={router.robot_lan_ip} -p port:=5000" in lab.read("r01", compose)
    assert router.state()["forwarding"]["enabled"] == "1"
    assert doc["robots"][0]["data"]["router_after"]["forwarding"] is True
    code, doc, text = cli(capsys, *argv, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok" and "already forwards" in doc["robots"][0]["message"]
    code, doc, text = cli(capsys, "-i", str(lab.inventory_path), "gps", "status", "-r", "r01", "--json")
    d = doc["robots"][0]["data"]
    assert d["verdict"] == "fix" and d["driver"]["mode"] == "service"
    assert abs(d["fix"]["lat"] - 47.3769123) < 1e-6 and abs(d["fix"]["lon"] - 8.5417456) < 1e-6
    code, doc, text = cli(capsys, "-i", str(lab.inventory_path), "gps", "disable", "-r", "r01", "--yes", "--json")
    assert code == 0 and lab.read("r01", compose) == before


def test_doctor_gps_check(router_lab: tuple[Any, Router], env: Path, reset: None,
                          capsys: pytest.CaptureFixture[str]) -> None:
    """A robot whose inventory says it has GNSS (desired.gps.enabled) gets a gps finding."""
    lab, router = router_lab
    text = lab.inventory_path.read_text()
    assert "  r01:\n" in text
    inv = lab.inventory_path.parent / "inventory-gps.yaml"  # beside it: its relative paths hold
    inv.write_text(text.replace("  r01:\n", "  r01:\n    desired:\n      gps: {enabled: true}\n", 1))

    def finding() -> dict[str, Any]:
        _code, doc, _out = cli(capsys, "-i", str(inv), "doctor", "-r", "r01", "--json")
        (f,) = [f for f in doc["robots"][0]["data"]["findings"] if f["check"] == "gps"]
        return dict(f)

    try:
        f = finding()
        assert f["state"] == "fail" and f["detail"].startswith("no data") and "gps status -r r01" in f["fix"]
        assert cli(capsys, "-i", str(inv), "gps", "router", "set", "-r", "r01", "--address", router.ip, "--enable",
                   "--yes")[0] == 0
        f = finding()
        assert f["detail"].startswith("fix: ") and f["state"] == "warn" and "gps enable -r r01" in f["fix"]
    finally:
        inv.unlink()


def test_show_and_set_on_a_2_3_2_robot(jazzy_router_lab: tuple[Any, Router], env: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    """`gps router show|set` through a husarion_ugv 2.3.2 robot: the router forwards NMEA to it, as
    through a Humble robot."""
    lab, router = jazzy_router_lab
    base = ["-i", str(lab.inventory_path)]
    code, doc, text = cli(capsys, *base, "gps", "router", "show", "-r", "r01", "--address", router.ip, "--json")
    assert code == 0 and doc["robots"][0]["data"]["forwarding"] is False, text
    try:
        code, doc, text = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip,
                              "--enable", "--sentences", "GPGGA,GPRMC", "--yes", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed", text
        got = arrives(lab)
        assert "$GPGGA," in got and "$GPRMC," in got and "$GPGSA" not in got
    finally:
        code, doc, text = cli(capsys, *base, "gps", "router", "set", "-r", "r01", "--address", router.ip,
                              "--disable", "--yes", "--json")
        assert code == 0, text
