"""The lab a page's ```console lab samples run on (tests/ux/docsamples.py, lab mode): the shape
the docs' samples name (docs/lab.md, "From pytest": 5 robots r01..r05, docker on, stacks
2.0.4 / 2.1.1 / 2.2.2 / 2.0.4 / 2.1.1, r05 reachable only through r01), or the page's own
(SHAPES), one fresh lab per page (a page's samples change its robots in the page's order), torn
down after the page.

The docs' lab takes its subnets from 10.200.100.0 up (FIRST_SUBNET: three digits, so that an
address is as wide, and a table wraps the same, whatever other labs are up), and the docs show
them as the lab on an idle machine has them: its LAN 10.200.100.x, then the robots' own LANs
10.200.101.x, 10.200.102.x ... in the order the lab made them (:func:`shown_subnets`); a command
naming one runs on the lab actually up."""

from __future__ import annotations

import re
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from tests.lab import Lab, missing_requirements
from tests.lab.computers import ComputerSpec, HttpService, trust_on_robot
from tests.lab.nmea import Sender

from .docsamples import Outcome, follow

IMAGES = ("2.0", "2.1.1", "2.2")
JUMPS = {"r05": "r01"}


def lab_unavailable() -> str | None:
    """Why the docs' lab cannot run on this machine (not root, a binary missing), or None."""
    why = missing_requirements(docker=True)
    return "; ".join(why) if why else None


@dataclass(frozen=True)
class Shape:
    """A page's lab: robots (stacks cycled), jumps, User Computers (tests/lab/computers.py) and
    the password typed at a password prompt (``--ask-password``)."""

    robots: int = 5
    images: tuple[str, ...] = IMAGES
    jumps: dict[str, str] = field(default_factory=lambda: dict(JUMPS))
    computers: tuple[ComputerSpec, ...] = ()
    password: str = ""
    prepare: Callable[[Lab], None] | None = None
    """What else the page's lab holds, made once it is up (images, stand-ins of the robots' LAN)."""


NUC_PASSWORD = "husarion"
NUC2_SECRET = "lab-nuc2-secret"

SHUTDOWN = Shape(2, ("2.1.1", "2.2"), {}, (
    # r01's LAN (2.1.1, SSH era): 10.200.101.101 ..103
    ComputerSpec("nuc", behind="r01", password=NUC_PASSWORD, admin="group", operator_key=False),  # Ubuntu-like
    ComputerSpec("pi", behind="r01", robot_key=True),  # the robot's key, no sudo rule
    ComputerSpec("arm", behind="r01", sudo_rule=True),  # the sudo rule, not the robot's key
    # r02's LAN (2.2.2, HTTP era): 10.200.102.101, .102
    ComputerSpec("bare", behind="r02"),  # no husarion-shutdown
    ComputerSpec("nuc2", behind="r02", http=HttpService(3003, NUC2_SECRET), poweroff_delay=0.5),
), NUC_PASSWORD)
"""docs/shutdown.md: r01 on 2.1.1 and r02 on 2.2.2 with computers on their LANs, built as
tests/shutdown/test_shutdown_lab.py builds its own (no power-off for real: the stand-ins)."""

WEBUI_SUDO_PASSWORD = "lab-w1-password"

REMOTE = Shape(3, jumps={}, computers=(
    ComputerSpec("w1", behind="r01", password=WEBUI_SUDO_PASSWORD, admin="group", webui=True),  # sudo asks
    ComputerSpec("w2", behind="r02", admin="nopasswd", webui=True),
))
"""docs/remote.md: r01..r03 on 2.0.4, 2.1.1 and 2.2.2; User Computers with the snap stand-in behind
r01 and r02, as tests/remote/webui/test_webui_lab.py builds them (no snapd: the stand-in)."""

ROUTER_PASSWORD = "lab-rutx11-pass"


def _gps_lab(lab: Lab) -> None:
    """docs/gps.md: the nmea-gps stand-in image on the 2.0.4 robots (as tests/gps/test_gps_lab.py
    imports it) and the RUTX11 stand-in on r01's LAN (tests/lab/router.py, as
    tests/gps/test_gps_router_lab.py adds it: GNSS on, forwarding off, as delivered)."""
    from tests.lab.nmea_image import use_nmea_image
    from tests.lab.router import add_router

    for robot in lab.robots:
        if robot.stack.key == "2.0.4":
            use_nmea_image(lab, robot.name)
    add_router(lab, "r01", password=ROUTER_PASSWORD)


GPS = Shape(password=ROUTER_PASSWORD, prepare=_gps_lab)
"""docs/gps.md: the docs' lab with the nmea-gps image and r01's RUTX11 (the password typed at ``read -s``)."""

