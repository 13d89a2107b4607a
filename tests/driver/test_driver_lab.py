"""Issue-7 acceptance on the lab: driver status / logs / restart / versions / update and
config restore-defaults on real sshd + dockerd + compose v2 robots (the driver is the lab's
ros2 stand-in; the three driver tags are one busybox image, so an update is a real recreate
from another image reference, and a tag that is not there cannot be pulled: no network)."""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.clirun import run_cli
from tests.labtools import COMPOSE, containers, robot_of, robots_put_back
from tests.ports import free_port

pytestmark = pytest.mark.lab

UGV_IMAGE = "husarion/husarion-ugv:humble-2.2.2-20250702"


def tree(lab: Any, name: str, home: str = "/home/husarion") -> str:
    """~/config as a listing of checksum and path, then path and owner (empty when absent)."""
    return lab.sh(name, f"cd {home} && [ -d config ] && find config -type f -exec md5sum {{}} + | sort; "
                        "[ -d config ] && find config -exec stat -c '%n %U' {} + | sort; true").stdout


@pytest.fixture
def pristine(lab: Any) -> Iterator[None]:
    """Put every robot back as it was: compose.yaml, ~/config, backups, running stack."""
    def ids(name: str) -> dict[str, str]:
        return {k: v["id"] for k, v in containers(lab, name).items()}

    running = {r.name: ids(r.name) for r in lab.robots}
    with robots_put_back(lab, lambda name, changed: changed or ids(name) != running[name]):
        yield


def snapshot(lab: Any) -> dict[str, Any]:
    """What must be the same after this module: files, config trees, backups, containers (not their ids)."""
    out: dict[str, Any] = {}
    for r in lab.robots:
        ctrs = {k: {x: v[x] for x in ("image", "state", "cmd", "mounts")} for k, v in containers(lab, r.name).items()}
        out[r.name] = (lab.read(r.name, COMPOSE), tree(lab, r.name), ctrs,
                       lab.sh(r.name, "ls -A /home/husarion/.panther-ops 2>/dev/null; true").stdout)
    return out


@pytest.fixture(scope="module", autouse=True)
def leaves_the_lab_as_found(lab: Any) -> Iterator[None]:
    before = snapshot(lab)
    yield
    assert snapshot(lab) == before


def test_status_logs_and_versions_read_every_robot(lab: Any, capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    inv = str(lab.inventory_path)
    before = {r.name: containers(lab, r.name) for r in lab.robots}
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "status", "--all", "--json")
    assert code == 0, doc
    for res in doc["robots"]:
        d = res["data"]
        r = lab.robot(res["robot"])
        assert res["outcome"] == "ok" and res["warnings"] == []
        assert d["service"] == r.driver_container and d["image"] == r.image == d["compose_image"]
        assert d["state"] == "running" and d["command_drift"] is False and d["image_drift"] is False
        assert d["restart_count"] == 0 and d["exit_code"] == 0 and d["health"] is None
        assert d["uptime_s"] > 0 and d["started_at"].startswith("20")
        assert d["command"] == before[r.name][r.driver_container]["cmd"]

    code, _, out, _ = run_cli(capsys, "-i", inv, "driver", "logs", "--all", "-n", "2")
    assert code == 0
    lines = out.splitlines()
    assert [ln.split(" | ")[0] for ln in lines] == [n for n in lab.names for _ in range(2)]
    assert all("[ros2-standin]" in ln or "[INFO]" in ln for ln in lines)
    code, _, out, _ = run_cli(capsys, "-i", inv, "driver", "logs", "-r", "r05", "--since", "1d", "-t")
    assert code == 0 and " | " not in out and re.match(r"^20\d\d-\d\d-\d\dT", out)

    monkeypatch.setenv("PANTHER_OPS_DOCKERHUB_URL", f"http://127.0.0.1:{free_port()}/{{repo}}")
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "versions", "--all", "--remote", "--json")
    assert code == 0, doc
    for res in doc["robots"]:
        local = res["data"]["local"]
        assert {e["image"] for e in local} >= {"husarion/panther:humble-2.0.4-20240628",
                                               "husarion/panther:humble-2.1.1-20240828", UGV_IMAGE}
        assert [e["image"] for e in local if e["in_use"]] == [lab.robot(res["robot"]).image]
        assert [e["image"] for e in local if e["in_compose"]] == [lab.robot(res["robot"]).image]
        assert res["data"]["newer"] == []
    assert all(v["error"].startswith("registry unreachable") for v in doc["data"]["remote"].values())
    assert {r.name: containers(lab, r.name) for r in lab.robots} == before


