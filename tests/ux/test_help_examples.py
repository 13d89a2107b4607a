"""Every example of a command's --help shows one per line, verbatim, at 80 and at 200 columns
(issue 26, finding 3: click rewrapped them into one paragraph, cut mid-command)."""

from __future__ import annotations

from collections import defaultdict

import pytest

from panther_ops.cli.app import main

from .examples import help_examples


def _by_command() -> dict[str, list[str]]:
    out: dict[str, list[str]] = defaultdict(list)
    for example in help_examples():
        out[example.where.removeprefix("--help of ")].append(example.line)
    return dict(out)


BY_COMMAND = _by_command()


def test_the_help_texts_have_examples() -> None:
    assert len(BY_COMMAND) > 60 and "panther-ops" in BY_COMMAND and "config set" in BY_COMMAND


@pytest.mark.parametrize("columns", [80, 200])
@pytest.mark.parametrize("command", sorted(BY_COMMAND))
def test_each_example_is_a_line_of_its_own(command: str, columns: int, capsys: pytest.CaptureFixture[str],
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", str(columns))
    argv = [] if command == "panther-ops" else command.split()
    capsys.readouterr()
    assert main([*argv, "--help"]) == 0
    lines = [line.strip() for line in capsys.readouterr().out.splitlines()]
    for example in BY_COMMAND[command]:
        assert any(line == example or line.endswith(" " + example) for line in lines), (
            f"`{example}` is not a line of `{command} --help`:\n" + "\n".join(lines))
