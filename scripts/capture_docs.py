#!/usr/bin/env python3
"""Re-capture every console sample of docs/*.md and README.md from a real run.

Each ``$ panther-ops ...`` line of a ```console block (and the shell lines beside it) is run
as a reader runs it: on a fresh demo fleet, in a temporary directory shown as ``/home/me``, on
an 80-column terminal with NO_COLOR=1, the samples of a page in the page's order
(tests/ux/docsamples.py says exactly how, and what is normalised before comparing: backup ids,
dates, fingerprints, durations, clock offsets, sizes). A sample whose output differs is
rewritten in place with what the terminal showed.

Not run, and listed with the reason: blocks marked ```console lab, and commands that need a
robot reached over SSH (tests/ux/examples.py: NEEDS_A_ROBOT).

With --lab (as root), the samples of the ```console lab blocks instead: per page, a lab of
simulated robots of the docs' shape is brought up (tests/ux/doclab.py: r01..r05, real sshd,
dockerd and Compose v2; docs/lab.md; or the page's own shape, e.g. shutdown.md's robots with
User Computers on their LANs), the page's lab samples run on it in order with the same
normalisation (the lab's addresses shown as on an idle machine, a password prompt answered with
the lab's password, a teleop's keys typed), and it is torn down. A block marked ``scene=NAME``
first has the lab brought into the state its text describes (tests/ux/doclab.py: SCENES). Not
run, and listed: blocks marked ```console lab-standin, lab samples that need more (Docker Hub, a
card reader), and the pages and samples of docsamples.LAB_PAGES_NOT_YET and NOT_YET_IN_LAB (with
the reason each).

Examples:
  python scripts/capture_docs.py                     # rewrite the samples that differ
  python scripts/capture_docs.py --check             # exit 1 and a diff when one differs
  python scripts/capture_docs.py --check docs/commands.md --list
  sudo python scripts/capture_docs.py --lab docs/driver.md   # the lab samples of one page

Exit status: 0 when every run sample matches (or was rewritten), 1 with --check when one
differs, 2 on bad usage.
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.ux.docsamples import docs, follow, lab_docs  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("docs", nargs="*", type=Path, help="Docs to capture (default: every doc with a sample).")
    parser.add_argument("--check", action="store_true", help="Change nothing: exit 1 and a diff when a sample differs.")
    parser.add_argument("--list", action="store_true", help="List the samples not run, with the reason.")
    parser.add_argument("--jobs", type=int, default=2, help="Docs followed at once (default 2; 1 with --lab).")
    parser.add_argument("--lab", action="store_true",
                        help="Run the ```console lab samples on a lab per page (root; docs/lab.md).")
    args = parser.parse_args(argv)
    known = lab_docs() if args.lab else docs()
    chosen = [p.resolve() for p in args.docs] or (lab_docs(run=True) if args.lab else known)
    for p in chosen:
        if p not in known:
            parser.error(f"{p}: not a doc with a console {'lab ' if args.lab else ''}sample (docs/*.md, README.md)")
    if args.lab:
        from tests.ux.doclab import follow_on_lab, lab_unavailable

        if (why := lab_unavailable()) is not None:
            parser.error(f"--lab: the lab cannot run here: {why}")
        outcomes = [follow_on_lab(doc) for doc in chosen]
    else:
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            outcomes = list(pool.map(follow, chosen))
    differ = 0
    for outcome in outcomes:
        rel = outcome.doc.relative_to(ROOT)
        for diff in outcome.diffs:
            sys.stdout.write(diff)
        if outcome.diffs:
            differ += len(outcome.diffs)
            if not args.check:
                outcome.doc.write_text(outcome.text)
                print(f"{rel}: {len(outcome.diffs)} sample(s) re-captured", file=sys.stderr)
        if args.list:
            for where, command, reason in outcome.skipped:
                print(f"not run {where}: $ {command}\n  {reason}", file=sys.stderr)
    skipped = sum(len(o.skipped) for o in outcomes)
    print(f"{len(outcomes)} docs: {differ} sample(s) {'differ' if args.check else 're-captured'}, "
          f"{skipped} not run (--list says why)", file=sys.stderr)
    return 1 if args.check and differ else 0


if __name__ == "__main__":
    sys.exit(main())
