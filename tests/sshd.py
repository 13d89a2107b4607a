"""A real OpenSSH sshd on loopback (no namespaces, no lab): keys only, one authorized_keys file,
for tests of how connecting goes wrong (a key refused, no key offered, a host key unknown).

It logs in as the user running the tests (root here: ``PermitRootLogin prohibit-password``);
the commands panther-ops would run after logging in are not what these tests look at.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path

from tests.ports import free_port

SSHD = shutil.which("sshd") or "/usr/sbin/sshd"


def missing() -> str | None:
    """Why a loopback sshd cannot run here, or None."""
    if not os.path.exists(SSHD) or not shutil.which("ssh-keygen"):
        return "OpenSSH's sshd and ssh-keygen are needed"
    if os.geteuid() != 0:
        return "sshd runs as root"
    return None


def keygen(path: Path) -> Path:
    """A new ed25519 key pair without a passphrase at ``path`` (and ``path``.pub)."""
    subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-C", path.name, "-f", str(path)], check=True)
    return path


class LoopbackSshd:
    """sshd on 127.0.0.1:``port`` with its own host key; ``authorize(key)`` lets a key in and
    ``known_hosts`` is a file that knows the host key (as ``panther-ops trust`` would write it)."""

    def __init__(self, root: Path, extra: Sequence[str] = ()) -> None:
        """``extra``: more sshd_config lines (e.g. an AuthorizedKeysCommand)."""
        self.root = root
        root.mkdir(parents=True, exist_ok=True)
        self.port = free_port()
        self.host_key = keygen(root / "ssh_host_ed25519_key")
        self.authorized_keys = root / "authorized_keys"
        self.authorized_keys.write_text("")
        self.known_hosts = root / "known_hosts"
        self.known_hosts.write_text(f"[127.0.0.1]:{self.port} " + " ".join(
            (root / "ssh_host_ed25519_key.pub").read_text().split()[:2]) + "\n")
        config = root / "sshd_config"
        config.write_text("\n".join([
            f"ListenAddress 127.0.0.1:{self.port}",
            f"HostKey {self.host_key}",
            f"PidFile {root / 'sshd.pid'}",
            f"AuthorizedKeysFile {self.authorized_keys}",
            "PubkeyAuthentication yes",
            "PasswordAuthentication no",
            "KbdInteractiveAuthentication no",
            "UsePAM no",
            "PermitRootLogin prohibit-password",
            "StrictModes no",
            "LogLevel VERBOSE",
            *extra,
        ]) + "\n")
        Path("/run/sshd").mkdir(exist_ok=True)  # its privilege-separation directory
        with (root / "sshd.log").open("wb") as log:
            self.proc = subprocess.Popen([SSHD, "-D", "-e", "-f", str(config)], stderr=log)
        deadline = time.monotonic() + 5
        while "Server listening" not in (root / "sshd.log").read_text(errors="replace"):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.close()
                raise RuntimeError("sshd did not start: " + (root / "sshd.log").read_text(errors="replace"))
            time.sleep(0.02)

    def authorize(self, key: Path) -> None:
        with self.authorized_keys.open("a") as fh:
            fh.write(Path(f"{key}.pub").read_text())

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(5)
