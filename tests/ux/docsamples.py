"""Every console sample of docs/*.md and README.md, re-run as a reader runs it, and compared
with (or written over) what the doc shows (scripts/capture_docs.py; tests/ux/test_docs_samples.py).

A sample is a ``$ ...`` line of a ```console block and the lines under it. Per doc, the
samples run in the order of the page (a reader follows it) in one fresh directory that holds
the demo fleet (``panther-ops demo init``) and the files the examples name
(tests/ux/workspace.py; no ``templates/``: an installed user has none), each line through
``bash`` on a pseudo-terminal 80 columns wide with ``NO_COLOR=1`` (what an operator's
terminal shows, live progress redrawn in place, the recap included; tests/ux/screen.py), the
shell's variables, directory and ``$?`` carried from one line to the next.

Not run on the demo fleet, with the reason listed (``--list``): a block marked ```console lab
(the lab of docs/lab.md), and a sample whose command needs a robot (tests/ux/examples.py:
NEEDS_A_ROBOT). Their text is left as written.

The lab mode (``follow(doc, lab)``; ``capture_docs.py --lab``; tests/ux/test_docs_samples_lab.py)
runs the samples of a page's ```console lab blocks, in the page's order, on one lab of simulated
robots brought up for the page (tests/ux/doclab.py: real sshd, dockerd and Compose v2), the lab's
directory shown as ``lab/`` beside the reader; the keys of a sample of TYPED (teleop) typed on its
terminal. A lab sample that needs more than the lab (a real
power-off, snapd) is in a block marked ```console lab-standin: not run, listed with the
reason.

What varies from run to run is normalised before comparing (:func:`comparable`), and only the
directory's path in what is written (:func:`shown`)."""

from __future__ import annotations

import contextlib
import difflib
import io
import re
import shlex
import shutil
import sys
import tempfile
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from .examples import DOC_FILES, NEEDS_A_ROBOT, ROOT, ConsoleBlock, Sample, console_blocks, needs_a_robot
from .screen import Screen
from .termrun import keys_on_pty, shell_on_pty
from .workspace import reader_workspace

COLS = 80
HOME = "/home/me"
"""The reader's directory (and $HOME) as the docs show it."""

LAB = "lab"
"""The mark of a block that needs the lab (```console lab)."""

LAB_STANDIN = "lab-standin"
"""The mark of a lab block that is not re-run (```console lab-standin): what it shows is what the
lab's stand-in prints for a part the lab cannot run (a real power-off, snapd, a router), from the
lab test that runs it (named in the sample's reason)."""

SCENE = "scene="
"""A lab block's mark ``scene=NAME``: before the block runs, the lab is brought into the state the
text around it describes (tests/ux/doclab.py: SCENES, e.g. a driver in a crash loop); the state
stays for the rest of the page, as it would for a reader."""

NOT_YET_IN_LAB: dict[tuple[str, str], str] = {
    ("driver.md", "panther-ops -i lab/inventory.yaml driver restart -r r05 --yes --settle 2"):
        "the recreate starts a new crash loop (delays from 100 ms again): what the check sees of it within "
        "--settle 2 (restarting, or restarted once and running) depends on where that loop is when it looks "
        "(both seen in three runs); no point before the command fixes it",
}
"""(page, command) of lab samples the lab mode does not run yet, with the reason (listed, left as written)."""

NOT_YET_BLOCKS: dict[tuple[str, str], str] = {}
"""(page, first command of a block) of lab blocks the lab mode does not run yet: the reason."""


@dataclass(frozen=True)
class Typed:
    """Keys a reader types at a command's terminal (the command a session's leader on it, as in
    an operator's shell): once ``ready`` shows, each key, then its pause (seconds)."""

    ready: str
    keys: tuple[tuple[str, float], ...]


TYPED: dict[tuple[str, str], Typed] = {
    # as tests/remote/teleop/test_teleop_lab.py drives it: forward, a faster speed, stop, Ctrl-C
    ("remote.md", "panther-ops -i lab/inventory.yaml teleop -r r01        # the lab's Python image (rclpy stand-in)"):
        Typed("Reading from the keyboard and publishing on", (("i", 1.0), ("q", 0.5), ("k", 0.5), ("\x03", 1.0))),
}
"""(page, command) of samples whose reader types keys (teleop), and the keys."""

