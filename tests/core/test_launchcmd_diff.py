"""Command-line words of a ros2 launch command, and unified diffs."""

from __future__ import annotations

import pytest

from panther_ops.core.config.launchcmd import (
    CommandSyntaxError,
    Token,
    arg_word,
    parse_launch_argv,
    shell_quote,
    shell_tokens,
    split_arg,
)
from panther_ops.core.yaml.diff import changed_lines, unified_diff
from panther_ops.errors import InputError


def words(text: str) -> list[str]:
    return [t.value for t in shell_tokens(text)]


def test_shell_words() -> None:
    assert words("ros2  launch\n  pkg  f.py a:=1") == ["ros2", "launch", "pkg", "f.py", "a:=1"]
    assert words("a:='x y' b:=\"q\\\"z\" 'c:=1 2'") == ["a:=x y", 'b:=q"z', "c:=1 2"]
    assert words("p:=$(find panther_description)/config/WH01.yaml") == [
        "p:=$(find panther_description)/config/WH01.yaml"]
    assert words("p:=$(ros2 pkg prefix x)/share n:=${NS:-panther}") == [
        "p:=$(ros2 pkg prefix x)/share", "n:=${NS:-panther}"]
    assert words(r"a:=b\ c") == ["a:=b c"]
    tok = shell_tokens("x 'k:=v'")[1]
    assert tok == Token("k:=v", 2, 8, "'", True)
    for bad in ("a:='x", 'a:="x', "a:=$(find x"):
        with pytest.raises(CommandSyntaxError):
            shell_tokens(bad)


def test_quoting_of_new_words() -> None:
    assert shell_quote("WH02") == "WH02"
    assert shell_quote("/config/a.yaml") == "/config/a.yaml"
    assert shell_quote("$(find p)/x") == "'$(find p)/x'"
    assert shell_quote("it's") == "'it'\\''s'"
    assert shell_quote("") == "''"
    assert shell_quote('a"b', '"') == '"a\\"b"'
    assert words(arg_word("k", "it's $(x y)")) == ["k:=it's $(x y)"]
    like = shell_tokens("k:=\"old\"")[0]
    assert arg_word("k", "new", like) == 'k:="new"'
    whole = shell_tokens("'k:=old'")[0]
    assert arg_word("k", "new", whole) == "'k:=new'"
    assert split_arg("wheel_type:=WH01") == ("wheel_type", "WH01")
    assert split_arg("a:=b:=c") == ("a", "b:=c")
    assert split_arg("--debug") is None and split_arg("1x:=2") is None


def test_parse_launch_argv() -> None:
    assert parse_launch_argv(["ros2", "launch", "pkg", "f.launch.py", "a:=1", "b:=2"]) == (
        "pkg", "f.launch.py", {"a": "1", "b": "2"}, ())
    assert parse_launch_argv(["ros2", "launch", "-d", "pkg", "f.py"])[3] == ("-d",)
    assert parse_launch_argv(["ros2", "launch", "--launch-prefix", "gdb", "pkg", "f.py"])[:2] == ("pkg", "f.py")
    assert parse_launch_argv(["ros2", "launch", "/husarion_utils/nmea_navsat.launch.py", "robot_namespace:=p"]) == (
        None, "/husarion_utils/nmea_navsat.launch.py", {"robot_namespace": "p"}, ())
    with pytest.raises(InputError, match="not `ros2 launch"):
        parse_launch_argv(["bash", "-c", "ros2 launch pkg f.py"], path="compose.yaml", line=3)
    with pytest.raises(InputError):
        parse_launch_argv(["ros2", "launch", "a:=1"])


def test_unified_diff_headers_and_markers() -> None:
    assert unified_diff("a\n", "a\n", "/home/husarion/compose.yaml") == ""
    diff = unified_diff("a\nb\n", "a\nc\n", "/home/husarion/compose.yaml")
    assert diff.splitlines()[:3] == ["--- a/home/husarion/compose.yaml", "+++ b/home/husarion/compose.yaml", "@@ -1,2 +1,2 @@"]
    assert changed_lines(diff) == ["-b", "+c"]
    nonl = unified_diff("a\nb", "a\nc", "f.yaml")
    assert nonl.endswith("-b\n\\ No newline at end of file\n+c\n\\ No newline at end of file\n")
    assert unified_diff("x\n", "y\n", "rel/path.yaml").startswith("--- a/rel/path.yaml\n+++ b/rel/path.yaml\n")


def test_a_created_or_removed_file_is_dev_null_in_its_header() -> None:
    """As diff -N and git write it: patch(1) and git apply create or delete the file."""
    created = unified_diff(None, "a\n", "/home/husarion/config/x.yaml")
    assert created.splitlines()[:3] == ["--- /dev/null", "+++ b/home/husarion/config/x.yaml", "@@ -0,0 +1 @@"]
    removed = unified_diff("a\n", None, "/home/husarion/config/x.yaml")
    assert removed.splitlines()[:3] == ["--- a/home/husarion/config/x.yaml", "+++ /dev/null", "@@ -1 +0,0 @@"]
    emptied = unified_diff("a\n", "", "/home/husarion/config/x.yaml")  # the file stays, empty
    assert emptied.splitlines()[:2] == ["--- a/home/husarion/config/x.yaml", "+++ b/home/husarion/config/x.yaml"]
    assert unified_diff(None, None, "x") == ""
