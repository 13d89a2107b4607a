"""The manager stays deployable alone: no CLI / transport / typer / rich, Python 3.10 syntax."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

MANAGER = Path(__file__).resolve().parents[2] / "panther_ops" / "manager"

CHECK = """
import pkgutil, importlib, sys
import panther_ops.manager as manager
for info in pkgutil.walk_packages(manager.__path__, "panther_ops.manager."):
    importlib.import_module(info.name)
for name in manager.__all__:
    getattr(manager, name)
bad = sorted(m for m in sys.modules if m.split(".")[0] in {"typer", "rich"}
             or m.startswith(("panther_ops.cli", "panther_ops.transport")))
print(",".join(bad))
"""


def test_importing_every_manager_module_pulls_in_no_cli_layer() -> None:
    done = subprocess.run([sys.executable, "-c", CHECK], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == ""


def test_the_shutdown_executor_imports_without_py_trees_or_pillow() -> None:
    code = ("import sys, panther_ops.manager.shutdown_executor; "
            "print(sorted(m for m in ('py_trees', 'PIL') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def python310() -> str | None:
    for candidate in ("/root/.pyenv/versions/3.10.13/bin/python", shutil.which("python3.10")):
        if candidate and Path(candidate).is_file():
            probe = subprocess.run([candidate, "-c", "import sys; print(sys.version_info[:2])"],
                                   check=False, capture_output=True, text=True)
            if probe.returncode == 0 and probe.stdout.strip() == "(3, 10)":
                return candidate
    return None


def test_every_module_compiles_with_python_3_10() -> None:
    interpreter = python310()
    if interpreter is None:
        pytest.skip("no Python 3.10 interpreter here")
    code = ("import sys, pathlib\n"
            "for p in pathlib.Path(sys.argv[1]).rglob('*.py'):\n"
            "    compile(p.read_text(), str(p), 'exec')\n"
            "print(sys.version_info[:2])")
    done = subprocess.run([interpreter, "-c", code, str(MANAGER)], check=False,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "(3, 10)"
