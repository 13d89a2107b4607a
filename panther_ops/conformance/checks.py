"""The offline checks: a release's table (tests/golden/upstream/<tag>.json) against the project.

Four checks per release, each a list of `Result` (one per item, so a fix flips one item):

- ``defaults``: every upstream default file of a panther-ops kind is accepted by that kind's
  validator on a robot of the release. When a template equals the upstream file
  semantically, the validator is run here on the template (the same parsed content) for the
  kinds whose validator reads nothing beside the file; otherwise the verdict recorded when
  the table was made is used (re-run `scripts/conformance.py` after changing a validator).
- ``launch``: every argument bringup and its includes declare is in the catalogue with the
  same kind, choices, defaults and source, and the catalogue has nothing more (`catalogue`).
- ``templates``: every template equals its upstream file semantically, or each difference is
  listed in `reasons.REASONS`; every file of a kind has a template; every template is traced
  (an upstream file at some tag, or `reasons.OWN`). Which template stands for which file:
  `template_pairs` (core/robot/files.py per release, with each release's stock BT projects
  under templates/config/<generation>/<pkg>/behavior_trees, the demo's config tree, the compose
  file of husarion/panther-docker or, 2.2+, husarion_ugv_ros's own
  docker/demo/compose.hardware.yaml).
- ``tree`` (the 2.2+ releases the demo fleet runs): the demo's config tree holds the files
  the image's ``update_config_directory`` copies into ``~/config`` on a Panther.

A release panther-ops does not support yet (husarion_ugv 2.3, `preview`) is checked the same
way against its preview's base release (2.2.2): its catalogue, compose template and config
tree; its default files and configuration templates with its own file-kind rules
(`preview.kinds_stack`); one more item, ``release``, says that panther-ops refuses it.

A result is ok (True), a failure (False) or not checked (None, with the reason: e.g. no
local mirror of the compose file's repository).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from panther_ops.conformance import catalogue
from panther_ops.conformance.digest import Leaves, diff, leaves
from panther_ops.conformance.preview import checked_stack, kinds_stack, preview_for
from panther_ops.conformance.reasons import own, reason_for
from panther_ops.conformance.validate import run_validator
from panther_ops.core.fleet.templates import templates_dir
from panther_ops.core.robot.files import config_files, family_dirs
from panther_ops.core.stack import Generation, Stack, stack_from_version
from panther_ops.errors import OpsError

TREE_TEMPLATE = "config-tree/husarion-ugv-2.2"
PROXY_KINDS = frozenset({"controller", "wheel", "components", "shutdown-hosts", "battery", "joy2twist"})
"""Kinds whose validator reads only the file: an equal template stands for upstream's file."""


@dataclass(frozen=True)
class Result:
    """One item of a check: ``ok`` True (conforms), False (does not), None (not checked: ``summary`` says why)."""

    tag: str
    check: str
    item: str
    ok: bool | None
    summary: str
    details: tuple[str, ...] = ()

    @property
    def failed(self) -> bool:
        return self.ok is False

    @property
    def id(self) -> str:
        return f"{self.tag}:{self.check}:{self.item}"


@dataclass(frozen=True)
class Pair:
    """A template and the upstream file it stands for (None: no such file at this tag)."""

    template: str | None
    upstream: str | None
    note: str = ""


def load_tables(directory: Path) -> list[dict[str, Any]]:
    """Every release table in ``directory``, oldest release first."""
    tables = [json.loads(p.read_text(encoding="utf-8")) for p in directory.glob("*.json")]
    return sorted(tables, key=lambda t: tuple(int(x) for x in t["tag"].split(".")))


def _template_leaves(template: str) -> tuple[str, Leaves] | None:
    path = templates_dir() / template
    if not path.is_file():
        return None
    return leaves(path.name, path.read_bytes())


