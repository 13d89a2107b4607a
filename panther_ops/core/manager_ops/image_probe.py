"""Asking the driver image what it offers the deployed manager (see `checks.py`) and the stock
manager's parameter files it has (`stock.py`): over the robot's one connection, ``docker exec``
in the running driver container (so a file mounted over the image's is the one read), else a
throw-away container of the image without network."""

from __future__ import annotations

import posixpath
from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import running_containers
from panther_ops.core.manager_ops.checks import PROBE, ImageFacts, parse_probe
from panther_ops.core.manager_ops.stock import stock_manager
from panther_ops.core.robot.robot_config import RobotConfig
from panther_ops.errors import RemoteStateError


def _run_probe(client: Any, cfg: RobotConfig, hosts_file: str) -> str:
    # the hosts file, then the stock manager's parameter files of this release (what it runs with)
    argv = ["sh", "-c", PROBE, "probe", hosts_file, *stock_manager(cfg.stack.version).paths()]
    image = cfg.compose.driver_image
    for ctr in running_containers(client, cfg.service, posixpath.dirname(cfg.compose_path)):
        tags = getattr(ctr.image, "tags", []) or []
        if image in tags:
            code, out = ctr.exec_run(["/ros_entrypoint.sh", *argv], demux=False)
            if code in (126, 127):  # no entrypoint script in this image: run the probe directly
                code, out = ctr.exec_run(argv, demux=False)
            if code == 0:
                return str((out or b"").decode(errors="replace"))
    out = client.containers.run(image, argv, remove=True, network_mode="none", stdout=True, stderr=False)
    return str((out or b"").decode(errors="replace"))


def probe_image(ctx: RobotContext, cfg: RobotConfig, hosts_file: str) -> ImageFacts | None:
    """The image's programs and hosts file (None: no docker engine, e.g. a demo robot)."""
    client = ctx.transport.docker()
    if client is None:
        return None
    try:
        output = _run_probe(client, cfg, hosts_file)
    except Exception as exc:  # docker SDK errors: the check could not run, so nothing is deployed
        raise RemoteStateError(f"cannot check the driver image {cfg.compose.driver_image} on {ctx.robot.name}: "
                               f"{exc}", hint="is the image on the robot? panther-ops driver status") from None
    return parse_probe(cfg.compose.driver_image, output)
