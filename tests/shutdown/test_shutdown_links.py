"""What `shutdown` runs on the robot to reach a LAN host, and how the answers are read
(core/shutdown/links.py: pure), and docker's errors as panther-ops' own (transport)."""

from __future__ import annotations

import subprocess
from collections.abc import Iterator

import docker.errors
import pytest
import requests

from panther_ops.core.shutdown.links import (
    http_answer,
    http_get_command,
    ping_answered,
    ping_command,
    route_source,
)
from panther_ops.transport.base import CommandResult
from panther_ops.transport.docker_client import EngineError, EngineRefused, NotInEngine, engine_errors
from panther_ops.transport.lan import TargetError
from tests.loopback_http import QuietHandler, serving


def result(status: int, out: str = "", err: str = "") -> CommandResult:
    return CommandResult("cmd", status, out, err)


def test_ping_waits_one_second_first_then_a_fraction() -> None:
    assert ping_command("10.15.20.3", 1.0).argv == ("10.15.20.3", "1")
    assert ping_command("10.15.20.3", 0.25).argv == ("10.15.20.3", "0.25")
    assert "ping -c 1 -W 1" in (ping_command("10.15.20.3", 1.0).script or "")


def test_ping_answer_is_exit_0_no_answer_exit_1_anything_else_fails() -> None:
    assert ping_answered("r01", "10.15.20.3", result(0)) is True
    assert ping_answered("r01", "10.15.20.3", result(1)) is False
    with pytest.raises(TargetError, match=r"r01: ping 10.15.20.3 on the robot failed \(exit 127\): ping: not found"):
        ping_answered("r01", "10.15.20.3", result(127, err="ping: not found\n"))


def test_http_answer_reads_the_status_on_the_last_line() -> None:
    assert http_answer(result(0, "Forbidden\n403")) == (403, "Forbidden", "")
    assert http_answer(result(0, "a\nb\n200")) == (200, "a\nb", "")
    assert http_answer(result(7, "\n000", "connection refused\n")) == (None, "", "connection refused")
    assert http_answer(result(28, "")) == (None, "", "exit 28")


def test_http_get_brackets_ipv6_and_keeps_the_path() -> None:
    assert http_get_command("fd00::3", 3003, "/shutdown?ts=1", 5.0).argv[:2] == ("http://[fd00::3]:3003/shutdown?ts=1",
                                                                                "5")
    assert http_get_command("10.15.20.3", 3003, "/shutdown", 2.5).argv[:2] == ("http://10.15.20.3:3003/shutdown",
                                                                              "2.5")


def test_route_source_is_the_word_after_src() -> None:
    line = "10.15.20.3 dev eth0 src 10.15.20.2 uid 1000 \\    cache"
    assert route_source(result(0, line)) == "10.15.20.2"
    assert route_source(result(0, "10.15.20.3 dev eth0")) is None
    assert route_source(result(2, line)) is None


class _Teapot(QuietHandler):
    def do_GET(self) -> None:
        self.reply(418, f"refused {self.path}".encode())


@pytest.fixture
def server() -> Iterator[int]:
    with serving(_Teapot) as port:
        yield port


def test_the_get_script_and_its_reading_against_a_real_server(server: int) -> None:
    cmd = http_get_command("127.0.0.1", server, "/shutdown?ts=5", 5.0)
    done = subprocess.run(["sh", "-c", cmd.script or "", "sh", *map(str, cmd.argv)], capture_output=True, text=True,
                          timeout=30, check=False)
    res = CommandResult("get", done.returncode, done.stdout, done.stderr)
    assert http_answer(res) == (418, "refused /shutdown?ts=5", "")


def test_the_get_script_without_a_server_is_no_answer() -> None:
    cmd = http_get_command("127.0.0.1", 9, "/shutdown", 2.0)  # discard port: nothing listens
    done = subprocess.run(["sh", "-c", cmd.script or "", "sh", *map(str, cmd.argv)], capture_output=True, text=True,
                          timeout=30, check=False)
    status, _, error = http_answer(CommandResult("get", done.returncode, done.stdout, done.stderr))
    assert status is None and error


def _api_error(cls: type[docker.errors.APIError], code: int, message: str) -> docker.errors.APIError:
    response = requests.Response()
    response.status_code = code
    return cls(message, response=response, explanation=message)


@pytest.mark.parametrize(("raised", "expected"), [
    (_api_error(docker.errors.ImageNotFound, 404, "No such image: x:1"), NotInEngine),
    (_api_error(docker.errors.NotFound, 404, "No such container: x"), NotInEngine),
    (_api_error(docker.errors.APIError, 500, "engine broke"), EngineRefused),
    (docker.errors.DockerException("no engine"), EngineError),
])
def test_engine_errors_become_panther_ops_errors(raised: Exception, expected: type[EngineError]) -> None:
    with pytest.raises(expected) as caught, engine_errors():
        raise raised
    assert type(caught.value) is expected
    assert caught.value.message == str(raised)
    assert caught.value.__cause__ is raised


def test_engine_errors_leave_other_errors_alone() -> None:
    with pytest.raises(ConnectionError), engine_errors():
        raise ConnectionError("socket closed")