def template_pairs(table: Mapping[str, Any], stack: Stack, base: Stack | None = None) -> list[Pair]:
    """Which template stands for which upstream file at this release (see the module docstring):
    the configuration files of ``stack``, the demo tree and compose file of ``base`` (a preview
    release's base, `preview.checked_stack`; None: ``stack``)."""
    base = base or stack
    pkgs: Mapping[str, str] = table["packages"]
    present = {f["path"] for f in table["files"]}
    pairs: list[Pair] = []
    for cf in config_files(stack, robot_model="panther"):
        upstream = f"{pkgs.get(cf.package, cf.package)}/config/{cf.filename}"
        pairs.append(Pair(None if cf.template is None else f"config/{cf.template}",
                          upstream if upstream in present else None, cf.note))
    paired = {p.template for p in pairs}
    covered = {p.upstream for p in pairs if p.upstream}  # an overlay's file shadows the base's: first wins
    for directory in family_dirs(stack):  # the release's other files (what `config pull` hands out by path)
        root = templates_dir() / "config" / directory
        for path in sorted(q for q in root.rglob("*") if q.is_file() and q.suffix in (".yaml", ".xml", ".btproj")):
            rel = path.relative_to(root).as_posix()
            template = f"config/{directory}/{rel}"
            package, _, rest = rel.partition("/")
            upstream = f"{pkgs.get(package, package)}/{rest}"
            if template not in paired and upstream in present and upstream not in covered:
                pairs.append(Pair(template, upstream))
                paired.add(template)
                covered.add(upstream)
    if table.get("tree") and base.version_str in demo_tags():
        root = templates_dir() / TREE_TEMPLATE
        for path in sorted(p for p in root.rglob("*") if p.is_file()):
            rel = path.relative_to(root).as_posix()
            package, _, rest = rel.partition("/")
            upstream = f"{pkgs.get(package, package)}/{rest}"
            pairs.append(Pair(f"{TREE_TEMPLATE}/{rel}", upstream if upstream in present else None))
    compose = table.get("compose")
    for path in sorted((templates_dir() / "compose").glob("*.yaml")):
        if path.stem.rsplit("-", 1)[-1] == base.version_str:
            if compose:
                pairs.append(Pair(f"compose/{path.name}", f"{compose['repo']}@{compose['commit'][:12]}:"
                                                          f"{compose['path']}"))
            else:
                pairs.append(Pair(f"compose/{path.name}", None,
                                  "a robot's compose file comes from husarion/panther-docker's demo/compose."
                                  "minimal-setup.yaml (2.0-2.1) or husarion_ugv_ros's docker/demo/compose."
                                  "hardware.yaml (2.2+); this table has no digest of it (scripts/conformance.py "
                                  "--docker-repo, or a --repo whose tag holds the latter)"))
    return pairs


def check_release(table: Mapping[str, Any]) -> list[Result]:
    """Every check of one release table."""
    tag = table["tag"]
    try:
        stack = checked_stack(tag)
    except (OpsError, ValueError) as exc:
        return [Result(tag, "release", tag, False, f"panther-ops does not support {tag}: {exc}")]
    own_stack = kinds_stack(tag)  # a preview release's files: its own kind rules
    pairs = template_pairs(table, own_stack, stack)
    results = [*default_results(table, own_stack, pairs), *launch_results(table, stack),
               *template_results(table, pairs), *tree_results(table)]
    preview = preview_for(tag)
    if preview is None:
        return results
    refused = f"panther-ops refuses {preview.distro} {tag} (core/stack.py parse_image)"
    return [Result(tag, "release", tag, False,
                   f"{refused}: {preview.issue}; its default files and configuration templates are checked "
                   f"with its own file-kind rules, the other items as on {preview.base}, the release "
                   f"panther-ops supports nearest to it"), *results]


