"""`gps listen` and the NMEA decoder: a real UDP sender on 127.0.0.1, sentences made with
pynmea2, coordinates exact to 1e-6 degree, garbage counted and never raised."""

from __future__ import annotations

import datetime as dt
import json
import socket

import pytest

from panther_ops.cli.app import main
from panther_ops.core.gps.nmea import NmeaDecoder
from tests.lab import nmea
from tests.ports import free_port

LAT, LON = 53.1978123, -18.3732456
WHEN = dt.datetime(2026, 11, 24, 3, 4, 5, tzinfo=dt.timezone.utc)


def test_decoder_gga_rmc_exact() -> None:
    dec = NmeaDecoder()
    fixes = dec.feed(nmea.burst(LAT, LON, when=WHEN))
    assert len(fixes) == 1
    f = fixes[0]
    assert abs(f.lat - LAT) < 1e-6 and abs(f.lon - LON) < 1e-6  # type: ignore[operator]
    assert (f.fix_quality, f.satellites, f.hdop, f.altitude_m, f.talker) == (1, 9, 0.8, 120.4, "GP")
    assert f.time == "03:04:05" and f.date == "2026-11-24"  # the RMC after the GGA, same datagram
    assert (f.valid, f.speed_knots, f.course_deg) == (True, 0.02, 84.4)
    # a GGA alone finds the RMC seen before only when the time matches
    other = dec.feed(nmea.burst(LAT, LON, when=WHEN.replace(second=6)).split(b"\r\n")[0] + b"\r\n")
    assert other[0].time == "03:04:06" and other[0].date is None
    rmc_first = [s for s in nmea.sentences(LAT, LON, when=WHEN) if "RMC" in s]
    gga = [s for s in nmea.sentences(LAT, LON, when=WHEN) if "GGA" in s]
    fixes = dec.feed(("\r\n".join(rmc_first + gga) + "\r\n").encode())
    assert fixes[0].date == "2026-11-24" and fixes[0].valid is True and fixes[0].speed_knots == 0.02
    assert dict(dec.stats.by_type) == {"GGA": 3, "GSA": 1, "RMC": 2, "GSV": 1}
    assert (dec.stats.malformed, dec.stats.bad_checksum, dec.stats.unknown_type) == (0, 0, 0)


def test_decoder_counts_garbage_without_raising() -> None:
    good = nmea.sentences(LAT, LON, when=WHEN)
    gga = good[0]
    bad_sum = gga[:-2] + ("00" if gga[-2:] != "00" else "11")
    no_sum = gga.split("*")[0]
    garbage = [
        bad_sum, no_sum, "hello world", "$GPGGA,,,,*", "\x00\xff\x10", "$GPXYZ,1,2,3*" + "00",
        "$GPGGA,030405.00,53AB.000,N,01822.39,E,1,09,0.8,1.0,M,0,M,,",
    ]
    dec = NmeaDecoder()
    fixes = dec.feed(("\r\n".join(garbage + good) + "\r\n").encode("latin-1"))
    assert len(fixes) == 1 and abs(fixes[0].lat - LAT) < 1e-6  # type: ignore[operator]
    s = dec.stats
    assert s.sentences == len(garbage) + len(good)
    assert s.bad_checksum >= 2 and s.malformed + s.bad_checksum + s.unknown_type == len(garbage)
    assert dict(s.by_type) == {"GGA": 1, "GSA": 1, "RMC": 1, "GSV": 1}


def test_no_fix_epoch_has_no_position() -> None:
    dec = NmeaDecoder()
    (f,) = dec.feed(nmea.burst(LAT, LON, when=WHEN, quality=0))
    assert (f.lat, f.lon, f.fix_quality, f.has_fix) == (None, None, 0, False)


def test_listen_json_from_a_real_udp_sender(capsys: pytest.CaptureFixture[str]) -> None:
    port = free_port(socket.SOCK_DGRAM)
    junk = b"$GPGGA,garbage*00\r\nnot nmea at all\r\n"
    sender = nmea.Sender(lambda: ("127.0.0.1", port), LAT, LON, period=0.05,
                         payload=lambda: junk + nmea.burst(LAT, LON)).start()
    try:
        code = main(["gps", "listen", "--udp", f"127.0.0.1:{port}", "--count", "3", "--timeout", "20", "--json"])
    finally:
        sender.stop()
    out = capsys.readouterr().out
    doc = json.loads(out)
    assert code == 0 and doc["exit_code"] == 0 and doc["command"] == "gps listen"
    assert len(doc["fixes"]) == 3
    for fix in doc["fixes"]:
        assert abs(fix["lat"] - LAT) < 1e-6 and abs(fix["lon"] - LON) < 1e-6
        assert (fix["fix_quality"], fix["satellites"], fix["hdop"]) == (1, 9, 0.8)
    counts = doc["counts"]
    assert counts["by_type"]["GGA"] == 3 and counts["by_type"]["RMC"] >= 2
    assert counts["bad_checksum"] + counts["malformed"] >= 6  # two junk lines per datagram, three or more datagrams


def test_listen_human_lines(capsys: pytest.CaptureFixture[str]) -> None:
    port = free_port(socket.SOCK_DGRAM)
    sender = nmea.Sender(lambda: ("127.0.0.1", port), LAT, LON, period=0.05).start()
    try:
        code = main(["gps", "listen", "--udp", f"127.0.0.1:{port}", "-n", "2", "--timeout", "20"])
    finally:
        sender.stop()
    cap = capsys.readouterr()
    lines = cap.out.splitlines()
    assert code == 0 and len(lines) == 2 and f"{LAT:.7f}"[:9] in lines[0] and "quality 1" in lines[0]
    assert "2 fixes" in cap.err


def test_listen_timeout_without_data_is_exit_3(capsys: pytest.CaptureFixture[str]) -> None:
    port = free_port(socket.SOCK_DGRAM)
    code = main(["gps", "listen", "--udp", f"127.0.0.1:{port}", "--count", "1", "--timeout", "0.3", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 3 and doc["fixes"] == [] and doc["counts"]["datagrams"] == 0


@pytest.mark.parametrize("addr", ["127.0.0.1:70000", "127.0.0.1", "bad host:5000", ":5000", "127.0.0.1:x"])
def test_listen_bad_address_exit_2(addr: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["gps", "listen", "--udp", addr, "--timeout", "0.2"]) == 2
    assert "--udp" in capsys.readouterr().err