LAB_PAGES_NOT_YET: dict[str, str] = {}
"""Pages whose lab samples need more than the docs' lab (tests/ux/doclab.py) and are not run yet:
the reason (listed by ``capture_docs.py --lab --list``; their text is left as written)."""

LAB_SUBNET = re.compile(r"\b10\.200\.\d+\.")
"""The lab's addresses: the third byte is the lab's own network (the first free one when it came up)."""

_LAB_ADDRESS = re.compile(r"\b10\.200\.(\d+)\.")


def relabel(text: str, subnets: dict[int, int]) -> str:
    """``text`` with each lab address 10.200.W.x on subnet ``subnets[W]`` instead (in one pass:
    the maps may cross). The docs show a lab's addresses as those of the lab on an idle machine
    (tests/ux/doclab.py: subnets numbered from 1 in the order the lab made them), so that a
    command naming one (``--host 10.200.2.101``) runs on the lab actually up."""
    if not subnets:
        return text
    return _LAB_ADDRESS.sub(lambda m: f"10.200.{subnets.get(int(m[1]), int(m[1]))}.", text)


INSTALLED = "<panther-ops>"
"""Where panther-ops' own files are (this checkout, or site-packages when installed), as the docs show it."""


def shown(text: str, workspace: Path, lab_dir: Path | None = None) -> str:
    """The output as the doc shows it: the temporary directory is the reader's ``/home/me``,
    panther-ops' own directory `INSTALLED`, the lab's directory ``lab`` (as the reader names it)."""
    if lab_dir is not None:  # a diff's a/PATH and b/PATH too (a/lab/known_hosts, not alab/known_hosts)
        text = text.replace(f"a{lab_dir}/", "a/lab/").replace(f"b{lab_dir}/", "b/lab/").replace(str(lab_dir), "lab")
    return text.replace(str(workspace), HOME).replace(str(ROOT), INSTALLED)


_VARIES = (
    (re.compile(r"\d{8}T\d{4,6}Z?(-[0-9a-f]{4})?"), "<backup-id>"),  # backup ids, archive stamps
    (re.compile(r"\d{4}-\d\d-\d\d[T ]\d\d:\d\d(:\d\d(\.\d+)?)?(Z|[+-]\d\d:?\d\d)?"), "<time>"),
    (re.compile(r"\b\d{4}-\d\d-\d\d\b"), "<date>"),  # a date the terminal wrapped from its time
    (re.compile(r"\b\d\d:\d\d:\d\d\b"), "<clock>"),  # and the time on the next line
    (re.compile(r"SHA256:[0-9a-f]{64}\b"), "SHA256:<fingerprint>"),  # a certificate's (the lab router's, made per lab)
    (re.compile(r"SHA256:[A-Za-z0-9+/]{43}"), "SHA256:<fingerprint>"),
    (re.compile(r"\bssh-ed25519 AAAAC3NzaC1lZDI1NTE5AAAA[A-Za-z0-9+/]{44}"), "ssh-ed25519 <key>"),  # a lab's host keys
    # the manager's build: a hash of its sources (docs/manager-deploy.md), new with every change to them
    (re.compile(r"\b(\d+\.\d+\.\d+)-[0-9a-f]{12}\b"), "\\1-<build>"),
    (re.compile(r"\bsha256 [0-9a-f]{12}\b"), "sha256 <digest>"),  # the digest of such a build's file
    # a simulated run's time in the manager's log (real time: its first tick at 0.0 or 0.1 s, by the load)
    (re.compile(r"^t= *\d+\.\d(?= )"), "t=<sim time>"),
    (re.compile(r"[+-]?\d+(\.\d+)? ?(s|ms|GiB|MiB|KiB|B|%)(?!\w)"), "<n> \\2"),  # times, clock offsets, sizes
    (re.compile(r'"duration_s": \d+(\.\d+)?'), '"duration_s": <n>'),  # a JSON document's durations
    (re.compile(r'"stamp": \d+(\.\d+)?'), '"stamp": <time>'),  # a ROS message's time (a NavSatFix's header)
    (re.compile(r"\b(\d+m )?\d+s\b"), "<uptime>"),
    (re.compile(r"[━─═]+"), "─"),  # a rule as long as a column that holds one of the above
    (LAB_SUBNET, "10.200.<lab>."),
    (re.compile(r"(?<=│ )[0-9a-f]{12}(?= │)"), "<image-id>"),  # a docker image's id, in a table cell
    (re.compile(r"/_ros2cli_\d+"), "/_ros2cli_<pid>"),  # the node name of a `ros2 topic pub`
    (re.compile(r" +"), " "),
)