def default_results(table: Mapping[str, Any], stack: Stack, pairs: list[Pair]) -> list[Result]:
    out: list[Result] = []
    tag = table["tag"]
    for row in table["files"]:
        if "kind" not in row:
            continue
        verdict: Mapping[str, Any] = row["verdict"]
        how = f"recorded by scripts/conformance.py from {table['repo']}@{table['commit'][:12]}"
        equal = [p.template for p in pairs if p.upstream == row["path"] and p.template
                 and _template_leaves(p.template) == (row["format"], _leaves(row))]
        if equal and row["kind"] in PROXY_KINDS:
            template = equal[0]
            data = (templates_dir() / template).read_bytes()
            verdict = run_validator(tag, row["kind"], row["path"], data, None,
                                    row["robot"]["wheel_type"], row["robot"]["robot_model"])
            how = f"run now on templates/{template} (semantically equal)"
        accepted = verdict["accepted"]
        robot = row["robot"]["robot_model"] + (f" {row['robot']['wheel_type']}" if row["robot"]["wheel_type"] else "")
        on = tag if stack.version_str == tag else f"{stack.version_str} (today's validator; {tag}'s file)"
        summary = ("accepted" if accepted else "refused" if accepted is False else "not run") + \
            f" as {row['kind']} on a {robot} {on} ({how})"
        details = tuple(verdict["errors"]) if not accepted else tuple(verdict.get("warnings", ()))
        out.append(Result(tag, "defaults", row["path"], bool(accepted), summary, details))
    return out


def _leaves(row: Mapping[str, Any]) -> Leaves:
    """A table's leaves (``"path": "type:hash"``) as `digest.Leaves`."""
    return {k: (v.rpartition(":")[0], v.rpartition(":")[2]) for k, v in row["leaves"].items()}


def launch_results(table: Mapping[str, Any], stack: Stack) -> list[Result]:
    tag = table["tag"]
    rows = {r["name"]: r for r in table["launch"]["args"]}
    ours = catalogue.declared(stack)
    out: list[Result] = []
    for name, row in rows.items():
        where = ", ".join(row["declared_in"])
        spec = ours.get(name)
        if spec is None:
            out.append(Result(tag, "launch", name, False, f"declared by {where}; not in the catalogue",
                              (f"upstream: {_row_text(row)}",)))
            continue
        problems = catalogue.compare(row, spec, stack)
        notes = tuple(f"note: also declared by {o['file']} with default {o['default']['image']!r}"
                      for o in row.get("other_defaults", []))
        out.append(Result(tag, "launch", name, not problems,
                          f"{'equal to' if not problems else 'differs from'} {where}", (*problems, *notes)))
    for name, spec in ours.items():
        if name not in rows:
            out.append(Result(tag, "launch", name, False,
                              f"in the catalogue ({spec.key}, {spec.availability()}); not declared by {tag}'s bringup "
                              "or its includes"))
    return out


def _row_text(row: Mapping[str, Any]) -> str:
    choices = f" choices {row['choices']}" if row.get("choices") else ""
    return f"{row['kind']}{choices}, default {row['default']['image']!r} ({row['source']})"


def _compared(table: Mapping[str, Any], pair: Pair) -> tuple[str, Leaves, tuple[str, Leaves] | None]:
    """(upstream format, upstream leaves, the template's format and leaves or None if it is missing)."""
    assert pair.template is not None and pair.upstream is not None
    path = templates_dir() / pair.template
    compose = table.get("compose")
    if pair.template.startswith("compose/") and compose:
        from panther_ops.conformance.digest import compose_leaves

        ours = ("yaml", compose_leaves(path.read_bytes())) if path.is_file() else None
        return "yaml", _leaves(compose), ours
    row = next(f for f in table["files"] if f["path"] == pair.upstream)
    return row["format"], _leaves(row), _template_leaves(pair.template)


