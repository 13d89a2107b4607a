#!/usr/bin/env python3
"""Check panther-ops against Husarion's releases (docs/conformance.md).

Given local git mirrors of the upstream repositories and release tags, distil each release
into its table (tests/golden/upstream/<tag>.json: launch arguments, digests of the default
files, the validators' verdicts, the config tree), then run the checks of
panther_ops/conformance/checks.py and write the report. Without --repo, the checks run
from the committed tables alone (what the unit tests do).

Examples:
  python scripts/conformance.py --repo /work/.mirror/husarion+husarion_ugv_ros/repo --tag 2.2.2 --summary
  python scripts/conformance.py --repo PANTHER_ROS --repo HUSARION_UGV_ROS --tag 2.0.4 --tag 2.1.1 \\
      --tag 2.2.0 --tag 2.2.2 --tables tests/golden/upstream --report docs/conformance.md
  python scripts/conformance.py --report docs/conformance.md      # from the committed tables

Exit status: 0 when every check passes or fails only where panther_ops/conformance/known.py
says it does (with --strict: every check passes), 1 when an item fails that is not known,
2 on bad usage (a tag no --repo has, an unreadable mirror).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from panther_ops.conformance.checks import check_release, load_tables, untraced_templates  # noqa: E402
from panther_ops.conformance.known import known  # noqa: E402
from panther_ops.conformance.report import render, summary  # noqa: E402
from panther_ops.conformance.upstream import GitRelease, UpstreamError  # noqa: E402

DEFAULT_TABLES = ROOT / "tests" / "golden" / "upstream"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/conformance.py",
        description="Check panther-ops (file validators, launch-argument catalogue, templates) against "
                    "Husarion's releases, read from local git mirrors; write the release tables and "
                    "docs/conformance.md.",
        epilog="Without --repo the checks run from the tables in --tables (no mirror needed). Exit status: 0 when "
               "every item passes or fails as panther_ops/conformance/known.py says; 1 when an item fails that "
               "known.py does not list (or any failure, with --strict); 2 on bad usage (a tag no --repo has).",
    )
    parser.add_argument("--repo", action="append", default=[], type=Path, metavar="GIT_DIR",
                        help="a local git mirror of husarion/panther_ros or husarion/husarion_ugv_ros "
                             "(bare or not); repeatable: each --tag is read from the first that has it")
    parser.add_argument("--tag", action="append", default=[], metavar="TAG",
                        help="a release tag to distil (e.g. 2.2.2); repeatable; needs --repo")
    parser.add_argument("--docker-repo", action="append", default=[], type=Path, metavar="GIT_DIR",
                        help="a local git mirror of husarion/panther-docker: a tag it has adds the digest of "
                             "its demo/compose.minimal-setup.yaml to the table (templates/compose is compared "
                             "with it); repeatable. A release that holds its own docker/demo/compose.hardware.yaml "
                             "(husarion_ugv_ros 2.2+) is compared with that one when no --docker-repo has the tag")
    parser.add_argument("--repo-name", metavar="OWNER/NAME",
                        help="the repository's name in the tables (default: from a mirror laid out as "
                             ".../OWNER+NAME/repo)")
    parser.add_argument("--tables", type=Path, default=DEFAULT_TABLES, metavar="DIR",
                        help="where the release tables are written and read "
                             f"(default: {DEFAULT_TABLES.relative_to(ROOT)})")
    parser.add_argument("--no-write", action="store_true",
                        help="distil the tags but do not write their tables (check them in memory)")
    parser.add_argument("--report", type=Path, metavar="FILE", help="write the markdown report here")
    parser.add_argument("--summary", action="store_true", help="print one line per release and check")
    parser.add_argument("--strict", action="store_true", help="exit 1 on any failing item, known or not")
    return parser


def _release(repos: list[Path], tag: str) -> GitRelease:
    for repo in repos:
        release = GitRelease(repo, tag)
        try:
            release.commit  # noqa: B018 - resolves the tag
        except UpstreamError:
            continue
        return release
    raise UpstreamError(f"tag {tag} is in none of: {', '.join(map(str, repos)) or '(no --repo given)'}")


def _has(repos: list[Path], tag: str) -> bool:
    try:
        _release(repos, tag)
    except UpstreamError:
        return False
    return True


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.tag and not args.repo:
        print("scripts/conformance.py: --tag needs --repo (a local git mirror)", file=sys.stderr)
        return 2
    from panther_ops.conformance.distil import distil, distil_compose, own_compose

    fresh = {}
    for tag in args.tag:
        try:
            release = _release(args.repo, tag)
            table = distil(release, repo=args.repo_name)
            docker = _release(args.docker_repo, tag) if _has(args.docker_repo, tag) else None
            compose = distil_compose(docker) if docker is not None else own_compose(release, repo=args.repo_name)
            if compose is not None:
                table["compose"] = compose
        except UpstreamError as exc:
            print(f"scripts/conformance.py: {exc}", file=sys.stderr)
            return 2
        fresh[tag] = table
        if not args.no_write:
            args.tables.mkdir(parents=True, exist_ok=True)
            path = args.tables / f"{tag}.json"
            path.write_text(json.dumps(table, indent=1, sort_keys=False) + "\n", encoding="utf-8")
            print(f"wrote {path} ({table['repo']}@{table['commit']})", file=sys.stderr)
    tables = {t["tag"]: t for t in (load_tables(args.tables) if args.tables.is_dir() else [])}
    tables.update(fresh)
    ordered = sorted(tables.values(), key=lambda t: tuple(int(x) for x in t["tag"].split(".")))
    results = [r for t in ordered for r in check_release(t)] + untraced_templates(ordered)
    if args.report:
        args.report.write_text(render(ordered, results), encoding="utf-8")
        print(f"wrote {args.report}", file=sys.stderr)
    if args.summary or not args.report:
        print("\n".join(summary(results)))
    failing = [r for r in results if r.failed]
    unknown = [r for r in failing if known(r.id) is None]
    for r in unknown:
        print(f"not known: {r.id}: {r.summary}", file=sys.stderr)
    return 1 if (unknown or (args.strict and failing)) else 0


if __name__ == "__main__":
    sys.exit(main())
