"""`config pull --output/--dest`: the files land where asked, written atomically, kept inside
--dest (core/config/pull_files.py, transport/localfile.py)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from panther_ops.core.config.pull_files import LocalWrite, local_writes, write_files
from panther_ops.core.kinds import FileKind
from panther_ops.errors import UsageError


@pytest.fixture()
def demo(tmp_path: Path) -> Path:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"


def test_dest_gets_one_file_per_robot(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dest = tmp_path / "pulled"
    assert main(["-i", str(demo), "config", "pull", "controller", "--all", "--dest", str(dest)]) == 0
    files = sorted(p.relative_to(dest).as_posix() for p in dest.rglob("*") if p.is_file())
    assert files == ["panther-01/controller.yaml", "panther-02/controller.yaml", "panther-03/controller.yaml",
                     "panther-04/controller.yaml"]
    assert capsys.readouterr().out.count("panther-0") >= 3  # the results table, not the files


def test_output_replaces_a_file_keeping_its_mode(demo: Path, tmp_path: Path) -> None:
    out = tmp_path / "controller.yaml"
    out.write_text("old\n")
    out.chmod(0o640)
    assert main(["-i", str(demo), "config", "pull", "controller", "-r", "panther-01", "-o", str(out)]) == 0
    assert out.read_text() != "old\n" and out.stat().st_mode & 0o777 == 0o640
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temporary file left


def test_a_new_file_gets_the_umask_mode(tmp_path: Path) -> None:
    old = os.umask(0o027)
    try:
        write_files([LocalWrite(tmp_path / "d" / "x.yaml", b"x: 1\n")])
    finally:
        os.umask(old)
    assert (tmp_path / "d" / "x.yaml").stat().st_mode & 0o777 == 0o640


def test_a_robot_directory_leading_out_of_dest_is_refused(tmp_path: Path) -> None:
    dest, elsewhere = tmp_path / "dest", tmp_path / "elsewhere"
    dest.mkdir()
    elsewhere.mkdir()
    (dest / "panther-01").symlink_to(elsewhere)
    with pytest.raises(UsageError, match="leads outside it"):
        local_writes({"panther-01": b"x"}, FileKind.CONTROLLER, None, dest)
    assert local_writes({"panther-02": b"x"}, FileKind.CONTROLLER, None, dest) == [
        LocalWrite(dest / "panther-02" / "controller.yaml", b"x", "panther-02")]