def template_results(table: Mapping[str, Any], pairs: Iterable[Pair]) -> list[Result]:
    tag = table["tag"]
    out: list[Result] = []
    covered: set[str] = set()
    for pair in pairs:
        if pair.upstream:
            covered.add(pair.upstream)
        if pair.template is None:
            if pair.upstream is None:
                continue
            why = reason_for(tag, pair.upstream, "(no template)")
            out.append(Result(tag, "templates", f"(none) -> {pair.upstream}", why is not None,
                              f"no template of {pair.upstream}" + (f": {why}" if why else ""),
                              (pair.note,) if pair.note else ()))
            continue
        if pair.upstream is None:
            mine = own(pair.template)
            if mine:
                out.append(Result(tag, "templates", pair.template, True, f"panther-ops' own: {mine}"))
            elif pair.note:
                out.append(Result(tag, "templates", pair.template, None, pair.note))
            else:
                out.append(Result(tag, "templates", pair.template, False, f"no upstream counterpart at {tag}"))
            continue
        fmt, upstream, ours = _compared(table, pair)
        if ours is None:
            out.append(Result(tag, "templates", pair.template, False, "the template file is missing"))
            continue
        if ours[0] != fmt:
            out.append(Result(tag, "templates", pair.template, False,
                              f"{pair.upstream}: format {fmt}, template {ours[0]}"))
            continue
        differences = diff(upstream, ours[1])
        unexplained = [d for d in differences if reason_for(tag, pair.template, d.path) is None]
        explained = [f"{d.line()}: {reason_for(tag, pair.template, d.path)}" for d in differences
                     if d not in unexplained]
        summary = (f"equal to {pair.upstream}" if not differences else
                   f"{len(differences)} difference(s) from {pair.upstream}, {len(unexplained)} without a reason")
        out.append(Result(tag, "templates", pair.template, not unexplained, summary,
                          (*(d.line() for d in unexplained), *explained)))
    for row in table["files"]:
        if "kind" in row and row["path"] not in covered:
            why = reason_for(tag, row["path"], "(no template)")
            out.append(Result(tag, "templates", f"(none) -> {row['path']}", why is not None,
                              f"no template of {row['path']} ({row['kind']})" + (f": {why}" if why else "")))
    return out


def demo_tags() -> set[str]:
    """The releases of the demo fleet's robots whose config tree is templates/config-tree (2.2+)."""
    from panther_ops.core.demo.fleet import DEMO_ROBOTS

    return {r.compose_template.removesuffix(".yaml").rsplit("-", 1)[-1] for r in DEMO_ROBOTS
            if r.compose_template.startswith("husarion-ugv")}


def tree_results(table: Mapping[str, Any]) -> list[Result]:
    """The demo's ~/config tree against the files the image copies (the demo's 2.2+ releases)."""
    tree = table.get("tree")
    try:
        checked = checked_stack(table["tag"]).version_str
    except (OpsError, ValueError):
        return []
    if not tree or checked not in demo_tags():
        return []
    root = templates_dir() / TREE_TEMPLATE
    ours = {p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file()}
    ours = {p for p in ours if not own(f"{TREE_TEMPLATE}/{p}")}
    upstream = set(tree["panther"])
    missing, extra = sorted(upstream - ours), sorted(ours - upstream)
    details = (*(f"missing: {p}" for p in missing), *(f"not copied by the image: {p}" for p in extra))
    summary = (f"templates/{TREE_TEMPLATE} holds the {len(upstream)} files {tree['script']} copies for a Panther"
               if not details else f"templates/{TREE_TEMPLATE}: {len(missing)} missing, {len(extra)} extra "
               f"(against {tree['script']}, Panther)")
    return [Result(table["tag"], "tree", "panther", not details, summary, details)]


def untraced_templates(tables: Iterable[Mapping[str, Any]]) -> list[Result]:
    """Templates no release's pairs name and `reasons.OWN` does not list."""
    traced: set[str] = set()
    for table in tables:
        try:
            stack, base = kinds_stack(table["tag"]), checked_stack(table["tag"])
        except (OpsError, ValueError):
            continue
        traced.update(p.template for p in template_pairs(table, stack, base) if p.template)
    used = _used_by_generation()
    root = templates_dir()
    out: list[Result] = []
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        rel = path.relative_to(root).as_posix()
        if rel in traced or own(rel):
            continue
        if rel in used:
            out.append(Result("all", "templates", rel, None,
                              f"used on panther-ops' stack generation {used[rel]} only, "
                              "and no release table covers it"))
        else:
            out.append(Result("all", "templates", rel, False,
                              "not traced: no release table names this file, and reasons.OWN does not list it"))
    return out


def _used_by_generation() -> dict[str, str]:
    """Template (under templates/) -> the first stack generation whose config files use it."""
    out: dict[str, str] = {}
    for generation in Generation:
        first = generation.value.split("-")[0].rstrip("+")
        for model in ("panther", "lynx"):
            for cf in config_files(stack_from_version(first), robot_model=model):
                if cf.template:
                    out.setdefault(f"config/{cf.template}", generation.value)
    return out
