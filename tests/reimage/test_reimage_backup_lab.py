"""`reimage plan`/`backup` on lab robots: real sshd, strict host keys, one connection each."""

from __future__ import annotations

import base64
import hashlib
import json
import stat
import tarfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.clirun import run_cli
from tests.lab import Lab

HOME = "/home/husarion"
CONTROLLER = f"{HOME}/config/panther_controller/config/WH02_controller.yaml"
HOSTS = f"{HOME}/config/panther_manager/config/shutdown_hosts_config.yaml"
MANAGER = f"{HOME}/panther-ops/manager/deployed.json"


@pytest.fixture(scope="module")
def blab(lab_factory: Callable[..., Lab]) -> Lab:
    return lab_factory(2, docker=False, images=("2.1.1", "2.2"))


def run(capsys: pytest.CaptureFixture[str], lab: Lab, *argv: str) -> tuple[int, dict[str, Any]]:
    code, _, out, _ = run_cli(capsys, "-i", str(lab.inventory_path), *argv)
    return code, json.loads(out)


def host_key_fingerprint(lab: Lab, name: str) -> str:
    pub = (lab.robot(name).dir / "etc/ssh/ssh_host_ed25519_key.pub").read_text().split()[1]
    return "SHA256:" + base64.b64encode(hashlib.sha256(base64.b64decode(pub)).digest()).decode().rstrip("=")


def customise(lab: Lab) -> None:
    """r01 (2.1.1): a controller file mounted into the driver, shutdown hosts, a deployed manager."""
    compose = lab.read("r01", f"{HOME}/compose.yaml")
    mount = "      - ~/.ssh/id_rsa:/root/.ssh/id_rsa\n"
    assert mount in compose
    extra = (f"      - {CONTROLLER}:/ros2_ws/install/panther_controller/share/panther_controller/config/"
             "WH02_controller.yaml\n")
    if extra not in compose:
        lab.write("r01", f"{HOME}/compose.yaml", compose.replace(mount, mount + extra))
    lab.write("r01", CONTROLLER, "controller_manager:\n  ros__parameters:\n    update_rate: 100\n")
    lab.write("r01", HOSTS, "hosts:\n  - ip: 10.15.20.3\n    username: husarion\n")
    lab.write("r01", MANAGER, '{"version": "0.1.0"}\n')


def test_plan_and_backup_of_lab_robots(blab: Lab, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    customise(blab)
    code, doc = run(capsys, blab, "reimage", "plan", "-r", "r01", "--json")
    assert code == 0, doc
    (r,) = doc["robots"]
    files = {f["path"]: f for f in r["data"]["files"]}
    roles = {p: f["role"] for p, f in files.items()}
    assert roles[f"{HOME}/compose.yaml"] == "compose file"
    assert roles[CONTROLLER] == "config tree" and roles[HOSTS] == "shutdown hosts"
    assert roles[MANAGER] == "panther-ops manager"
    assert roles[f"{HOME}/.ssh/authorized_keys"] == "ssh authorized_keys"
    assert files[f"{HOME}/.ssh/id_rsa"]["secret"] is True and files[f"{HOME}/.ssh/id_rsa.pub"]["secret"] is False
    assert files[f"{HOME}/.ssh/id_rsa"]["mode"] == "0600" and files[f"{HOME}/.ssh/id_rsa"]["owner"] == "husarion:husarion"

    out = tmp_path / "backups"
    code, doc = run(capsys, blab, "reimage", "backup", "--all", "--out", str(out), "--json")
    assert code == 0, doc
    assert sorted(x["robot"] for x in doc["robots"]) == ["r01", "r02"]
    for res in doc["robots"]:
        name = res["robot"]
        archive = Path(res["data"]["archive"])
        assert stat.S_IMODE(archive.stat().st_mode) == 0o600
        with tarfile.open(archive) as tar:
            fh = tar.extractfile("manifest.json")
            assert fh is not None
            manifest = json.load(fh)
            ident = manifest["robot"]
            assert ident["name"] == name and ident["serial"] == blab.robot(name).serial
            assert ident["host_key"] == host_key_fingerprint(blab, name)
            assert ident["stack_version"] == {"r01": "2.1.1", "r02": "2.2.2"}[name]
            assert ident["model"] == "panther"
            # the OS build as the robot states it (2.2's robot_config.env; 2.1's env has none)
            assert ident["os_build"] == ({"r02": blab.robot(name).stack.system_build_version}.get(name))
            for f in manifest["files"]:
                data = blab.read_bytes(name, f["path"])
                member = tar.extractfile("files" + f["path"])
                assert member is not None and member.read() == data, f["path"]
                assert f["sha256"] == hashlib.sha256(data).hexdigest()
            paths = {f["path"] for f in manifest["files"]}
            assert {f"{HOME}/compose.yaml", f"{HOME}/.ssh/id_rsa", f"{HOME}/.ssh/authorized_keys"} <= paths
            if name == "r01":
                assert {CONTROLLER, HOSTS, MANAGER} <= paths
            else:  # the 2.2 config tree, with its shutdown hosts file
                assert f"{HOME}/config/husarion_ugv_manager/config/shutdown_hosts.yaml" in paths
