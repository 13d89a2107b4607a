"""What the ROS 2 CLI prints, parsed (pure functions of the text).

The robot runs several ROS 2 commands in one go; each one's output comes after a marker
line ``@@<action>`` and is followed by ``@@exit <status>`` (see :mod:`calls`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

MARK = "@@"
_RESPONSE = re.compile(r"Trigger_Response\(success=(True|False), message=(['\"])(.*)\2\)\s*$", re.M)
_DATA = re.compile(r"^data:\s*(true|false)\s*$", re.M | re.I)


@dataclass(frozen=True)
class Section:
    """One ROS 2 command's output and exit status."""

    action: str
    text: str
    status: int | None


@dataclass(frozen=True)
class Answers:
    """Everything one robot answered: the namespace used, then each action's section."""

    namespace: str
    sections: dict[str, Section]
    container: str | None = None
    """The driver container that answered (when the robot said)."""

    def get(self, action: str) -> Section | None:
        return self.sections.get(action)


def docker_stream(raw: bytes) -> tuple[str, str]:
    """The docker engine's multiplexed exec output as (stdout, stderr): frames of an 8-byte
    header (stream 1 or 2, three zero bytes, big-endian length) and the payload. Anything
    else (the engine's JSON error) is returned whole as stderr."""
    out: list[bytes] = []
    err: list[bytes] = []
    i = 0
    while i + 8 <= len(raw) and raw[i] in (0, 1, 2) and raw[i + 1:i + 4] == b"\0\0\0":
        size = int.from_bytes(raw[i + 4:i + 8], "big")
        (err if raw[i] == 2 else out).append(raw[i + 8:i + 8 + size])
        i += 8 + size
    if i < len(raw):
        if i == 0:
            return "", raw.decode(errors="replace")
        out.append(raw[i:])  # a frame cut short: what arrived
    return b"".join(out).decode(errors="replace"), b"".join(err).decode(errors="replace")


def split(output: str) -> Answers:
    """Split the combined output into its sections (``@@ns``, ``@@<action>``, ``@@exit``)."""
    namespace = ""
    sections: dict[str, Section] = {}
    current: str | None = None
    lines: list[str] = []
    for line in output.splitlines():
        if line.startswith(f"{MARK}ns"):
            namespace = line[len(MARK) + 2:].strip()
        elif line.startswith(f"{MARK}exit") and current is not None:
            word = line[len(MARK) + 4:].strip()
            sections[current] = Section(current, "\n".join(lines), int(word) if word.isdigit() else None)
            current, lines = None, []
        elif line.startswith(MARK):
            current, lines = line[len(MARK):].strip(), []
        elif current is not None:
            lines.append(line)
    if current is not None:  # cut short: no exit status
        sections[current] = Section(current, "\n".join(lines), None)
    return Answers(namespace, sections)


def e_stop_state(text: str) -> bool | None:
    """``ros2 topic echo --once .../hardware/e_stop`` (std_msgs/Bool): True = triggered."""
    m = _DATA.search(text)
    return None if m is None else m.group(1).lower() == "true"


def trigger_response(text: str) -> tuple[bool, str] | None:
    """``ros2 service call ... std_srvs/srv/Trigger``: (success, message), None without one."""
    found = _RESPONSE.findall(text)
    if not found:
        return None
    success, _, message = found[-1]
    return success == "True", message


def publishers(text: str) -> list[str] | None:
    """``ros2 topic info -v``: the publishing nodes (full names), None when it is not that."""
    if "Publisher count:" not in text:
        return None
    head = text.split("Subscription count:", 1)[0]
    nodes: list[str] = []
    name: str | None = None
    for raw in head.splitlines():
        line = raw.strip()
        if line.startswith("Node name:"):
            name = line.split(":", 1)[1].strip()
        elif line.startswith("Node namespace:") and name is not None:
            ns = line.split(":", 1)[1].strip().rstrip("/")
            nodes.append(f"{ns}/{name}" if ns else f"/{name}")
            name = None
    if name is not None:
        nodes.append(f"/{name}")
    return nodes