def test_status_logs_and_versions_on_a_2_3_2_robot(jazzy_lab: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """The commands of the test above on a husarion_ugv 2.3.2 (Jazzy) robot beside a 2.2.2 one: its
    driver found and read as the 2.2 robot's (the same container name, husarion_ugv_ros@2.3.2:
    docker/demo/compose.hardware.yaml), its Jazzy image named."""
    inv = str(jazzy_lab.inventory_path)
    humble, jazzy = jazzy_lab.robots
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "status", "--all", "--json")
    assert code == 0, doc
    by = {r["robot"]: r for r in doc["robots"]}
    for r in (humble, jazzy):
        d = by[r.name]["data"]
        assert by[r.name]["outcome"] == "ok" and d["service"] == "husarion_ugv_ros" and d["state"] == "running"
        assert d["image"] == r.image == d["compose_image"] and d["command_drift"] is False
    assert by[jazzy.name]["data"]["image"] == "husarion/husarion-ugv:jazzy-2.3.2-20260622"
    code, _, out, _ = run_cli(capsys, "-i", inv, "driver", "logs", "-r", jazzy.name, "-n", "2")
    assert code == 0 and len(out.splitlines()) == 2 and all("[ros2-standin]" in ln or "[INFO]" in ln
                                                             for ln in out.splitlines())
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "versions", "-r", jazzy.name, "--json")
    assert code == 0, doc
    local = doc["robots"][0]["data"]["local"]
    assert [e["image"] for e in local if e["in_use"]] == [jazzy.image]


def test_status_shows_drift_and_restart_recreates(lab: Any, pristine: None,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), robot_of(lab, "2.1.1")
    code, _, _, _ = run_cli(capsys, "-i", inv, "config", "set", "wheel_type", "WH02", "-r", name, "--yes",
                            "--no-restart")
    assert code == 0
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "status", "-r", name, "--json")
    (res,) = doc["robots"]
    assert code == 0 and res["data"]["command_drift"] is True
    assert any("launch command differs" in w for w in res["warnings"])
    old = containers(lab, name)["panther_ros"]
    code, _, _, err = run_cli(capsys, "-i", inv, "driver", "restart", "-r", name)
    assert code == 2 and "pass --yes" in err
    assert containers(lab, name)["panther_ros"]["id"] == old["id"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "restart", "-r", name, "--yes", "--settle", "1", "--json")
    assert code == 0, doc
    (res,) = doc["robots"]
    new = containers(lab, name)["panther_ros"]
    assert res["outcome"] == "changed" and res["data"]["previous_container"] == old["id"][:12]
    assert res["data"]["container"] == new["id"][:12] != old["id"][:12]
    assert new["state"] == "running" and "wheel_type:=WH02" in new["cmd"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "status", "-r", name, "--json")
    assert doc["robots"][0]["data"]["command_drift"] is False and doc["robots"][0]["warnings"] == []


