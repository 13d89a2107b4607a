"""husarion_ugv's stock files of the config tree, as panther-ops' templates write them."""

from __future__ import annotations

from panther_ops.core.stack import UGV_REPO, Stack
from panther_ops.errors import UsageError


def stock_text(rel: str, version: tuple[int, int, int] = (2, 2, 2)) -> str:
    """The stock file ``rel`` (under the config tree) of husarion_ugv ``version`` (panther-ops' template of it,
    semantically equal to upstream's: tests/golden/upstream and docs/conformance.md)."""
    from panther_ops.core.fleet.templates import read_template, template_path
    from panther_ops.core.robot.files import family_dirs

    label = ".".join(map(str, version))
    distro = "jazzy" if version >= (2, 3, 0) else "humble"
    stack = Stack(f"{UGV_REPO}:{distro}-{label}", distro, version, None)
    for directory in family_dirs(stack):
        if template_path("config", directory, *rel.split("/")).is_file():
            return read_template("config", directory, *rel.split("/"))
    raise UsageError(f"panther-ops has no template of {rel} for husarion_ugv {label}")
