"""`reimage plan` and `reimage backup` on the demo fleet (local robot directories)."""

from __future__ import annotations

import hashlib
import io
import json
import stat
import tarfile
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from panther_ops.core.fleet.inventory_file import load_inventory


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
    assert outcome == {"panther-01": "ok", "panther-02": "unreachable", "panther-03": "ok", "panther-04": "ok"}
    assert sorted(p.name.rsplit("-", 1)[0] for p in out.iterdir()) == ["panther-01", "panther-03", "panther-04"]


def _backup(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], robot: str) -> Path:
    code, doc, _ = run(capsys, "-i", str(demo), "reimage", "backup", "-r", robot, "--out", str(tmp_path / "bk"),
                       "--json")
    assert code == 0
    return Path(doc["robots"][0]["data"]["archive"])


def test_restore_puts_the_files_back_then_applies_desired(
    demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    root = demo / "robots" / "panther-03"
    hosts = root / "home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"
    archive = _backup(demo, tmp_path, capsys, "panther-03")
    saved = hosts.read_bytes()
    hosts.write_text("hosts: []\n")
    (root / "home/husarion/config/common/.env").unlink()
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-03", "--from", str(archive),
                        "--dry-run")
    assert code == 0 and "+++ b/home/husarion/config/common/.env" in text and hosts.read_text() == "hosts: []\n"
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-03", "--from", str(archive),
                        "--yes")
    assert code == 0, text
    assert hosts.read_bytes() == saved and (root / "home/husarion/config/common/.env").exists()
    assert "restore 2 file(s)" in text and "panther-ops doctor" in text
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-03", "--from", str(archive),
                        "--yes")
    assert code == 0 and "every file is as in the backup" in text


def test_restore_masks_a_private_key_in_its_diff(
    demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    key = demo / "robots" / "panther-02" / "home/husarion/.ssh/id_rsa"
    content = "-----BEGIN OPENSSH PRIVATE KEY-----\nstand-in\n-----END OPENSSH PRIVATE KEY-----\n"
    key.write_text(content)
    key.chmod(0o600)
    archive = _backup(demo, tmp_path, capsys, "panther-02")
    key.unlink()
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-02", "--from", str(archive),
                        "--yes")
    assert code == 0, text
    assert f"+(secret: {len(content)} bytes, sha256 " in text and "stand-in" not in text
    assert key.read_text().startswith("-----BEGIN") and stat.S_IMODE(key.stat().st_mode) == 0o600


def test_restore_refusals(demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    archive = _backup(demo, tmp_path, capsys, "panther-01")
    compose = demo / "robots" / "panther-01" / "home/husarion/compose.yaml"
    before = compose.read_text()
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-02", "--from", str(archive))
    assert code == 2 and "is of robot 'panther-01', not 'panther-02'" in text
    other_line = before.replace("husarion/panther:humble-2.1.1-20240828", "husarion/husarion-ugv:humble-2.2.2-20250702")
    compose.write_text(other_line)
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-01", "--from", str(archive),
                        "--yes")
    assert code == 2 and "the robot now runs stack 2.2.2" in " ".join(text.split())
    assert "across release lines" in " ".join(text.split()) and compose.read_text() == other_line
    compose.write_text(before)
    damaged = tmp_path / "damaged.tar.gz"
    with tarfile.open(archive) as src, tarfile.open(damaged, "w:gz") as dst:
        for m in src.getmembers():
            fh = src.extractfile(m)
            data = fh.read() if fh is not None else b""
            if m.name.endswith("compose.yaml"):
                data = data.replace(b"panther", b"PANTHER", 1)
            dst.addfile(m, io.BytesIO(data))
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-01", "--from", str(damaged))
    assert code == 2
    assert "/home/husarion/compose.yaml does not match its sha256 in the manifest (damaged)" in " ".join(text.split())
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-01", "--from",
                        str(tmp_path / "nope.tar.gz"))
    assert code == 2 and "no such file" in text


def test_restore_reads_what_is_there_now_even_where_the_new_compose_mounts_nothing(
    demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    home = demo / "robots" / "panther-01" / "home/husarion"
    compose = home / "compose.yaml"
    factory = compose.read_text()
    mount = "      - ~/.ssh/id_rsa:/root/.ssh/id_rsa\n"
    compose.write_text(factory.replace(mount, mount + "      - ./my_controller.yaml:/config/my_controller.yaml\n"))
    (home / "my_controller.yaml").write_text("backed: up\n")
    code, doc, _ = run(capsys, "-i", str(demo), "reimage", "plan", "-r", "panther-01", "--json")
    roles = {f["path"]: f["role"] for f in doc["robots"][0]["data"]["files"]}
    assert roles["/home/husarion/my_controller.yaml"] == "driver mount"
    archive = _backup(demo, tmp_path, capsys, "panther-01")
    compose.write_text(factory)
    (home / "my_controller.yaml").write_text("there: now\n")
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-01", "--from", str(archive),
                        "--dry-run")
    assert code == 0
    assert "-there: now\n+backed: up" in text


def test_restore_onto_a_newer_release_keeps_its_image_and_reapplies_the_customisations(
    demo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    compose = demo / "robots" / "panther-01" / "home/husarion/compose.yaml"
    factory = compose.read_text()
    mount = "      - ~/.ssh/id_rsa:/root/.ssh/id_rsa\n"
    compose.write_text(factory.replace(mount, mount + "      - ~/maps:/maps:ro\n"))
    code, _, text = run(capsys, "-i", str(demo), "config", "set", "wheel_type", "WH04", "-r", "panther-01", "--yes")
    assert code == 0, text
    archive = _backup(demo, tmp_path, capsys, "panther-01")
    newer = factory.replace("humble-2.1.1-20240828", "humble-2.1.2-20241108")
    compose.write_text(newer)  # reinstalled with a newer 2.1.x image
    code, _, text = run(capsys, "-i", str(demo), "reimage", "restore", "-r", "panther-01", "--from", str(archive),
                        "--yes")
    assert code == 0, text
    flat = " ".join(text.split())
    assert "stack 2.1.1 -> 2.1.2: the new image's compose file kept, re-applied: wheel_type:=WH04, mount ~/maps:/maps:ro" \
        in flat
    assert "+ - ~/maps:/maps:ro" in flat  # the diff shown
    now = compose.read_text()
    assert "husarion/panther:humble-2.1.2-20241108" in now and "humble-2.1.1" not in now
    assert "      - ~/maps:/maps:ro\n" in now
    assert "wheel_type:=WH02" in now  # then the inventory's desired: block (apply) on top


def test_plan_counts_one_file_in_the_singular(demo: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, doc, _ = run(capsys, "-i", str(demo), "reimage", "plan", "-r", "panther-01", "--json")
    assert code == 0 and doc["robots"][0]["message"].startswith("1 file, ")  # panther-01 holds only compose.yaml