def comparable(lines: list[str] | tuple[str, ...]) -> list[str]:
    """The lines with what varies run to run replaced (backup ids, times and dates, host key
    fingerprints, durations, clock offsets and sizes, and so the widths of the columns that
    hold them; the lab's network and its images' ids); trailing blank lines dropped."""
    out = []
    for line in lines:
        text = line
        for pattern, repl in _VARIES:
            text = pattern.sub(repl, text)
        out.append(text.rstrip())
    while out and not out[-1]:
        out.pop()
    return out


ELIDED = "..."
"""An output line that stands for any number of lines of the real output (as doctest's ELLIPSIS)."""

LONGEST = 40
"""A longer output is written abridged: its first and last lines, ``...`` between."""


def matches(sample: list[str] | tuple[str, ...], real: list[str]) -> bool:
    """Whether the sample shows the real output: line for line once normalised, an ``...``
    line matching any run of lines."""
    pattern = "".join("(?:.*\n)*?" if line == ELIDED else re.escape(line) + "\n" for line in comparable(sample))
    return re.fullmatch(pattern, "".join(f"{line}\n" for line in comparable(real))) is not None


def abridged(real: list[str]) -> list[str]:
    if len(real) <= LONGEST:
        return real
    return [*real[:10], ELIDED, *real[-20:]]


@dataclass
class Outcome:
    doc: Path
    diffs: list[str]
    """A unified diff per sample that differs from its run."""
    skipped: list[tuple[str, str, str]]
    """(where, command, reason) of the samples not run."""
    text: str
    """The doc with every run sample's output as captured."""


AS_WRITTEN = "as-written"
"""The mark of a block shown as written, not re-run (```console as-written): it needs a real
robot, the user's shell, a card reader, or a file the text describes."""


def skip_reasons(block: ConsoleBlock, in_lab: bool = False) -> list[str | None]:
    """Per sample of the block, why it is not run (None: it is) on the demo fleet, or with
    ``in_lab`` on the lab (then only the samples of ```console lab blocks run). A shell line
    (``echo $?``) goes with the panther-ops command above it (or, at the top, below it)."""
    if in_lab:
        if LAB not in block.marks:
            why = ("the block is marked `console lab-standin`" if LAB_STANDIN in block.marks
                   else "not a lab block (run on the demo fleet)")
            return [why for _ in block.samples]
        whole = LAB_PAGES_NOT_YET.get(block.doc.name) or NOT_YET_BLOCKS.get((block.doc.name, block.samples[0].command))
        if whole:
            return [whole for _ in block.samples]
        own = [(NOT_YET_IN_LAB.get((block.doc.name, s.command))
                or (needs_a_robot(s.example, in_lab=True) if s.example is not None else None)) for s in block.samples]
        return _with_commands(block, own)
    own = [needs_a_robot(s.example) if s.example is not None else None for s in block.samples]
    if LAB in block.marks or LAB_STANDIN in block.marks or AS_WRITTEN in block.marks:
        mark = ("the block is marked `console lab` (capture_docs.py --lab runs it)" if LAB in block.marks else
                "the block is marked `console lab-standin`" if LAB_STANDIN in block.marks else
                "the block is marked `console as-written` (shown as written, not re-run)")
        return [reason or mark for reason in own]
    return _with_commands(block, own)


def _with_commands(block: ConsoleBlock, own: list[str | None]) -> list[str | None]:
    commands = [n for n, s in enumerate(block.samples) if s.example is not None]
    out: list[str | None] = []
    for n, sample in enumerate(block.samples):
        if sample.example is not None:
            out.append(own[n])
            continue
        above = [c for c in commands if c < n]
        ruling = above[-1] if above else min(c for c in commands if c > n)
        out.append(own[ruling] and f"goes with `{block.samples[ruling].command}`: {own[ruling]}")
    return out


