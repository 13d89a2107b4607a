"""The lab a page's ```console lab samples run on (tests/ux/docsamples.py, lab mode): the shape
the docs' samples name (docs/lab.md, "From pytest": 5 robots r01..r05, docker on, stacks
2.0.4 / 2.1.1 / 2.2.2 / 2.0.4 / 2.1.1, r05 reachable only through r01), one fresh lab per page
(a page's samples change its robots in the page's order), torn down after the page."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from tests.lab import Lab, missing_requirements

from .docsamples import Outcome, follow

IMAGES = ("2.0", "2.1.1", "2.2")
JUMPS = {"r05": "r01"}


def lab_unavailable() -> str | None:
    """Why the docs' lab cannot run on this machine (not root, a binary missing), or None."""
    why = missing_requirements(docker=True)
    return "; ".join(why) if why else None


SHAPES: dict[str, tuple[int, dict[str, str]]] = {
    "remote.md": (3, {}),  # docs/remote.md: r01..r03 on 2.0.4, 2.1.1 and 2.2.2
}
"""Pages whose samples name another lab than the docs' one: robots, jumps."""


@contextmanager
def page_lab(prefix: str | None = None, page: str = "") -> Iterator[Lab]:
    """A lab of the page's shape (the docs' one unless SHAPES says), up for one page, torn down after it."""
    n, jumps = SHAPES.get(page, (5, JUMPS))
    lab = Lab(n, docker=True, images=IMAGES, jumps=jumps, prefix=prefix, ephemeral=True)
    lab.up()
    try:
        yield lab
    finally:
        lab.down()


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


def _publisher(lab: Lab) -> None:
    """docs/remote.md: on r01 a ``ros2 topic pub`` publishes on cmd_vel."""
    from tests.remote.estop.test_estop_lab import start_publisher

    start_publisher(lab, "r01")


def _host_key_changed(lab: Lab) -> None:
    """docs/results.md: r03 offers another host key than known_hosts holds."""
    lab.rotate_host_key("r03")


SCENES: dict[str, Callable[[Lab], None]] = {
    "r02-drift": _drift,
    "r05-crash-loop": _crash_loop,
    "r03-host-key-changed": _host_key_changed,
    "r01-cmd-vel-publisher": _publisher,
}
"""The states a page's text describes before a sample (```console lab scene=NAME)."""


def follow_on_lab(doc: Path, prefix: str | None = None) -> Outcome:
    """The page's lab samples run on a lab of their own (see docsamples.follow)."""
    with page_lab(prefix, doc.name) as lab:
        return follow(doc, lab.dir, lambda name: SCENES[name](lab))
