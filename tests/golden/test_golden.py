"""Golden corpus: each case's edit must produce exactly the expected unified diff.

Set PANTHER_OPS_UPDATE_GOLDEN=1 to rewrite the ``expect`` of every case from the current
code (then review the changes with git diff before committing).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
import yaml

from panther_ops.core.yaml.diff import unified_diff
from panther_ops.core.yaml.document import Block, YamlDocument
from tests.golden.golden_ops import CASES, apply_case

CASE_FILES = sorted(CASES.glob("*.yaml"))
UPDATE = os.environ.get("PANTHER_OPS_UPDATE_GOLDEN") == "1"


def _comments(text: str) -> list[str]:
    return sorted(m.group(0).strip() for m in re.finditer(r"(?:^|\s)#[^\n]*", text))


@pytest.mark.parametrize("case_file", CASE_FILES, ids=[p.stem for p in CASE_FILES])
def test_golden_case(case_file: Path) -> None:
    case = yaml.safe_load(case_file.read_text(encoding="utf-8"))
    outcome = apply_case(case)
    diff = unified_diff(outcome.before, outcome.after, case.get("path", case["input"]))
    if UPDATE:
        doc = YamlDocument(case_file.read_text(encoding="utf-8"), str(case_file))
        doc.set("expect", Block(diff))
        case_file.write_text(doc.text, encoding="utf-8")
        return
    assert diff == case["expect"], f"{case_file.name}: {case.get('description', '')}"
    for note in case.get("notes") or []:
        assert any(note in n for n in outcome.notes), f"note {note!r} not in {outcome.notes}"
    # what the diff does not touch is byte-identical; on top of that, nothing is lost:
    removed = [line[1:] for line in diff.splitlines() if line.startswith("-") and not line.startswith("---")]
    before_comments = _comments(outcome.before)
    after_comments = _comments(outcome.after)
    for comment in before_comments:
        if not any(comment in line for line in removed):
            assert comment in after_comments, f"comment lost: {comment}"
    anchors_before = re.findall(r"&[\w-]+", outcome.before)
    assert all(a in outcome.after for a in anchors_before), "an anchor was lost"
    assert outcome.before.count("<<: *") <= outcome.after.count("<<: *") or case.get("removes_merge")
    yaml.safe_load(outcome.after)  # a YAML 1.1 reader still parses the result


def test_corpus_is_large_enough() -> None:
    assert len(CASE_FILES) >= 40
    inputs = {yaml.safe_load(p.read_text())["input"] for p in CASE_FILES}
    assert len(inputs) >= 12
