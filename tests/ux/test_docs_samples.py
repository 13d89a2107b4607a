"""Every console sample of docs/ and README.md shows what a real run shows (issue 26, finding 7):
each doc's samples re-run on a fresh demo fleet by scripts/capture_docs.py's code
(tests/ux/docsamples.py) and compared; a difference fails with its diff (re-capture with
``python scripts/capture_docs.py``)."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

import pytest

from .docsamples import ELIDED, comparable, docs, follow, marks, matches
from .examples import ROOT, console_blocks

DOCS = docs()


@pytest.mark.parametrize("doc", DOCS, ids=[str(d.relative_to(ROOT)) for d in DOCS])
def test_every_sample_of_the_doc_is_what_a_run_shows(doc: Path) -> None:
    outcome = follow(doc)
    assert not outcome.diffs, "".join(outcome.diffs) + "\nre-capture: python scripts/capture_docs.py " + \
        str(doc.relative_to(ROOT))


def test_the_samples_are_the_docs_console_blocks_and_most_run() -> None:
    """Not vacuous: the docs hold samples, most of them run on the demo fleet, and a block that
    does not run is marked as such."""
    blocks = [b for d in DOCS for b in console_blocks(d)]
    assert {d.name for d in DOCS} >= {"getting-started.md", "commands.md", "configuration.md", "output.md"}
    run = [b for b in blocks if "lab" not in b.marks and "as-written" not in b.marks]
    assert len(run) >= 40
    assert all(marks(b) == b.marks for b in blocks)


def test_a_changed_sample_is_caught(tmp_path: Path) -> None:
    """The comparison: what varies run to run is not a difference; a changed word, a missing
    line (the inventory line, the recap) is; ``...`` stands for lines left out."""
    real = ["inventory: demo-fleet (from -i)", "┃ panther-01 │ changed │ backup 20261122T164449Z-dec5 │",
            "3 robots: 3 changed in 0.8 s", "recap", "panther-01  changed  connect 0.0 s  plan 0.7 s"]
    again = ["inventory: demo-fleet (from -i)", "┃ panther-01 │ changed │ backup 20270101T000000Z-ab12 │",
             "3 robots: 3 changed in 12.5 s", "recap", "panther-01  changed  connect 0.1 s  plan 0.6 s"]
    assert matches(again, real)
    assert comparable(again) == comparable(real)
    assert not matches(real[1:], real)  # no inventory line
    assert not matches(real[:3], real)  # no recap
    assert not matches([line.replace("changed", "ok") for line in real], real)
    assert matches([real[0], ELIDED, real[-1]], real)
    assert not matches([real[0], ELIDED, "4 robots: 4 changed in 0.8 s"], real)


def test_the_reader_types_an_answer_at_its_question_and_a_password_unseen(tmp_path: Path) -> None:
    """The lab mode's terminal (docs/shutdown.md's `setup --ask-password`): the answer of a
    ``[y/N]`` sample line is typed when the question shows, and echoed after it; the page's
    password once the prompt turned the echo off, so it is read but never shown."""
    from .termrun import shell_on_pty

    script = ("import getpass, sys; sys.stderr.write('Trust it? [y/N]: '); sys.stderr.flush(); a = input(); "
              "p = getpass.getpass('password of husarion@10.200.2.101: '); "
              "print('answer', a, 'password', 'right' if p == 'lab-secret' else 'wrong:' + p)")
    run = shell_on_pty(f"{sys.executable} -c {shlex.quote(script)}", cols=80, cwd=tmp_path,
                       env={"PATH": "/usr/bin:/bin"}, timeout=20, answers=("y",), password="lab-secret")
    lines = run.out.replace("\r", "").splitlines()
    assert run.code == 0, run.out
    assert lines == ["Trust it? [y/N]: y", "password of husarion@10.200.2.101: ", "answer y password right"]
    assert "lab-secret" not in run.out


def test_the_lab_addresses_are_shown_as_on_an_idle_machine() -> None:
    """A lab up beside others has other subnets: the docs' addresses are relabelled both ways
    (the maps may cross: 7 -> 2 while 2 -> 1)."""
    from .docsamples import relabel

    shown = {2: 1, 7: 2, 9: 3}
    line = "10.200.7.101 answers ping from r01 (10.200.2.5), 10.200.9.1 and 10.200.11.4"
    assert relabel(line, shown) == "10.200.2.101 answers ping from r01 (10.200.1.5), 10.200.3.1 and 10.200.11.4"
    back = {doc: real for real, doc in shown.items()}
    assert relabel(relabel(line, shown), back) == line
    assert relabel("110.200.7.1 10.2000.7.1", shown) == "110.200.7.1 10.2000.7.1"


def test_the_reader_types_the_password_at_a_read_s_and_keys_at_a_terminal(tmp_path: Path) -> None:
    """docs/gps.md's ``read -rsp`` of the router's password gets the page's password, unseen, and
    carried to the next line; docs/remote.md's teleop gets its keys once its banner shows, on a
    terminal of the docs' width that the command controls (a Ctrl-C is the terminal's)."""
    from .docsamples import COLS, READ_SECRET, Reader
    from .examples import Sample
    from .termrun import keys_on_pty

    reader = Reader(tmp_path, password="lab-secret", page="gps.md")
    assert READ_SECRET.match("read -rsp 'router password: ' P; echo") and not READ_SECRET.match("readlink -s x")
    assert reader.run(Sample(0, "read -rsp 'router password: ' P; echo; export P", ())) == ["router password:"]
    assert reader.run(Sample(1, 'echo "${#P} ${P:0:3}"', ())) == ["10 lab"]
    code, out = keys_on_pty(["/bin/bash", "-c", "stty size; echo ready; read -rn1 k; echo got $k; exec sleep 30"],
                            [(b"i", 0.3), (b"\x03", 0.5)], ready="ready", timeout=20, env={"PATH": "/usr/bin:/bin"},
                            cols=COLS)
    lines = out.replace("\r", "").splitlines()
    # the key echoed by the terminal, then read; the Ctrl-C the terminal's SIGINT to the command
    assert (lines, code) == ([f"50 {COLS}", "ready", "igot i", "^C"], -2), out


def test_a_labs_host_keys_and_the_managers_sim_time_vary_the_rest_does_not() -> None:
    """A lab makes new host keys each time it comes up, and a simulated run's time stamps (real time)
    differ by a tenth with the machine's load: not a difference; another address or call is."""
    key = "ssh-ed25519 AAAAC3NzaC1lZDI1NTE5AAAAI"
    doc = [f"+10.200.100.11 {key}KQJcjx2sVoxkjSPj21aVL0hZTuYNAAERYZGifBdGtnP", "t=    0.0 call hardware/fan_enable(data=True) -> ok"]
    run = [f"+10.200.100.11 {key}Lw1lvsM8zQ2ZPwuG/V8SuVFoShn1wwezpkMhXhvMEOx", "t=    0.1 call hardware/fan_enable(data=True) -> ok"]
    assert matches(doc, run)
    assert not matches(doc, [run[0].replace(".11 ", ".12 "), run[1]])
    assert not matches(doc, [run[0], run[1].replace("True", "False")])
