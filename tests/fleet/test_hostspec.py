"""Hosts and jump specs of the inventory: what passes, what is refused and why."""

from __future__ import annotations

from pathlib import Path

import pytest

from panther_ops.core.fleet.hostspec import HostSpecError, JumpSpec, check_host, parse_jump
from panther_ops.core.fleet.inventory_file import load_inventory
from panther_ops.core.yaml.located import load_yaml
from panther_ops.errors import InputError


@pytest.mark.parametrize("host", ["10.15.20.2", "fd00::1", "fc94:b01d:1803:8dd8:b293:5c7d:7639:932a", "panther-07",
                                  "panther_07", "gw.example.org", "gw.example.org.", "localhost", "r01"])
def test_good_hosts(host: str) -> None:
    assert check_host(host) == host


@pytest.mark.parametrize(("host", "why"), [
    ("-oProxyCommand=x", "starts with '-'"), ("a b", "whitespace"), ("a\nb", "whitespace"), ("a;b", ";"),
    ("$(id)", "$"), ("`id`", "`"), ("a/b", "'/'"), ("a\x00b", "control"), ("10.0.0.256", "IPv4"),
    ("-a.b", "'-'"), ("a-.b", "not an IP address or hostname"), ("a..b", "not an IP address or hostname"),
    ("x" * 300, "longer"), ("", "empty"),
])
def test_bad_hosts(host: str, why: str) -> None:
    with pytest.raises(HostSpecError) as exc:
        check_host(host)
    assert why in str(exc.value)


@pytest.mark.parametrize(("spec", "parsed"), [
    ("gw", JumpSpec(None, "gw", None)),
    ("op@gw.example.org:2222", JumpSpec("op", "gw.example.org", 2222)),
    ("op@[fd00::1]:22", JumpSpec("op", "fd00::1", 22)),
    ("op@[fd00::1]", JumpSpec("op", "fd00::1", None)),
    ("fd00::1", JumpSpec(None, "fd00::1", None)),
    ("10.15.20.1:22", JumpSpec(None, "10.15.20.1", 22)),
])
def test_good_jumps(spec: str, parsed: JumpSpec) -> None:
    assert parse_jump(spec) == parsed


@pytest.mark.parametrize("spec", ["-J gw", "op@gw;id", "op@gw:0", "op@gw:x", "Root@gw", "op@[gw]:22", "op@[fd00::1",
                                  "op@gw/x", "@gw", "op@"])
def test_bad_jumps(spec: str) -> None:
    with pytest.raises(HostSpecError):
        parse_jump(spec)


def test_an_ipv6_jump_reaches_the_endpoint(tmp_path: Path) -> None:
    f = tmp_path / "fleet.yaml"
    f.write_text("version: 1\nrobots:\n  r1: {host: 10.15.20.2, jump: 'op@[fd00::1]:2222', connect_timeout: 3}\n")
    inv = load_inventory(str(f))
    jump = inv.endpoint(inv.robots["r1"]).jump
    assert jump is not None and (jump.host, jump.port, jump.user) == ("fd00::1", 2222, "op")


def test_aliases_still_work_and_recursion_is_refused() -> None:
    doc = load_yaml("base: &b {user: husarion}\nr1: {<<: *b, host: a}\nr2: *b\n", "f.yaml")
    assert doc["r1"] == {"user": "husarion", "host": "a"} and doc["r2"] == {"user": "husarion"}
    with pytest.raises(InputError, match="recursive"):
        load_yaml("a: &a [1, *a]\n", "f.yaml")