def marks(block: ConsoleBlock) -> tuple[str, ...]:
    """The block's marks as they should be when none of its commands runs on the demo fleet:
    ``lab`` (one needs the lab) or ``as-written`` (a real robot, the user's shell, a card ...)."""
    reasons = [r for s, r in zip(block.samples, skip_reasons(block), strict=True) if s.example is not None]
    if {AS_WRITTEN, LAB, LAB_STANDIN} & set(block.marks) or any(r is None for r in reasons):
        return block.marks
    return (LAB if NEEDS_A_ROBOT[0][1] in reasons else AS_WRITTEN, *block.marks)


READ_SECRET = re.compile(r"read -\w*s\w* ")
"""A shell's ``read -s`` (a secret read without echo, e.g. the router's password): the lab's password typed."""

_IN_PROCESS = threading.Lock()
"""The directories are filled by panther-ops run in this process (its cwd, sys.stdout): one at a time."""


class Reader:
    """One reader's directory and shell state, following one doc."""

    def __init__(self, root: Path, lab_dir: Path | None = None, subnets: dict[int, int] | None = None,
                 password: str = "", page: str = "",
                 ctrl_c: Callable[[str], Callable[[str], bool] | None] | None = None) -> None:
        self.page = page
        """The doc's name (TYPED)."""
        self.dir = root / "home"
        self.dir.mkdir()
        self.lab_dir = lab_dir
        self.shown_subnets = subnets or {}
        """The lab's subnets as the docs show them (see relabel), and what a command's are."""
        self.run_subnets = {doc: real for real, doc in self.shown_subnets.items()}
        self.password = password
        """Typed at a password prompt (``--ask-password``: the lab's User Computers' one)."""
        self.ctrl_c = ctrl_c
        """Per command, when to type Ctrl-C (on what the terminal shows so far), or None."""
        if lab_dir is not None:  # docs/lab.md: the docs write the lab's directory as lab/
            (self.dir / "lab").symlink_to(lab_dir)
        bin_dir = root / "bin"
        bin_dir.mkdir()
        (bin_dir / "panther-ops").write_text(
            f"#!{sys.executable}\nfrom panther_ops.cli.app import run\nrun()\n")
        (bin_dir / "panther-ops").chmod(0o755)
        self.state = root / "state"
        self.state.mkdir()
        with _IN_PROCESS, contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            extra = reader_workspace(self.dir)
        self.env = {
            **{k: v for k, v in extra.items() if k != "PATH"},
            "PATH": f"{bin_dir}:{ROOT / 'tests' / 'standins'}:/usr/local/bin:/usr/bin:/bin",
            "HOME": str(self.dir), "TERM": "xterm-256color", "NO_COLOR": "1", "LANG": "C.UTF-8",
            "PYTHONPATH": str(ROOT), "PYTHONDONTWRITEBYTECODE": "1",
        }
        (self.state / "cwd").write_text(str(self.dir))
        (self.state / "rc").write_text("0")
        (self.state / "env").write_text("")

    def run(self, sample: Sample) -> list[str]:
        """What the terminal shows after ``$ command``: its lines."""
        example = sample.example
        if example is not None and example.argv[:2] == ["demo", "init"] and "--dest" not in example.argv:
            shutil.rmtree(self.dir / "demo-fleet", ignore_errors=True)  # the reader creates it here
        s = shlex.quote(str(self.state))
        command = relabel(sample.command.replace(HOME, str(self.dir)), self.run_subnets)  # the doc's /home/me: the
        # reader's directory; its lab addresses: the lab's
        script = (f"cd \"$(cat {s}/cwd)\"; . {s}/env; (exit $(cat {s}/rc))\n{command}\n"
                  f"__rc=$?; export -p > {s}/env; pwd > {s}/cwd; echo $__rc > {s}/rc; exit $__rc\n")
        answers = tuple(m.group(1) for line in sample.output if (m := re.search(r"\[y/N\]: (\w+)$", line)))
        password = self.password if "--ask-password" in sample.command or READ_SECRET.match(sample.command) else ""
        if (typed := TYPED.get((self.page, sample.command))) is not None:
            _, out = keys_on_pty(["/bin/bash", "-c", script], [(k.encode(), pause) for k, pause in typed.keys],
                                 ready=typed.ready, timeout=120, env=self.env, cols=COLS)
        else:
            out = shell_on_pty(script, cols=COLS, cwd=self.dir, env=self.env, answers=answers, password=password,
                               ctrl_c=self.ctrl_c(sample.command) if self.ctrl_c else None).out
        screen = Screen(10**6)  # a line the terminal wraps at its edge is one line (as copied from it)
        screen.feed(out)
        lines = screen.text()
        while lines and not lines[-1]:
            lines.pop()
        return [relabel(shown(line, self.dir, self.lab_dir), self.shown_subnets) for line in lines]


