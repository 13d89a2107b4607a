"""Command-line words of a ros2 launch command, and unified diffs."""

from __future__ import annotations

import pytest

from panther_ops.core.robot.launchcmd import (
    CommandSyntaxError,
    Token,
    arg_word,
    check_script_word,
    launch_words,
    parse_launch_argv,
    put_arg,
    remove_args,
    script_span,
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


# ------------------------------------------------ the script of bash -c "..." (upstream's gamepad)

UPSTREAM_SCRIPT = ("ros2 launch joy2twist gamepad_controller.launch.py joy2twist_params_file:=$(ros2 pkg prefix "
                   "joy2twist)/share/joy2twist/config/joy2twist_panther.yaml namespace:=panther")
"""husarion/panther-docker@2.0.4 and @2.1.1:demo/compose.minimal-setup.yaml, the gamepad's bash -c script."""


def test_the_script_of_bash_c_is_read_with_its_substitution_kept() -> None:
    argv = words(f'bash -c "{UPSTREAM_SCRIPT}"')
    assert argv == ["bash", "-c", UPSTREAM_SCRIPT]
    shell, launch = launch_words(argv)
    assert shell == ("bash", "-c")
    assert launch[4] == ("joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/share/joy2twist/config/"
                         "joy2twist_panther.yaml")  # shlex would split $(...) in two words
    assert parse_launch_argv(launch)[:3] == ("joy2twist", "gamepad_controller.launch.py", {
        "joy2twist_params_file": "$(ros2 pkg prefix joy2twist)/share/joy2twist/config/joy2twist_panther.yaml",
        "namespace": "panther"})
    assert launch_words(["/bin/sh", "-c", "ros2 launch p f.py"])[1] == ["ros2", "launch", "p", "f.py"]
    assert launch_words(["ros2", "launch", "p", "f.py"]) == ((), ["ros2", "launch", "p", "f.py"])
    assert launch_words(["bash", "-c", "ros2 launch p f.py", "$0"])[0] == ()  # not only a script: argv as is
    for script in ("ros2 launch p f.py; rm -rf /", ". /x.sh && ros2 launch p f.py", "ros2 launch p f.py > /log",
                   "ros2 launch p f.py a:=`id`", "ros2 launch p f.py\n  a:=1"):
        with pytest.raises(InputError, match="more than one command"):
            launch_words(["bash", "-c", script], path="compose.yaml", line=3)
    assert launch_words(["bash", "-c", "ros2 launch p f.py 'a:=x;y' b:=$(c | d)"])[1][4:] == ["a:=x;y", "b:=$(c | d)"]


def test_put_and_remove_inside_a_script_round_trip() -> None:
    text = f'bash -c "{UPSTREAM_SCRIPT}"'
    start, end, quote = script_span(text)
    assert (text[start:end], quote) == (UPSTREAM_SCRIPT, '"')
    script = text[start:end]
    new = put_arg(script, "joy2twist_params_file", lambda like: arg_word("joy2twist_params_file", "/config/p.yaml",
                                                                         like))
    assert new == UPSTREAM_SCRIPT.replace("$(ros2 pkg prefix joy2twist)/share/joy2twist/config/joy2twist_panther.yaml",
                                          "/config/p.yaml")
    added = put_arg(script, "use_sim", lambda like: arg_word("use_sim", "True", like))
    assert added == UPSTREAM_SCRIPT + " use_sim:=True"
    assert remove_args(added, "use_sim") == UPSTREAM_SCRIPT
    lines = "ros2 launch p f.py\n        a:=1"  # a script over lines of a folded block: a line of its own
    assert put_arg(lines, "b", lambda like: "b:=2") == lines + "\n        b:=2"
    assert remove_args(lines + "\n        b:=2", "b") == lines
    with pytest.raises(InputError, match="edit this one by hand"):
        script_span('bash -c "ros2 launch p f.py a:=\\"x\\""')  # escapes: not the script as written
    with pytest.raises(InputError, match="edit this one by hand"):
        script_span("bash -c ros2' launch p f.py'")


@pytest.mark.parametrize(("value", "named"), [
    ('a"b', 'a double quote (")'), ("$(find p)/x.yaml", "a dollar sign ($)"), ("a`id`", "a backquote (`)"),
    ("a\\b", "a backslash (\\)"), ("it's", "quoted for the shell it needs a backslash (\\)")])
def test_a_word_the_double_quotes_would_change_is_refused_naming_the_value(value: str, named: str) -> None:
    word = arg_word("p", value)
    with pytest.raises(InputError) as exc:
        check_script_word(word, '"', name="p", value=value, path="compose.yaml", line=7)
    assert f"launch argument p: the value {value!r}" in exc.value.message and named in exc.value.message
    assert "compose.yaml:7" in exc.value.message
    check_script_word(word, None, name="p", value=value)  # the script of a list command: no outer quotes
    check_script_word(arg_word("p", "/config/a b.yaml"), '"', name="p", value="/config/a b.yaml")  # 'a b' kept
    with pytest.raises(InputError, match="single quote"):
        check_script_word("p:='a b'", "'", name="p", value="a b")
