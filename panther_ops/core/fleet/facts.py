"""Facts about a robot, gathered in one round trip and parsed by pure functions.

``PROBE`` prints sections separated by ``@@name`` lines; :func:`parse_probe` turns that
output into a :class:`RobotFacts`. The docker state is read separately through the docker
SDK over the same connection.
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass, field

from panther_ops.transport.base import Command

PROBE = r"""
r="${PANTHER_OPS_ROOT:-}"; c="$1"; case "$c" in "~/"*) c="$HOME/${c#"~/"}";; esac
echo @@hostname; if [ -n "$r" ] && [ -f "$r/etc/hostname" ]; then cat "$r/etc/hostname"; else hostname; fi
echo @@home; printf '%s\n' "$HOME"
echo @@env
for f in "$r/run/husarion/robot_config.env" "$r/run/husarion/panther_config.env"; do
  [ -f "$f" ] && { echo "#file $f"; cat "$f"; echo; }
done
echo @@os; [ -f "$r/etc/os-release" ] && grep '^PRETTY_NAME=' "$r/etc/os-release"
echo @@compose; [ -f "$r$c" ] && cat "$r$c"
echo @@df; df -Pk "$r$HOME" 2>/dev/null | tail -n 1
echo @@docker
if command -v docker >/dev/null 2>&1 && [ -z "$r" ]; then
  docker version -f '{{.Server.Version}} {{.Server.APIVersion}}' 2>&1 | grep -v '^$' | head -n 1
  docker compose version --short 2>&1 | grep -v '^$' | head -n 1
else
  echo none
fi
echo @@end
"""


@dataclass
class RobotFacts:
    """What one probe says about a robot."""

    hostname: str = ""
    home: str = ""
    env: dict[str, str] = field(default_factory=dict)
    env_files: list[str] = field(default_factory=list)
    os_name: str = ""
    compose_text: str | None = None
    disk_free_bytes: int | None = None
    disk_total_bytes: int | None = None
    docker_server: str | None = None
    docker_api: str | None = None
    docker_error: str | None = None
    compose_version: str | None = None
    compose_error: str | None = None

    @property
    def system_build_version(self) -> str | None:
        return self.env.get("SYSTEM_BUILD_VERSION")

    @property
    def robot_model(self) -> str | None:
        if "ROBOT_MODEL_NAME" in self.env:
            return self.env["ROBOT_MODEL_NAME"]
        if "PANTHER_ROBOT_VERSION" in self.env or "PANTHER_SERIAL_NO" in self.env:
            return "panther"
        return self.env.get("ROBOT_MODEL")

    @property
    def serial(self) -> str | None:
        return self.env.get("ROBOT_SERIAL_NO") or self.env.get("PANTHER_SERIAL_NO")

    @property
    def robot_version(self) -> str | None:
        return self.env.get("ROBOT_VERSION") or self.env.get("PANTHER_ROBOT_VERSION")


def probe_command(compose_file: str) -> Command:
    return Command.sh(PROBE, compose_file)


def _sections(text: str) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    current: list[str] | None = None
    for line in text.splitlines():
        if line.startswith("@@") and line[2:].isidentifier():
            current = out.setdefault(line[2:], [])
        elif current is not None:
            current.append(line)
    return out


def parse_env(text: str) -> dict[str, str]:
    """Parse a KEY=VALUE env file (``export``, quotes and comments allowed)."""
    env: dict[str, str] = {}
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("export "):
            line = line[7:].strip()
        key, sep, value = line.partition("=")
        if not sep or not key.strip().isidentifier():
            continue
        try:
            parts = shlex.split(value, comments=True)
        except ValueError:
            parts = [value]
        env[key.strip()] = parts[0] if len(parts) == 1 else " ".join(parts)
    return env


def _float(lines: list[str] | None) -> float | None:
    try:
        return float(lines[0].strip()) if lines else None
    except ValueError:
        return None


def clock_offset(remote_stdout: str, sent: float, received: float) -> float | None:
    """Robot clock minus ours, from ``date +%s.%N`` run between ``sent`` and ``received``.

    The robot read its clock about half-way through the round trip; the error is at most
    half the round trip (milliseconds on a warm connection).
    """
    remote = _float(remote_stdout.split()[:1])
    return None if remote is None else remote - (sent + received) / 2


def signed_seconds(seconds: float) -> str:
    """A clock offset as shown: ``+0.25 s``, ``-1.30 s``; one that rounds to nothing is ``+0.00 s``
    (never ``-0.00 s``)."""
    shown = f"{seconds:+.2f}"
    return "+0.00 s" if float(shown) == 0 else f"{shown} s"


def parse_probe(stdout: str) -> RobotFacts:
    s = _sections(stdout)
    facts = RobotFacts()
    facts.hostname = "\n".join(s.get("hostname", [])).strip()
    facts.home = "\n".join(s.get("home", [])).strip()
    env_lines: list[str] = []
    for line in s.get("env", []):
        if line.startswith("#file "):
            facts.env_files.append(line[6:].strip())
        else:
            env_lines.append(line)
    facts.env = parse_env("\n".join(env_lines))
    for line in s.get("os", []):
        if line.startswith("PRETTY_NAME="):
            facts.os_name = line.split("=", 1)[1].strip().strip('"')
    if s.get("compose"):
        facts.compose_text = "\n".join(s["compose"]) + "\n"
    df = " ".join(s.get("df", [])).split()
    if len(df) >= 4 and df[1].isdigit() and df[3].isdigit():
        facts.disk_total_bytes = int(df[1]) * 1024
        facts.disk_free_bytes = int(df[3]) * 1024
    docker = [line.strip() for line in s.get("docker", []) if line.strip()]
    if docker and docker[0] != "none":
        first = docker[0].split()
        if len(first) == 2 and first[0][:1].isdigit():
            facts.docker_server, facts.docker_api = first
        else:
            facts.docker_error = docker[0]
        if len(docker) > 1:
            if docker[1][:1].isdigit() or docker[1].startswith("v"):
                facts.compose_version = docker[1].lstrip("v")
            else:
                facts.compose_error = docker[1]
    return facts
