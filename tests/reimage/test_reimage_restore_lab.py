"""`reimage restore` onto a "reinstalled" lab robot (new host key, factory home), with docker."""

from __future__ import annotations

import json
import tarfile
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml

from panther_ops.cli.app import main
from tests.lab import Lab
from tests.lab.pyimage import use_python_image

HOME = "/home/husarion"
COMPOSE = f"{HOME}/compose.yaml"
HOSTS = f"{HOME}/config/panther_manager/config/shutdown_hosts_config.yaml"
MANAGER = f"{HOME}/panther-ops/manager/deployed.json"
SERVICE = "panther_ops_manager"


@pytest.fixture(scope="module")
def rlab(lab_factory: Callable[..., Lab]) -> Lab:
    """One 2.1.1 robot whose driver image is the lab's Python stand-in (as the manager lab tests
    use), so `manager deploy` (simulation mode) runs the manager on the robot's own image."""
    lab = lab_factory(1, docker=True, images=("2.1.1",))
    use_python_image(lab, "r01")
    return lab


@pytest.fixture(scope="module")
def factory(rlab: Lab) -> str:
    """r01's compose file as the lab made it (read before any test changes it)."""
    return rlab.read("r01", COMPOSE)


def po(capsys: pytest.CaptureFixture[str], lab: Lab, *argv: str) -> tuple[int, str]:
    capsys.readouterr()
    code = main(["-i", str(lab.inventory_path), *argv])
    out, err = capsys.readouterr()
    return code, out + err


def manifest_files(archive: Path) -> dict[str, bytes]:
    with tarfile.open(archive) as tar:
        fh = tar.extractfile("manifest.json")
        assert fh is not None
        out = {}
        for f in json.load(fh)["files"]:
            member = tar.extractfile("files" + f["path"])
            assert member is not None
            out[f["path"]] = member.read()
        return out


def reinstall(lab: Lab, factory_compose: str) -> None:
    """What a fresh image leaves: a new host key, the home's customisations gone, the factory
    compose file (the operator's authorized key stays, as the image's first login sets it)."""
    lab.rotate_host_key("r01")
    lab.docker("r01", "rm", "-f", SERVICE)  # a fresh image runs no manager
    lab.exec("r01", ["rm", "-rf", f"{HOME}/config", f"{HOME}/panther-ops", f"{HOME}/.ssh/id_rsa",
                     f"{HOME}/.ssh/id_rsa.pub", f"{HOME}/.ssh/known_hosts"], check=True)
    lab.write("r01", COMPOSE, factory_compose)


def container_state(lab: Lab, name: str) -> str:
    cp = lab.docker("r01", "inspect", "-f", "{{.State.Status}}", name)
    return str(cp.stdout).strip() if cp.returncode == 0 else "absent"


def manager_files(lab: Lab) -> dict[str, bytes]:
    out = lab.sh("r01", f"find {HOME}/panther-ops/manager -type f").stdout
    return {p: lab.read_bytes("r01", p) for p in sorted(str(out).split())}


def driver_cmd(lab: Lab) -> str:
    cp = lab.docker("r01", "inspect", "-f", "{{json .Config.Cmd}}", lab.robot("r01").driver_container, check=True)
    return str(cp.stdout)


