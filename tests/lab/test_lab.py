"""Self-tests of the simulated robot lab: each simulated property checked for real.

Uses the session `lab` fixture (tests/conftest.py): r01 2.0.4 (jump host of r05),
r02 2.1.1, r03 2.2.2, r04 2.0.4, r05 2.1.1 behind r01. Tests that change a robot undo it.
"""

from __future__ import annotations

import os
import socket
import subprocess
import time
from pathlib import Path

import paramiko
import pytest
import yaml

from tests.lab import Lab
from tests.lab.files import stack
from tests.lab.state import LabState

pytestmark = pytest.mark.lab


def run_ssh(lab: Lab, name: str, command: str, **kw: object) -> str:
    client = lab.connect(name, **kw)  # type: ignore[arg-type]
    try:
        _, out, err = client.exec_command(command, timeout=10)
        status = out.channel.recv_exit_status()
        text = out.read().decode()
        assert status == 0, f"{name}: {command!r} exited {status}: {err.read().decode()}"
        return text
    finally:
        client.close()


def openssh_hostname(lab: Lab, name: str) -> str:
    """`hostname` on robot `name` with the OpenSSH client and the lab's ssh_config (batch mode)."""
    cp = subprocess.run(["ssh", "-F", str(lab.ssh_config_path), "-o", "BatchMode=yes", name, "hostname"],
                        capture_output=True, text=True, timeout=20, check=False)
    assert cp.returncode == 0, cp.stderr
    return cp.stdout.strip()


def host_ping(ip: str) -> int:
    return subprocess.run(["ping", "-c", "1", "-W", "1", ip], capture_output=True, check=False).returncode


def driver_command(lab: Lab, name: str) -> str:
    doc = yaml.safe_load(lab.read(name, "/home/husarion/compose.yaml"))
    cmd = doc["services"][lab.robot(name).driver_container]["command"]
    return cmd if isinstance(cmd, str) else " ".join(cmd)


def wait_until(pred, timeout: float, interval: float = 0.05) -> bool:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(interval)
    return bool(pred())


# -------------------------------------------------------------------------------------
# operator files and ssh
# -------------------------------------------------------------------------------------
def test_inventory_ssh_config_and_known_hosts(lab: Lab) -> None:
    inv = yaml.safe_load(lab.inventory_path.read_text())
    assert inv["version"] == 1
    assert inv["settings"] == {"ssh_config": "ssh_config", "known_hosts": "known_hosts"}
    assert inv["defaults"] == {"user": "husarion", "identity_file": "id_ed25519"}
    assert sorted(inv["robots"]) == ["r01", "r02", "r03", "r04", "r05"]
    assert inv["robots"]["r05"]["jump"] == "r01"
    assert inv["robots"]["r03"]["groups"] == ["lab", "stack-2.2.2"]
    assert "jump" not in inv["robots"]["r01"]
    known = lab.known_hosts_path.read_text().splitlines()
    for r in lab.robots:
        assert inv["robots"][r.name]["host"] == r.ip
        assert any(line.startswith(f"{r.ip} ssh-ed25519 AAAA") for line in known)
    assert openssh_hostname(lab, "r01") == "r01"


def test_hostname_over_paramiko_on_every_robot(lab: Lab) -> None:
    for r in lab.robots:
        before = lab.sshd_accepts(r.name)
        assert run_ssh(lab, r.name, "hostname").strip() == r.name
        assert lab.sshd_accepts(r.name) == before + 1


