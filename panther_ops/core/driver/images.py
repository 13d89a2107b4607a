"""Driver images: references, tags, target parsing and Docker Hub's released Humble tags."""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from panther_ops.core.robot.compose import image_repo
from panther_ops.core.stack import PANTHER_REPO, UGV_REPO
from panther_ops.errors import OpsError, UsageError

DRIVER_REPOS = (PANTHER_REPO, UGV_REPO)
HUB_URL = "https://hub.docker.com/v2/namespaces/husarion/repositories/{repo}/tags?page_size=100"
"""Docker Hub's tag list (what Husarion's configurator asks); ``{repo}`` is panther / husarion-ugv."""
HUB_TAG = re.compile(r"^humble-\d+\.\d+\.\d+-\d{8}(-stable)?$", re.ASCII)
"""Released Humble driver tags (the configurator's filter, for Humble)."""
HUB_TIMEOUT_S = 5.0
NEWEST_HUMBLE = "husarion/husarion-ugv:humble-2.2.2-20250702"
NEWEST_JAZZY = "husarion/husarion-ugv:jazzy-2.3.2-20260622"
"""husarion_ugv_ros@2.3.2:docker/demo/compose.hardware.yaml."""
_TAG_WORD = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,127}$")
_TAG = re.compile(
    r"^(?P<distro>[a-z]+)-(?P<major>\d+)\.(?P<minor>\d+)\.(?P<patch>\d+)"
    r"(?:-(?P<date>\d{8}))?(?:-(?P<suffix>[A-Za-z0-9._-]+))?$", re.ASCII  # \d: 0-9, not other scripts' digits
)


def repo_for(version: tuple[int, int, int]) -> str:
    """The Docker Hub repository of a driver version: 2.2+ husarion/husarion-ugv, else husarion/panther."""
    return UGV_REPO if version >= (2, 2, 0) else PANTHER_REPO


@dataclass(frozen=True)
class TargetImage:
    """What `driver update` was asked for, checked before any robot is contacted."""

    text: str
    tag: str
    repo: str | None
    """The repository when a full reference was given (None: a tag, repo from the version)."""
    version: tuple[int, int, int]
    warnings: tuple[str, ...] = ()

    def ref_for(self, current: str) -> str:
        """The full reference for a robot whose compose.yaml has ``current``.

        A bare tag keeps the registry prefix of the current image (a mirror stays a mirror)
        and takes the repository of its version; a full reference is used as given.
        """
        if self.repo is not None:
            return self.text
        name = current.split("@", 1)[0]
        head, sep, tail = name.rpartition(":")
        if sep and "/" not in tail:
            name = head
        prefix = name[: len(name) - len(image_repo(name))] if name.endswith(image_repo(name)) else ""
        return f"{prefix}{repo_for(self.version)}:{self.tag}"


def _crossed(tag: str, distro: str, version: tuple[int, int, int]) -> UsageError:
    return UsageError(
        f"{tag}: {distro} {'.'.join(map(str, version))} is not a driver panther-ops supports: husarion_ugv runs ROS 2 "
        "Humble up to 2.2.x and ROS 2 Jazzy from 2.3.x (there is no Humble 2.3 nor Jazzy 2.2; 2.4 and later are "
        "not supported yet)",
        hint=f"the newest Humble driver is {NEWEST_HUMBLE}; the newest Jazzy one {NEWEST_JAZZY}",
    )


def parse_target(text: str, *, force: bool = False) -> TargetImage:
    """Check a `driver update` argument: a tag (``humble-2.1.2-20241125``) or a full reference.

    Humble 2.0-2.2.x and Jazzy 2.3.x (a 2.2 robot's `driver update` to 2.3 is a migration,
    `migrate/plan.py`); crossed pairs and later lines are refused; the repository must be the one
    of the version's family (2.2+ husarion/husarion-ugv, 2.0-2.1 husarion/panther) unless
    ``force`` (then a warning).

    Raises:
        UsageError: anything else (exit 2, before any robot is contacted).
    """
    ref = text.strip()
    if not ref:
        raise UsageError("empty image tag")
    if "@" in ref:
        raise UsageError(f"{ref}: a digest does not say the driver version; give the tag",
                         hint="e.g. panther-ops driver update humble-2.1.2-20241125")
    repo: str | None = None
    tag = ref
    if "/" in ref or ":" in ref:
        name, sep, tag = ref.rpartition(":")
        if not sep or "/" in tag or not name:
            raise UsageError(f"{ref!r} has no tag", hint="REPOSITORY:TAG, e.g. husarion/panther:humble-2.1.2-20241125")
        repo = image_repo(name)
        if repo not in DRIVER_REPOS:
            raise UsageError(f"{ref}: {repo} is not a Panther driver image",
                             hint=f"expected {PANTHER_REPO}:<tag> (2.0-2.1) or {UGV_REPO}:<tag> (2.2)")
    if not _TAG_WORD.match(tag):
        raise UsageError(f"{tag!r} is not a docker image tag")
    m = _TAG.match(tag)
    if not m:
        raise UsageError(f"tag {tag!r} does not say the driver version",
                         hint="tags look like humble-<X.Y.Z>-<YYYYMMDD>, e.g. humble-2.1.2-20241125 "
                              "(panther-ops driver versions --remote lists them)")
    version = (int(m["major"]), int(m["minor"]), int(m["patch"]))
    if (m["distro"] == "jazzy" and not (2, 3, 0) <= version < (2, 4, 0)) or (m["distro"] == "humble" and \
            version >= (2, 3, 0)):
        raise _crossed(tag, m["distro"], version)
    if m["distro"] not in ("humble", "jazzy"):
        raise UsageError(f"{tag}: ROS 2 {m['distro'].capitalize()} is not a Panther driver distribution here",
                         hint="panther-ops manages humble-<X.Y.Z>-<YYYYMMDD> (2.0-2.2) and jazzy-2.3.<Z>-<YYYYMMDD>")
    if version < (2, 0, 0):
        raise UsageError(f"{tag}: ROS 1 drivers (1.x) are not supported")
    warnings: list[str] = []
    expected = repo_for(version)
    if repo is not None and repo != expected:
        message = (f"{ref}: driver {'.'.join(map(str, version))} is published as {expected}, not {repo} "
                   "(2.2+ is husarion/husarion-ugv, 2.0-2.1 husarion/panther)")
        if not force:
            raise UsageError(message, hint=f"use {expected}:{tag}, or just the tag {tag}")
        warnings.append(message + " (--force)")
    return TargetImage(ref, tag, repo, version, tuple(warnings))


