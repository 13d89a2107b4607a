"""`demo init` prints the `export PANTHER_OPS_INVENTORY=...` line (issue 26): pasted into the
shell, the demo fleet is the inventory in use from any directory, with no -i."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

CLI_DIR = Path(sys.executable).parent


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PANTHER_OPS_INVENTORY"}
    env["PATH"] = f"{CLI_DIR}{os.pathsep}{env.get('PATH', '')}"
    return env


def test_the_export_line_makes_the_demo_fleet_the_inventory_in_use(tmp_path: Path) -> None:
    bash = shutil.which("bash")
    assert bash
    work, elsewhere = tmp_path / "my work", tmp_path / "elsewhere"  # a blank in the path: quoted
    work.mkdir()
    elsewhere.mkdir()
    p = subprocess.run([bash, "-c", "panther-ops demo init"], cwd=work, env=_env(), capture_output=True, text=True,
                       timeout=120, check=True)
    exports = [line for line in p.stdout.splitlines() if line.startswith("export ")]
    assert exports == [f"export PANTHER_OPS_INVENTORY='{work / 'demo-fleet'}'"], p.stdout
    # pasted into a shell, then a command from another directory, without -i
    script = f"{exports[0]}\ncd '{elsewhere}' && panther-ops status --all --json"
    run = subprocess.run([bash, "-c", script], env=_env(), capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr
    assert f"inventory: {work / 'demo-fleet'} (from $PANTHER_OPS_INVENTORY)" in run.stderr
    assert [r["robot"] for r in json.loads(run.stdout)["robots"]] == ["panther-01", "panther-02", "panther-03", "panther-04"]


def test_the_json_document_carries_the_export_line(tmp_path: Path) -> None:
    p = subprocess.run([str(CLI_DIR / "panther-ops"), "demo", "init", "--dest", "fleet", "--json"], cwd=tmp_path,
                       env=_env(), capture_output=True, text=True, timeout=120, check=True)
    doc = json.loads(p.stdout)
    assert doc["export"] == f"export PANTHER_OPS_INVENTORY={tmp_path / 'fleet'}"
