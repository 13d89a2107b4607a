"""Issue-13 acceptance on the lab: `gps enable|disable` on 2.0.4, 2.1.1 and 2.2.2 robots with
real sshd + dockerd + compose v2. The driver is the lab's ros2 stand-in; the nmea-gps service
runs the lab's stand-in of husarion/nmea-gps (tests/lab/nmea_image.py), which listens on the
configured UDP port: a datagram sent to the robot shows up in its log."""

from __future__ import annotations

import socket
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from tests.clirun import run_cli
from tests.lab.nmea import burst
from tests.lab.nmea_image import use_nmea_image
from tests.labtools import COMPOSE, containers, robot_of, robots_put_back

pytestmark = pytest.mark.lab

PARAMS = "/home/husarion/config/husarion_ugv_localization/config/nmea_navsat.yaml"


@pytest.fixture
def restored(lab: Any) -> Iterator[None]:
    """compose.yaml, ~/config, backups and the running stack of every robot put back."""
    with robots_put_back(lab, lambda name, changed: changed or "nmea-gps" in " ".join(containers(lab, name))):
        yield


def udp_ports(lab: Any, name: str) -> set[int]:
    """UDP ports bound in the robot's network namespace (/proc/net/udp)."""
    rows = lab.sh(name, "cat /proc/net/udp").stdout.splitlines()[1:]
    return {int(row.split()[1].rsplit(":", 1)[1], 16) for row in rows if row.strip()}


def test_enable_twice_disable_on_three_stacks(lab: Any, restored: None, capsys: pytest.CaptureFixture[str]) -> None:
    inv = str(lab.inventory_path)
    names = {v: robot_of(lab, v) for v in ("2.0.4", "2.1.1", "2.2.2")}
    use_nmea_image(lab, names["2.0.4"])
    before = {n: lab.read(n, COMPOSE) for n in names.values()}
    running = {n: containers(lab, n) for n in names.values()}
    target = [a for n in names.values() for a in ("-r", n)]

    code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "enable", *target, "--yes", "--settle", "1", "--json")
    assert code == 0, (doc, err)
    by = {r["robot"]: r for r in doc["robots"]}
    assert {r["outcome"] for r in by.values()} == {"changed"}, by

    # 2.0.4: the nmea-gps service runs, only it was created; the driver was not recreated
    old = names["2.0.4"]
    after = containers(lab, old)
    gps = [c for k, c in after.items() if "nmea-gps" in k]
    assert len(gps) == 1 and gps[0]["state"] == "running" and gps[0]["image"] == "husarion/nmea-gps:humble-2.0.1-20240617"
    assert gps[0]["cmd"] == ["ros2", "launch", "/husarion_utils/nmea_navsat.launch.py", "robot_namespace:=panther"]
    assert {k: v["id"] for k, v in after.items() if "nmea-gps" not in k} == {k: v["id"] for k, v in running[old].items()}
    assert "\n  nmea-gps:\n    image: husarion/nmea-gps:humble-2.0.1-20240617\n" in lab.read(old, COMPOSE)
    assert 5000 in udp_ports(lab, old)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.sendto(burst(53.1978, 18.3732), (lab.robot(old).ip, 5000))
    deadline = time.monotonic() + 10
    while "1 datagrams" not in lab.docker(old, "logs", next(k for k in after if "nmea-gps" in k)).stdout:
        assert time.monotonic() < deadline, "the nmea-gps stand-in did not receive the datagram"
        time.sleep(0.2)

    # 2.1.1 and 2.2.2: the argument on the driver, which was recreated with it
    for version, word in (("2.1.1", "launch_nmea_gps:=True"), ("2.2.2", "launch_nmea_gps:=true")):
        n = names[version]
        driver = lab.robot(n).driver_container
        ctr = containers(lab, n)[driver]
        assert word in ctr["cmd"] and ctr["state"] == "running" and ctr["id"] != running[n][driver]["id"]
        assert word in lab.read(n, COMPOSE)

    code, doc, _, _ = run_cli(capsys, "-i", inv, "gps", "enable", *target, "--yes", "--settle", "1", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["ok"] * 3, doc

    code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "disable", *target, "--yes", "--settle", "1", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["changed"] * 3, (doc, err)
    for n in names.values():
        assert lab.read(n, COMPOSE) == before[n]
        now = containers(lab, n)
        assert set(now) == set(running[n])
        assert all(now[k]["cmd"] == running[n][k]["cmd"] and now[k]["state"] == "running" for k in now)
    assert 5000 not in udp_ports(lab, old)


def test_other_port_on_22_and_204(lab: Any, restored: None, capsys: pytest.CaptureFixture[str]) -> None:
    inv = str(lab.inventory_path)
    ugv, old = robot_of(lab, "2.2.2"), robot_of(lab, "2.0.4")
    use_nmea_image(lab, old)
    before = {n: lab.read(n, COMPOSE) for n in (ugv, old)}
    code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "enable", "-r", ugv, "-r", old, "--port", "5003",
                             "--namespace", "rover", "--yes", "--settle", "1", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["changed"] * 2, (doc, err)
    assert "    port: 5003\n" in lab.read(ugv, PARAMS)
    driver = containers(lab, ugv)[lab.robot(ugv).driver_container]
    assert "nmea_params_path:=/config/husarion_ugv_localization/config/nmea_navsat.yaml" in driver["cmd"]
    assert driver["state"] == "running"  # the stand-in driver fails on a missing *_path file: it is there
    gps = next(c for k, c in containers(lab, old).items() if "nmea-gps" in k)
    assert gps["state"] == "running" and "port:=5003" in gps["cmd"] and "__ns:=/rover" in gps["cmd"]
    assert 5003 in udp_ports(lab, old)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "gps", "disable", "-r", ugv, "-r", old, "--yes", "--settle", "1",
                           "--json")
    assert code == 0 and {n: lab.read(n, COMPOSE) for n in (ugv, old)} == before
    assert lab.sh(ugv, f"test -e {PARAMS}").returncode == 1


