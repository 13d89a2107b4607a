"""The conformance failures known today, each tied to the finding of issue #24 that fixes it.

A key is an ``fnmatch`` pattern over a result's id (``<tag>:<check>:<item>``). The report
marks a failure with its finding; tests/conformance/test_conformance.py expects these items to fail
(``xfail(strict=True)``), so the test of an item turns red the day a fix makes it pass:
then delete its line here (and re-run scripts/conformance.py if the fix changed a
validator, so the recorded verdicts follow).

``new`` entries are failures the conformance tool found that issue #24 does not list.
``issue #25`` entries are the items of husarion_ugv 2.3 (Jazzy) that the validators and config
templates, still 2.2's, fail on: the to-do list of issue #25.
"""

from __future__ import annotations

from fnmatch import fnmatchcase

FINDINGS: dict[str, str] = {
    "finding 1": "husarion_ugv 2.2's own files are refused",
    "finding 2": "controller templates lack the IMU's namespace prefix",
    "finding 3": "where 2.2 reads a default from (image or ~/config tree) is wrong in the catalogue",
    "finding 4": "2.1.1's NMEA launch arguments are missing from the catalogue",
    "finding 5": "templates that are not upstream's, or missing",
    "finding 8": "simulation files",
    "finding 9": "config pull joy2twist has no default to give",
    "new": "found by the conformance tool; not in issue #24's list",
    "issue #25": "husarion_ugv 2.3 (ROS 2 Jazzy): the stack, catalogue and compose templates are 2.3's; what "
                 "the validators and config templates (still 2.2's) say of 2.3's files (docs/jazzy.md)",
}
"""Label -> what it is: the findings of issue #24 that known failures belong to."""

KNOWN: dict[str, tuple[str, str]] = {
}
"""Result id pattern -> (label in `FINDINGS`, what in particular)."""


def known(result_id: str) -> tuple[str, str] | None:
    """The label and note of a failing result, or None (not known: a regression or a new finding)."""
    for pattern, entry in KNOWN.items():
        if fnmatchcase(result_id, pattern):
            return entry
    return None
