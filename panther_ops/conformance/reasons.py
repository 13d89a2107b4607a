"""Why a template differs from upstream's file, or has no upstream file: the reasons table.

A template must equal its upstream file semantically (`digest`), or each difference must be
listed here with its reason. An entry matches a release tag (``tags``, empty: every tag), a
template (``template``: its path under ``templates/``, ``fnmatch`` pattern) and a key path
(``path``, ``fnmatch`` pattern; ``*`` every key). Keep each reason true and short, and name
its source (``repo@tag:path``, a doc, an issue) when there is one.

`OWN` lists the templates that are panther-ops' own (no upstream counterpart by design):
they are traced here instead of to an upstream file.
"""

from __future__ import annotations

from dataclasses import dataclass
from fnmatch import fnmatchcase


@dataclass(frozen=True)
class Reason:
    template: str
    path: str
    reason: str
    tags: tuple[str, ...] = ()

    def matches(self, tag: str, template: str, path: str) -> bool:
        return ((not self.tags or tag in self.tags) and fnmatchcase(template, self.template)
                and fnmatchcase(path, self.path))


REASONS: tuple[Reason, ...] = ()
"""Listed differences between a template and its upstream file (none yet: every difference
the conformance report shows is a finding to fix, or to list here with its reason)."""


OWN: dict[str, str] = {
    "config/README.md": "the templates' own documentation",
    "gps/demo.nmea": "recorded NMEA sentences the demo robots answer with (docs/gps.md)",
    "behavior_trees/shutdown.xml": "panther-ops' Shutdown tree: `manager deploy` puts it in place of the stock "
                                   "one before husarion_ugv 2.2.1 (ExecuteCommand, as 2.2.1+'s stock tree, "
                                   "instead of ShutdownSingleHost localhost: an intended difference listed in "
                                   "docs/manager.md and core/manager_ops/stock.py, shown by deploy's plan)",
    "behavior_trees/*": "panther-ops' own trees (docs/manager.md, \"Why the release's own trees\"): the manual's "
                        "behaviours, run by `manager run` and `bt validate`'s reference, the XML twin of "
                        "panther_ops/manager/trees/*.py; neither deployed nor handed out as a release's "
                        "default (`manager deploy` and `config pull` use the release's stock project, "
                        "templates/config/<generation>/<pkg>/behavior_trees)",
    "manager/scenarios/*.yaml": "simulation scenarios of panther-ops' manager (docs/manager.md)",
    "lights/*": "panther-ops' manager's own LED configuration and animation images "
                "(panther_ops/manager/paths.py), not an upstream default file",
    "config/panther-2.*/panther_lights/config/user_animations.yaml":
        "panther_ros 2.0-2.1 ship no user_animations.yaml: an example of panther-ops' own "
        "(templates/config/README.md)",
    "joy2twist/joy2twist_panther.yaml": "written from husarion/joy2twist@2f8ad45:joy2twist/config/"
                                        "joy2twist_panther.yaml (the gamepad image of panther_ros 2.0-2.1), a "
                                        "repository this tool does not read: tests/kinds/test_joy2twist_template.py "
                                        "compares them",
    "config-tree/husarion-ugv-2.2/common/.env": "the robot's ~/config/common/.env is written by the robot's OS "
                                                "image, not by husarion_ugv_ros (templates/config/README.md)",
}
"""Template (``fnmatch`` pattern under ``templates/``) -> why it has no upstream counterpart."""


def reason_for(tag: str, template: str, path: str) -> str | None:
    """The listed reason for a difference at ``path`` of ``template`` on ``tag``, or None."""
    for entry in REASONS:
        if entry.matches(tag, template, path):
            return entry.reason
    return None


def own(template: str) -> str | None:
    """Why ``template`` (path under ``templates/``) is panther-ops' own, or None."""
    for pattern, why in OWN.items():
        if fnmatchcase(template, pattern):
            return why
    return None