@pytest.mark.parametrize("version", ["2.1.1", "2.2.2"])
def test_stop_and_start_keep_the_same_container(lab: Any, pristine: None, version: str,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), robot_of(lab, version)
    old = {k: v for k, v in containers(lab, name).items() if v["state"] == "running"}
    driver = next(k for k in old if "panther_ros" in k or "husarion_ugv_ros" in k)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "stop", "-r", name, "--yes", "--json")
    assert code == 0, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "changed" and res["message"].startswith("stopped "), res
    now = containers(lab, name)
    assert now[driver]["state"] == "exited" and now[driver]["id"] == old[driver]["id"]
    assert all(now[k]["state"] == "running" for k in old if k != driver), "only the driver is stopped"
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "stop", "-r", name, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok" and "already stopped" in doc["robots"][0]["message"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "status", "-r", name, "--json")
    assert code == 3 and doc["robots"][0]["outcome"] == "failed"
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "start", "-r", name, "--yes", "--settle", "1", "--json")
    assert code == 0, doc
    assert doc["robots"][0]["outcome"] == "changed" and "running after 1 s" in doc["robots"][0]["message"]
    now = containers(lab, name)
    assert now[driver]["state"] == "running" and now[driver]["id"] == old[driver]["id"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "start", "-r", name, "--yes", "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok" and "already running" in doc["robots"][0]["message"]


def test_update_20_to_21_is_a_real_recreate(lab: Any, pristine: None, capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), robot_of(lab, "2.0.4")
    before = lab.read(name, COMPOSE)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "update", "humble-2.1.1-20240828", "-r", name, "--yes",
                              "--settle", "1", "--json")
    assert code == 0, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "changed" and res["data"]["image_local"] is True
    assert res["data"]["stack_from"] == "panther_ros 2.0.4" and res["data"]["stack_to"] == "panther_ros 2.1.1"
    after = lab.read(name, COMPOSE)
    assert after == before.replace("image: husarion/panther:humble-2.0.4-20240628",
                                   "image: husarion/panther:humble-2.1.1-20240828")
    ctr = containers(lab, name)["panther_ros"]
    assert ctr["image"] == "husarion/panther:humble-2.1.1-20240828" and ctr["state"] == "running"
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "update", "humble-2.1.1-20240828", "-r", name, "--yes",
                              "--json")
    assert code == 0 and doc["robots"][0]["outcome"] == "ok" and lab.read(name, COMPOSE) == after
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "versions", "-r", name, "--json")
    local = doc["robots"][0]["data"]["local"]
    assert [e["tag"] for e in local if e["in_use"]] == ["humble-2.1.1-20240828"]


def test_update_to_a_tag_not_on_the_robot_rolls_back(lab: Any, pristine: None,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), robot_of(lab, "2.0.4", 1)
    before = lab.read_bytes(name, COMPOSE)
    old = containers(lab, name)["panther_ros"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "update", "humble-2.1.2-20241125", "-r", name, "--yes",
                              "--settle", "1", "--json")
    assert code == 3, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "rolled-back" and res["data"]["image_local"] is False
    assert any("is not on the robot: it needs a pull" in w for w in res["warnings"])
    assert res["message"].startswith("docker compose up failed") and "restored backup" in res["message"]
    assert lab.read_bytes(name, COMPOSE) == before
    ctr = containers(lab, name)["panther_ros"]
    assert ctr["image"] == old["image"] and ctr["state"] == "running"

    now = containers(lab, name)["panther_ros"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "update", "humble-2.1.2-20241125", "-r", name, "--yes",
                              "--pull", "--settle", "1", "--json")
    assert code == 3, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "rolled-back" and res["message"].startswith("docker compose pull failed")
    assert res["message"].endswith("the driver was not touched")
    assert lab.read_bytes(name, COMPOSE) == before
    assert containers(lab, name)["panther_ros"]["id"] == now["id"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "history", "-r", name, "--json")
    statuses = [e["status"].split(":")[0] for e in doc["robots"][0]["data"]["history"]]
    assert statuses == ["rolled-back", "rolled-back"]


def test_bad_tags_exit_2_and_change_nothing(lab: Any, pristine: None, capsys: pytest.CaptureFixture[str]) -> None:
    inv = str(lab.inventory_path)
    before = {r.name: lab.read_bytes(r.name, COMPOSE) for r in lab.robots}
    for tag, needle in (("jazzy-2.4.0-20270101", "jazzy: husarion_ugv 2.3.0, 2.3.1, 2.3.2"), ("latest", "does not say the driver version"),
                        ("husarion/panther:humble-2.2.2-20250702", "published as husarion/husarion-ugv"),
                        ("humble-2.2.2-20250702", "that is a reinstall")):
        code, _, _, err = run_cli(capsys, "-i", inv, "driver", "update", tag, "--all", "--yes")
        assert code == 2 and needle in err, (tag, err)
    assert {r.name: lab.read_bytes(r.name, COMPOSE) for r in lab.robots} == before
    for r in lab.robots:
        assert lab.sh(r.name, "ls -A /home/husarion/.panther-ops 2>/dev/null | wc -l").stdout.strip() == "0"