def follow(doc: Path, lab_dir: Path | None = None, scene: Callable[[str], None] | None = None, *,
           subnets: dict[int, int] | None = None, password: str = "",
           ctrl_c: Callable[[str], Callable[[str], bool] | None] | None = None) -> Outcome:
    """Run the samples of ``doc`` in order; the diffs, the skipped ones, and the doc rewritten.
    With ``lab_dir`` (a lab up for this page, tests/ux/doclab.py), the samples of its
    ```console lab blocks, on that lab, ``scene(NAME)`` called before a block marked
    ``scene=NAME``, its addresses shown as ``subnets`` says (see relabel), ``password`` typed at a
    password prompt, Ctrl-C typed in a command once ``ctrl_c(command)(what the terminal shows)``
    holds; the other blocks are left as they are."""
    lines = doc.read_text().splitlines()
    diffs: list[str] = []
    skipped: list[tuple[str, str, str]] = []
    blocks = console_blocks(doc)
    if lab_dir is not None:
        blocks = [b for b in blocks if LAB in b.marks or LAB_STANDIN in b.marks]
    with tempfile.TemporaryDirectory(prefix="panther-ops-docs-") as tmp:
        reader = Reader(Path(tmp), lab_dir, subnets, password, doc.name, ctrl_c)
        for block in reversed(_in_order(blocks, reader, skipped, diffs, doc, scene)):
            lines[block[0]:block[1]] = block[2]
    text = "\n".join(lines) + "\n"
    return Outcome(doc, diffs, skipped, text)


def _in_order(blocks: list[ConsoleBlock], reader: Reader, skipped: list[tuple[str, str, str]],
              diffs: list[str], doc: Path, scene: Callable[[str], None] | None = None) -> list[tuple[int, int, list[str]]]:
    """Each block's new lines (its opening fence to its closing one, not included), from the top."""
    out = []
    rel = doc.relative_to(ROOT)
    for block in blocks:
        for mark in block.marks:
            if mark.startswith(SCENE) and scene is not None and LAB in block.marks:
                scene(mark.removeprefix(SCENE))
        body: list[str] = []
        if marks(block) != block.marks:
            diffs.append(f"{block.where}: mark the block ```{' '.join(('console', *marks(block)))} "
                         "(none of its commands runs on the demo fleet)\n")
        body.append(block.indent + " ".join(("```console", *marks(block))))
        body += block.head
        for sample, reason in zip(block.samples, skip_reasons(block, reader.lab_dir is not None), strict=True):
            where = f"{rel}:{sample.line + 1}"
            if reason is not None:
                skipped.append((where, sample.command, reason))
                output = list(sample.output)
            else:
                real = reader.run(sample)
                output = list(sample.output)
                if not matches(sample.output, real) or len(sample.output) > LONGEST:
                    output = abridged(real)
                    diffs.append("".join(difflib.unified_diff(
                        [f"{x}\n" for x in sample.output], [f"{x}\n" for x in real],
                        f"{where} (the doc): $ {sample.command}", f"{where} (a real run)")))
            body.append(f"{block.indent}$ {sample.command}")
            body += [(block.indent + x) if x else "" for x in output]
        out.append((block.start, block.end, body))
    return out


def docs() -> list[Path]:
    """The docs that hold a console sample."""
    return [f for f in DOC_FILES if console_blocks(f)]


def lab_docs(*, run: bool = False) -> list[Path]:
    """The docs that hold a ```console lab block; with ``run``, those with a lab sample that runs."""
    def runs(f: Path) -> bool:
        return any(r is None for b in console_blocks(f) if LAB in b.marks for r in skip_reasons(b, in_lab=True))

    return [f for f in DOC_FILES if any(LAB in b.marks for b in console_blocks(f)) and (not run or runs(f))]