def tag_key(tag: str) -> tuple[Any, ...]:
    """Sort key of a driver tag: version, then build date, then the rest."""
    m = _TAG.match(tag)
    if not m:
        return ((-1, -1, -1), "", tag)
    return ((int(m["major"]), int(m["minor"]), int(m["patch"])), m["date"] or "", tag)


def _version_of(tag: str) -> tuple[int, int, int] | None:
    m = _TAG.match(tag)
    return (int(m["major"]), int(m["minor"]), int(m["patch"])) if m else None


class RegistryError(OpsError):
    """Docker Hub could not be asked (no network, timeout, not JSON)."""


@dataclass(frozen=True)
class HubTag:
    repo: str
    name: str
    last_updated: str | None = None
    digest: str | None = None
    size: int | None = None

    def to_json(self) -> dict[str, Any]:
        return {"tag": self.name, "image": f"{self.repo}:{self.name}", "last_updated": self.last_updated,
                "digest": self.digest, "size": self.size}


def parse_hub_page(doc: Any, repo: str) -> tuple[list[HubTag], str | None]:
    """One page of Docker Hub's tag list -> (released Humble tags, next page URL)."""
    if not isinstance(doc, dict) or not isinstance(doc.get("results"), list):
        raise RegistryError("unexpected answer from Docker Hub (no results list)")
    tags: list[HubTag] = []
    for item in doc["results"]:
        if not isinstance(item, dict):
            continue
        name = item.get("name")
        if not isinstance(name, str) or not HUB_TAG.match(name):
            continue
        size = item.get("full_size")
        tags.append(HubTag(repo, name, item.get("last_updated") or item.get("tag_last_pushed"),
                           item.get("digest"), size if isinstance(size, int) else None))
    nxt = doc.get("next")
    return tags, nxt if isinstance(nxt, str) and nxt else None


def newer_tags(current: str, remote: list[HubTag]) -> list[str]:
    """Remote images of the current image's repository with a newer version (newest first)."""
    repo = image_repo(current)
    cur = _version_of(current.rpartition(":")[2])
    if cur is None:
        return []
    out = [t for t in remote if t.repo == repo and (_version_of(t.name) or (0, 0, 0)) > cur]
    return [f"{t.repo}:{t.name}" for t in sorted(out, key=lambda t: tag_key(t.name), reverse=True)]


def local_images(images: list[Mapping[str, Any]], *, compose_image: str | None, running_ref: str | None,
                 running_image_id: str | None) -> list[dict[str, Any]]:
    """Driver images among an engine's images (``/images/json`` attrs), newest version first.

    ``in_use`` marks the reference the driver container was created from (several tags may
    share one image id); by id only when that reference is no tag here (an id or a digest).
    """
    refs = {ref for img in images for ref in (img.get("RepoTags") or [])}
    by_ref = running_ref in refs
    out: list[dict[str, Any]] = []
    for img in images:
        for ref in img.get("RepoTags") or []:
            if not isinstance(ref, str) or image_repo(ref) not in DRIVER_REPOS:
                continue
            in_use = ref == running_ref if by_ref else bool(running_image_id) and img.get("Id") == running_image_id
            out.append({"image": ref, "repo": image_repo(ref), "tag": ref.rpartition(":")[2],
                        "id": str(img.get("Id", ""))[:19], "size": img.get("Size"), "in_use": in_use,
                        "in_compose": ref == compose_image})
    out.sort(key=lambda e: (tag_key(e["tag"]), e["repo"]), reverse=True)
    return out