SHAPES: dict[str, Shape] = {
    "gps.md": GPS,
    "remote.md": REMOTE,
    "shutdown.md": SHUTDOWN,
}
"""Pages whose samples name another lab than the docs' one."""

POWER_OFF = {"/sbin/shutdown", "/sbin/poweroff", "/sbin/reboot"}
FIRST_SUBNET = 100


@contextmanager
def page_lab(prefix: str | None = None, page: str = "") -> Iterator[Lab]:
    """A lab of the page's shape (the docs' one unless SHAPES says), up for one page, torn down after it."""
    shape = SHAPES.get(page, Shape())
    lab = Lab(shape.robots, docker=True, images=shape.images, jumps=shape.jumps, prefix=prefix, ephemeral=True,
              first_subnet=FIRST_SUBNET)
    lab.up()
    try:
        if shape.computers:
            lab.add_computers(list(shape.computers))
            for name in (*lab.names, *lab.computer_names):  # rule 2: a power-off is the lab's stand-in
                missing = POWER_OFF - set(lab.standins(name))
                assert not missing, f"{name}: no power-off stand-in over {sorted(missing)}"
        if shape.prepare is not None:
            shape.prepare(lab)
        yield lab
    finally:
        lab.down()


def shown_subnets(lab: Lab) -> dict[int, int]:
    """The lab's subnets (third bytes) as the docs show them: its LAN 100, the robots' own LANs 101,
    102 ... in the order the lab made them (as on an idle machine, where they are the first free ones)."""
    st = lab.st
    return {st.subnet: FIRST_SUBNET,
            **{w: n for n, w in enumerate(st.jump_subnets.values(), start=FIRST_SUBNET + 1)}}


def _panther_ops(lab: Lab, *args: str) -> None:
    """panther-ops run on the lab (a scene's step, not shown)."""
    subprocess.run([sys.executable, "-c", "from panther_ops.cli.app import run; run()", "-i",
                    str(lab.inventory_path), "-q", *args], check=True, capture_output=True, timeout=120)


def _drift(lab: Lab) -> None:
    """docs/driver.md: r02's compose.yaml edited, its container not recreated."""
    _panther_ops(lab, "config", "set", "wheel_type", "WH02", "-r", "r02", "--yes", "--no-restart")


def _crash_loop(lab: Lab) -> None:
    """docs/driver.md: r05 given a controller file that does not exist (edited by hand, as
    panther-ops refuses it): the driver's launch fails, and restarts under ``restart: always``."""
    compose = "/home/husarion/compose.yaml"
    text = lab.read("r05", compose)
    launch = "ros2 launch panther_bringup bringup.launch.py"
    assert launch in text, text
    lab.write("r05", compose, text.replace(launch, f"{launch} controller_config_path:=/nonexistent/ctrl.yaml", 1))
    lab.compose("r05", "up", "-d")
    _loop_waits(lab, "r05", LOOP_RESTARTS)


LOOP_RESTARTS = 9
"""docker doubles a crash loop's delay before each restart (100 ms, 200 ms ... at most a minute): once
the driver failed for the 9th time (restart count 9), it waits 25.6 s in ``restarting`` (room for a
loaded machine: the page reads it within a few seconds)."""


def _loop_waits(lab: Lab, name: str, restarts: int) -> None:
    """The defined point of a crash loop the page reads: the moment the driver failed once more and its
    restart count reached ``restarts`` (state ``restarting``, the count just gone up), so that what is
    read next sees it waiting to restart, not in one of its starts (a few hundred ms each)."""
    container = lab.robot(name).driver_container
    deadline = time.monotonic() + 120
    last: tuple[str, int] | None = None
    while time.monotonic() < deadline:
        state, count = lab.docker(name, "inspect", "-f", "{{.State.Status}} {{.RestartCount}}", container,
                                  check=True).stdout.split()
        now = (state, int(count))
        if state == "restarting" and now[1] >= restarts and last is not None and last != now:
            return
        last = now
        time.sleep(0.05)
    raise AssertionError(f"{name}: its crash loop did not reach {restarts} restarts in 120 s")


def _publisher(lab: Lab) -> None:
    """docs/remote.md: on r01 a ``ros2 topic pub`` publishes 0.1 m/s on cmd_vel at 10 Hz (a moving command:
    the driver refuses a reset)."""
    from tests.remote.estop.test_estop_lab import start_publisher

    start_publisher(lab, "r01")


