"""Every example of the CLI's --help texts and of docs/ (and README.md), collected, and what each
needs: the demo fleet (then it runs in test_examples.py) or a robot reached over SSH (the lab,
docs/lab.md, or a real one), with the reason."""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC_FILES = (*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md")


@dataclass(frozen=True)
class Example:
    where: str
    """``--help of config set`` or ``docs/commands.md:102``."""
    line: str
    """The command line as written (one ``panther-ops`` command, the prompt and comment removed)."""

    @property
    def argv(self) -> list[str]:
        words = shlex.split(self.line.split(" | ")[0].split(" < ")[0])
        assert words[0] == "panther-ops", self.line
        return words[1:]


def help_examples() -> list[Example]:
    """The examples of every command's --help (after ``Example:``/``Examples:``), and the root's."""
    import typer.main

    from panther_ops.cli.app import _register, app

    _register()
    out: list[Example] = []

    def walk(cmd: object, path: list[str]) -> None:
        text = getattr(cmd, "help", None) or ""
        name = " ".join(path) or "panther-ops"
        for line in _example_lines(text, root=not path):
            out.append(Example(f"--help of {name}", line))
        for sub_name, sub in sorted(getattr(cmd, "commands", {}).items()):
            walk(sub, [*path, sub_name])

    walk(typer.main.get_command(app), [])
    return out


def _example_lines(text: str, *, root: bool) -> list[str]:
    lines: list[str] = []
    seen = False
    for raw in text.splitlines():
        line = raw.strip()
        if re.match(r"Examples?:", line):
            seen = True
            line = re.sub(r"^Examples?:\s*", "", line)
        if root and line.startswith("panther-ops "):  # the root help: "Try ...:" then the commands
            seen = True
        if seen and line.startswith("panther-ops "):
            lines += [part.strip() for part in line.split("&&")]
    return lines


def doc_examples() -> list[Example]:
    """``$ panther-ops ...`` lines of docs/*.md and README.md, and bare ``panther-ops ...`` lines of
    their code blocks that are commands (not a synopsis with ``[...]`` or ``A|B``)."""
    out: list[Example] = []
    for f in DOC_FILES:
        in_block = False
        for n, raw in enumerate(f.read_text().splitlines(), 1):
            if raw.startswith("```"):
                in_block = not in_block
                continue
            if not in_block:
                continue
            line = raw.strip()
            if (command := prompt_command(line)) is not None:
                line = command
            elif not (raw.startswith("panther-ops ") and not re.search(r"[\[\](]|\w\|\w|  \S", line[12:])):
                continue
            line = re.sub(r"\s+#.*$", "", line)
            out += [Example(f"{f.relative_to(ROOT)}:{n}", part.strip()) for part in line.split("&&")]
    return out


def prompt_command(line: str) -> str | None:
    """The ``panther-ops`` command of a console line ``$ panther-ops ...`` (a ``.venv/bin/``
    prefix dropped), else None."""
    if line.startswith("$ panther-ops ") or line.startswith("$ .venv/bin/panther-ops "):
        return line[2:].replace(".venv/bin/", "")
    return None


@dataclass(frozen=True)
class Sample:
    """One ``$ ...`` line of a console block and the output lines under it, as written."""
    line: int
    """Its 0-based line number in the file."""
    command: str
    """The shell line after ``$ ``."""
    output: tuple[str, ...]

    @property
    def example(self) -> Example | None:
        """The panther-ops command it runs (its environment assignments dropped), if any."""
        words = self.command.split()
        while words and re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", words[0]):
            words.pop(0)
        command = prompt_command("$ " + " ".join(words))
        return None if command is None else Example("", re.sub(r"\s+#.*$", "", command))


@dataclass(frozen=True)
class ConsoleBlock:
    """A fenced ```console block of a doc: its fences' 0-based line numbers, the words after
    ``console`` (``lab``: it needs the lab or a robot), its indent and its samples."""
    doc: Path
    start: int
    end: int
    marks: tuple[str, ...]
    indent: str
    head: tuple[str, ...]
    """Lines above its first ``$`` line, as written."""
    samples: tuple[Sample, ...]

    @property
    def where(self) -> str:
        return f"{self.doc.relative_to(ROOT)}:{self.start + 1}"


def console_blocks(doc: Path) -> list[ConsoleBlock]:
    """The ```console blocks of ``doc`` that hold a ``$ panther-ops`` line."""
    lines = doc.read_text().splitlines()
    out: list[ConsoleBlock] = []
    n = 0
    while n < len(lines):
        fence = re.fullmatch(r"(\s*)```console\b(.*)", lines[n])
        if not fence:
            n += 1
            continue
        indent, end = fence.group(1), n + 1
        while not lines[end].strip().startswith("```"):
            end += 1
        samples: list[Sample] = []
        head: list[str] = []
        for at in range(n + 1, end):
            text = lines[at][len(indent):] if lines[at].startswith(indent) else lines[at].lstrip()
            if text.startswith("$ "):
                samples.append(Sample(at, text[2:], ()))
            elif samples:
                last = samples[-1]
                samples[-1] = Sample(last.line, last.command, (*last.output, text))
            else:
                head.append(lines[at])
        if any(s.example is not None for s in samples):
            out.append(ConsoleBlock(doc, n, end, tuple(fence.group(2).split()), indent, tuple(head),
                                    tuple(samples)))
        n = end + 1
    return out


ROUTER = r"gps router (show|set) |gps (enable|status|watch) .*--router\b"
"""A command that talks to the robot's RUTX11 (docs/gps.md's lab has a stand-in of it on r01's LAN)."""

TELEOP = r"^panther-ops (-i \S+ )?teleop "
"""Keyboard teleoperation (docs/remote.md's lab types its keys: tests/ux/docsamples.py, TYPED)."""

NEEDS_A_ROBOT: tuple[tuple[str, str], ...] = (
    (r"-i (lab|/root/\.cache/panther-ops-lab)|\br0\d\b|lab-r0\d|'lab-\*'",
     "runs on the lab's robots (docs/lab.md: sshd + dockerd + Compose v2), as shown"),
    (r"\btrust panther-07\b|-r panther-11\b", "a robot of a real fleet (not in the demo fleet)"),
    (r"--ask-password", "asks a password on the terminal (the lab's shutdown tests run it)"),
    (r"--ask-sudo-password", "asks the User Computers' sudo password on the terminal (tests/remote/webui/"
     "test_webui_lab.py gives it as $PANTHER_OPS_SUDO_PASSWORD)"),
    (TELEOP, "drives a robot's driver container from an interactive terminal "
     "(tests/remote/teleop/test_teleop_lab.py, on a pty)"),
    (r"^panther-ops shutdown --hosts (?!.*--dry-run)", "powers real computers off (the lab's shutdown tests)"),
    (r"shutdown robot .*--yes", "powers the robot off"),
    (r"shutdown setup ", "sets a computer up over the robot's LAN (the lab's shutdown tests)"),
    (r"--remote|--pull\b", "asks Docker Hub (network)"),
    (r" -f\b| --follow\b", "follows a live container log (docker on the robot)"),
    (r"config rollback (?!--file ).*--to \d", "needs a backup id from that robot's `config history`"),
    (r"\b(?!(GP|GL|GN|GA|PQ)[A-Z]{3}\b)[A-Z]{4,}\b(?!=)", "a placeholder to fill in (e.g. ROBOT)"),  # not an NMEA id
    (r"reimage (flash|verify) ", "writes or reads a card in a reader (tests/reimage/test_reimage_flash_lab.py: loop devices)"),
    (r"reimage bmap ", "needs an OS image file (tests/reimage/test_reimage_bmap_lab.py builds a card image and maps it)"),
    (r"reimage restore ", "needs a backup archive of that robot (tests/reimage/test_reimage_restore_lab.py)"),
    (r"gps (listen|watch) ", "waits for NMEA from a sender on the robot's network (tests/gps/test_gps_listen.py sends it)"),
    (ROUTER,
     "talks to the robot's RUTX11 router (credentials, its REST API behind the robot's SSH; "
     "tests/gps/test_gps_router_lab.py runs it on the lab's stand-in router)"),
    (r"--install-completion", "installs into the user's shell (tests/ux/test_completion.py, in a throw-away HOME)"),
    (r"<TAB>", "a shell completing the line (tests/ux/test_completion.py asks the entry point as bash and zsh do)"),
)
"""An example matching the pattern needs more than the demo fleet: the reason."""

IN_THE_LAB = frozenset({r"--ask-password", r"shutdown robot .*--yes", r"shutdown setup ", ROUTER, TELEOP,
                        r"reimage restore "})
"""Patterns of NEEDS_A_ROBOT the docs' lab runs (tests/ux/doclab.py: docs/shutdown.md's User
Computers on the robots' LANs, the password typed at its prompt, the power-off stand-ins;
docs/gps.md's RUTX11 stand-in on r01's LAN; keys typed on a terminal; docs/reimage.md's backup
archive of a lab robot, reinstalled)."""

EXPECTED_EXIT = {
    "panther-ops lights validate bad_animations.yaml": 2,
    "panther-ops shutdown hosts validate bad.yaml": 2,
    "panther-ops -i demo-fleet config push bad_hosts.yaml --as shutdown-hosts -r panther-01 --yes": 2,
    "panther-ops -i demo-fleet config push proj/My.btproj --as bt-lights -r panther-01 --yes": 2,
    "panther-ops manager run --sim --scenario low_batery": 2,
    "panther-ops shutdown hosts validate hosts.yaml --stack 9.9.9": 2,
    "panther-ops sim world set w.sdf --latitude 91 --yes": 2,
    "panther-ops sim world set dms.sdf --longitude 21.0122 --yes": 2,
    "panther-ops sim world show dms.sdf": 3,
    "panther-ops -i demo-fleet webui set webui.port=８０８１ -r panther-01 --yes": 2,
    "panther-ops -i demo-fleet webui set ros.transport=udp --dds-file lan.xml -r panther-01 --yes": 2,
    "panther-ops -i demo-fleet webui set port=8081 webui.port=8082 -r panther-01 --yes": 2,
    "panther-ops sim battery check bad_battery.yaml": 2,
    "panther-ops sim battery charge start --namespace robot1 --yes": 3,
    "panther-ops config rollback --file hosts.yaml --to 20261124T1244 --yes": 2,
    "panther-ops -i demo-fleet config push bad_pad.yaml --as joy2twist --all --yes": 2,
    "panther-ops -i demo-fleet config set controller.cmd_vel_timeout 0 -r panther-01 --yes": 2,
    "panther-ops -i demo-fleet config push bad_srv_pad.yaml --as joy2twist --all --yes": 2,
    "panther-ops -i demo-fleet config set namespace fleet/2nd -r panther-01 --yes --force": 2,
    'panther-ops -i demo-fleet config set wheel_config_path "/config/my wheel.yaml" -r panther-03 --yes': 2,
    "panther-ops -i demo-fleet config set controller_config_path /home/husarion/c.yaml -r panther-03 --yes": 2,
    "panther-ops -i demo-fleet config push no_prefix_controller.yaml --as controller -r panther-02 --yes": 2,
    "panther-ops -q config diff --all --exit-code": 6,  # the demo fleet's warehouse group wants WH02: drift
    "panther-ops -i demo-fleet -q config diff --all --exit-code": 6,
    "panther-ops -i demo-fleet status -r panther-9 --json": 2,  # docs/json.md: an error's document
}
"""Examples that show a refusal: their exit code."""

AFTER = {
    "panther-ops -i demo-fleet config set wheel_type custom -r panther-01 --yes": (
        "panther-ops -i demo-fleet config push my_wheels.yaml --as wheel -r panther-01 --yes",
        "panther-ops -i demo-fleet config push my_wheels_controller.yaml --as controller -r panther-01 --yes"),
    "panther-ops bt validate MyLightsBT.btproj": (
        "panther-ops -i demo-fleet config pull bt-lights -r panther-01 -o MyLightsBT.btproj",),
    "panther-ops -i demo-fleet config push MyLightsBT.btproj --as bt-lights -r panther-01 --yes": (
        "panther-ops -i demo-fleet config pull bt-lights -r panther-01 -o MyLightsBT.btproj",),
    "panther-ops bt validate PantherSafetyBT.btproj": (
        "panther-ops -i demo-fleet config pull bt-safety -r panther-01 -o PantherSafetyBT.btproj",),
    "panther-ops lights preview led_config.yaml --id 1 --out ready.gif": (
        "panther-ops -i demo-fleet config pull led -r panther-01 -o led_config.yaml",),
}
"""Examples that continue the ones above them in their block (the manual's custom wheels:
both files pushed, then ``wheel_type custom``; a pulled BT project validated and pushed back;
the stock file of a robot's release pulled, then read):
run alone, those run first."""


def needs_a_robot(example: Example, *, in_lab: bool = False) -> str | None:
    """Why the example does not run on the demo fleet (None: it does), or with ``in_lab`` on
    the lab of docs/lab.md (its robots, as the docs name them, and `IN_THE_LAB` are not a reason then)."""
    for pattern, reason in NEEDS_A_ROBOT[1 if in_lab else 0:]:
        if re.search(pattern, example.line) and not (in_lab and pattern in IN_THE_LAB):
            return reason
    return None
