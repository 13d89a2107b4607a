"""`config history --file FILE` and `config rollback --file FILE`: a local hosts file's backups
(kept beside it by `shutdown hosts add|remove FILE`) listed and restored through the change
pipeline, on real temporary directories. Addresses are RFC 5737 documentation addresses."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from panther_ops.cli.app import main
from tests.badinput.harness import tree_hashes

START = "# the bench\nhosts:\n  - ip: 192.0.2.3\n    username: husarion\n"


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, " ".join(err.split())  # rich wraps long lines


def add(capsys: pytest.CaptureFixture[str], file: Path, *args: str) -> str:
    """``shutdown hosts add FILE ... --yes``: the id of the backup it left."""
    code, out, err = run(capsys, "shutdown", "hosts", "add", str(file), *args, "--yes", "--json")
    assert code == 0, err
    return str(json.loads(out)["robots"][0]["data"]["backup"])


def history(capsys: pytest.CaptureFixture[str], file: Path) -> list[dict[str, object]]:
    code, out, err = run(capsys, "config", "history", "--file", str(file), "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert [r["robot"] for r in doc["robots"]] == [str(file)]
    return list(doc["robots"][0]["data"]["history"])


@pytest.fixture
def hosts(tmp_path: Path) -> Path:
    path = tmp_path / "hosts.yaml"
    path.write_text(START)
    return path


def test_history_lists_the_files_backups_newest_last(hosts: Path, capsys: pytest.CaptureFixture[str],
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    first = add(capsys, hosts, "--ip", "192.0.2.5", "--user", "pi")
    second = add(capsys, hosts, "--ip", "192.0.2.6", "--user", "pi")  # often in the same second
    other = hosts.parent / "other.yaml"  # another hosts file of the same directory: its own history
    add(capsys, other, "--ip", "192.0.2.9", "--user", "pi")
    entries = history(capsys, hosts)
    assert [e["id"] for e in entries] == [first, second]
    assert [e["command"] for e in entries] == ["shutdown hosts add pi@192.0.2.5", "shutdown hosts add pi@192.0.2.6"]
    assert all(e["status"] == "applied" and e["created"] for e in entries)
    assert entries[0]["files"][0]["path"] == str(hosts.resolve())  # type: ignore[index]
    assert [e["command"] for e in history(capsys, other)] == ["shutdown hosts add pi@192.0.2.9"]
    monkeypatch.chdir(hosts.parent)  # the file named as an operator in its directory would
    code, out, _ = run(capsys, "config", "history", "--file", "hosts.yaml")
    assert code == 0 and first in out and second in out and "shutdown hosts add pi@192.0.2.6" in out
    # a file never edited: no backups yet
    code, out, _ = run(capsys, "config", "history", "--file", str(hosts.parent / "new.yaml"))
    assert code == 0 and "no backups yet" in out


def test_rollback_plans_the_exact_diff_then_restores_through_the_pipeline(
        hosts: Path, capsys: pytest.CaptureFixture[str]) -> None:
    add(capsys, hosts, "--ip", "192.0.2.5", "--user", "pi")
    after_first = hosts.read_text()
    newest = add(capsys, hosts, "--ip", "192.0.2.6", "--user", "pi")
    before = tree_hashes(hosts.parent)
    code, out, err = run(capsys, "config", "rollback", "--file", str(hosts), "--dry-run", "--json")
    assert code == 0, err
    res = json.loads(out)["robots"][0]
    assert res["outcome"] == "changed" and res["data"]["backup_restored"] == newest
    assert res["diffs"][0]["unified"].endswith("     username: pi\n-  - ip: 192.0.2.6\n-    username: pi\n")
    assert tree_hashes(hosts.parent) == before  # a dry run writes nothing
    code, _, err = run(capsys, "config", "rollback", "--file", str(hosts))  # stdin is no terminal, no --yes
    assert code == 2 and "--yes" in err and tree_hashes(hosts.parent) == before
    current = hosts.read_text()
    code, out, err = run(capsys, "config", "rollback", "--file", str(hosts), "--yes", "--json")
    assert code == 0, err
    res = json.loads(out)["robots"][0]
    assert res["outcome"] == "changed" and hosts.read_text() == after_first
    # the state it replaced was backed up first: the rollback is in the history and can be undone
    bdir = hosts.parent / ".panther-ops" / "backups" / res["data"]["backup"]
    assert (bdir / "files" / "0").read_text() == current
    entries = history(capsys, hosts)
    assert entries[-1]["id"] == res["data"]["backup"] and entries[-1]["command"] == "config rollback"
    assert entries[-1]["summary"] == f"restore backup {newest} (before: shutdown hosts add pi@192.0.2.6)"
    code, out, _ = run(capsys, "config", "rollback", "--file", str(hosts), "--to", newest, "--yes", "--json")
    assert code == 0 and json.loads(out)["robots"][0]["outcome"] == "ok"  # already as before it
    assert not [p for p in hosts.parent.iterdir() if ".panther-ops." in p.name]  # nothing staged left


def test_rollback_to_an_id_or_prefix_and_the_creation_of_the_file(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    new = tmp_path / "new.yaml"
    created = add(capsys, new, "--ip", "192.0.2.5", "--user", "pi")  # the file did not exist
    add(capsys, new, "--ip", "192.0.2.6", "--user", "pi")
    code, _, err = run(capsys, "config", "rollback", "--file", str(new), "--to", created[:-2], "--yes", "--json")
    assert code == 0, err
    assert not new.exists()  # as before the change that created it
    code, _, err = run(capsys, "config", "rollback", "--file", str(new), "--yes", "--json")  # undo the rollback
    assert code == 0, err
    assert "192.0.2.6" in new.read_text() and new.stat().st_mode & 0o777 == 0o600  # it may hold a secret


def test_a_rollback_masks_secrets_and_validates_what_it_restores(hosts: Path,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    hosts.write_text("hosts:\n  - ip: 192.0.2.5\n    port: 3003\n    secret: bench-secret-value\n")
    backup = add(capsys, hosts, "--ip", "192.0.2.6", "--http", "--secret-env", "NUC_SECRET")
    hosts.write_text("hosts:\n  - ip: 192.0.2.5\n    port: 3003\n    secret: another-secret-value\n")
    code, out, err = run(capsys, "config", "rollback", "--file", str(hosts), "--dry-run")
    assert code == 0, err
    assert "secret: ****" in out and "secret-value" not in out + err
    # a backup whose content is no valid hosts file is not written back
    (hosts.parent / ".panther-ops" / "backups" / backup / "files" / "0").write_text(
        "hosts:\n  - ip: '192.0.2.5; reboot'\n    username: pi\n")
    before = tree_hashes(hosts.parent)
    code, _, err = run(capsys, "config", "rollback", "--file", str(hosts), "--yes")
    assert code == 2 and "hosts.yaml" in err and "'192.0.2.5; reboot' is not an IP address" in err
    assert tree_hashes(hosts.parent) == before


def test_a_backup_naming_another_file_is_never_offered(hosts: Path, capsys: pytest.CaptureFixture[str]) -> None:
    add(capsys, hosts, "--ip", "192.0.2.5", "--user", "pi")
    victim = hosts.parent / "victim.txt"
    victim.write_text("keep me\n")
    forged = hosts.parent / ".panther-ops" / "backups" / "20991231T235959Z-abcd"  # the newest, if it counted
    (forged / "files").mkdir(parents=True)
    (forged / "files" / "0").write_text("overwritten\n")
    manifest = {"id": forged.name, "created": "2099-12-31T23:59:59+00:00", "command": "x", "summary": "x",
                "recreate": ["panther_ros"], "files": [{"path": str(victim), "backup": "files/0"}]}
    (forged / "manifest.json").write_text(json.dumps(manifest))
    assert forged.name not in [e["id"] for e in history(capsys, hosts)]
    before = tree_hashes(hosts.parent)
    code, _, err = run(capsys, "config", "rollback", "--file", str(hosts), "--to", "20991231", "--yes")
    assert code == 2 and f"backup {forged.name} is not a backup of {hosts}" in err and str(victim) in err
    assert tree_hashes(hosts.parent) == before
    code, out, err = run(capsys, "config", "rollback", "--file", str(hosts), "--yes", "--json")  # the newest of hosts
    assert code == 0, err
    assert victim.read_text() == "keep me\n" and json.loads(out)["robots"][0]["diffs"][0]["path"] == \
        str(hosts.resolve())


@pytest.mark.parametrize(("args", "named"), [
    (["--to", "20991231"], ["backup '20991231' not found for {file}", "newest backups: "]),
    (["--to", "../../etc"], ["--to", "'../../etc'", "backup id"]),
    (["-r", "panther-01"], ["either --file FILE", "not both"]),
])
def test_bad_ids_and_selections_exit_2(hosts: Path, capsys: pytest.CaptureFixture[str], args: list[str],
                                       named: list[str]) -> None:
    add(capsys, hosts, "--ip", "192.0.2.5", "--user", "pi")
    before = tree_hashes(hosts.parent)
    code, _, err = run(capsys, "config", "rollback", "--file", str(hosts), *args, "--yes")
    assert code == 2
    for text in named:
        assert text.format(file=hosts) in err, err
    assert tree_hashes(hosts.parent) == before


def test_bad_files_exit_2_naming_what_is_allowed(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for file, named in ((tmp_path, "is a directory"), (tmp_path / "no" / "hosts.yaml", "does not exist"),
                        (tmp_path / "a\nb.yaml", "control character"), (fifo, "not a regular file")):
        for command in (["config", "history"], ["config", "rollback", "--yes"]):
            code, _, err = run(capsys, *command, "--file", str(file))
            assert code == 2 and named in err and "shutdown hosts add|remove FILE" in err, (file, err)
    code, _, err = run(capsys, "config", "rollback", "--file", str(tmp_path / "hosts.yaml"), "--yes")
    assert code == 2 and "no backups of" in err and ".panther-ops/backups/" in err


def test_a_file_changed_since_the_rollback_was_planned_is_not_written(hosts: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan
    from panther_ops.core.fleet.runner import RobotContext, open_transport
    from panther_ops.core.shutdown.localfile import local_target, plan_local_rollback
    from panther_ops.results import Outcome

    add(capsys, hosts, "--ip", "192.0.2.5", "--user", "pi")
    inv, target = local_target(hosts, "--file")
    transport = open_transport(inv, target)
    transport.connect()
    try:
        ctx = RobotContext(target, transport, inv)
        plan = plan_local_rollback(ctx, hosts, None)
        assert plan.recreate == () and plan.edits[0].after == START.encode()
        hosts.write_text(hosts.read_text() + "# edited meanwhile\n")
        res = apply_plan(ctx, plan, ApplyOptions(restart=False, command="config rollback"))
    finally:
        transport.close()
    assert res.outcome is Outcome.FAILED and "changed on the robot since it was read" in res.message
    assert hosts.read_text().endswith("# edited meanwhile\n")


def test_a_moved_directory_keeps_its_history_and_writes_only_the_file_named(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    first = tmp_path / "first"
    first.mkdir()
    (first / "hosts.yaml").write_text(START)
    backup = add(capsys, first / "hosts.yaml", "--ip", "192.0.2.5", "--user", "pi")
    moved = tmp_path / "moved"
    first.rename(moved)
    first.mkdir()  # a file of the old path, which the manifest still names: never written
    (first / "hosts.yaml").write_text("untouched\n")
    hosts = moved / "hosts.yaml"
    assert [e["id"] for e in history(capsys, hosts)] == [backup]
    code, out, err = run(capsys, "config", "rollback", "--file", str(hosts), "--yes", "--json")
    assert code == 0, err
    assert json.loads(out)["robots"][0]["diffs"][0]["path"] == str(hosts)
    assert hosts.read_text() == START and (first / "hosts.yaml").read_text() == "untouched\n"


def test_a_masked_diff_marks_a_replaced_secret_only() -> None:
    from panther_ops.core.fleet.plan import MaskedFileEdit

    one = b"hosts:\n  - ip: 192.0.2.5\n    port: 3003\n    secret: first-value\n"
    two = one.replace(b"first-value", b"second-value")
    added = one + b"  - ip: 192.0.2.6\n    port: 3003\n    secret: second-value\n"
    diff = MaskedFileEdit("/h.yaml", one, two).diff().unified
    assert "-    secret: **** (old value)\n+    secret: **** (new value)\n" in diff and "value" not in \
        diff.replace("(old value)", "").replace("(new value)", "")
    diff = MaskedFileEdit("/h.yaml", one, added).diff().unified  # a host added: nothing replaced
    assert "+    secret: ****\n" in diff and "(new value)" not in diff and "second" not in diff
