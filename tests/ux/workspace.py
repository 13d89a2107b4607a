"""The directory a reader of the examples has: the demo fleet as ``demo-fleet/`` and the files
the examples name (``my_controller.yaml``, ``bad_hosts.yaml``, ...). Used by test_examples.py
(every example runs) and scripts/capture_docs.py (every console sample re-captured)."""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from panther_ops.cli.app import main
from tests.badinput.test_file_kinds import JOY2TWIST
from tests.config.test_custom_wheels import custom_controller, custom_wheel
from tests.sim_world import WORLD

from .examples import ROOT

BAD_HOSTS = "hosts:\n  - ip: not an address\n    username: Husarion\n"
GOOD_HOSTS = "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
BAD_ANIMATIONS = "user_animations:\n  - id: 5\n    animation: {}\n"
BAD_PUSHED_HOSTS = "hosts:\n  - ip: '10.15.20.5; touch x'\n    username: husarion\n    port: 70000\n"
BAD_BATTERY = "simulate_discharging: true\ninitial_charge_percentage: 140\n"
ESCAPING_BTPROJ = ('<?xml version="1.0"?>\n<root BTCPP_format="4" project_format="1.0">\n'
                   '  <include path="../../../.ssh/authorized_keys"/>\n</root>\n')


@contextmanager
def _inside(path: Path) -> Iterator[None]:
    before = Path.cwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(before)


def reader_workspace(tmp_path: Path) -> dict[str, str]:
    """Fill ``tmp_path`` as a reader's directory; the environment variables the examples
    expect, to set (the secret of docs/shutdown.md, Gazebo's stand-in CLI of docs/gps.md).
    No ``templates/``: an installed user has none (a shipped file is named, or pulled)."""
    assert main(["demo", "init", "--dest", str(tmp_path / "demo-fleet")]) == 0
    shutil.copytree(ROOT / "templates" / "behavior_trees", tmp_path / "my_trees")
    lights = ROOT / "templates" / "lights"
    shutil.copytree(lights / "animations", tmp_path / "animations")
    for name in ("my_animations.yaml", "my_awesome_user_animations.yaml"):
        shutil.copy(lights / "user_animations.example.yaml", tmp_path / name)
    (tmp_path / "bad_animations.yaml").write_text(BAD_ANIMATIONS)
    (tmp_path / "bad.yaml").write_text(BAD_HOSTS)
    (tmp_path / "my_hosts.yaml").write_text(GOOD_HOSTS)
    (tmp_path / "hosts.yaml").write_text(GOOD_HOSTS + "  - ip: 10.15.20.9\n    username: pi\n")
    (tmp_path / "bad_hosts.yaml").write_text(BAD_PUSHED_HOSTS)
    (tmp_path / "chained.yaml").write_text("hosts:\n  - ip: 10.15.20.3\n    username: husarion\n"
                                           "    command: sync && sudo shutdown now\n")
    config = ROOT / "templates" / "config" / "panther-2.1"  # a simulation workspace's files (docs/gps.md)
    shutil.copy(config / "panther_description" / "config" / "components.yaml", tmp_path / "components.yaml")
    shutil.copy(config / "panther_gazebo" / "config" / "battery_plugin_config.yaml",
                tmp_path / "battery_plugin_config.yaml")
    (tmp_path / "my_world.sdf").write_text(WORLD)
    (tmp_path / "w.sdf").write_text(WORLD)
    (tmp_path / "dms.sdf").write_text(WORLD.replace("53.1978", "53°11'52\"N"))  # docs/gps.md: refused, with the fix
    (tmp_path / "bad_battery.yaml").write_text(BAD_BATTERY)
    wh01_20 = ROOT / "templates/config/panther-2.0/panther_controller/config/WH01_controller.yaml"
    (tmp_path / "no_prefix_controller.yaml").write_text(  # docs/configuration.md: the IMU under a namespace
        wh01_20.read_text().replace("      use_namespace_as_sensor_name_prefix: true\n", ""))
    (tmp_path / "my_wheels.yaml").write_bytes(custom_wheel("2.1.1"))  # docs/configuration.md: custom wheels
    (tmp_path / "my_wheels_controller.yaml").write_bytes(custom_controller("2.1.1"))
    (tmp_path / "pad.yaml").write_text(JOY2TWIST)
    (tmp_path / "bad_pad.yaml").write_text(JOY2TWIST.replace("dead_man_switch: 4", "dead_man_switch: LB"))
    (tmp_path / "bad_srv_pad.yaml").write_text(JOY2TWIST.replace("reset_srv: hardware/e_stop_reset",
                                                                 "reset_srv: hardware/e-stop-reset"))
    (tmp_path / "proj").mkdir()
    (tmp_path / "proj" / "My.btproj").write_text(ESCAPING_BTPROJ)
    # the reader's simulation (docs/gps.md): Gazebo's CLI, a stand-in serving the recharge
    # services of a panther without a namespace and of one spawned under 'panther'
    (tmp_path / "gz-services").write_text("".join(
        f"/model/{m}/battery/{b}/recharge/{a}\n" for m, b in (("panther", "battery"), ("panther", "panther/battery"))
        for a in ("start", "stop")))
    with _inside(tmp_path):
        assert main(["-i", "demo-fleet", "config", "pull", "controller", "-r", "panther-01", "-o",
                     "my_controller.yaml"]) == 0
        # hosts.yaml (GOOD_HOSTS) with a backup beside it, for `config history|rollback --file hosts.yaml`
        assert main(["shutdown", "hosts", "remove", "hosts.yaml", "--ip", "10.15.20.9", "--yes"]) == 0
    assert (tmp_path / "hosts.yaml").read_text() == GOOD_HOSTS
    return {
        "NUC_SECRET": "a-long-shared-secret-for-the-nuc",
        "PATH": f"{ROOT / 'tests' / 'standins'}:{os.environ['PATH']}",
        "PANTHER_OPS_STANDIN_GZ_SERVICES": str(tmp_path / "gz-services"),
        "PANTHER_OPS_STANDIN_GZ_CALLS": str(tmp_path / "gz-calls"),
    }