def test_forced_move_to_22_and_back(lab: Any, pristine: None, capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), robot_of(lab, "2.1.1")
    original = lab.read(name, COMPOSE)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "update", "humble-2.2.2-20250702", "-r", name, "--force",
                              "--yes", "--settle", "1", "--json")
    assert code == 0, doc
    assert doc["robots"][0]["data"]["service_from"] == "panther_ros"
    ctrs = containers(lab, name)
    assert "panther_ros" not in ctrs
    assert ctrs["husarion_ugv_ros"]["image"] == UGV_IMAGE and ctrs["husarion_ugv_ros"]["state"] == "running"
    assert ctrs["husarion_ugv_ros"]["cmd"][:4] == ["ros2", "launch", "husarion_ugv_bringup", "bringup.launch.py"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "driver", "update", "humble-2.1.1-20240828", "-r", name, "--force",
                              "--yes", "--settle", "1", "--json")
    assert code == 0, doc
    assert lab.read(name, COMPOSE) == original
    ctrs = containers(lab, name)
    assert "husarion_ugv_ros" not in ctrs and ctrs["panther_ros"]["state"] == "running"


def test_restore_defaults_21_removes_what_push_added(lab: Any, pristine: None, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), "r05"  # 2.1.1, reached through r01
    original = lab.read(name, COMPOSE)
    mine = tmp_path / "my_controller.yaml"
    mine.write_text("/**:\n  drive_controller:\n    ros__parameters:\n      linear:\n        x:\n"
                    "          max_velocity: 0.8\n")
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "push", str(mine), "--as", "controller", "-r", name,
                              "--yes", "--settle", "1", "--json")
    assert code == 0, doc
    code, doc, out, _ = run_cli(capsys, "-i", inv, "config", "restore-defaults", "-r", name, "--dry-run")
    assert code == 0 and "-      - /home/husarion/config/panther_controller/config/my_controller.yaml" in out
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "restore-defaults", "-r", name, "--yes", "--settle", "1",
                              "--json")
    assert code == 0, doc
    assert doc["robots"][0]["data"]["unset_args"] == ["controller_config_path"]
    assert lab.read(name, COMPOSE) == original
    ctr = containers(lab, name)["panther_ros"]
    assert ctr["state"] == "running" and not any("controller_config_path" in w for w in ctr["cmd"])
    assert not any(t.startswith("/config") for t in ctr["mounts"])
    assert lab.read_bytes(name, "/home/husarion/config/panther_controller/config/my_controller.yaml") == \
        mine.read_bytes()


def test_restore_defaults_22_without_the_script_restores_config(lab: Any, pristine: None,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), robot_of(lab, "2.2.2")
    before = tree(lab, name)
    old = containers(lab, name)["husarion_ugv_ros"]
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "restore-defaults", "-r", name, "--yes", "--settle", "1",
                              "--json")
    assert code == 3, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "rolled-back"
    assert "update_config_directory: not found" in res["message"]
    archive = res["data"]["archive"]
    assert archive == f"/home/husarion/.panther-ops/backups/{res['data']['backup']}/config.tar.gz"
    assert f"/home/husarion/config restored from {archive}" in res["message"]
    assert tree(lab, name) == before
    assert containers(lab, name)["husarion_ugv_ros"]["id"] == old["id"]
    listing = lab.exec(name, ["tar", "-tzf", archive], user="husarion", check=True).stdout
    assert "config/common/.env" in listing


UPDATE_CONFIG_STANDIN = """#!/bin/sh
# stand-in of husarion_ugv_ros' update_config_directory: defaults into /config, owned by the robot user
set -e
mkdir -p /config/husarion_ugv_controller/config /config/husarion_ugv_lights/config
echo "# default from the image" > /config/husarion_ugv_controller/config/WH01_controller.yaml
echo "robot_model: $ROBOT_MODEL_NAME" > /config/husarion_ugv_lights/config/model.yaml
chown -R 1000:1000 /config
"""


