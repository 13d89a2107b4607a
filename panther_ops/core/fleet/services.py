"""A compose project's containers on a robot's docker engine, found by compose's labels.

A robot may run more than one compose project (an operator's own ``~/gps/compose.yaml`` with
an ``nmea-gps`` service, say). Containers are told apart by the project directory compose
records on each (``com.docker.compose.project.working_dir``): what is removed or verified is
only ever the project's own.
"""

from __future__ import annotations

import posixpath
from typing import Any

from panther_ops.core.fleet.runner import RobotContext

SERVICE_LABEL = "com.docker.compose.service"
WORKING_DIR_LABEL = "com.docker.compose.project.working_dir"


def project_dir(ctx: RobotContext, compose_file: str, home: str | None = None) -> str:
    """The absolute directory of ``compose_file`` on the robot: what compose records as the
    project's working directory (``~`` and relative paths are from the robot user's home,
    ``home`` when a plan read it, else asked on the robot's connection once)."""
    directory = posixpath.dirname(compose_file) or "~"
    if not directory.startswith("/"):
        home = home or ctx.transport.home()
        directory = home + directory[1:] if directory == "~" or directory.startswith("~/") else f"{home}/{directory}"
    return posixpath.normpath(directory)


def service_containers(client: Any, service: str, working_dir: str | None = None, *,
                       own_only: bool = False) -> list[Any]:
    """Containers of a compose service, running ones first.

    ``working_dir`` (absolute, see ``project_dir``): those of the project in that directory
    first; with ``own_only`` only those (what may be removed or verified), else any other
    project's follow (what a status may still show when the project's own are gone).
    """
    found = list(client.containers.list(all=True, filters={"label": f"{SERVICE_LABEL}={service}"}))
    if working_dir is not None and own_only:
        found = [c for c in found if _labels(c).get(WORKING_DIR_LABEL) == working_dir]
    found.sort(key=lambda c: (working_dir is not None and _labels(c).get(WORKING_DIR_LABEL) != working_dir,
                              not (c.attrs.get("State") or {}).get("Running")))
    return found


def running_containers(client: Any, service: str, working_dir: str | None = None) -> list[Any]:
    """The service's running containers, the project's own first (to read from or exec in)."""
    return [c for c in service_containers(client, service, working_dir)
            if (c.attrs.get("State") or {}).get("Running")]


def _labels(container: Any) -> dict[str, str]:
    labels = (container.attrs.get("Config") or {}).get("Labels") or {}
    return labels if isinstance(labels, dict) else {}
