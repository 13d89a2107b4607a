"""The background import of paramiko is safe by design (cli/context.py `_import_paramiko`).

Two threads importing modules of one package at the same time can meet a half-initialised
module: CPython breaks the lock cycle of a package and a submodule imported from two threads
by handing one of them the unfinished module (a NameError inside PyYAML's C loader was seen
when the planners and fabric were imported in the background as well). The rule held here:
while the thread imports paramiko, what the main thread imports to read the inventory shares
with it nothing but single standard-library modules (which import no package back), and the
thread has ended before the robots' tasks start.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.clirun import run_cli

PROBE = r"""
import json, sys, threading
from panther_ops.cli import context
from panther_ops.core.fleet.inventory_file import load_inventory
mode, inventory = sys.argv[1], sys.argv[2]
seen = {}
def start(thread):  # the modules as they are when the thread would start; it is not started:
    seen["yaml"] = "yaml" in sys.modules  # each side is measured alone
    seen["before"] = set(sys.modules)
threading.Thread.start = start
context._import_paramiko()
if mode == "inventory":
    load_inventory(inventory)
else:
    import paramiko
print(json.dumps({"yaml_first": seen["yaml"], "new": sorted(set(sys.modules) - seen["before"])}))
"""


def _imported(mode: str, inventory: Path) -> set[str]:
    done = subprocess.run([sys.executable, "-c", PROBE, mode, str(inventory)], check=True, capture_output=True,
                          text=True, timeout=120)
    doc = json.loads(done.stdout)
    assert doc["yaml_first"], "PyYAML must be imported before the thread starts"
    return set(doc["new"])


def test_the_inventory_and_paramiko_share_only_single_stdlib_modules(demo: Path) -> None:
    inventory, paramiko = _imported("inventory", demo), _imported("paramiko", demo)
    assert "paramiko" in paramiko and inventory, "the probe imported nothing: it proves nothing"
    shared = inventory & paramiko
    stdlib = set(sys.stdlib_module_names)
    packages = {name.partition(".")[0] for name in shared if "." in name}
    assert not packages, f"package modules imported by both threads: {sorted(shared)}"
    assert all(name in stdlib or name.lstrip("_") in stdlib for name in shared), sorted(shared - stdlib)
    assert not any(name == "yaml" or name.startswith("yaml.") for name in inventory), "yaml is imported first"


def test_the_thread_has_ended_before_the_robots_are_contacted(demo: Path, monkeypatch: pytest.MonkeyPatch,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    import threading

    from panther_ops.cli import context
    from panther_ops.core.fleet import runner

    alive: list[bool] = []
    real = runner.run_fleet

    def recording(*args: object, **kwargs: object) -> object:
        alive.append(any(t.name == "import-paramiko" and t.is_alive() for t in threading.enumerate()))
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(runner, "run_fleet", recording)
    assert context  # the CLI imports run_fleet from the runner module when it runs
    code, doc, _, err = run_cli(capsys, "-i", str(demo), "status", "--all", "--json")
    assert code == 0, err
    assert doc["robots"] and alive and not any(alive)