@pytest.fixture
def image_with_script(lab: Any, tmp_path: Path) -> Iterator[str]:
    """The 2.2 robot's driver tag, re-pointed at the stand-in image plus an update_config_directory script."""
    name = robot_of(lab, "2.2.2")
    original = lab.docker(name, "image", "inspect", "-f", "{{.Id}}", UGV_IMAGE, check=True).stdout.strip()
    script = tmp_path / "update_config_directory"
    script.write_text(UPDATE_CONFIG_STANDIN)
    script.chmod(0o755)
    lab.docker(name, "rm", "-f", "mk-ucd")
    lab.docker(name, "create", "--name", "mk-ucd", UGV_IMAGE, check=True)
    lab.docker(name, "cp", str(script), "mk-ucd:/usr/local/bin/update_config_directory", check=True)
    made = lab.docker(name, "commit", "--change", 'ENTRYPOINT ["/ros_entrypoint.sh"]', "--change",
                      'CMD ["ros2", "launch", "--help"]', "mk-ucd", UGV_IMAGE, check=True).stdout.strip()
    lab.docker(name, "rm", "-f", "mk-ucd")
    try:
        yield name
    finally:
        lab.docker(name, "tag", original, UGV_IMAGE, check=True)
        lab.compose(name, "up", "-d", "--force-recreate")
        lab.docker(name, "rmi", made)


def test_restore_defaults_22_hard_runs_the_image_script(lab: Any, pristine: None, image_with_script: str,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    inv, name = str(lab.inventory_path), image_with_script
    lab.sh(name, "echo 'mine: 1' > /home/husarion/config/extra.yaml && chown husarion: /home/husarion/config/extra.yaml")
    env_before = lab.read(name, "/home/husarion/config/common/.env")
    before = tree(lab, name)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "restore-defaults", "--hard", "-r", name, "--yes",
                              "--settle", "1", "--json")
    assert code == 0, doc
    (res,) = doc["robots"]
    assert res["outcome"] == "changed" and res["message"].startswith("defaults restored in /home/husarion/config")
    assert res["message"].endswith(f"previous /home/husarion/config in {res['data']['archive']}")
    assert lab.read(name, "/home/husarion/config/husarion_ugv_controller/config/WH01_controller.yaml") == \
        "# default from the image\n"
    assert lab.read(name, "/home/husarion/config/husarion_ugv_lights/config/model.yaml") == "robot_model: panther\n"
    assert lab.read(name, "/home/husarion/config/common/.env") == env_before
    assert lab.sh(name, "[ -e /home/husarion/config/extra.yaml ] && echo yes || echo no").stdout.strip() == "no"
    assert containers(lab, name)["husarion_ugv_ros"]["state"] == "running"
    lab.sh(name, f"rm -rf /tmp/r && mkdir /tmp/r && tar -xzpf {res['data']['archive']} -C /tmp/r", check=True)
    assert tree(lab, name, "/tmp/r") == before  # the archive holds ~/config as it was (extra.yaml included)
    code, doc, _, _ = run_cli(capsys, "-i", inv, "config", "history", "-r", name, "--json")
    (entry,) = doc["robots"][0]["data"]["history"]
    assert entry["command"] == "config restore-defaults --hard" and entry["status"] == "applied"


def test_logs_follow_ends_cleanly_on_ctrl_c(lab: Any) -> None:
    name = robot_of(lab, "2.2.2")
    proc = subprocess.Popen([sys.executable, "-m", "panther_ops.cli.app", "-i", str(lab.inventory_path), "driver",
                             "logs", "-r", name, "-f", "-n", "1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        first = proc.stdout.readline() if proc.stdout else b""
        assert first.strip(), "the last line of the log comes first"
        marker = f"followed-{time.monotonic_ns()}"
        lab.docker(name, "exec", "husarion_ugv_ros", "sh", "-c", f"echo {marker} > /proc/1/fd/1", check=True)
        line = proc.stdout.readline() if proc.stdout else b""
        assert line.decode().strip() == marker
        proc.send_signal(signal.SIGINT)
        _out, err = proc.communicate(timeout=15)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert b"Traceback" not in err and f"{name}: following husarion_ugv_ros (Ctrl-C to stop)".encode() in err
