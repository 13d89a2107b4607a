"""Every unmodified default file of Husarion's releases, read from a local git mirror of
husarion/husarion_ugv_ros (it holds panther_ros' history too), is accepted by its kind's
validator on a robot of that release (issue 24, finding 1). Skipped when no mirror is there:
tests/kinds/test_upstream_file_kinds.py checks the same facts from tables, without a network.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

from panther_ops.core.kinds import FileKind, Target, check_file
from panther_ops.core.stack import stack_from_version

MIRROR = Path(os.environ.get("PANTHER_OPS_UPSTREAM_MIRROR", "/work/.mirror/husarion+husarion_ugv_ros/repo"))
TAGS = ("2.0.4", "2.1.1", "2.2.0", "2.2.2")


def _files(tag: str) -> list[str]:
    out = subprocess.run(["git", "-C", str(MIRROR), "ls-tree", "-r", "--name-only", tag], capture_output=True,
                         text=True, check=True).stdout
    return out.splitlines()


def _cases(tag: str, files: list[str]) -> list[tuple[FileKind, str, str | None]]:
    """(kind, path, wheel type) of each default file of the release."""
    cases: list[tuple[FileKind, str, str | None]] = []
    for path in files:
        name = path.rsplit("/", 1)[-1]
        if "/test" in path or not path.endswith((".yaml", ".btproj")):
            continue
        if path.endswith("_description/config/" + name) and name[:2] == "WH":
            cases.append((FileKind.WHEEL, path, name[:4]))
        elif path.endswith("_controller/config/" + name) and name.endswith("_controller.yaml"):
            cases.append((FileKind.CONTROLLER, path, name[:4]))
        elif name == "components.yaml" and "_description/config/" in path:
            cases.append((FileKind.COMPONENTS, path, None))
        elif "_lights/config/" in path and name.endswith(("animations.yaml", "led_config.yaml")):
            cases.append((FileKind.USER_ANIMATIONS if name.startswith("user") else FileKind.LED, path, None))
        elif path.endswith(".btproj") and "_manager/behavior_trees/" in path:
            cases.append((FileKind.BT_LIGHTS if "Lights" in name else FileKind.BT_SAFETY, path, None))
        elif name.startswith("shutdown_hosts") and "/config/" in path:
            cases.append((FileKind.SHUTDOWN_HOSTS, path, None))
        elif name.startswith("joy2twist") and "_bringup/config/" in path:
            cases.append((FileKind.JOY2TWIST, path, None))
    return cases


@pytest.mark.skipif(not (MIRROR / "HEAD").exists(), reason=f"no upstream mirror at {MIRROR}")
@pytest.mark.parametrize("tag", TAGS)
def test_every_default_file_of_the_release_is_accepted(tag: str, tmp_path: Path) -> None:
    files = _files(tag)
    cases = _cases(tag, files)
    assert len(cases) >= 10, cases
    stack = stack_from_version(tag)
    for kind, path, wheel in cases:
        directory = tmp_path / tag / path.rsplit("/", 1)[0]
        directory.mkdir(parents=True, exist_ok=True)
        siblings = [f for f in files if f.rsplit("/", 1)[0] == path.rsplit("/", 1)[0] and f.endswith(".xml")]
        for sibling in [path, *siblings] if path.endswith(".btproj") else [path]:  # a project's included trees
            blob = subprocess.run(["git", "-C", str(MIRROR), "show", f"{tag}:{sibling}"], capture_output=True,
                                  check=True).stdout
            (tmp_path / tag / sibling).write_bytes(blob)
        local = tmp_path / tag / path
        check_file(kind, str(local), local.read_bytes(), local=local, target=Target(stack, wheel or "WH01"))
