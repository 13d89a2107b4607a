"""Every ```console lab sample of docs/ shows what a run on the lab shows (issue 26, finding 7):
each page's lab samples re-run in the page's order on a lab of their own (tests/ux/doclab.py:
r01..r05, real sshd, dockerd and Compose v2) by scripts/capture_docs.py's code and compared;
a difference fails with its diff (re-capture with ``sudo python scripts/capture_docs.py --lab``).
Needs root (a lab): skipped without, failed under CI=true (tests/conftest.py)."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from .doclab import follow_on_lab
from .docsamples import LAB, LAB_PAGES_NOT_YET, LAB_STANDIN, NOT_YET_IN_LAB, lab_docs, skip_reasons
from .examples import ROOT, console_blocks

DOCS = lab_docs(run=True)


@pytest.mark.parametrize("doc", DOCS, ids=[str(d.relative_to(ROOT)) for d in DOCS])
def test_every_lab_sample_of_the_doc_is_what_the_lab_shows(doc: Path, lab_ready: None) -> None:
    from tests.conftest import skip_or_fail

    from .doclab import lab_unavailable

    if (why := lab_unavailable()) is not None:
        skip_or_fail(why)
    started = time.monotonic()
    outcome = follow_on_lab(doc)
    print(f"{doc.name}: {time.monotonic() - started:.1f} s")
    assert not outcome.diffs, "".join(outcome.diffs) + "\nre-capture: sudo python scripts/capture_docs.py --lab " + \
        str(doc.relative_to(ROOT))


def test_most_lab_samples_run_and_the_rest_say_why() -> None:
    """Not vacuous: on the pages whose lab samples run, 25 or more do; every one that does not says
    why, and the exceptions listed are samples of the docs (a list that does not rot)."""
    blocks = [b for d in DOCS for b in console_blocks(d) if LAB in b.marks or LAB_STANDIN in b.marks]
    reasons = [r for b in blocks for s, r in zip(b.samples, skip_reasons(b, in_lab=True), strict=True)
               if s.example is not None]
    run = [r for r in reasons if r is None]
    assert len(run) >= 25 and len(reasons) - len(run) <= 25, [r for r in reasons if r]
    commands = {(b.doc.name, s.command) for d in lab_docs() for b in console_blocks(d) for s in b.samples}
    assert set(NOT_YET_IN_LAB) <= commands, set(NOT_YET_IN_LAB) - commands
    assert set(LAB_PAGES_NOT_YET) <= {d.name for d in lab_docs()}
