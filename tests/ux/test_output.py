"""The output module: terminal or pipe, colour, width; diffs exact (issue 16, finding 1)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from panther_ops.cli.app import _command_words
from panther_ops.cli.render import print_diffs
from panther_ops.core.yaml.diff import unified_diff
from panther_ops.results import Diff, FleetResult, Outcome, RobotResult

from .termrun import on_pty, piped, plain

SET_WHEEL = ["config", "set", "wheel_type", "WH02"]


def _diff_blocks(text: str) -> dict[str, str]:
    """The diff text shown under each ``robot: /path`` heading."""
    blocks: dict[str, list[str]] = {}
    current: list[str] | None = None
    for line in text.splitlines(keepends=True):
        m = re.match(r"(panther-\d\d): /", line)
        if m:
            current = blocks.setdefault(m.group(1), [])
        elif current is not None and line[:1] in (" ", "+", "-", "@", "\\"):
            current.append(line)
        else:
            current = None
    return {robot: "".join(lines) for robot, lines in blocks.items()}


def test_diff_lines_are_never_wrapped_on_a_narrow_terminal(demo: Path) -> None:
    run = on_pty(["-i", str(demo), *SET_WHEEL, "--all", "--dry-run"], cols=70)
    assert run.code == 0, run.out
    shown = plain(run.out).splitlines()
    # the long command lines stay whole, each with its marker
    assert "+    command: ros2 launch panther_bringup bringup.launch.py wheel_type:=WH02" in shown
    assert ("+    command: ros2 launch husarion_ugv_bringup bringup.launch.py common_dir_path:=/config "
            "launch_gamepad:=true wheel_type:=WH02") in shown
    blocks = _diff_blocks(plain(run.out))
    assert set(blocks) == {"panther-01", "panther-02", "panther-03", "panther-04"}
    for robot, block in blocks.items():  # every line of a hunk is marked (nothing folded into a context line)
        assert "wheel_type:=WH02" in block
        assert not any(line.startswith(" ") and "wheel_type:=WH02" in line for line in block.splitlines()), robot


def test_a_diff_line_longer_than_the_pipe_width_is_written_whole(capsys: pytest.CaptureFixture[str]) -> None:
    long_before = "command: " + " ".join(f"arg{i}:=value{i}" for i in range(40)) + "\n"
    long_after = long_before.replace("arg39:=value39", "arg39:=changed")
    unified = unified_diff(long_before, long_after, "/home/husarion/compose.yaml")
    fleet = FleetResult("t", [RobotResult("r1", Outcome.CHANGED, "m", diffs=[Diff("/home/husarion/compose.yaml",
                                                                                    unified)])])
    print_diffs(fleet)
    out = capsys.readouterr().out
    assert len(long_before) > 300
    assert unified in out  # byte for byte, no colour in a pipe


def test_piped_dry_run_is_a_patch_each_robot_applies_from_its_root(demo: Path, tmp_path: Path) -> None:
    """``config set ... --dry-run | patch -p1 --dry-run`` from a copy of the robot's tree (real patch)."""
    patch = shutil.which("patch")
    assert patch, "patch(1) is needed (scripts/install-test-deps.sh)"
    for robot in ("panther-01", "panther-02", "panther-03"):
        run = piped(["-i", str(demo), *SET_WHEEL, "-r", robot, "--dry-run"])
        assert run.code == 0, run.err
        assert "\x1b[" not in run.out  # plain when piped
        tree = tmp_path / f"copy-{robot}"
        shutil.copytree(demo / "robots" / robot, tree)
        before = (tree / "home/husarion/compose.yaml").read_text()
        check = subprocess.run([patch, "-p1", "--dry-run"], input=run.out, cwd=tree, capture_output=True,
                               text=True, check=False)
        assert check.returncode == 0, check.stdout + check.stderr
        assert "checking file home/husarion/compose.yaml" in check.stdout
        assert "FAILED" not in check.stdout and "fuzz" not in check.stdout and "offset" not in check.stdout
        subprocess.run([patch, "-p1", "--quiet"], input=run.out, cwd=tree, text=True, check=True)
        after = (tree / "home/husarion/compose.yaml").read_text()
        assert after != before and "wheel_type:=WH02" in after
    # --all: the one output is one patch for the fleet's tree (a directory per robot: the demo
    # fleet's robots/), every robot's file patched, no hunk fuzzed or shifted
    run = piped(["-i", str(demo), *SET_WHEEL, "--all", "--dry-run"])
    assert run.code == 0, run.err
    fleet_tree = tmp_path / "copy-of-robots"
    shutil.copytree(demo / "robots", fleet_tree)
    check = subprocess.run([patch, "-p1", "--dry-run"], input=run.out, cwd=fleet_tree, capture_output=True,
                           text=True, check=False)
    assert check.returncode == 0, check.stdout + check.stderr
    assert [line for line in check.stdout.splitlines() if line.startswith("checking file")] == [
        f"checking file {robot}/home/husarion/compose.yaml" for robot in ("panther-01", "panther-02", "panther-03", "panther-04")]
    assert "FAILED" not in check.stdout and "fuzz" not in check.stdout and "offset" not in check.stdout
    subprocess.run([patch, "-p1", "--quiet"], input=run.out, cwd=fleet_tree, text=True, check=True)
    for robot in ("panther-01", "panther-02", "panther-03", "panther-04"):
        assert "wheel_type:=WH02" in (fleet_tree / robot / "home/husarion/compose.yaml").read_text()
        untouched = (demo / "robots" / robot / "home/husarion/compose.yaml").read_text()
        assert "wheel_type:=WH02" not in untouched  # a dry run wrote nothing


