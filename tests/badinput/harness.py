"""The bad-input corpus harness: one case is a command with input a user can get wrong.

Every case runs panther-ops in-process on a fresh copy of the demo fleet (plus the files the
case brings) and must end with exit 2, a message that names the offending file, key or value,
no traceback and no "internal error", and every file under the case's directory (the demo
robots' trees, their backups and history, the operator's own files) byte-identical before and
after.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from panther_ops.cli.app import main

DEMO = "demo"
"""Directory of the demo fleet inside a case's directory (its inventory: ``{demo}``)."""


@dataclass(frozen=True)
class Case:
    """A command with bad input and what its refusal must name.

    ``args`` follow the global options; ``{demo}`` stands for the demo fleet's directory and
    ``{tmp}`` for the case's directory (files of ``files`` are written there first). The
    inventory is the demo fleet unless ``inventory`` gives another file's content (written
    to ``{tmp}/inventory.yaml``) or ``args`` start with ``-i`` themselves.
    """

    id: str
    args: Sequence[str]
    names: Sequence[str]
    """Texts the error output must contain: the file, key or value at fault, what is allowed."""
    files: Mapping[str, str | bytes] = field(default_factory=dict)
    inventory: str | None = None
    stdin: str | None = None

    def __str__(self) -> str:
        return self.id


def tree_hashes(root: Path) -> dict[str, str]:
    """sha256 (and mode) of every file, and every directory and link, below ``root``."""
    out: dict[str, str] = {}
    for dirpath, dirnames, filenames in os.walk(root, followlinks=False):
        rel_dir = os.path.relpath(dirpath, root)
        out[rel_dir + "/"] = oct(os.lstat(dirpath).st_mode)
        for name in dirnames + filenames:
            path = os.path.join(dirpath, name)
            rel = os.path.join(rel_dir, name)
            st = os.lstat(path)
            if os.path.islink(path):
                out[rel] = "link:" + os.readlink(path)
            elif os.path.isfile(path):
                with open(path, "rb") as fh:
                    out[rel] = f"{oct(st.st_mode)}:{hashlib.sha256(fh.read()).hexdigest()}"
    return out


def prepare(case: Case, tmp: Path) -> list[str]:
    """The demo fleet and the case's files under ``tmp``; the full argument list."""
    assert main(["demo", "init", "--dest", str(tmp / DEMO)]) == 0
    for name, content in case.files.items():
        path = tmp / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content.format(demo=tmp / DEMO, tmp=tmp))
    args = [a.format(demo=tmp / DEMO, tmp=tmp) for a in case.args]
    if case.inventory is not None:
        (tmp / "inventory.yaml").write_text(case.inventory.format(demo=tmp / DEMO, tmp=tmp))
        return ["-i", str(tmp / "inventory.yaml"), *args]
    if args[:1] in (["-i"], ["--inventory"]):
        return args
    return ["-i", str(tmp / DEMO), *args]


def check_refused(case: Case, tmp: Path, capsys: pytest.CaptureFixture[str],
                  monkeypatch: pytest.MonkeyPatch) -> str:
    """Run ``case`` and assert the refusal; returns its error output."""
    args = prepare(case, tmp)
    monkeypatch.setenv("PANTHER_OPS_CACHE_DIR", str(tmp.parent / (tmp.name + "-cache")))
    if case.stdin is not None:
        import io

        monkeypatch.setattr("sys.stdin", io.StringIO(case.stdin))
    before = tree_hashes(tmp)
    capsys.readouterr()
    code = main(args)
    out, err = capsys.readouterr()
    both = out + err
    assert "internal error" not in both, f"{case}: internal error\n{both}"
    assert "Traceback" not in both, f"{case}: traceback\n{both}"
    assert code == 2, f"{case}: exit {code}, not 2\n{both}"
    for name in case.names:
        assert name.format(demo=tmp / DEMO, tmp=tmp) in err, f"{case}: {name!r} not named in\n{err}"
    after = tree_hashes(tmp)
    changed = sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))
    assert not changed, f"{case}: files changed: {changed}"
    return err