def _publisher_stopped(lab: Lab) -> None:
    """docs/remote.md, before teleop: r01's ``ros2 topic pub`` stopped."""
    from tests.remote.estop.test_estop_lab import stop_publishers

    stop_publishers(lab, "r01")


def _on_python_image(lab: Lab, name: str) -> None:
    """The robot's driver recreated from the lab's Python image (python3, the rclpy stand-in; the
    lab's Python image under the driver's tag, tests/lab/pyimage.py), as
    tests/remote/teleop/test_teleop_lab.py and tests/manager_ops/test_manager_lab.py do."""
    from tests.lab.pyimage import use_python_image

    use_python_image(lab, name)
    cp = lab.compose(name, "up", "-d", "--force-recreate", lab.robot(name).driver_container)
    assert cp.returncode == 0, cp.stderr


def _r01_python_driver(lab: Lab) -> None:
    """docs/remote.md, teleop: r01 on the Python image, its E-stop (triggered by a new driver) reset."""
    _on_python_image(lab, "r01")
    _panther_ops(lab, "estop", "reset", "-r", "r01", "--yes")


def _r03_python_driver(lab: Lab) -> None:
    """docs/manager-deploy.md: r03 (2.2.2) on the Python image (Python 3.10 for the manager)."""
    _on_python_image(lab, "r03")


def _host_key_changed(lab: Lab) -> None:
    """docs/results.md: r03 offers another host key than known_hosts holds."""
    lab.rotate_host_key("r03")


def _r01_lan_listed(lab: Lab) -> None:
    """docs/shutdown.md, before ``shutdown check``: r01's hosts file also lists arm (10.200.101.103),
    and the robot trusts the host keys of pi and arm (known_hosts, as a first ``ssh`` from it would)."""
    _panther_ops(lab, "shutdown", "hosts", "add", "-r", "r01", "--ip", str(lab.computer("arm").ip), "--user",
                 "husarion", "--yes", "--settle", "1")
    for name in ("pi", "arm"):
        trust_on_robot(lab, "r01", name)
    text = lab.read("r01", "/home/husarion/config/panther_manager/config/shutdown_hosts_config.yaml")
    assert "10.15.20." not in text, text  # nothing but the lab's computers is ever contacted (rule 3)


def _user_computers(lab: Lab) -> None:
    """docs/remote.md: the inventory names r01's and r02's User Computers (``user_computer``)."""
    from tests.labtools import user_computer_inventory

    user_computer_inventory(lab, lab.inventory_path, {"r01": "w1", "r02": "w2"})


def _desired_webui(lab: Lab) -> None:
    """docs/remote.md: r02's WebUI installed and running on 8080, its snap without a namespace, and
    ``desired.webui`` of r02 in the inventory."""
    import yaml

    from tests.remote.webui.test_webui_lab import without_namespace_on_8080

    _panther_ops(lab, "webui", "install", "-r", "r02")
    _panther_ops(lab, "webui", "start", "-r", "r02")
    without_namespace_on_8080(lab, "w2")
    doc = yaml.safe_load(lab.inventory_path.read_text())
    doc["robots"]["r02"]["desired"] = {"webui": {"transport": "rmw_cyclonedds_cpp", "port": 8082, "layout": "panther"}}
    lab.inventory_path.write_text(yaml.safe_dump(doc))


GGA_AT = (52.2296756, 21.0122287)
_SENDERS: dict[Path, list[Sender]] = {}
"""The GGA senders a page's scene started, by lab: stopped by a later scene or when the page ends."""


def _gga_to_r01_r03(lab: Lab) -> None:
    """docs/gps.md: a GGA sentence at 52.2296756 21.0122287 every 0.5 s to r01's and r03's NMEA
    port (5000), one a datagram, as tests/gps/test_gps_lab.py sends them (the NMEA driver reads
    only the last sentence of a datagram)."""
    from tests.lab.nmea import sentences

    gga = (sentences(*GGA_AT)[0] + "\r\n").encode()
    for name in ("r01", "r03"):
        to = (lab.robot(name).ip, 5000)
        _SENDERS.setdefault(lab.dir, []).append(Sender(lambda to=to: to, *GGA_AT, period=0.5, payload=lambda: gga).start())


def _gga_stopped(lab: Lab) -> None:
    """docs/gps.md, the router's part: no NMEA arrives at a robot but what its router forwards."""
    for sender in _SENDERS.pop(lab.dir, []):
        sender.stop()


MANAGER_FIRST_STATUS = re.compile(r"^t=\s+0\.\d \w+: battery", re.M)
"""The manager's first status line (the simulated robot at t=0; the next one comes 10 s later)."""


