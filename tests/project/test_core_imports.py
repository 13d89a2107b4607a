"""Core does no I/O of its own: no module of panther_ops/core imports paramiko, subprocess,
socket, urllib.request, docker or fabric, at the top, inside a function or under
TYPE_CHECKING (the transport does; pyproject's import-linter contract says the same for
whole packages, this walk also names urllib.request)."""

from __future__ import annotations

import ast
from pathlib import Path

import panther_ops.core

FORBIDDEN = ("paramiko", "subprocess", "socket", "urllib.request", "docker", "fabric")
CORE = Path(panther_ops.core.__file__).parent


def forbidden_imports(source: str) -> list[tuple[int, str]]:
    """(line, module) of every import in `source` of a FORBIDDEN module or one of its parts."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module, *(f"{node.module}.{a.name}" for a in node.names)]
        else:
            continue
        for name in names:
            if any(name == bad or name.startswith(bad + ".") for bad in FORBIDDEN):
                found.append((node.lineno, name))
                break
    return found


def test_the_walk_finds_lazy_and_type_checking_imports_and_only_those() -> None:
    source = (
        "from typing import TYPE_CHECKING\n"
        "import urllib.parse\n"
        "from urllib.parse import urlsplit\n"
        "import socketserver\n"
        "PROGRAM = 'import subprocess'\n"
        "if TYPE_CHECKING:\n"
        "    import paramiko\n"
        "def f():\n"
        "    from urllib import request\n"
        "    import docker.errors\n"
        "    from fabric import Connection\n"
        "    import subprocess as sp\n"
        "    from socket import socketpair\n"
    )
    assert forbidden_imports(source) == [(7, "paramiko"), (9, "urllib.request"), (10, "docker.errors"),
                                         (11, "fabric"), (12, "subprocess"), (13, "socket")]


def test_core_imports_no_side_effect_module() -> None:
    files = sorted(CORE.rglob("*.py"))
    assert len(files) > 100  # the whole of core is walked
    found = [f"{path.relative_to(CORE.parent)}:{line}: {name}"
             for path in files for line, name in forbidden_imports(path.read_text(encoding="utf-8"))]
    assert found == [], "core must leave these to panther_ops/transport:\n" + "\n".join(found)
