"""The harness itself: it catches a change, a wrong exit code and a missing name."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

import pytest

from tests.badinput import test_file_kinds, test_inputs, test_integrity, test_names_paths_hosts, test_upstream_rules
from tests.badinput.harness import Case, check_refused, tree_hashes

CASES = [
    Case("unknown-key", ["config", "set", "no_such_key", "1", "-r", "panther-01", "--yes"], ["no_such_key"]),
    Case("unknown-robot", ["status", "-r", "nobody-*"], ["nobody-*"]),
]


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    check_refused(case, tmp_path, capsys, monkeypatch)


@pytest.mark.parametrize("corpus", [test_file_kinds, test_inputs, test_integrity, test_names_paths_hosts,
                                    test_upstream_rules], ids=lambda m: m.__name__.rsplit(".", 1)[-1])
def test_each_corpus_names_a_case_once(corpus: ModuleType) -> None:
    """A case id given twice would run (pytest tells the two apart) but name two cases alike."""
    assert len({c.id for c in corpus.CASES}) == len(corpus.CASES)


def test_harness_sees_a_write(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                              monkeypatch: pytest.MonkeyPatch) -> None:
    good = Case("good", ["config", "set", "wheel_type", "WH02", "-r", "panther-03", "--yes"], [])
    with pytest.raises(AssertionError, match="exit 0, not 2"):
        check_refused(good, tmp_path, capsys, monkeypatch)


def test_harness_sees_a_missing_name(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                     monkeypatch: pytest.MonkeyPatch) -> None:
    case = Case("unnamed", ["config", "set", "no_such_key", "1", "-r", "panther-01"], ["something else"])
    with pytest.raises(AssertionError, match="not named"):
        check_refused(case, tmp_path, capsys, monkeypatch)


def test_tree_hashes_notice_content_and_mode(tmp_path: Path) -> None:
    (tmp_path / "f").write_text("a")
    first = tree_hashes(tmp_path)
    (tmp_path / "f").write_text("b")
    second = tree_hashes(tmp_path)
    (tmp_path / "f").chmod(0o600)
    assert first != second != tree_hashes(tmp_path)
