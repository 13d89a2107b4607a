"""`gps status` without a lab: the demo fleet's recorded NMEA, and the verdict rules."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.gps.nmea import Fix
from panther_ops.core.gps.status import FIX, NO_DATA, NO_FIX, NOT_FORWARDING, WRONG_TARGET, verdict


def test_demo_fleet_answers_with_recorded_nmea(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    capsys.readouterr()
    assert main(["-i", str(tmp_path / "demo"), "gps", "status", "--all", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [r["outcome"] for r in doc["robots"]] == ["ok"] * 4
    d = doc["robots"][0]["data"]
    assert d["recorded"] is True and d["verdict"] == FIX and d["driver"] == {"mode": "off"}
    assert abs(d["fix"]["lat"] - 53.1978127) < 1e-6 and abs(d["fix"]["lon"] - 18.3732456) < 1e-6
    assert d["counts"]["by_type"] == {"GGA": 3, "GSA": 3, "GSV": 3, "RMC": 3} and d["counts"]["malformed"] == 0


def _fix(quality: int) -> Fix:
    return Fix(lat=1.0 if quality else None, lon=2.0 if quality else None, fix_quality=quality, satellites=7,
               hdop=1.1, altitude_m=None, time=None, talker="GP")


ROUTER = {"gps_enabled": True, "forwarding": True, "hostname": "10.15.20.2", "port": "5000", "proto": "udp"}


@pytest.mark.parametrize(("fix", "n", "router", "want"), [
    (_fix(1), 8, None, FIX),
    (_fix(0), 8, ROUTER, NO_FIX),
    (None, 4, None, NO_FIX),  # GSV/GSA only: data, no position
    (None, 0, None, NO_DATA),
    (None, 0, ROUTER, NO_DATA),
    (None, 0, {**ROUTER, "forwarding": False}, NOT_FORWARDING),
    (None, 0, {**ROUTER, "gps_enabled": False}, NOT_FORWARDING),
    (None, 0, {**ROUTER, "proto": "tcp"}, NOT_FORWARDING),
    (None, 0, {**ROUTER, "port": "5001"}, WRONG_TARGET),
    (None, 0, {**ROUTER, "hostname": "10.15.20.3"}, WRONG_TARGET),
])
def test_verdicts(fix: Fix | None, n: int, router: dict[str, object] | None, want: str) -> None:
    assert verdict(fix, n, router, ("10.15.20.2", 5000))[0] == want


def test_watch_json_rounds_and_needs_count(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    capsys.readouterr()
    inv = str(tmp_path / "demo")
    assert main(["-i", inv, "gps", "watch", "-r", "panther-02", "--count", "2", "--window", "0.5", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["command"] == "gps watch" and len(doc["rounds"]) == 2
    assert doc["rounds"][1]["time"] - doc["rounds"][0]["time"] >= 0.45
    assert [r["robots"][0]["data"]["verdict"] for r in doc["rounds"]] == [FIX, FIX]
    assert main(["-i", inv, "gps", "watch", "-r", "panther-02", "--json"]) == 2
    assert "--count" in capsys.readouterr().err


def test_doctor_gps_check_for_robots_with_gnss(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    demo = tmp_path / "demo"
    assert main(["demo", "init", "--dest", str(demo)]) == 0
    inv = demo / "inventory.yaml"
    text = inv.read_text()
    assert "  panther-01:\n" in text
    inv.write_text(text.replace("  panther-01:\n", "  panther-01:\n    desired:\n      gps: {enabled: true}\n", 1))
    capsys.readouterr()

    def gps_findings() -> dict[str, list[dict[str, object]]]:
        main(["-i", str(demo), "doctor", "--all", "--json"])
        doc = json.loads(capsys.readouterr().out)
        return {r["robot"]: [f for f in r["data"]["findings"] if f["check"] == "gps"] for r in doc["robots"]}

    found = gps_findings()
    assert found["panther-02"] == [] and found["panther-03"] == []  # no GNSS in their inventory
    (f,) = found["panther-01"]
    assert f["state"] == "warn" and str(f["detail"]).startswith("fix: ") and "no NMEA driver" in str(f["detail"])
    assert f["fix"] == "panther-ops gps enable -r panther-01"
    assert main(["-i", str(demo), "gps", "enable", "-r", "panther-01", "--yes"]) == 0
    capsys.readouterr()
    (f,) = gps_findings()["panther-01"]
    assert f["state"] == "ok" and f["fix"] is None
