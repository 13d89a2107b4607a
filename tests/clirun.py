"""The CLI run in-process, as tests read it."""

from __future__ import annotations

import json
from typing import Any

import pytest

from panther_ops.cli.app import main


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of ``panther-ops *argv``."""
    capsys.readouterr()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any], str, str]:
    """Exit code, the JSON document printed (empty when nothing was), stdout, stderr.

    With ``--json`` any output must be one JSON document: ``json.loads`` raises otherwise."""
    code, out, err = run(capsys, *argv)
    parse = out.strip() and ("--json" in argv or out.strip().startswith("{"))
    doc = json.loads(out) if parse else {}
    return code, doc, out, err
