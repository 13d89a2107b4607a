"""The BT projects `manager deploy` uploads: the robot's release's own stock projects.

The stock lights/safety managers run their release's projects
(``<pkg>_manager/behavior_trees/{Panther,}{Lights,Safety}BT.btproj`` with lights.xml, safety.xml,
shutdown.xml); panther-ops' templates of them, equal to upstream's (docs/conformance.md), are
under ``templates/config/<generation>/<pkg>/behavior_trees`` (a version's overlay first, as
`config pull` reads them). The one file replaced is the Shutdown tree of the releases whose
stock tree powers the robot off with ``ShutdownSingleHost(ip=localhost, username=husarion)``
(panther_ros 2.0.2 - husarion_ugv 2.2.0, e.g. husarion/panther_ros@2.1.1:panther_manager/
behavior_trees/shutdown.xml): the deployed manager checks SSH host keys and the robot's own
key is normally not in its known_hosts, so that step would fail; panther-ops'
``templates/behavior_trees/shutdown.xml`` does it as 2.2.1+'s stock tree does
(``ExecuteCommand {SHUTDOWN_LOCALHOST_COMMAND}``, husarion/husarion_ugv_ros@2.2.2:
husarion_ugv_manager/behavior_trees/shutdown.xml), with the same user and command over ssh.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from panther_ops.core.fleet.templates import template_path
from panther_ops.core.robot.files import family_dirs, stock_bt_project
from panther_ops.core.stack import Stack

OWN_SHUTDOWN_BEFORE = (2, 2, 1)
"""Releases before this one get panther-ops' shutdown.xml (their stock one uses ShutdownSingleHost localhost)."""


@dataclass(frozen=True)
class DeployedProjects:
    """The project files of one release as deployed: name -> (template, what it is)."""

    lights: str
    safety: str
    files: dict[str, tuple[Path, str]]


def deployed_projects(stack: Stack) -> DeployedProjects:
    """The release's stock projects (overlay files over the base's), shutdown.xml as above."""
    package = f"{stack.package_prefix}_manager"
    files: dict[str, tuple[Path, str]] = {}
    for directory in reversed(family_dirs(stack)):
        root = template_path("config", directory, package, "behavior_trees")
        if root.is_dir():
            for path in sorted(root.iterdir()):
                files[path.name] = (path, f"{stack.label()}'s stock {path.name} "
                                          f"(templates/config/{directory}/{package}/behavior_trees)")
    if stack.version < OWN_SHUTDOWN_BEFORE:
        files["shutdown.xml"] = (template_path("behavior_trees", "shutdown.xml"),
                                 "panther-ops' shutdown.xml (templates/behavior_trees): the robot powers off by "
                                 "ExecuteCommand {SHUTDOWN_LOCALHOST_COMMAND}, not ShutdownSingleHost localhost")
    lights, safety = (stock_bt_project(stack, which)[1] for which in ("Lights", "Safety"))
    if lights not in files or safety not in files:
        raise FileNotFoundError(f"no stock BT project template of {stack.label()} under templates/config")
    return DeployedProjects(lights, safety, files)
