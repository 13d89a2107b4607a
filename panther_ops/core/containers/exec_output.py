"""What a script run in the driver container (:mod:`driver_exec`) hands back, parsed (pure).

The docker engine's multiplexed exec stream, and the sections the container script prints:
``@@ns <namespace>``, then for each action ``@@<action>``, its output, ``@@exit <status>``.
"""

from __future__ import annotations

from dataclasses import dataclass

MARK = "@@"


@dataclass(frozen=True)
class Section:
    """One command's output and exit status."""

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


def container_of(stderr: str) -> str | None:
    """The driver container the robot script used (its ``@@container`` line on stderr)."""
    for line in stderr.splitlines():
        if line.startswith("@@container "):
            return line.split(" ", 1)[1].strip() or None
    return None