def test_a_dry_run_that_creates_a_file_is_a_patch_that_creates_it(demo: Path, tmp_path: Path) -> None:
    """A controller limit on 2.1.1 writes a new file beside the compose change: ``--- /dev/null``
    as diff -N writes it, and both ``patch -p1`` and ``git apply`` make the file the robot gets."""
    run = piped(["-i", str(demo), "config", "set", "controller.linear.x.max_velocity", "1.0", "-r", "panther-01",
                 "--dry-run"])
    assert run.code == 0, run.err
    new = "home/husarion/config/panther_controller/config/WH01_controller.yaml"
    assert f"--- /dev/null\n+++ b/{new}\n@@ -0,0 +1," in run.out
    tools = [["patch", "-p1", "--quiet"], ["git", "apply", "-p1", "-"]]
    for argv in tools:
        assert shutil.which(argv[0]), f"{argv[0]} is needed (scripts/install-test-deps.sh)"
        tree = tmp_path / f"copy-{argv[0]}"
        shutil.copytree(demo / "robots" / "panther-01", tree)
        done = subprocess.run(argv, input=run.out, cwd=tree, capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stdout + done.stderr
        assert "max_velocity: 1.0" in (tree / new).read_text()
        compose = (tree / "home/husarion/compose.yaml").read_text()
        assert "controller_config_path:=/config/panther_controller/config/WH01_controller.yaml" in compose
    assert not (demo / "robots" / "panther-01" / new).exists()  # a dry run wrote nothing


def test_colour_follows_the_terminal_no_color_and_the_color_option(demo: Path) -> None:
    args = ["-i", str(demo), *SET_WHEEL, "-r", "panther-01", "--dry-run"]
    assert "\x1b[32m+" in on_pty(args).out  # a terminal: additions green
    assert "\x1b[3" not in on_pty(args, env={"NO_COLOR": "1"}).out
    assert "\x1b[3" not in on_pty(["--color", "never", *args]).out
    coloured = piped(["--color", "always", *args])
    assert coloured.code == 0 and "\x1b[32m+" in coloured.out
    assert "\x1b[" not in piped(args).out
    assert "\x1b[32m+" in piped(["--color", "always", *args], env={"NO_COLOR": "1"}).out  # the flag wins


def test_the_color_option_takes_a_value_before_the_command() -> None:
    assert _command_words(["--color", "never", "config", "set", "x", "1"]) == ("config", "set")
    assert _command_words(["--color=always", "status"]) == ("status", None)


def test_a_bad_color_value_is_a_usage_error(demo: Path) -> None:
    run = piped(["--color", "sometimes", "-i", str(demo), "status", "--all"])
    assert run.code == 2 and "sometimes" in run.err


def test_text_from_robots_is_shown_as_it_is_no_emoji_codes(capsys: pytest.CaptureFixture[str]) -> None:
    """A file or host name such as ``a:x:b`` is printed as written: rich's emoji codes are off."""
    from panther_ops.cli.output import print_message
    from panther_ops.cli.render import error, esc

    print_message(f"robot said {esc('compose:x: and :thumbs_up:')}")
    error("/home/husarion/:warning:.yaml: not found")
    err = capsys.readouterr().err
    assert "robot said compose:x: and :thumbs_up:" in err
    assert "error /home/husarion/:warning:.yaml: not found" in err
