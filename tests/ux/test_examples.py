"""Every example of --help and of docs/ runs on the demo fleet, or is marked as needing a robot
reached over SSH (issue 16, finding 4 and Deliver); and a command's output piped and on a
pseudo-terminal differs only in styling."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

from panther_ops.cli.app import main

from .examples import AFTER, EXPECTED_EXIT, Example, doc_examples, help_examples, needs_a_robot
from .termrun import on_pty, piped, plain
from .workspace import reader_workspace

EXAMPLES = help_examples() + doc_examples()
ON_DEMO = [e for e in EXAMPLES if needs_a_robot(e) is None]
ON_A_ROBOT = [e for e in EXAMPLES if needs_a_robot(e) is not None]
NO_INVENTORY = ("demo", "bt", "manager run", "lights validate", "lights preview", "shutdown hosts validate")


@pytest.fixture
def workspace(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A directory as a reader of the examples would have (tests/ux/workspace.py), its cwd."""
    for name, value in reader_workspace(tmp_path).items():
        monkeypatch.setenv(name, value)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _argv(example: Example) -> list[str]:
    """The example's arguments on the demo fleet: its -i (the reader's own inventory) becomes
    demo-fleet; one without -i gets it (as $PANTHER_OPS_INVENTORY would)."""
    argv = example.argv
    if "-i" in argv:
        at = argv.index("-i")
        return [*argv[:at], "-i", "demo-fleet", *argv[at + 2:]]
    if " ".join(argv).startswith(NO_INVENTORY):
        return argv
    return ["-i", "demo-fleet", *argv]


@pytest.mark.parametrize("example", ON_DEMO, ids=[f"{e.where}: {e.line}" for e in ON_DEMO])
def test_example_runs_on_the_demo_fleet(example: Example, workspace: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    for before in AFTER.get(example.line, ()):
        _run(Example(example.where, before), workspace, capsys)
    _run(example, workspace, capsys)


DOCS_IN_ORDER = sorted({e.where.split(":")[0] for e in ON_DEMO if not e.where.startswith("--help")})


@pytest.mark.parametrize("doc", DOCS_IN_ORDER)
def test_a_docs_examples_run_in_order_on_one_demo_fleet(doc: str, workspace: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    """As a reader follows a page: each example after the ones above it (``config set wheel_type
    WH02 -g warehouse --yes``, then a controller limit that WH02 allows)."""
    for example in [e for e in ON_DEMO if e.where.split(":")[0] == doc]:
        _run(example, workspace, capsys)


def _run(example: Example, workspace: Path, capsys: pytest.CaptureFixture[str]) -> None:
    if example.argv[:2] == ["demo", "init"]:
        (workspace / "fresh").mkdir(exist_ok=True)
        shutil.rmtree(workspace / "fresh" / "demo-fleet", ignore_errors=True)
        with pytest.MonkeyPatch.context() as mp:
            mp.chdir(workspace / "fresh")
            assert main(example.argv) == 0
            assert (workspace / "fresh" / "demo-fleet" / "inventory.yaml").is_file()
        return
    capsys.readouterr()
    code = main(_argv(example))
    out, err = capsys.readouterr()
    if code == 2 and "confirmation" in err and "--yes" not in example.argv:
        # on a terminal the example asks first; the operator's "y" is --yes
        code = main([*_argv(example), "--yes"])
        out, err = capsys.readouterr()
    assert code == EXPECTED_EXIT.get(example.line, 0), f"{example.where}: {example.line}\n{out}\n{err}"
    assert "internal error" not in err and "Traceback" not in err
    if "| jq" in example.line:  # --json: exactly one JSON document on stdout
        assert json.loads(out) is not None
    if "| grep calls" in example.line:
        assert "calls=" in out


def test_every_example_is_run_or_marked() -> None:
    """The collection is not empty and every example is accounted for (run, or with a reason)."""
    assert len(EXAMPLES) >= 100
    assert {e.where.split(":")[0] for e in EXAMPLES} >= {"docs/commands.md", "README.md", "docs/manager.md"}
    assert sum(1 for e in EXAMPLES if e.where.startswith("--help")) >= 45
    assert all(needs_a_robot(e) for e in ON_A_ROBOT)
    assert len(ON_DEMO) >= 70


READ_ONLY = (["status", "--all"], ["config", "get", "wheel_type", "--all"], ["driver", "status", "--all"],
             ["config", "diff", "--all"], ["inventory", "list"], ["config", "set", "wheel_type", "WH02", "--all",
                                                                    "--dry-run"],
             ["manager", "status", "--all"], ["shutdown", "check", "--all"], ["doctor", "--all"],
             ["config", "pull", "controller", "-r", "panther-01"], ["inventory", "show", "panther-01"],
             ["shutdown", "hosts", "list", "-r", "panther-01"], ["driver", "versions", "--all"],
             ["bt", "validate", "my_trees/PantherSafetyBT.btproj"],
             ["lights", "validate", "my_animations.yaml"], ["config", "history", "--all"],
             ["gps", "status", "--all"], ["estop", "status", "--all"], ["webui", "status", "--all"],
             ["webui", "url", "--all"], ["reimage", "plan", "--all"], ["gps", "enable", "--all", "--dry-run"],
             ["apply", "--all", "--dry-run"], ["manager", "logs", "--all"])


@pytest.mark.parametrize("args", READ_ONLY, ids=[" ".join(a) for a in READ_ONLY])
def test_piped_and_on_a_terminal_differ_only_in_styling(args: list[str], workspace: Path) -> None:
    argv = ["-i", "demo-fleet", *args]
    pipe = piped(argv, cwd=workspace)
    term = on_pty(argv, cols=160, cwd=workspace, stderr_pipe=True)  # stdout on the terminal, as wide as a pipe
    assert pipe.code == term.code
    assert "\x1b[" not in pipe.out
    shown = [_unmeasured(line) for line in plain(term.out).splitlines()]
    assert shown == [_unmeasured(line) for line in pipe.out.splitlines()]
    assert "\x1b[" not in term.err  # stderr was piped there


def _unmeasured(line: str) -> str:
    """The line without what two runs measure differently (clock offsets, free space, times)."""
    return re.sub(r"[+-]?\d+(\.\d+)?", "N", line).rstrip()
