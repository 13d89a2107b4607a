"""The quick ssh_config reader answers exactly as paramiko's SSHConfig does, or not at all."""

from __future__ import annotations

from pathlib import Path

import paramiko
import pytest

from panther_ops.transport import ssh_config
from panther_ops.transport.base import Endpoint
from panther_ops.transport.ssh_config_read import USED, read_config

LAB_STYLE = "".join(
    f"""
Host r{i:02d}
    HostName 10.200.1.{10 + i}
    User husarion
    Port 22
    IdentityFile /lab/id_ed25519
    IdentitiesOnly yes
    UserKnownHostsFile /lab/known_hosts
    StrictHostKeyChecking yes
    ConnectTimeout 5
"""
    for i in range(1, 31)
)

LAYERED = """
# global settings before any Host apply to every host
ConnectTimeout 7
Host panther-0? !panther-09
    User husarion
    IdentityFile ~/.ssh/fleet_key
Host panther-01 panther-02
    HostName 10.200.9.2
    Port 2201
    IdentityFile ~/.ssh/one
    IdentityFile ~/.ssh/fleet_key
Host panther-02
    HostName ignored.example
    ProxyJump bastion
Host *.lab
    UserKnownHostsFile /etc/fleet/known_hosts ~/.ssh/known_hosts
  Host=bastion
    hostname=bastion.example.com
    PORT = 2022
Host *
    User operator
    IdentityFile ~/.ssh/id_ed25519
    ControlPath ~/.ssh/cm-%r@%h:%p
"""

CASES = {
    "lab": (LAB_STYLE, ["r01", "r15", "r30", "r31", "10.200.1.11"]),
    "layered": (LAYERED, ["panther-01", "panther-02", "panther-05", "panther-09", "x.lab", "bastion", "other",
                          "panther-1"]),
    "empty": ("", ["anything"]),
    "only globals": ("User u\nPort 2222\nIdentityFile ~/k\n", ["a", "b"]),
    "brackets": ("Host robot[12]\n  Port 23\nHost robot?\n  User q\n", ["robot1", "robot3", "robot12"]),
}


def _paramiko(text: str, host: str) -> dict[str, object]:
    got = paramiko.SSHConfig.from_text(text).lookup(host)
    return {k: v for k, v in got.items() if k in USED}


@pytest.mark.parametrize("case", sorted(CASES))
def test_answers_as_paramiko_does(case: str) -> None:
    text, hosts = CASES[case]
    quick = read_config(text)
    assert quick is not None, "the reader should know this file"
    for host in hosts:
        assert quick.lookup(host) == _paramiko(text, host), host


@pytest.mark.parametrize("text", [
    "Match host r01\n  User x\n",
    "Include ~/.ssh/config.d/*\n",
    "Host r01\n  CanonicalizeHostname yes\n",
    'Host "r 01"\n  Port 22\n',
    "Host r01\n  HostName '%h.lab'\n",
    "Host r01\n  HostName %h.lab\n",
    "Host r01\n  IdentityFile ~/.ssh/%u_key\n",
    "Host r01\n  ProxyJump %r@bastion\n",
    "Host\n",
    "Host r01\n  HostName a\\b\n",
])
def test_gives_up_where_paramiko_must_read(text: str) -> None:
    assert read_config(text) is None


def test_tokens_in_unused_settings_do_not_matter() -> None:
    text = "Host *\n  ControlPath ~/.ssh/%C\n  ProxyCommand ssh -W %h:%p gw\n  User u\n"
    quick = read_config(text)
    assert quick is not None and quick.lookup("r") == _paramiko(text, "r")


def test_resolve_is_the_same_with_and_without_the_quick_reader(tmp_path: Path,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    conf = tmp_path / "ssh_config"
    conf.write_text(LAYERED)
    endpoints = [Endpoint(name=h, host=h, ssh_config=str(conf)) for h in
                 ("panther-01", "panther-02", "panther-05", "x.lab", "other")]
    endpoints.append(Endpoint(name="p", host="panther-01", port=22, user="me", ssh_config=str(conf)))
    quick = [ssh_config.resolve(e) for e in endpoints]
    assert [ssh_config.resolve_quick(e) for e in endpoints] == quick
    monkeypatch.setattr(ssh_config, "read_file", lambda path: None)  # the quick reader gives up
    ssh_config._lookups.clear()
    conf.write_text(LAYERED + "\n")  # a new version of the file: parsed afresh, by paramiko
    assert [ssh_config.resolve(e) for e in endpoints] == quick
    assert all(ssh_config.resolve_quick(e) is None for e in endpoints)


def test_a_lookup_visits_only_the_blocks_that_can_match() -> None:
    quick = read_config(LAB_STYLE + "Host *.lab !x.lab\n  User y\n")
    assert quick is not None
    assert quick.by_name["r07"] == (7,)
    assert quick.wild == (0, 31)  # the implicit global block and the wildcard one