def test_backup_reinstall_restore(rlab: Lab, factory: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # a customised robot: wheel type, a custom controller file (mounted), shutdown hosts, the manager's files
    changes = (("wheel_type", "WH02"), ("controller.linear.x.max_velocity", "0.8"))
    for key, value in changes:
        code, text = po(capsys, rlab, "config", "set", key, value, "-r", "r01", "--yes", "--settle", "1")
        assert code == 0, text
    rlab.write("r01", HOSTS, "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    code, text = po(capsys, rlab, "manager", "deploy", "-r", "r01", "--sim", "--yes", "--settle", "2")
    assert code == 0, text
    deployed = manager_files(rlab)
    assert MANAGER in deployed and any(p.endswith("/panther_ops_manager.pyz") for p in deployed)
    service = yaml.safe_load(rlab.read("r01", COMPOSE))["services"][SERVICE]
    assert container_state(rlab, SERVICE) == "running"
    code, text = po(capsys, rlab, "reimage", "backup", "-r", "r01", "--out", str(tmp_path), "--json")
    assert code == 0, text
    (archive,) = tmp_path.glob("r01-*.tar.gz")
    saved = manifest_files(archive)
    assert {COMPOSE, HOSTS, f"{HOME}/.ssh/id_rsa"} | set(deployed) <= set(saved)
    assert all(saved[p] == data for p, data in deployed.items())
    assert any("controller" in p for p in saved)
    old_fp = rlab.host_fingerprint("r01")

    reinstall(rlab, factory)
    new_fp = rlab.host_fingerprint("r01")
    assert new_fp != old_fp
    code, text = po(capsys, rlab, "reimage", "restore", "-r", "r01", "--from", str(archive), "--yes")
    flat = " ".join(text.split())
    assert code == 2, text
    assert f"r01 offers host key ssh-ed25519 {new_fp}; the backup recorded {old_fp}" in flat
    assert "is not trusted (changed" in flat and "panther-ops trust r01 --replace" in flat
    assert rlab.read("r01", COMPOSE) == factory  # nothing written
    with pytest.raises(FileNotFoundError):
        rlab.read_bytes("r01", MANAGER)
    assert container_state(rlab, SERVICE) == "absent"

    code, text = po(capsys, rlab, "trust", "r01", "--replace", "--yes")
    assert code == 0, text
    code, text = po(capsys, rlab, "reimage", "restore", "-r", "r01", "--from", str(archive), "--yes",
                    "--settle", "1")
    assert code == 0, text
    assert "(secret: " in text and "BEGIN OPENSSH PRIVATE KEY" not in text  # the key's diff is masked
    for path, data in saved.items():
        assert rlab.read_bytes("r01", path) == data, path
    assert manager_files(rlab) == deployed  # the deployed manager, byte for byte, nothing more
    assert yaml.safe_load(rlab.read("r01", COMPOSE))["services"][SERVICE] == service
    assert "wheel_type:=WH02" in driver_cmd(rlab)
    assert container_state(rlab, rlab.robot("r01").driver_container) == "running"
    assert "doctor" in text
    code, text = po(capsys, rlab, "manager", "status", "-r", "r01", "--json")
    assert code == 0, text
    # the next test restores onto a newer release: without the manager, as before it was deployed
    code, text = po(capsys, rlab, "manager", "remove", "-r", "r01", "--yes", "--settle", "1")
    assert code == 0, text


def test_restore_onto_a_newer_release_keeps_its_image_and_reapplies_the_customisations(
    rlab: Lab, factory: str, tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    """After the first test r01 runs customised (wheel type, controller file mounted): backed up,
    then reinstalled with a newer 2.1.x image (the lab's stand-in image under the newer tag)."""
    code, text = po(capsys, rlab, "reimage", "backup", "-r", "r01", "--out", str(tmp_path))
    assert code == 0, text
    (archive,) = tmp_path.glob("r01-*.tar.gz")
    customised = rlab.read("r01", COMPOSE)
    assert "wheel_type:=WH02" in customised and "controller_config_path:=" in customised
    old_tag, new_tag = "husarion/panther:humble-2.1.1-20240828", "husarion/panther:humble-2.1.2-20241108"
    assert old_tag in factory
    rlab.docker("r01", "tag", old_tag, new_tag, check=True)
    rlab.write("r01", COMPOSE, factory.replace(old_tag, new_tag))
    code, text = po(capsys, rlab, "reimage", "restore", "-r", "r01", "--from", str(archive), "--yes",
                    "--settle", "1")
    assert code == 0, text
    flat = " ".join(text.split())
    assert "stack 2.1.1 -> 2.1.2: the new image's compose file kept, re-applied: wheel_type:=WH02" in flat
    assert "+ command: ros2 launch panther_bringup bringup.launch.py wheel_type:=WH02" in flat  # the diff
    now = rlab.read("r01", COMPOSE)
    assert new_tag in now and old_tag not in now
    assert "wheel_type:=WH02" in now and "controller_config_path:=" in now
    cp = rlab.docker("r01", "inspect", "-f", "{{.Config.Image}}", rlab.robot("r01").driver_container, check=True)
    assert str(cp.stdout).strip() == new_tag
    assert "wheel_type:=WH02" in driver_cmd(rlab)