def test_robot_accounts_and_files(lab: Lab) -> None:
    out = lab.exec("r02", ["id"], user="husarion").stdout
    assert out.startswith("uid=1000(husarion) gid=1000(husarion)")
    assert "(docker)" in out
    assert "PANTHER_SERIAL_NO=1002" in lab.read("r02", "/run/husarion/panther_config.env")
    env = lab.read("r03", "/run/husarion/robot_config.env")
    assert "ROBOT_SERIAL_NO=1003" in env
    assert "SYSTEM_BUILD_VERSION=v2.2.0" in env
    assert "ROS_DOMAIN_ID=" in lab.read("r03", "/home/husarion/config/common/.env")
    login = run_ssh(lab, "r03", "bash -lc 'echo $ROBOT_MODEL_NAME $SYSTEM_BUILD_VERSION'")
    assert login.split() == ["panther", "v2.2.0"]
    # the host's accounts are untouched: husarion exists only inside the robots
    assert "husarion:" not in Path("/etc/passwd").read_text()
    lab.write("r02", "/home/husarion/lab-note.txt", "hello\n")
    assert run_ssh(lab, "r02", "cat ~/lab-note.txt; stat -c %U ~/lab-note.txt").split() == ["hello", "husarion"]
    lab.exec("r02", ["rm", "/home/husarion/lab-note.txt"], check=True)


# -------------------------------------------------------------------------------------
# docker stack
# -------------------------------------------------------------------------------------
def test_driver_container_runs_with_the_compose_command(lab: Lab) -> None:
    for r in lab.robots:
        ctr = r.driver_container
        state = lab.docker(r.name, "inspect", "-f", "{{.State.Status}} {{.Config.Image}}", ctr)
        assert state.returncode == 0, state.stderr
        status, image = state.stdout.split()
        assert status == "running"
        assert image in stack(r.stack.key).images()
        cmd = " ".join(driver_command(lab, r.name).split())
        assert f"[ros2-standin] {cmd}" in lab.docker(r.name, "logs", ctr).stdout
        # the release in /version.txt, as the real images have it (the ros2 stand-in answers its interfaces)
        assert lab.docker(r.name, "exec", ctr, "cat", "/version.txt").stdout == f"{r.stack.key}\n"


def test_compose_force_recreate_applies_new_command_fast(lab: Lab) -> None:
    name = "r02"
    original = lab.read(name, "/home/husarion/compose.yaml")
    old_id = lab.docker(name, "inspect", "-f", "{{.Id}}", "panther_ros").stdout.strip()
    marker = f"lab_marker:=t{int(time.time())}"
    edited = original.replace(
        "command: ros2 launch panther_bringup bringup.launch.py",
        f"command: ros2 launch panther_bringup bringup.launch.py {marker}",
    )
    assert edited != original
    try:
        lab.write(name, "/home/husarion/compose.yaml", edited)
        t0 = time.monotonic()
        cp = lab.compose(name, "up", "-d", "--force-recreate")
        elapsed = time.monotonic() - t0
        assert cp.returncode == 0, cp.stderr
        assert elapsed < 3.0, f"recreate took {elapsed:.1f} s"
        new_id = lab.docker(name, "inspect", "-f", "{{.Id}}", "panther_ros").stdout.strip()
        assert new_id != old_id
        assert wait_until(lambda: marker in lab.docker(name, "logs", "panther_ros").stdout, 3)
    finally:
        lab.write(name, "/home/husarion/compose.yaml", original)
        lab.compose(name, "up", "-d")


