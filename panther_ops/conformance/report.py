"""docs/conformance.md: the checks' results per release, rendered from the tables and the project."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from panther_ops.conformance.checks import Result
from panther_ops.conformance.known import FINDINGS, known
from panther_ops.conformance.preview import PREVIEWS, preview_for

CHECKS = (("defaults", "upstream default files accepted"), ("launch", "launch arguments equal to the catalogue"),
          ("templates", "templates equal (or explained)"), ("tree", "demo config tree complete"))
MAX_DETAILS = 12

HOW_TO = """\
## How to re-run

The tool reads local git mirrors (no work tree needed: `git show TAG:PATH`), never the network:

```
python scripts/conformance.py \\
    --repo /work/.mirror/husarion+panther_ros/repo \\
    --repo /work/.mirror/husarion+husarion_ugv_ros/repo \\
    --docker-repo /work/.mirror/husarion+panther-docker/repo \\
    --tag 2.0.4 --tag 2.1.1 --tag 2.2.0 --tag 2.2.2 --tag 2.3.0 --tag 2.3.1 --tag 2.3.2 \\
    --tables tests/golden/upstream --report docs/conformance.md
```

Each `--tag` is read from the first `--repo` that has it. The compose templates are
compared with the robot's compose file of the same tag: husarion/panther-docker's
`demo/compose.minimal-setup.yaml` when a `--docker-repo` has the tag (2.0-2.1), else the
release's own `docker/demo/compose.hardware.yaml` (husarion_ugv_ros 2.2+); both are
digested by the same rules. For each tag it parses bringup
and the launch files it includes (`ast`, nothing is run), runs every kind's validator on
the release's default files, writes the release's table `tests/golden/upstream/<tag>.json`
and then this report. `python scripts/conformance.py --report docs/conformance.md` (no
`--repo`) renders the report from the tables alone, as the tests check it; `--summary`
prints one line per check and tag. A new release is one more `--tag` (then its table is
committed and, when panther-ops supports it, its failures fixed or listed in
`panther_ops/conformance/known.py`).

The unit test `tests/conformance/test_conformance.py` runs the same checks from the tables, one
test per item: the known failures below are `xfail(strict=True)`, so a fix turns its test
red until its line in `known.py` is removed.
"""

WHAT = """\
## What is checked

- **Default files**: every upstream file of a kind panther-ops writes (`config push --as`)
  is accepted by that kind's validator for a robot of that release (the wheel type of its
  name; `lynx_*` and WH05 files: a Lynx). The verdict is the one recorded when the table
  was made; where a template equals the upstream file semantically, the validator is run
  again on the template.
- **Launch arguments**: the catalogue (`panther_ops/core/kinds/arg_catalogue.py`) has
  exactly the arguments bringup and the launch files of the same repository it includes
  declare, with their kind (bool, choice, free text), choices, default and where the
  default is read from. Defaults are evaluated with every environment variable unset, in
  three contexts: *image* (no `common_dir_path`), *tree* (`common_dir_path:=/config`, the
  2.2 robot's `~/config`), *variant* (tree, `wheel_type=WH02`, `robot_model=lynx`,
  `localization_mode=enu`, `fuse_gps=True`).
- **Templates**: every template under `templates/` equals the upstream file it stands for
  (`panther_ops/core/robot/files.py` per release; each release's stock BT projects under
  `templates/config/<generation>/<pkg>/behavior_trees`; the demo's 2.2 config tree)
  semantically: the same keys, the same values and types (`2` and `2.0` differ), or each difference has a reason in
  `panther_ops/conformance/reasons.py`. Every file of a kind has a template. A template with
  no upstream counterpart is listed there as panther-ops' own. The compose templates are
  compared with husarion/panther-docker's `demo/compose.minimal-setup.yaml` (2.0-2.1) or
  husarion_ugv_ros's own `docker/demo/compose.hardware.yaml` (2.2+) at the same tag (lists
  of volumes, devices... as sets; white space in strings collapsed).
- **Config tree**: the demo's `templates/config-tree/husarion-ugv-2.2` holds the files the
  image's `update_config_directory` copies into `~/config` on a Panther.