def _manager_sim(lab: Lab) -> None:
    """docs/manager-deploy.md: the manager deployed in simulation on r03 (``manager deploy --sim``, as
    tests/manager_ops/test_manager_lab.py deploys it), its log up to its first status line (t=0; the page
    shows the log's start, which later lines do not change)."""
    _panther_ops(lab, "manager", "deploy", "-r", "r03", "--sim", "--yes", "--settle", "2")
    deadline = time.monotonic() + 60
    while not MANAGER_FIRST_STATUS.search(log := _both(lab.docker("r03", "logs", "panther_ops_manager"))):
        assert time.monotonic() < deadline, log
        time.sleep(0.2)


def _both(cp: subprocess.CompletedProcess[str]) -> str:
    return f"{cp.stdout}{cp.stderr}"


def _r02_write_lock_held(lab: Lab) -> Callable[[], None]:
    """docs/output.md: another change holds r02's write lock (``~/.panther-ops/write.lock``, taken
    with ``flock`` by a session of its own on the robot, as a second operator's write takes it):
    r02's write waits for it. Released (the session's input closed) when the page is done."""
    holder = subprocess.Popen(lab.ssh_argv("r02", "mkdir -p .panther-ops && flock .panther-ops/write.lock "
                                                  "sh -c 'echo held; exec cat >/dev/null'"),
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert holder.stdout is not None and holder.stdout.readline() == "held\n"

    def release() -> None:
        assert holder.stdin is not None
        holder.stdin.close()
        holder.wait(timeout=30)

    return release


def _r01_reinstalled(lab: Lab) -> None:
    """docs/reimage.md: r01 customised (``config set wheel_type WH02``), backed up into lab/backups
    (``reimage backup``), then "reinstalled" as tests/reimage/test_reimage_restore_lab.py reinstalls
    it: a new host key, its config tree, key pair and customised compose file gone."""
    from tests.reimage.test_reimage_restore_lab import COMPOSE, reinstall

    factory = lab.read("r01", COMPOSE)
    _panther_ops(lab, "config", "set", "wheel_type", "WH02", "-r", "r01", "--yes", "--settle", "1")
    _panther_ops(lab, "reimage", "backup", "-r", "r01", "--out", str(lab.dir / "backups"))
    reinstall(lab, factory)


SCENES: dict[str, Callable[[Lab], Callable[[], None] | None]] = {
    "gga-to-r01-r03": _gga_to_r01_r03,
    "gga-stopped": _gga_stopped,
    "r02-drift": _drift,
    "r05-crash-loop": _crash_loop,
    "r03-host-key-changed": _host_key_changed,
    "r01-cmd-vel-publisher": _publisher,
    "r01-publisher-stopped": _publisher_stopped,
    "r01-python-driver": _r01_python_driver,
    "r01-lan-listed": _r01_lan_listed,
    "user-computers": _user_computers,
    "r02-desired-webui": _desired_webui,
    "r03-python-driver": _r03_python_driver,
    "r03-manager-sim": _manager_sim,
    "r02-write-lock-held": _r02_write_lock_held,
    "r01-reinstalled": _r01_reinstalled,
}
"""The states a page's text describes before a sample (```console lab scene=NAME); one that returns
a function has it called when the page is done (the state let go)."""


def _four_changed_r02_waits(shown: str) -> bool:
    """After the plan (its diffs shown: the writes began), the live view: four robots changed, r02 alone
    in its write for a second or more (it waits for its lock: scene r02-write-lock-held). (While
    planning, a robot planned counts as done too.)"""
    _, plan, applying = shown.partition("\nplan: ")
    return bool(plan) and re.search(r"r02 +write +[1-9]\d*\.\d s\n4/5 robots done +4 changed", applying) is not None


CTRL_C: dict[tuple[str, str], Callable[[str], bool]] = {
    ("output.md", "panther-ops -i lab/inventory.yaml config set wheel_type WH04 --all --yes"): _four_changed_r02_waits,
}
"""(page, command) of a lab sample in which Ctrl-C is typed: once what the terminal shows says so."""


def follow_on_lab(doc: Path, prefix: str | None = None) -> Outcome:
    """The page's lab samples run on a lab of their own (see docsamples.follow)."""
    with page_lab(prefix, doc.name) as lab, ExitStack() as undo:
        undo.callback(_gga_stopped, lab)

        def scene(name: str) -> None:
            if (release := SCENES[name](lab)) is not None:
                undo.callback(release)

        return follow(doc, lab.dir, scene, subnets=shown_subnets(lab), password=SHAPES.get(doc.name, Shape()).password,
                      ctrl_c=lambda command: CTRL_C.get((doc.name, command)))
