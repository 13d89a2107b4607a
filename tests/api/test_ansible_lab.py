"""Issue-29 acceptance (Deliver 5): the collection panther_ops.fleet, built by
scripts/build-collection.py and installed with ansible-galaxy, run by ansible-core through
ansible-runner against the lab's robots (real sshd): check mode changes nothing and reports the
diff `--dry-run` reports; a run converges; a second run changes nothing; a bad value fails with
panther-ops's message and writes nothing; a canary play (serial 1, max_fail_percentage 0) stops
at the failed robot and leaves the rest untouched."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from panther_ops.core.fleet.inventory_ansible import export_ansible
from panther_ops.core.fleet.inventory_file import load_inventory
from tests.clirun import run_cli
from tests.labtools import COMPOSE, robot_of, robots_put_back

pytestmark = pytest.mark.lab

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent


@pytest.fixture(scope="module")
def collections(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The collection built from this checkout and installed with ansible-galaxy."""
    tmp = tmp_path_factory.mktemp("collection")
    tarball = subprocess.run([sys.executable, str(ROOT / "scripts/build-collection.py"), "--out", str(tmp / "dist")],
                             check=True, capture_output=True, text=True).stdout.strip()
    subprocess.run([str(BIN / "ansible-galaxy"), "collection", "install", tarball, "-p", str(tmp / "installed")],
                   check=True, capture_output=True)
    return tmp / "installed"


@pytest.fixture
def pristine(lab: Any) -> Iterator[None]:
    with robots_put_back(lab):
        yield


def inventory(lab: Any, names: list[str], bad: str | None = None) -> dict[str, Any]:
    """The lab's inventory exported for Ansible (`inventory export --ansible`), ``names`` only, in
    that order; ``bad``: that robot's port is one nothing listens on (it is unreachable)."""
    doc = export_ansible(load_inventory(str(lab.inventory_path)))
    hosts = doc["all"]["hosts"]
    doc["all"] = {"hosts": {n: hosts[n] for n in names}, "vars": doc["all"]["vars"]}
    if bad is not None:
        doc["all"]["hosts"][bad]["ansible_port"] = 1
    return doc


def play(tmp: Path, collections: Path, inv: dict[str, Any], task: dict[str, Any], *,
         check: bool = False) -> dict[str, dict[str, Any]]:
    """One playbook run through ansible-runner (``task``: one task, or a whole play); each
    host's task result (with its event)."""
    import ansible_runner

    playbook = task if "tasks" in task else {"hosts": "all", "gather_facts": False,
                                             "tasks": [{"name": "panther", **task}]}
    (tmp / "project").mkdir(parents=True, exist_ok=True)
    (tmp / "inventory").mkdir(exist_ok=True)
    (tmp / "project/site.yml").write_text(yaml.safe_dump([playbook]))
    (tmp / "inventory/hosts.yml").write_text(yaml.safe_dump(inv))
    env = {"ANSIBLE_COLLECTIONS_PATH": str(collections), "PYTHONPATH": str(ROOT),
           "PATH": f"{BIN}:{os.environ.get('PATH', '')}", "ANSIBLE_HOST_KEY_CHECKING": "True",
           "LC_ALL": "C.UTF-8", "LANG": "C.UTF-8"}  # ansible-core needs a UTF-8 locale
    r = ansible_runner.run(private_data_dir=str(tmp), playbook="site.yml", envvars=env, quiet=True,
                           cmdline="--diff" + (" --check" if check else ""))
    out: dict[str, dict[str, Any]] = {}
    for ev in r.events:
        if ev.get("event") in ("runner_on_ok", "runner_on_failed", "runner_on_unreachable"):
            data = ev["event_data"]
            out[data["host"]] = {**data["res"], "event": ev["event"]}
    return out