def test_bad_input_changes_nothing(lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    inv = str(lab.inventory_path)
    n = robot_of(lab, "2.1.1")
    before = lab.read(n, COMPOSE)
    # (--port 5001 on 2.1.1 is no bad input since issue 24 finding 4: its NMEA launch file takes params_file)
    for argv in (["--port", "70000"], ["--namespace", "a b"], ["--port", "５００１"], ["--ip", "10.15.20.256"]):
        code, _doc, _, err = run_cli(capsys, "-i", inv, "gps", "enable", "-r", n, "--yes", *argv)
        assert code == 2 and err, argv
    assert lab.read(n, COMPOSE) == before


def test_apply_desired_gps_recreates_only_the_service(lab: Any, restored: None,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    """`apply` with desired.gps on a 2.0.4 robot adds and starts nmea-gps; the driver is untouched."""
    name = robot_of(lab, "2.0.4")
    use_nmea_image(lab, name)
    text = lab.inventory_path.read_text()
    assert f"  {name}:\n" in text
    inv = lab.inventory_path.parent / "inventory-gps-desired.yaml"
    inv.write_text(text.replace(f"  {name}:\n", f"  {name}:\n    desired:\n      gps: {{enabled: true}}\n", 1))
    before = lab.read(name, COMPOSE)
    running = containers(lab, name)
    try:
        code, doc, _, err = run_cli(capsys, "-i", str(inv), "config", "diff", "-r", name, "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed" and lab.read(name, COMPOSE) == before
        code, doc, _, err = run_cli(capsys, "-i", str(inv), "apply", "-r", name, "--yes", "--settle", "1", "--json")
        assert code == 0 and doc["robots"][0]["outcome"] == "changed", (doc, err)
        after = containers(lab, name)
        gps = [c for k, c in after.items() if "nmea-gps" in k]
        assert len(gps) == 1 and gps[0]["state"] == "running"
        assert {k: v["id"] for k, v in after.items() if "nmea-gps" not in k} == {k: v["id"] for k, v in running.items()}
        code, doc, _, _ = run_cli(capsys, "-i", str(inv), "config", "diff", "-r", name, "--json")
        assert doc["robots"][0]["outcome"] == "ok"
        assert run_cli(capsys, "-i", str(inv), "gps", "disable", "-r", name, "--yes", "--settle", "1")[0] == 0
        assert lab.read(name, COMPOSE) == before
    finally:
        inv.unlink()


def test_a_failed_enable_rolls_back_without_a_trace_of_the_new_service(
        lab: Any, restored: None, capsys: pytest.CaptureFixture[str]) -> None:
    """2.0.4: the nmea-gps container crash-loops (its UDP port is held by another process in the
    robot's network namespace): compose.yaml comes back, the new service's container is removed
    (not left restarting as an orphan), and the rollback does not try to start a service the
    restored file no longer has."""
    import subprocess
    import sys

    inv = str(lab.inventory_path)
    old = robot_of(lab, "2.0.4")
    use_nmea_image(lab, old)
    before = lab.read(old, COMPOSE)
    running = containers(lab, old)
    holder = subprocess.Popen(
        ["ip", "netns", "exec", lab.robot(old).ns, sys.executable, "-c",
         "import socket, sys, time\ns = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)\n"
         "s.bind(('0.0.0.0', 5000))\nprint('bound', flush=True)\ntime.sleep(120)\n"],
        stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "bound"
        code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "enable", "-r", old, "--yes", "--settle", "2", "--json")
    finally:
        holder.kill()
        holder.wait()
    assert code == 3, (doc, err)
    result = doc["robots"][0]
    assert result["outcome"] == "rolled-back", result
    assert "after restore" not in result["message"], result
    assert "nmea-gps log: " in result["message"] and "bind: Address already in use" in result["message"], result
    assert lab.read(old, COMPOSE) == before
    now = containers(lab, old)
    assert not [k for k in now if "nmea-gps" in k], now
    assert {k: v["id"] for k, v in now.items()} == {k: v["id"] for k, v in running.items()}


def test_a_failed_enable_leaves_the_operators_own_nmea_gps_project_alone(
        lab: Any, restored: None, capsys: pytest.CaptureFixture[str]) -> None:
    """An operator who added the GPS by hand in a compose project of their own (~/handmade,
    service nmea-gps, holding UDP 5000): `gps enable`'s new container cannot bind the port, the
    change rolls back, and only the new container is removed; the operator's, a container of
    the same service name in another project, keeps running untouched."""
    from tests.lab.files import USER
    from tests.lab.nmea_image import NMEA_IMAGE

    inv = str(lab.inventory_path)
    old = robot_of(lab, "2.0.4")
    use_nmea_image(lab, old)
    lab.write(old, "/home/husarion/handmade/compose.yaml",
              f"services:\n  nmea-gps:\n    image: {NMEA_IMAGE}\n    network_mode: host\n    restart: always\n"
              "    command: ros2 run nmea_navsat_driver nmea_socket_driver --ros-args -p port:=5000\n")
    up = lab.exec(old, ["bash", "-lc", "cd ~/handmade && docker compose up -d"], user=USER, timeout=120)
    assert up.returncode == 0, up.stderr
    try:
        handmade = {k: v for k, v in containers(lab, old).items() if k.startswith("handmade-nmea-gps")}
        assert [v["state"] for v in handmade.values()] == ["running"], handmade
        deadline = time.monotonic() + 10
        while 5000 not in udp_ports(lab, old) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert 5000 in udp_ports(lab, old)
        before = lab.read(old, COMPOSE)
        code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "enable", "-r", old, "--yes", "--settle", "2", "--json")
        assert code == 3, (doc, err)
        result = doc["robots"][0]
        assert result["outcome"] == "rolled-back", result
        assert "bind: Address already in use" in result["message"], result
        assert lab.read(old, COMPOSE) == before
        now = containers(lab, old)
        assert [k for k in now if "nmea-gps" in k] == list(handmade), now
        (name, was), = handmade.items()
        assert (now[name]["id"], now[name]["state"]) == (was["id"], "running")
    finally:
        lab.exec(old, ["bash", "-lc", "cd ~/handmade && docker compose down; cd && rm -rf ~/handmade"], user=USER,
                 timeout=120)


def test_status_confirms_the_fix_from_the_robots_fix_topic(lab: Any, restored: None,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    """After `gps enable` the NMEA driver holds the port (2.0.4: the nmea-gps service; 2.2.2:
    launch_nmea_gps on the driver): `gps status` asks the robot's own /panther/gps/fix in the
    driver container. Without NMEA: a failed verdict naming the topic and the container; with
    GGA sentences arriving: the fix they carry (issue 24, finding 9)."""
    from tests.lab.nmea import Sender, sentences

    inv = str(lab.inventory_path)
    names = [robot_of(lab, "2.0.4"), robot_of(lab, "2.2.2")]
    use_nmea_image(lab, names[0])
    target = [a for n in names for a in ("-r", n)]
    code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "enable", *target, "--yes", "--settle", "1", "--json")
    assert code == 0 and [r["outcome"] for r in doc["robots"]] == ["changed"] * 2, (doc, err)
    deadline = time.monotonic() + 10
    while not all(5000 in udp_ports(lab, n) for n in names):  # each NMEA driver holds its port
        assert time.monotonic() < deadline, {n: udp_ports(lab, n) for n in names}
        time.sleep(0.2)

    code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "status", *target, "--window", "1", "--json")
    assert code == 3, (doc, err)
    for r in doc["robots"]:
        d = r["data"]
        assert (r["outcome"], d["verdict"]) == ("failed", "no fix message"), r
        driver = lab.robot(r["robot"]).driver_container
        assert f"nothing published on /panther/gps/fix within 6 s (asked in container {driver})" in r["message"], r
        assert d["source"] == "ros topic /panther/gps/fix" and d["container"] == driver

    lat, lon = 52.2296756, 21.0122287
    # a GGA sentence per datagram: the driver reads a datagram's lines split at "\n" and drops
    # one still ending in "\r", so of a CRLF burst only its last sentence (data/nmea-listen.c)
    gga = (sentences(lat, lon)[0] + "\r\n").encode()

    def to(ip: str) -> Callable[[], tuple[str, int]]:
        return lambda: (ip, 5000)

    senders = [Sender(to(lab.robot(n).ip), lat, lon, period=0.5, payload=lambda: gga).start() for n in names]
    try:
        code, doc, _, err = run_cli(capsys, "-i", inv, "gps", "status", *target, "--window", "1", "--json")
    finally:
        for s in senders:
            s.stop()
    assert code == 0, (doc, err)
    for r in doc["robots"]:
        d = r["data"]
        assert (r["outcome"], d["verdict"], d["source"]) == ("ok", "fix", "ros topic /panther/gps/fix"), r
        assert abs(d["fix"]["lat"] - lat) < 1e-7 and abs(d["fix"]["lon"] - lon) < 1e-7, d["fix"]
        assert d["fix"]["status"] == 0 and d["fix"]["altitude_m"] == pytest.approx(154.9), d["fix"]
        assert f"{lat:.7f} {lon:.7f}, alt 154.9 m, status 0 (fix) on /panther/gps/fix" in r["message"]
    assert {r["data"]["driver"]["mode"] for r in doc["robots"]} == {"service", "argument"}
