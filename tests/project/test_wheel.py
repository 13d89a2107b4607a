"""Installed from a wheel, panther-ops has its templates (package data ``panther_ops/templates``).

The full check (a fresh venv outside the checkout, the README's main job) is
scripts/wheel-check.sh, run by CI; this builds the wheel, installs it into a directory with
no dependencies and runs the commands that read templates from there.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_the_wheel_carries_the_templates_and_uses_them(tmp_path: Path) -> None:
    src, dist = tmp_path / "src", tmp_path / "dist"  # a clean copy: no build/ or egg-info of the checkout
    skip = shutil.ignore_patterns(".git", ".venv*", ".*cache", "build", "dist", "*.egg-info", "__pycache__",
                                  "demo-fleet", "bench")
    shutil.copytree(REPO, src, ignore=skip)
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(dist), str(src)],
                   check=True, timeout=240)
    (wheel,) = dist.glob("panther_ops-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    shipped = {p.relative_to(REPO).as_posix() for p in (REPO / "templates").rglob("*")
               if p.is_file() and "__pycache__" not in p.parts}
    assert shipped, "no templates in the checkout"
    missing = sorted(s for s in shipped if f"panther_ops/{s}" not in names)
    assert not missing, f"not in the wheel: {missing[:5]}"

    target = tmp_path / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target), str(wheel)],
                   check=True, timeout=240)
    env = {**os.environ, "PYTHONPATH": str(target), "PANTHER_OPS_CACHE_DIR": ""}
    run = tmp_path / "run"
    run.mkdir()

    def po(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-c", "from panther_ops.cli.app import main; import sys; "
                               "sys.exit(main(sys.argv[1:]))", *args], check=False, cwd=run, env=env,
                              capture_output=True, text=True, timeout=120)

    where = subprocess.run([sys.executable, "-c", "import panther_ops; from panther_ops.core.fleet.templates import "
                            "templates_dir; print(panther_ops.__file__); print(templates_dir())"],
                           cwd=run, env=env, capture_output=True, text=True, check=True)
    package, templates = where.stdout.split()
    assert Path(package).is_relative_to(target) and Path(templates).is_relative_to(target), where.stdout
    init = po("demo", "init", "--dest", "fleet")
    assert init.returncode == 0, init.stderr
    anim = target / "panther_ops" / "templates" / "lights" / "user_animations.example.yaml"
    check = po("lights", "validate", str(anim))
    assert check.returncode == 0, check.stderr
    status = po("-i", "fleet", "status", "--all", "--json")
    assert status.returncode == 0, status.stderr