Not covered: a compose template of 2.2.0 (panther-ops has none: its table holds the digest
of 2.2.0's `docker/demo/compose.hardware.yaml`, for a template to come), the 2.2 manager's
parameter files
(`husarion_ugv_manager/config/*_manager.yaml`: panther-ops has no kind or template for them),
the snap's hooks and the lab stand-ins.
"""


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _status(result: Result) -> str:
    if result.ok:
        return "ok"
    if result.ok is None:
        return "not checked"
    entry = known(result.id)
    if entry is None:
        return "**FAIL** (not known)"
    label, note = entry
    return f"**FAIL** ({label}{': ' + note if note else ''})"


def _details(results: Sequence[Result]) -> list[str]:
    lines: list[str] = []
    for r in results:
        if not r.failed or not r.details:
            continue
        shown = list(r.details[:MAX_DETAILS])
        more = len(r.details) - len(shown)
        lines.append(f"- `{r.item}`: " + "; ".join(f"`{_cell(d)}`" if len(d) < 160 else _cell(d) for d in shown)
                     + (f"; and {more} more" if more else ""))
    return lines


def _count(results: Sequence[Result], check: str) -> str:
    mine = [r for r in results if r.check == check]
    checked = [r for r in mine if r.ok is not None]
    if not mine:
        return "-"
    skipped = len(mine) - len(checked)
    return f"{sum(bool(r.ok) for r in checked)}/{len(checked)}" + (f" ({skipped} not checked)" if skipped else "")


def _overview(tables: Sequence[Mapping[str, Any]], results: Sequence[Result]) -> list[str]:
    out = ["| release | repository@commit | " + " | ".join(title for _, title in CHECKS) + " |",
           "|---|---|" + "---|" * len(CHECKS)]
    for table in tables:
        mine = [r for r in results if r.tag == table["tag"]]
        out.append(f"| {table['tag']} | {table['repo']}@`{table['commit']}` | "
                   + " | ".join(_count(mine, c) for c, _ in CHECKS) + " |")
    return out


def render(tables: Sequence[Mapping[str, Any]], results: Sequence[Result]) -> str:
    """The whole report (the releases panther-ops does not support yet in a section of their own)."""
    later = [t for t in tables if preview_for(t["tag"]) is not None]
    tables = [t for t in tables if preview_for(t["tag"]) is None]
    out = ["# Conformance with Husarion's releases", "",
           "Generated by `scripts/conformance.py` from the release tables in `tests/golden/upstream/` "
           "and the project's code and templates; do not edit by hand.", "",
           *_overview(tables, results)]
    every = [r for r in results if r.tag == "all"]
    if every:
        out.append(f"| (all) | every template traced to a release | | | {_count(every, 'templates')} | |")
    out += ["", "Counts are items ok / items checked. A failure names the finding of issue #24 that fixes it "
            "(or, for a release not supported yet, the issue that adds it) "
            "(`panther_ops/conformance/known.py`):", ""]
    out += [f"- **{label}**: {text}" for label, text in FINDINGS.items()]
    out += ["", HOW_TO, WHAT]
    for table in tables:
        out += _release(table, [r for r in results if r.tag == table["tag"]])
    if every:
        out += ["## Templates no release table traces", "", "| template | result |", "|---|---|"]
        out += [f"| `{r.item}` | {_status(r)}: {_cell(r.summary)} |" for r in every]
        out.append("")
    for preview in PREVIEWS:
        mine = [t for t in later if preview_for(t["tag"]) == preview]
        if mine:
            out += _not_yet(preview.issue, preview.title, preview.base, mine, results)
    return "\n".join(out).rstrip() + "\n"


def _not_yet(issue: str, title: str, base: str, tables: Sequence[Mapping[str, Any]],
             results: Sequence[Result]) -> list[str]:
    out = [f"## Not yet supported ({issue})", "",
           f"{title}: panther-ops refuses these releases today. Their default files and configuration "
           f"templates are checked with each release's own file-kind rules (the validators and "
           f"templates/config directories that know it); the rest as panther-ops reads {base}, the release "
           f"it supports nearest to them: {base}'s launch-argument catalogue against their bringup, {base}'s "
           f"compose template and the demo's {base} config tree against their files. Each failing item is a to-do of "
           f"{issue}, listed in `panther_ops/conformance/known.py` under that label (`xfail(strict=True)` "
           "in the tests: an item that passes once the release is supported turns red until its line is "
           "removed); `docs/jazzy.md` says what changed and how each file maps.", "",
           *_overview(tables, results), ""]
    for table in tables:
        out += _release(table, [r for r in results if r.tag == table["tag"]], level=3)
    return out


def _release(table: Mapping[str, Any], results: Sequence[Result], level: int = 2) -> list[str]:
    tag = table["tag"]
    h, sub = "#" * level, "#" * (level + 1)
    out = [f"{h} {tag}", "", f"{table['repo']}@`{table['commit']}` (tag {tag}); table "
           f"`tests/golden/upstream/{tag}.json`.", ""]
    refusals = [r for r in results if r.check == "release"]
    if refusals and len(refusals) == len(results):
        return out + [f"- {_status(r)}: {r.summary}" for r in results] + [""]
    out += [f"- {_status(r)}: {r.summary}" for r in refusals] + ([""] if refusals else [])
    launch = table["launch"]
    out += [f"{sub} Default files", "", "| file | result |", "|---|---|"]
    defaults = [r for r in results if r.check == "defaults"]
    out += [f"| `{r.item}` | {_status(r)}: {_cell(r.summary)} |" for r in defaults]
    out += ["", *_details(defaults), ""]
    args = {a["name"]: a for a in launch["args"]}
    out += [f"{sub} Launch arguments", "",
            f"Read from `{launch['entry']}` and its includes: " + ", ".join(f"`{f}`" for f in launch["files"][1:])
            + (". Not followed (other repositories): " + ", ".join(f"`{e}`" for e in launch["external"])
               if launch["external"] else "") + ".", "",
            "| argument | kind | default (image) | default (tree) | read from | catalogue |",
            "|---|---|---|---|---|---|"]
    lresults = [r for r in results if r.check == "launch"]
    for r in lresults:
        row = args.get(r.item)
        if row is None:
            out.append(f"| `{r.item}` | | | | | {_status(r)}: {_cell(r.summary)} |")
            continue
        kind = row["kind"] + (f" ({', '.join(row['choices'])})" if row["kind"] == "choice" and row["choices"] else "")
        out.append(f"| `{r.item}` | {kind} | `{row['default']['image']}` | `{row['default']['tree']}` | "
                   f"{row['source']} | {_status(r)} |")
    out += ["", *_details(lresults)]
    notes = [f"- `{a['name']}`: also declared by `{o['file']}`, default `{o['default']['image']}`"
             for a in launch["args"] for o in a.get("other_defaults", [])]
    notes += [f"- {p}" for p in launch.get("problems", [])]
    if notes:
        out += ["", "Notes:", "", *notes]
    out += ["", f"{sub} Templates", "", "| template | result |", "|---|---|"]
    tresults = [r for r in results if r.check == "templates"]
    out += [f"| `{r.item}` | {_status(r)}: {_cell(r.summary)} |" for r in tresults]
    out += ["", *_details(tresults), ""]
    tree = [r for r in results if r.check == "tree"]
    if tree:
        out += [f"{sub} Config tree", ""]
        out += [f"- {_status(r)}: {r.summary}" for r in tree]
        out += [*_details(tree), ""]
    return out


def summary(results: Sequence[Result]) -> list[str]:
    """One line per tag and check: ok/total and the failing items."""
    lines: list[str] = []
    for tag in dict.fromkeys(r.tag for r in results):
        for check in dict.fromkeys(r.check for r in results if r.tag == tag):
            mine = [r for r in results if r.tag == tag and r.check == check]
            bad = [r for r in mine if r.failed]
            skipped = sum(r.ok is None for r in mine)
            lines.append(f"{tag} {check}: {len(mine) - len(bad) - skipped}/{len(mine) - skipped} ok"
                         + (f", {skipped} not checked" if skipped else "")
                         + "".join(f"\n  FAIL {r.item}: {r.summary}" + ("" if known(r.id) else " [NOT KNOWN]")
                                   for r in bad))
    return lines