def test_standin_fails_on_missing_config_file(lab: Lab) -> None:
    name = "r04"
    image = "husarion/panther:humble-2.0.4-20240628"
    launch = ["ros2", "launch", "panther_bringup", "bringup.launch.py"]
    # a missing absolute path: error and exit 1, as the real launch does
    bad = lab.docker(name, "run", "--rm", image, *launch, "controller_config_path:=/nonexistent.yaml")
    assert bad.returncode == 1
    assert "file not found: '/nonexistent.yaml'" in bad.stdout  # the launch logs on stdout
    # $(find ...) values, empty values and existing paths are accepted: it keeps running
    ok = lab.docker(
        name,
        "run",
        "-d",
        "--name",
        "lab_accepts",
        image,
        *launch,
        "wheel_config_path:=$(find panther_description)/config/WH01.yaml",
        "battery_config_path:=",
        "common_dir_path:=/tmp",
    )
    assert ok.returncode == 0, ok.stderr
    try:
        time.sleep(0.3)
        st = lab.docker(name, "inspect", "-f", "{{.State.Status}}", "lab_accepts").stdout
        assert st.strip() == "running"
    finally:
        lab.docker(name, "rm", "-f", "lab_accepts")
    # through the robot's compose file, as panther-ops would change it
    original = lab.read(name, "/home/husarion/compose.yaml")
    edited = original.replace(
        "bringup.launch.py namespace:=panther",
        "bringup.launch.py namespace:=panther controller_config_path:=/nonexistent.yaml",
    )
    assert edited != original
    try:
        lab.write(name, "/home/husarion/compose.yaml", edited)
        assert lab.compose(name, "up", "-d").returncode == 0

        def failed() -> bool:
            out = lab.docker(
                name, "inspect", "-f", "{{.State.ExitCode}} {{.RestartCount}}", "panther_ros"
            ).stdout.split()
            return bool(out) and (out[0] != "0" or int(out[1]) > 0)

        assert wait_until(failed, 5)
        logs = lab.docker(name, "logs", "panther_ros")
        assert "file not found: '/nonexistent.yaml'" in logs.stdout
    finally:
        lab.write(name, "/home/husarion/compose.yaml", original)
        lab.compose(name, "up", "-d")


# -------------------------------------------------------------------------------------
# network edge cases
# -------------------------------------------------------------------------------------
def test_jump_robot_only_reachable_through_its_jump_host(lab: Lab) -> None:
    hidden = lab.robot("r05")
    assert hidden.jump == "r01"
    assert host_ping(hidden.ip) != 0
    assert host_ping(lab.robot("r01").ip) == 0
    with pytest.raises(OSError), socket.create_connection((hidden.ip, 22), timeout=2):
        pass
    assert openssh_hostname(lab, "r05") == "r05"
    assert run_ssh(lab, "r05", "hostname").strip() == "r05"  # paramiko over direct-tcpip


def test_link_down_makes_ssh_time_out(lab: Lab) -> None:
    lab.link_down("r04")
    try:
        t0 = time.monotonic()
        with pytest.raises((socket.timeout, TimeoutError, OSError, paramiko.SSHException)):
            lab.connect("r04", timeout=1.0)
        assert time.monotonic() - t0 < 5
        assert host_ping(lab.robot("r04").ip) != 0
    finally:
        lab.link_up("r04")
    assert run_ssh(lab, "r04", "hostname").strip() == "r04"


def test_rotate_host_key_is_rejected(lab: Lab) -> None:
    known_before = lab.known_hosts_path.read_text()
    old = lab.host_fingerprint("r04")
    lab.rotate_host_key("r04")
    try:
        assert lab.host_fingerprint("r04") != old
        assert lab.known_hosts_path.read_text() == known_before
        with pytest.raises(paramiko.BadHostKeyException):
            lab.connect("r04")
    finally:
        lab.restore_host_key("r04")
    assert lab.host_fingerprint("r04") == old
    assert run_ssh(lab, "r04", "hostname").strip() == "r04"
    # the other way back: accept the new key into known_hosts
    lab.rotate_host_key("r04")
    lab.accept_host_key("r04")
    assert lab.known_hosts_path.read_text() != known_before
    assert run_ssh(lab, "r04", "hostname").strip() == "r04"


def test_kill_and_start_sshd(lab: Lab) -> None:
    lab.kill_sshd("r04")
    try:
        with pytest.raises((paramiko.ssh_exception.NoValidConnectionsError, OSError)):
            lab.connect("r04", timeout=2)
    finally:
        lab.start_sshd("r04")
    assert run_ssh(lab, "r04", "hostname").strip() == "r04"


