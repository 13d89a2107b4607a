"""``desired.shutdown_hosts`` converged by `apply` and shown by `config diff` (issue 24: it was
accepted and documented, but nothing applied it): the robot's hosts file lists exactly the
inventory's hosts, in the format of the robot's release, through the hosts file's validator."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from panther_ops.cli.app import main

ROBOTS = """  panther-01:
    transport: local
    root: robots/panther-01
    groups: [warehouse]
"""
P03 = """    root: robots/panther-03
    groups: [field]
"""
HOSTS_21 = "home/husarion/config/panther_manager/config/shutdown_hosts_config.yaml"
HOSTS_22 = "home/husarion/config/husarion_ugv_manager/config/shutdown_hosts.yaml"


@pytest.fixture
def fleet(demo: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """panther-01 (2.1.1, the image's default file) wants one SSH host; panther-03 (2.2.2, the
    config tree's file) wants its User Computer with a secret from the environment."""
    monkeypatch.setenv("NUC_SECRET", "s3cr3t-nuc")
    inv = demo / "inventory.yaml"
    text = inv.read_text()
    assert ROBOTS in text and P03 in text
    text = text.replace(ROBOTS, ROBOTS + "    desired:\n      shutdown_hosts:\n"
                        "        - {ip: 10.15.20.4, username: husarion, timeout: 15.0}\n")
    text = text.replace(P03, P03 + "    desired:\n      shutdown_hosts:\n"
                        "        - {ip: 10.15.20.3, port: 3003, secret: {env: NUC_SECRET}}\n")
    inv.write_text(text)
    return demo


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, dict[str, object]], str]:
    capsys.readouterr()
    code = main([*argv, "--json"])
    out, err = capsys.readouterr()
    return code, {r["robot"]: r for r in json.loads(out).get("robots", [])}, err  # an error: its document


def test_config_diff_shows_the_hosts_change(fleet: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, robots, _ = run(capsys, "-i", str(fleet), "config", "diff", "-r", "panther-01", "-r", "panther-03")
    assert code == 0
    one, three = robots["panther-01"], robots["panther-03"]
    assert "shutdown hosts: removed husarion@10.15.20.3; added husarion@10.15.20.4" in str(one["message"])
    paths = [d["path"] for d in one["diffs"]]  # type: ignore[union-attr]
    assert paths == ["/home/husarion/compose.yaml", f"/{HOSTS_21}"]  # the default pushed, mounted, pointed at
    assert "shutdown_hosts_config_path:=/config/panther_manager/config/shutdown_hosts_config.yaml" in str(
        one["message"])
    assert three["message"] == "would change: shutdown hosts: updated http://10.15.20.3: secret"
    (diff,) = three["diffs"]  # type: ignore[misc]
    assert "+    secret: ****" in diff["unified"] and "s3cr3t" not in json.dumps(robots)
    assert not (fleet / "robots/panther-01" / HOSTS_21).exists(), "config diff writes nothing"


def test_apply_converges_and_a_second_run_changes_nothing(fleet: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, robots, _ = run(capsys, "-i", str(fleet), "apply", "-r", "panther-01", "-r", "panther-03", "--yes")
    assert code == 0 and {r["outcome"] for r in robots.values()} == {"changed"}
    one = yaml.safe_load((fleet / "robots/panther-01" / HOSTS_21).read_text())
    assert one == {"hosts": [{"ip": "10.15.20.4", "username": "husarion", "timeout": 15.0}]}
    three = yaml.safe_load((fleet / "robots/panther-03" / HOSTS_22).read_text())
    assert three["hosts"] == [{"ip": "10.15.20.3", "port": 3003, "timeout": 10.0, "secret": "s3cr3t-nuc"}]
    compose = (fleet / "robots/panther-01/home/husarion/compose.yaml").read_text()
    assert f"/{HOSTS_21}:/config/panther_manager/config/shutdown_hosts_config.yaml:ro" in compose
    code, robots, _ = run(capsys, "-i", str(fleet), "apply", "-r", "panther-01", "-r", "panther-03", "--yes")
    assert code == 0 and {r["message"] for r in robots.values()} == {"matches the inventory's desired state"}


def test_an_entry_of_the_other_release_is_refused_naming_the_file(fleet: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    """An SSH entry (username) on a 2.2.2 robot, whose manager calls hosts over HTTP: exit 2,
    the robot's file named, nothing written on any robot."""
    inv = fleet / "inventory.yaml"
    inv.write_text(inv.read_text().replace("{ip: 10.15.20.3, port: 3003, secret: {env: NUC_SECRET}}",
                                           "{ip: 10.15.20.3, username: husarion}"))
    before = (fleet / "robots/panther-03" / HOSTS_22).read_bytes()
    code, _, err = run(capsys, "-i", str(fleet), "apply", "-r", "panther-01", "-r", "panther-03", "--yes")
    assert code == 2 and HOSTS_22 in err
    assert (fleet / "robots/panther-03" / HOSTS_22).read_bytes() == before
    assert not (fleet / "robots/panther-01" / HOSTS_21).exists()


def test_a_secret_that_is_not_set_is_named(fleet: Path, capsys: pytest.CaptureFixture[str],
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("NUC_SECRET")
    code, _, err = run(capsys, "-i", str(fleet), "apply", "-r", "panther-03", "--yes")
    assert code == 2 and "desired.shutdown_hosts[0].secret: environment variable NUC_SECRET is not set" in err
