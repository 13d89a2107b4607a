"""`trust ROBOT` is an ordinary change (issue 28): its subject is the robot's host key in the
operator's known_hosts file, planned from the key a real sshd on loopback offers, shown as the
exact edit of that file, confirmed, and written by the pipeline (backup beside it, atomic
rename); no trusted connection to the robot is needed, since there is none yet."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.clirun import run_cli
from tests.sshd import LoopbackSshd, keygen

Capsys = pytest.CaptureFixture[str]
ROBOT = "newkey-05"


def _other_key(tmp_path: Path) -> str:
    """A valid ed25519 public key that is not the sshd's (type and base64)."""
    return " ".join(keygen(tmp_path / "other").with_suffix(".pub").read_text().split()[:2])


def _inventory(tmp_path: Path, port: int, kh: Path) -> str:
    inv = tmp_path / "inv.yaml"
    inv.write_text(f"settings: {{known_hosts: {kh}}}\nrobots:\n  {ROBOT}:\n    host: 127.0.0.1\n"
                   f"    port: {port}\n    user: root\n    connect_timeout: 2\n")
    return str(inv)


def test_trust_plans_the_known_hosts_edit_and_the_pipeline_writes_it(
        sshd: LoopbackSshd, tmp_path: Path, capsys: Capsys) -> None:
    kh = tmp_path / "ssh" / "known_hosts"
    kh.parent.mkdir()
    mine = f"# mine\nother.example {_other_key(tmp_path)}\n"
    kh.write_text(mine)
    inv = _inventory(tmp_path, sshd.port, kh)
    line = sshd.known_hosts.read_text()  # what the sshd offers, as known_hosts names it
    code, doc, _, err = run_cli(capsys, "-i", inv, "trust", ROBOT, "--json")  # nobody to answer
    assert code == doc["exit_code"] == 2 and "pass --yes" in doc["error"]["message"], err
    assert kh.read_text().count("\n") == 2
    code, doc, _, err = run_cli(capsys, "-i", inv, "trust", ROBOT, "--dry-run", "--json")
    (res,) = doc["robots"]
    assert code == 0 and res["outcome"] == "changed" and res["data"]["state"] == "new", err
    assert res["data"]["known_hosts_file"] == str(kh) and res["data"]["known_fingerprints"] == []
    assert res["diffs"][0]["path"] == str(kh) and "+" + line.strip() in res["diffs"][0]["unified"]
    assert kh.read_text().count("\n") == 2  # a dry run writes nothing
    code, doc, _, err = run_cli(capsys, "-i", inv, "trust", ROBOT, "--yes", "--json")
    assert code == 0 and doc["command"] == "trust" and doc["robots"][0]["outcome"] == "changed", err
    assert kh.read_text() == mine + line
    assert kh.stat().st_mode & 0o777 == 0o600
    backups = list((kh.parent / ".panther-ops" / "backups").iterdir())
    assert len(backups) == 1 and (backups[0] / "manifest.json").exists()
    code, doc, _, _ = run_cli(capsys, "-i", inv, "trust", ROBOT, "--json")
    (res,) = doc["robots"]
    assert code == 0 and res["outcome"] == "ok" and res["data"]["state"] == "known"
    code, doc, _, err = run_cli(capsys, "-i", inv, "status", "--json")  # now the robot's key is trusted
    assert "not in known_hosts" not in doc["robots"][0]["message"], doc


def test_a_changed_key_is_refused_unless_replace(sshd: LoopbackSshd, tmp_path: Path, capsys: Capsys) -> None:
    kh = tmp_path / "known_hosts"
    name = f"[127.0.0.1]:{sshd.port}"
    old = f"{name} {_other_key(tmp_path)}\n"
    kh.write_text("# hashed lines and comments are kept\n" + old)
    inv = _inventory(tmp_path, sshd.port, kh)
    code, doc, _, err = run_cli(capsys, "-i", inv, "trust", ROBOT, "--yes", "--json")
    (res,) = doc["robots"]
    assert code == 4 and "host key changed: refused" in res["message"], err
    assert f"trust {ROBOT} --replace" in res["data"]["hint"]
    assert kh.read_text().endswith(old)  # nothing recorded
    code, doc, _, err = run_cli(capsys, "-i", inv, "trust", ROBOT, "--replace", "--yes", "--json")
    (res,) = doc["robots"]
    assert code == 0 and res["data"]["state"] == "changed" and len(res["data"]["known_fingerprints"]) == 1, err
    assert kh.read_text() == "# hashed lines and comments are kept\n" + sshd.known_hosts.read_text()
