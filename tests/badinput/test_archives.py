"""The bad-input corpus of `reimage restore --from ARCHIVE`: a backup archive changed or damaged
after `reimage backup` wrote it is refused whole (exit 2), naming the member and what is wrong,
before anything is written on the robot or on this machine.

Every case starts from a real backup of the demo's panther-03 (its compose file customised,
a symbolic link in its config tree): restored untampered, it writes the compose file back
(``test_the_untampered_archive_is_restored``), so a tampered one that was not refused would
change a file the harness watches.
"""

from __future__ import annotations

import tarfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from panther_ops.cli.app import main
from tests.badinput import archives as a
from tests.badinput.harness import DEMO, Case, check_refused, prepare

RESTORE = ["reimage", "restore", "-r", a.ROBOT, "--from", "{tmp}/bk.tar.gz", "--yes"]
SHA = "0" * 64


@pytest.fixture(scope="module")
def base(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    return a.demo_backup(tmp_path_factory.mktemp("backup"))


@dataclass(frozen=True)
class Tampered:
    id: str
    tamper: a.Tamper | Callable[[bytes], bytes]
    names: Sequence[str]
    args: Sequence[str] = tuple(RESTORE)
    inventory: str | None = None
    whole: bool = False
    """``tamper`` changes the archive's bytes, not its list of members."""

    def __str__(self) -> str:
        return self.id


def _grown(info: tarfile.TarInfo, data: bytes) -> tuple[tarfile.TarInfo, bytes]:
    return info, data + b"# one line more\n"


def _flipped(info: tarfile.TarInfo, data: bytes) -> tuple[tarfile.TarInfo, bytes]:
    return info, data.replace(b"husarion", b"HUSARION", 1)


def _setuid(info: tarfile.TarInfo, data: bytes) -> tuple[tarfile.TarInfo, bytes]:
    info.mode = 0o4755
    return info, data


def _relinked(info: tarfile.TarInfo, data: bytes) -> tuple[tarfile.TarInfo, bytes]:
    info.linkname = "/root/.ssh/authorized_keys"
    return info, data


def _size_plus_one(doc: dict[str, Any]) -> None:
    a.file_entry(doc, a.ENV)["size"] += 1


def _listed_twice(doc: dict[str, Any]) -> None:
    doc["files"].append(dict(a.file_entry(doc, a.ENV)))


def _no_sha256(doc: dict[str, Any]) -> None:
    del a.file_entry(doc, a.ENV)["sha256"]


def _under_link(ms: list[a.Member]) -> list[a.Member]:
    """A file listed (and held) under the path the manifest lists as a symbolic link."""
    under = a.LINK + "/x"

    def listed(doc: dict[str, Any]) -> None:
        doc["files"].append({**a.file_entry(doc, a.ENV), "path": under[len("files"):]})

    env = next(m for m in ms if m[0].name == a.ENV)
    return a.manifest_edited(listed)([*ms, a.entry(under, env[1])])


def _unclean(ms: list[a.Member]) -> list[a.Member]:
    """A file listed (and held) under an unclean path: ``//home/...``."""
    def listed(doc: dict[str, Any]) -> None:
        a.file_entry(doc, a.ENV)["path"] = "//home/husarion/config/common/.env"

    def renamed(info: tarfile.TarInfo, data: bytes) -> tuple[tarfile.TarInfo, bytes]:
        info.name = "files//home/husarion/config/common/.env"
        return info, data

    return a.manifest_edited(listed)(a.changed(a.ENV, renamed)(ms))


SSH_INVENTORY = "version: 1\nrobots:\n  panther-03: {{host: panther-07}}\n"
"""The backup's robot reached over SSH, never contacted: the archive is refused before the inventory is read."""

CASES = [
    # members outside the manifest: paths out of the archive's root, links, special files, extras
    Tampered("archive-member-dotdot", a.added(a.entry("../../x", b"owned\n")), ["member '../../x'", "'..'"]),
    Tampered("archive-member-dotdot-inside", a.added(a.entry("files/home/husarion/../../../etc/cron.d/x", b"* * *\n")),
             ["member 'files/home/husarion/../../../etc/cron.d/x'", "climbs out of the archive's root"]),
    Tampered("archive-member-absolute", a.added(a.entry("/etc/cron.d/x", b"* * *\n")),
             ["member '/etc/cron.d/x'", "absolute path"]),
    Tampered("archive-member-symlink", a.added(a.entry("files/home/husarion/.ssh", kind=tarfile.SYMTYPE,
                                                       linkname="/root/.ssh")),
             ["member 'files/home/husarion/.ssh'", "symbolic link to '/root/.ssh'", "manifest does not list"]),
    Tampered("archive-member-hardlink", a.added(a.entry("files/home/husarion/shadow", kind=tarfile.LNKTYPE,
                                                        linkname="/etc/shadow")),
             ["member 'files/home/husarion/shadow'", "hard link to '/etc/shadow'"]),
    Tampered("archive-member-chardev", a.added(a.entry("files/home/husarion/null", kind=tarfile.CHRTYPE)),
             ["member 'files/home/husarion/null'", "character device"]),
    Tampered("archive-member-blockdev", a.added(a.entry("files/home/husarion/sda", kind=tarfile.BLKTYPE)),
             ["member 'files/home/husarion/sda'", "block device"]),
    Tampered("archive-member-fifo", a.added(a.entry("files/home/husarion/pipe", kind=tarfile.FIFOTYPE)),
             ["member 'files/home/husarion/pipe'", "fifo"]),
    Tampered("archive-member-directory", a.added(a.entry("files/home/husarion/.ssh", kind=tarfile.DIRTYPE,
                                                         mode=0o700)),
             ["member 'files/home/husarion/.ssh'", "directory"]),
    Tampered("archive-member-extra-file", a.added(a.entry("files/home/husarion/.bashrc", b"curl x | sh\n")),
             ["member 'files/home/husarion/.bashrc'", "is not in the manifest"]),
    Tampered("archive-member-extra-top", a.added(a.entry("evil.sh", b"#!/bin/sh\n")),
             ["member 'evil.sh'", "is not in the manifest"]),
    # members the manifest lists, but not as it lists them
    Tampered("archive-member-missing", a.dropped(a.ENV),
             [f"member '{a.ENV}': missing", "/home/husarion/config/common/.env is in the manifest but not in the archive"]),
    Tampered("archive-member-twice", a.repeated(a.ENV), [f"member '{a.ENV}'", "in the archive twice"]),
    Tampered("archive-manifest-twice", a.repeated("manifest.json"), ["member 'manifest.json'", "twice"]),
    Tampered("archive-member-size", a.changed(a.ENV, _grown), [f"member '{a.ENV}'", "but the manifest says 359"]),
    Tampered("archive-member-checksum", a.changed(a.COMPOSE, _flipped),
             [f"member '{a.COMPOSE}'", "does not match its sha256 in the manifest (damaged)"]),
    Tampered("archive-member-mode", a.changed(a.ENV, _setuid),
             [f"member '{a.ENV}'", "mode 4755, but the manifest says 0644"]),
    Tampered("archive-member-file-as-link", a.replaced(a.ENV, a.entry(a.ENV, kind=tarfile.SYMTYPE,
                                                                      linkname="/etc/shadow")),
             [f"member '{a.ENV}'", "symbolic link to '/etc/shadow', but the manifest lists a file"]),
    Tampered("archive-member-file-as-hardlink", a.replaced(a.ENV, a.entry(a.ENV, kind=tarfile.LNKTYPE,
                                                                          linkname="/etc/shadow")),
             [f"member '{a.ENV}'", "hard link to '/etc/shadow'"]),
    Tampered("archive-member-link-as-file", a.replaced(a.LINK, a.entry(a.LINK, b"x\n", mode=0o777)),
             [f"member '{a.LINK}'", "is a file, but the manifest lists a symbolic link to '../common/.env'"]),
    Tampered("archive-member-link-retargeted", a.changed(a.LINK, _relinked),
             [f"member '{a.LINK}'", "'/root/.ssh/authorized_keys', but the manifest says it links to '../common/.env'"]),
    # the manifest itself
    Tampered("archive-manifest-not-first", lambda ms: [*ms[1:], ms[0]],
             ["not a panther-ops backup", f"its first member is '{a.COMPOSE}'", "manifest.json"]),
    Tampered("archive-manifest-size", a.manifest_edited(_size_plus_one),
             [f"member '{a.ENV}'", "holds 359 bytes, but the manifest says 360"]),
    Tampered("archive-manifest-listed-twice", a.manifest_edited(_listed_twice),
             ["manifest.json", "/home/husarion/config/common/.env is listed twice"]),
    Tampered("archive-manifest-no-sha256", a.manifest_edited(_no_sha256),
             ["manifest.json", ".sha256: None", "64 lower-case hexadecimal digits"]),
    Tampered("archive-manifest-under-link", _under_link,
             ["manifest.json", "which the manifest lists as a symbolic link"]),
    Tampered("archive-manifest-unclean-path", _unclean,
             ["manifest.json", "'//home/husarion/config/common/.env' is not a clean path"]),
    Tampered("archive-manifest-not-json", a.manifest_edited(lambda doc: b"{\"version\": 1,"),
             ["manifest.json", "not JSON"]),
    Tampered("archive-manifest-version", a.manifest_edited(lambda doc: doc.update(version=2)),
             ["manifest.json", "version 2", "reads version 1"]),
    # data after the last member: tarfile stops quietly at a header it cannot read
    Tampered("archive-junk-after-the-end", a.appended(b"\x01" * 512 + b"rm -rf ~\n"),
             ["member 'files/home/husarion/", "followed by data that is not a member"], whole=True),
    Tampered("archive-second-archive-appended",
             a.appended(a.second_archive(a.entry("files/home/husarion/.bashrc", b"curl x | sh\n"))),
             ["member 'files/home/husarion/", "followed by data that is not a member"], whole=True),
    Tampered("archive-gzip-crc", a.crc_broken, ["not a readable backup archive", "CRC"], whole=True),
    # whatever else the command is given
    Tampered("archive-dry-run", a.added(a.entry("../../x", b"owned\n")), ["member '../../x'"],
             args=[*RESTORE[:-1], "--dry-run"]),
    Tampered("archive-ssh-robot", a.added(a.entry("files/home/husarion/.ssh", kind=tarfile.SYMTYPE,
                                                  linkname="/root/.ssh")),
             ["member 'files/home/husarion/.ssh'"], inventory=SSH_INVENTORY),
]


def test_the_corpus_is_unique() -> None:
    assert len({c.id for c in CASES}) == len(CASES) >= 30


def test_the_untampered_archive_is_restored(base: bytes, tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    """The corpus's base: restored as it is, it writes the robot's customised compose file back
    (a tampered archive that was not refused would change a watched file)."""
    args = prepare(Case("base", RESTORE, [], files={"bk.tar.gz": base}), tmp_path)
    compose = tmp_path / DEMO / "robots" / a.ROBOT / "home/husarion/compose.yaml"
    assert not compose.read_text().endswith(a.CUSTOMISED)
    code = main(args)
    assert code == 0, capsys.readouterr()
    assert compose.read_text().endswith(a.CUSTOMISED)
    assert "not restored: /home/husarion/config/husarion_ugv_lights/env-link (a symbolic link)" in \
        " ".join(capsys.readouterr().err.split())
    assert not (compose.parent / "config/husarion_ugv_lights/env-link").exists()


def test_repacking_keeps_an_archive_as_it_was(base: bytes, tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """The tampering tools change nothing by themselves: repacked untouched, the archive restores."""
    args = prepare(Case("repacked", RESTORE, [], files={"bk.tar.gz": a.tampered(base, lambda ms: ms)}), tmp_path)
    assert main(args) == 0, capsys.readouterr()


@pytest.mark.parametrize("case", CASES, ids=str)
def test_refused(case: Tampered, base: bytes, tmp_path: Path, capsys: pytest.CaptureFixture[str],
                 monkeypatch: pytest.MonkeyPatch) -> None:
    archive = case.tamper(base) if case.whole else a.tampered(base, case.tamper)  # type: ignore[arg-type]
    err = check_refused(Case(case.id, case.args, case.names, files={"bk.tar.gz": archive},
                             inventory=case.inventory), tmp_path, capsys, monkeypatch)
    assert "bk.tar.gz" in err