def test_clock_offset_shows_in_date_over_ssh(lab: Lab) -> None:
    lab.clock_offset("r02", 86400)
    try:
        remote = int(run_ssh(lab, "r02", "date +%s"))
        assert abs(remote - (time.time() + 86400)) < 10
    finally:
        lab.clock_offset("r02", 0)
    assert abs(int(run_ssh(lab, "r02", "date +%s")) - time.time()) < 10


def test_password_login(lab: Lab) -> None:
    with pytest.raises(paramiko.SSHException):
        lab.connect("r03", password="husarion")
    lab.password_login("r03")
    try:
        assert run_ssh(lab, "r03", "id -un", password="husarion").strip() == "husarion"
        with pytest.raises(paramiko.AuthenticationException):
            lab.connect("r03", password="not-the-password")
    finally:
        lab.password_login("r03", None)


# -------------------------------------------------------------------------------------
# power-off stand-in
# -------------------------------------------------------------------------------------
def test_poweroff_standin_takes_robot_offline_never_the_host(lab: Lab) -> None:
    name = "r04"
    r = lab.robot(name)
    standins = lab.standins(name)
    assert {"/sbin/shutdown", "/sbin/poweroff", "/sbin/reboot"} <= set(standins)
    # inside the robot /sbin/poweroff is the stand-in script; on the host it is untouched
    head = lab.exec(name, ["head", "-c", "200", "/sbin/poweroff"], check=True).stdout
    assert "Power-off stand-in of the panther-ops test lab" in head
    with open(os.path.realpath("/sbin/poweroff"), "rb") as f:
        assert f.read(4) == b"\x7fELF"
    # the robot's PID 1 is its own init, not the host's
    init = lab.exec(name, ["cat", "/proc/1/cmdline"], check=True).stdout
    assert "robot-init.sh" in init
    boot_id = Path("/proc/sys/kernel/random/boot_id").read_text()
    try:
        out = run_ssh(lab, name, "sudo -n /sbin/poweroff; echo rc=$?")
        assert out.strip() == "rc=0"
        assert wait_until(lambda: host_ping(r.ip) != 0, 5)
        calls = lab.power_calls(name)
        assert calls[-1]["action"] == "poweroff"
        assert calls[-1]["sudo_user"] == "husarion"
        assert calls[-1]["uid"] == 0
        with pytest.raises((socket.timeout, TimeoutError, OSError, paramiko.SSHException)):
            lab.connect(name, timeout=1.0)
    finally:
        lab.power_on(name)
    assert Path("/proc/sys/kernel/random/boot_id").read_text() == boot_id
    assert run_ssh(lab, name, "hostname").strip() == name


# -------------------------------------------------------------------------------------
# lifecycle: state file, crash recovery, teardown
# -------------------------------------------------------------------------------------
@pytest.mark.usefixtures("lab_ready")
def test_state_file_crash_recovery_and_teardown() -> None:
    prefix = f"lt{os.getpid() % 100000}"
    first = Lab(2, prefix=prefix, ephemeral=True).up()
    st = LabState.load(first.dir / "state.json")
    assert {r.ns for r in st.robots.values()} == {f"{prefix}-r01", f"{prefix}-r02"}
    assert all(r.proc("init") and r.proc("sshd") for r in st.robots.values())
    pids = [p.pid for r in st.robots.values() for p in r.procs]
    # "crash": never call down(); a new lab of the same prefix tears the leftovers down
    second = Lab(1, prefix=prefix, ephemeral=True)
    try:
        second.up()
        assert not any(Path(f"/proc/{p}").exists() and _not_zombie(p) for p in pids)
        assert run_ssh(second, "r01", "hostname").strip() == "r01"
    finally:
        second.down()
    netns = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True, check=False).stdout
    assert prefix not in netns
    links = subprocess.run(["ip", "-o", "link"], capture_output=True, text=True, check=False).stdout
    assert f"{prefix}-" not in links
    assert not (second.base / prefix).exists()


def _not_zombie(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rfind(")") + 2] not in "ZX"
