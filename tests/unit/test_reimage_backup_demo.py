"""`reimage plan` and `reimage backup` on the demo fleet (local robot directories)."""

from __future__ import annotations

import hashlib
import json
import stat
import tarfile
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.inventory import load_inventory


@pytest.fixture
def demo(tmp_path: Path) -> Path:
    assert main(["demo", "init", "--dest", str(tmp_path / "demo")]) == 0
    return tmp_path / "demo"


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any], str]:
    capsys.readouterr()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, (json.loads(out) if "--json" in argv else {}), out + err


def test_plan_lists_what_would_be_carried(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, doc, _ = run(capsys, "-i", str(demo), "reimage", "plan", "-r", "panther-03", "--json")
    assert code == 0
    (r,) = doc["robots"]
    paths = {f["path"]: f for f in r["data"]["files"]}
    root = demo / "robots" / "panther-03"
    on_robot = {"/" + str(p.relative_to(root)) for p in (root / "home/husarion").rglob("*") if p.is_file()}
    assert set(paths) == on_robot  # the compose file and the whole config tree, nothing else is there
    hosts = paths["/home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"]
    assert hosts["role"] == "shutdown hosts"
    data = (root / "home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml").read_bytes()
    assert hosts["sha256"] == hashlib.sha256(data).hexdigest() and hosts["size"] == len(data)
    assert paths["/home/husarion/compose.yaml"]["role"] == "compose file"
    ident = r["data"]["robot"]
    assert ident["serial"] == "PTH0203" and ident["stack_version"] == "2.2.2" and ident["model"] == "panther"
    assert "/home/husarion/.ssh/id_rsa" in r["data"]["missing"]
    code, _, text = run(capsys, "-i", str(demo), "reimage", "plan", "-r", "panther-03")
    assert code == 0 and "shutdown_hosts.yaml" in text and "compose file" in text


def test_backup_all_writes_one_private_archive_per_robot(
    demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    root = demo / "robots" / "panther-01"
    key = root / "home/husarion/.ssh/id_rsa"
    key.write_text("-----BEGIN OPENSSH PRIVATE KEY-----\nstand-in\n-----END OPENSSH PRIVATE KEY-----\n")
    key.chmod(0o600)
    out = tmp_path / "backups"
    code, doc, _ = run(capsys, "-i", str(demo), "reimage", "backup", "--all", "--out", str(out), "--json")
    assert code == 0
    inv = load_inventory(str(demo))
    assert sorted(r["robot"] for r in doc["robots"]) == sorted(inv.robots)
    assert stat.S_IMODE(out.stat().st_mode) == 0o700
    for r in doc["robots"]:
        archive = Path(r["data"]["archive"])
        assert archive.parent == out and archive.name.startswith(r["robot"] + "-")
        assert stat.S_IMODE(archive.stat().st_mode) == 0o600
        robot_root = demo / "robots" / r["robot"]
        with tarfile.open(archive) as tar:
            names = tar.getnames()
            assert names[0] == "manifest.json"
            fh = tar.extractfile("manifest.json")
            assert fh is not None
            manifest = json.load(fh)
            assert manifest["robot"]["name"] == r["robot"]
            assert manifest["desired"] == inv.robots[r["robot"]].desired
            assert manifest["files"], r["robot"]
            for f in manifest["files"]:
                data = (robot_root / f["path"].lstrip("/")).read_bytes()
                member = tar.extractfile("files" + f["path"])
                assert member is not None and member.read() == data
                assert f["sha256"] == hashlib.sha256(data).hexdigest()
                assert f["mode"] == f"{stat.S_IMODE((robot_root / f['path'].lstrip('/')).stat().st_mode):04o}"
    one = next(r for r in doc["robots"] if r["robot"] == "panther-01")
    secret = {f["path"]: f["secret"] for f in one["data"]["files"]}
    assert secret["/home/husarion/.ssh/id_rsa"] is True and secret["/home/husarion/compose.yaml"] is False
    assert one["data"]["desired"] == {"launch_args": {"wheel_type": "WH02"}}


def test_backup_out_must_be_a_directory(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "file"
    f.write_text("x")
    code, _, text = run(capsys, "-i", str(demo), "reimage", "backup", "--all", "--out", str(f))
    assert code == 2 and f"--out {f}: not a directory" in text


def test_an_unreachable_robot_does_not_stop_the_others(
    demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    import shutil

    shutil.rmtree(demo / "robots" / "panther-02")
    out = tmp_path / "backups"
    code, doc, _ = run(capsys, "-i", str(demo), "reimage", "backup", "--all", "--out", str(out), "--json")
    assert code == 3
    outcome = {r["robot"]: r["outcome"] for r in doc["robots"]}
    assert outcome == {"panther-01": "ok", "panther-02": "unreachable", "panther-03": "ok"}
    assert sorted(p.name.rsplit("-", 1)[0] for p in out.iterdir()) == ["panther-01", "panther-03"]
