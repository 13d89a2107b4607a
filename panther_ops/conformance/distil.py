"""Distil one upstream release into the table the offline checks read (tests/golden/upstream/<tag>.json).

What is kept, and why it is not a copy of upstream's files:

- ``launch``: per launch argument that bringup and its includes declare: its name, the
  files declaring it, its kind (``bool``/``choice``/``text``), its choices, its default
  evaluated in three contexts (`launch.CONTEXTS`) and where that default is read from.
  These are the facts the catalogue (core/kinds/arg_catalogue.py) must state.
- ``files``: per upstream default file panther-ops has a kind for, or a template of, or
  that the 2.2 config tree holds: its sha256, its format and its semantic digest (key
  paths, value types and a hash of each value: `digest`), and for a file of a kind, the
  verdict of that kind's validator at the time the table was made (accepted, or the
  errors) on a robot of that release, with the robot (wheel type, model) it was run for.
  The values themselves are not kept; a template is compared with upstream's file through
  the digests, and when a template equals upstream's file, the offline check re-runs the
  validator on the template (the same parsed content).
- ``tree``: the files ``update_config_directory`` (docker/utils, 2.2+) copies into the
  robot's ``~/config`` tree, per robot model.
- ``packages``: ROS package -> directory in the repository.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path, PurePosixPath
from typing import Any

from panther_ops.conformance import launch
from panther_ops.conformance.digest import file_format, leaves, sha256
from panther_ops.conformance.upstream import GitRelease, UpstreamError, classify, config_tree, packages

SCHEMA = 1
BRINGUP = ("husarion_ugv_bringup", "panther_bringup")
TREE_SCRIPT = "docker/utils/update_config_directory.sh"
ROBOT_MODELS = ("panther", "lynx")
_DIGESTED = re.compile(r"^(?:panther|husarion_ugv)_(?:bringup|controller|description|lights|manager|teleop)/"
                       r"(?:config|behavior_trees)/[^/]+\.(?:ya?ml|xml|btproj)$")
"""Files digested besides those of a kind and those of the config tree: the packages panther-ops
has templates of (a new template of such a file is checked without re-reading upstream)."""


def distil(release: GitRelease, *, repo: str | None = None) -> dict[str, Any]:
    """The table of ``release`` (reads the mirror; runs the validators)."""
    paths = release.paths
    pkgs = packages(paths, release.read)
    entry_pkg = next((p for p in BRINGUP if p in pkgs), None)
    if entry_pkg is None:
        raise UpstreamError(f"{release.tag}: no bringup package ({' or '.join(BRINGUP)}) in the release")
    texts = {p: release.read(p).decode() for p in paths if p.endswith(".launch.py")}
    entry = f"{pkgs[entry_pkg]}/launch/bringup.launch.py"
    trav = launch.traverse(entry, texts, pkgs)
    tree: dict[str, list[str]] | None = None
    if TREE_SCRIPT in paths:
        script = release.read(TREE_SCRIPT).decode()
        tree = {model: config_tree(script, paths, pkgs, model) for model in ROBOT_MODELS}
    in_tree = {f"{pkgs.get(p.split('/', 1)[0], p.split('/', 1)[0])}/{p.split('/', 1)[1]}"
               for files in (tree or {}).values() for p in files}
    wanted = [p for p in paths if classify(p) or _DIGESTED.match(p) or p in in_tree]
    files = [_file_row(release, p) for p in wanted]
    _verdicts(release, files)
    return {
        "schema": SCHEMA,
        "repo": repo or release.repo_name(),
        "tag": release.tag,
        "commit": release.commit,
        "packages": dict(sorted(pkgs.items())),
        "launch": {
            "entry": entry,
            "files": list(trav.files),
            "external": trav.external,
            "problems": trav.problems,
            "args": list(launch.arguments(trav)),
        },
        "tree": None if tree is None else {"script": TREE_SCRIPT, **tree},
        "files": files,
    }


COMPOSE_PATH = "demo/compose.minimal-setup.yaml"
"""The compose file of husarion/panther-docker a robot's compose.yaml is based on (templates/compose)."""
OWN_COMPOSE_PATH = "docker/demo/compose.hardware.yaml"
"""husarion_ugv_ros (2.2+) keeps the robot's compose file in its own repository, at this path."""


def own_compose(release: GitRelease, *, repo: str | None = None) -> dict[str, Any] | None:
    """The digest of the release's own compose file (`OWN_COMPOSE_PATH`, husarion_ugv_ros 2.2+),
    or None: the release has none (panther_ros: husarion/panther-docker holds it)."""
    if OWN_COMPOSE_PATH not in release.paths:
        return None
    return distil_compose(release, repo=repo, path=OWN_COMPOSE_PATH)


def distil_compose(release: GitRelease, *, repo: str | None = None, path: str = COMPOSE_PATH) -> dict[str, Any]:
    """The digest of the release's compose file (husarion/panther-docker's at the same tag, or
    the release's own, `own_compose`), with the rules of `digest.compose_leaves`."""
    from panther_ops.conformance.digest import compose_leaves

    data = release.read(path)
    return {"repo": repo or release.repo_name(), "commit": release.commit, "path": path, "sha256": sha256(data),
            "leaves": {k: f"{t}:{h}" for k, (t, h) in compose_leaves(data).items()}}


def _file_row(release: GitRelease, path: str) -> dict[str, Any]:
    data = release.read(path)
    fmt, digest = leaves(PurePosixPath(path).name, data)
    row: dict[str, Any] = {"path": path, "sha256": sha256(data), "format": fmt,
                           "leaves": {k: f"{t}:{h}" for k, (t, h) in digest.items()}}
    if file_format(path) != fmt:
        row["note"] = f"does not parse as {file_format(path)}"
    found = classify(path)
    if found is not None:
        row["kind"] = found.kind.value
        row["robot"] = {"wheel_type": found.wheel_type, "robot_model": found.robot_model}
    return row


def _verdicts(release: GitRelease, rows: list[dict[str, Any]]) -> None:
    """Run each kind's validator on the upstream file, laid out as in the package share."""
    from panther_ops.conformance.validate import run_validator

    kinds = [r for r in rows if "kind" in r]
    with tempfile.TemporaryDirectory(prefix="panther-ops-conformance-") as tmp:
        root = Path(tmp)
        release.extract(sorted({r["path"].split("/", 1)[0] for r in kinds}), root)
        for row in kinds:
            local = root / row["path"]
            verdict = run_validator(release.tag, row["kind"], row["path"], local.read_bytes(), local,
                                    row["robot"]["wheel_type"], row["robot"]["robot_model"])
            row["verdict"] = {k: [_local(line, root) for line in v] if isinstance(v, list) else v
                              for k, v in verdict.items()}


def _local(line: str, root: Path) -> str:
    """A message without this machine's paths (the extracted release, the project's checkout)."""
    from panther_ops.core.fleet.templates import templates_dir

    return line.replace(str(root) + "/", "").replace(str(templates_dir().parent) + "/", "")
