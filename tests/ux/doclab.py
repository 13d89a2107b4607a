"""The lab a page's ```console lab samples run on (tests/ux/docsamples.py, lab mode): the shape
the docs' samples name (docs/lab.md, "From pytest": 5 robots r01..r05, docker on, stacks
2.0.4 / 2.1.1 / 2.2.2 / 2.0.4 / 2.1.1, r05 reachable only through r01), one fresh lab per page
(a page's samples change its robots in the page's order), torn down after the page."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from tests.lab import Lab, missing_requirements

from .docsamples import Outcome, follow

IMAGES = ("2.0", "2.1.1", "2.2")
JUMPS = {"r05": "r01"}


def lab_unavailable() -> str | None:
    """Why the docs' lab cannot run on this machine (not root, a binary missing), or None."""
    why = missing_requirements(docker=True)
    return "; ".join(why) if why else None


@contextmanager
def page_lab(prefix: str | None = None) -> Iterator[Lab]:
    """A lab of the docs' shape, up for one page, torn down after it."""
    lab = Lab(5, docker=True, images=IMAGES, jumps=JUMPS, prefix=prefix, ephemeral=True)
    lab.up()
    try:
        yield lab
    finally:
        lab.down()


def follow_on_lab(doc: Path, prefix: str | None = None) -> Outcome:
    """The page's lab samples run on a lab of their own (see docsamples.follow)."""
    with page_lab(prefix) as lab:
        return follow(doc, lab.dir)