def test_check_converge_again_and_bad_value(lab: Any, pristine: None, collections: Path, tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    names = [robot_of(lab, "2.1.1"), robot_of(lab, "2.2.2")]
    inv = inventory(lab, names)
    before = {n: lab.read(n, COMPOSE) for n in names}
    task = {"panther_ops.fleet.config": {"key": "wheel_type", "value": "WH04", "restart": False}}

    # check mode: the plan, the same diff as --dry-run, nothing written
    checked = play(tmp_path / "check", collections, inv, task, check=True)
    code, doc, _, _ = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH04",
                              *[a for n in names for a in ("-r", n)], "--dry-run", "--json")
    assert code == 0, doc
    for r in doc["robots"]:
        res = checked[r["robot"]]
        assert res["changed"] is True and res["outcome"] == "changed", res
        assert res["diff"]["prepared"] == "".join(d["unified"] for d in r["diffs"])
        assert "wheel_type:=WH04" in res["diff"]["prepared"]
    assert {n: lab.read(n, COMPOSE) for n in names} == before

    # a run converges
    ran = play(tmp_path / "run", collections, inv, task)
    for n in names:
        assert ran[n]["changed"] is True and ran[n]["event"] == "runner_on_ok", ran[n]
        assert "wheel_type:=WH04" in lab.read(n, COMPOSE)
    after = {n: lab.read(n, COMPOSE) for n in names}

    # the second run changes nothing
    again = play(tmp_path / "again", collections, inv, task)
    for n in names:
        assert again[n]["changed"] is False and again[n]["outcome"] == "ok", again[n]
    assert {n: lab.read(n, COMPOSE) for n in names} == after

    # a bad value: the task fails with panther-ops's message, nothing is written
    bad = {"panther_ops.fleet.config": {"key": "wheel_type", "value": "WH99", "restart": False}}
    refused = play(tmp_path / "bad", collections, inv, bad)
    code, _, _, err = run_cli(capsys, "-i", str(lab.inventory_path), "config", "set", "wheel_type", "WH99",
                              "-r", names[0], "--yes")
    assert code == 2
    for n in names:
        assert refused[n]["event"] == "runner_on_failed", refused[n]
        assert "WH99" in refused[n]["msg"]
        assert "error " + " ".join(refused[n]["msg"].split()) in " ".join(err.split())  # the CLI's words
    assert {n: lab.read(n, COMPOSE) for n in names} == after


def canary_playbook() -> dict[str, Any]:
    """The canary playbook of docs/ansible.md, as written there."""
    text = (ROOT / "docs/ansible.md").read_text()
    block = text.split("<!-- canary playbook", 1)[1].split("```yaml\n", 1)[1].split("```", 1)[0]
    (doc,) = yaml.safe_load(block)
    return dict(doc)


def test_canary_stops_at_max_fail_percentage(lab: Any, pristine: None, collections: Path, tmp_path: Path) -> None:
    """docs/ansible.md's canary (serial 1, 2, 50%; max_fail_percentage 0) on four robots, the
    second batch holding an unreachable one: batch 1 changed, batch 2 ran (one failed), batch 3
    never started: its robot is untouched."""
    names = [r.name for r in lab.robots if not r.jump][:4]
    assert len(names) == 4
    inv = inventory(lab, names, bad=names[1])
    before = {n: lab.read(n, COMPOSE) for n in names}
    res = play(tmp_path, collections, inv, canary_playbook())
    assert res[names[0]]["changed"] is True and res[names[0]]["outcome"] == "changed", res
    assert res[names[1]]["event"] == "runner_on_failed" and res[names[1]]["outcome"] == "unreachable", res
    assert res[names[2]]["changed"] is True, res  # the same batch as the failed robot
    assert names[3] not in res  # max_fail_percentage: the play ended with batch 2
    for n in (names[0], names[2]):
        assert "wheel_type:=WH02" in lab.read(n, COMPOSE)
    assert lab.read(names[3], COMPOSE) == before[names[3]]
