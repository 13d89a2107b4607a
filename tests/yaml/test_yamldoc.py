"""YamlDocument: in-place edits keep every byte that is not edited."""

from __future__ import annotations

import math

import pytest

from panther_ops.core.yaml.document import (
    Alias,
    Block,
    DocumentError,
    Flow,
    PathError,
    Quoted,
    YamlDocument,
    parse_path,
)
from panther_ops.core.yaml.render import format_float, plain_ok
from panther_ops.errors import InputError, UsageError

COMPOSE = """\
# top comment
x-common: &common
  restart: always # shared
  environment:
    - A=1
    - B=2

services:
  drv:
    image: husarion/panther:humble-2.1.1-20240828
    <<: *common
    volumes:
      - /a:/a
      - '/b:/b' # quoted
    command: ros2 launch panther_bringup bringup.launch.py

  other:
    <<: *common
    image: busybox
"""


def doc(text: str = COMPOSE) -> YamlDocument:
    return YamlDocument(text, "compose.yaml")


# ------------------------------------------------------------------ paths & reading


def test_parse_path_forms() -> None:
    assert parse_path("a.b[2].c") == ("a", "b", 2, "c")
    assert parse_path("hosts.0.ip") == ("hosts", "0", "ip")
    assert parse_path(r"a\.b.c") == ("a.b", "c")
    assert parse_path(("/**", "drive_controller")) == ("/**", "drive_controller")
    with pytest.raises(PathError):
        parse_path("a[1")


def test_get_resolves_merges_and_reports_origin() -> None:
    d = doc()
    assert d.get("services.drv.restart") == "always"
    assert d.get("services.drv.environment") == ["A=1", "B=2"]
    assert d.origin("services.drv.restart") == "merged:common"
    assert d.origin("services.drv.image") == "own"
    assert d.origin("services.drv.nothing") is None
    assert d.get("services.drv.volumes[1]") == "/b:/b"
    assert d.get("services.drv.volumes.-1") == "/b:/b"
    assert d.get("missing", "dflt") == "dflt"
    assert d.keys("services.drv")[:2] == ["image", "volumes"]
    assert d.anchors() == {"common": 2}


def test_info_gives_line_column_and_style() -> None:
    d = doc()
    info = d.info("services.drv.volumes[1]")
    assert (info.kind, info.style, info.line, info.column, info.raw) == ("scalar", "'", 14, 8, "'/b:/b'")
    assert d.info("services.drv.volumes").style == "block"
    assert d.line_of("services.other.image") == 19
    assert d.line_of("nope") is None


def test_missing_path_error_names_file_and_line() -> None:
    with pytest.raises(PathError) as err:
        doc().get("services.drv.ulimits.rtprio")
    assert isinstance(err.value, InputError) and isinstance(err.value, UsageError)
    assert "compose.yaml:10" in str(err.value) and "services.drv.ulimits.rtprio" in str(err.value)


def test_invalid_yaml_names_the_line() -> None:
    with pytest.raises(DocumentError) as err:
        YamlDocument("a: 1\nb: [1, 2\nc: 3\n", "f.yaml")
    assert "f.yaml:" in str(err.value) and err.value.line is not None


def test_duplicate_keys_are_refused_with_both_lines() -> None:
    with pytest.raises(DocumentError) as err:
        YamlDocument("a: 1\nb: 2\na: 3\n", "f.yaml")
    assert err.value.line == 3 and "first at line 1" in str(err.value)


def test_multiple_documents_refused() -> None:
    with pytest.raises(DocumentError):
        YamlDocument("a: 1\n---\nb: 2\n")


# ------------------------------------------------------------------ scalar edits


def test_set_scalar_changes_only_that_value_keeping_quotes_and_comments() -> None:
    d = doc()
    assert d.set("services.drv.volumes[1]", "/c:/c")
    assert "      - '/c:/c' # quoted\n" in d.text
    assert d.text.replace("'/c:/c'", "'/b:/b'") == COMPOSE
    assert d.changed and "-      - '/b:/b' # quoted" in d.diff()


def test_set_same_value_is_a_noop() -> None:
    d = doc()
    assert d.set("services.drv.image", "husarion/panther:humble-2.1.1-20240828") is False
    assert d.set("services.drv.restart", "always") is False  # inherited, same value
    assert d.text == COMPOSE and d.notes == []


@pytest.mark.parametrize(
    ("value", "written"),
    [
        ("true", "'true'"),
        ("yes", "'yes'"),
        ("012", "'012'"),
        ("1.5", "'1.5'"),
        ("a: b", "'a: b'"),
        ("x #y", "'x #y'"),
        ("it's", "it's"),
        ("-x", "-x"),
        ("- x", "'- x'"),
        ("", "''"),
        ("tab\there", '"tab\\there"'),
        (True, "true"),
        (3, "3"),
        (2.0, "2.0"),
        (1e-05, "1.0e-05"),
        (None, "null"),
    ],
)
def test_scalar_rendering_reads_back_the_same(value: object, written: str) -> None:
    d = YamlDocument("k: old\n")
    d.set("k", value)
    assert d.text == f"k: {written}\n"
    assert d.get("k") == value


def test_boolean_case_and_double_quotes_are_kept() -> None:
    d = YamlDocument('a: True\nb: "x"\nc: FALSE\n')
    d.set("a", False)
    d.set("b", "y")
    d.set("c", True)
    assert d.text == 'a: False\nb: "y"\nc: TRUE\n'


def test_int_and_float_types_are_kept_apart() -> None:
    d = YamlDocument("v: 2\n")
    assert d.set("v", 2.0) is True  # ROS: an int is not a double
    assert d.text == "v: 2.0\n"
    assert d.set("v", 2.0) is False


def test_reverted_value_gets_its_original_text_back() -> None:
    text = "cov: [1.8e-3, 0.0]\nx: 0x10\n"
    d = YamlDocument(text)
    d.set("cov[0]", 0.5)
    d.set("x", 17)
    d.set("cov[0]", 0.0018)
    d.set("x", 16)
    assert d.text == text


def test_nan_and_inf() -> None:
    d = YamlDocument("a: .nan\nb: 1.0\n")
    assert math.isnan(d.get("a"))
    assert d.set("a", math.nan) is False
    d.set("b", math.inf)
    assert d.text.endswith("b: .inf\n")


def test_anchored_scalar_keeps_its_anchor() -> None:
    d = YamlDocument("a: &x 1\nb: *x\n")
    d.set("a", 2)
    assert d.text == "a: &x 2\nb: *x\n"
    assert d.get("b") == 2


def test_block_scalar_set_keeps_indicator_and_indentation() -> None:
    d = YamlDocument("cmd: >\n    ros2 launch a b\nz: 1\n")
    d.set("cmd", "ros2 launch a c\n")
    assert d.text == "cmd: >\n    ros2 launch a c\nz: 1\n"
    d.set("cmd", "two\nlines\n")
    assert d.get("cmd") == "two\nlines\n"
    assert d.text.startswith("cmd: |\n    two\n    lines\n")


def test_empty_value_gets_a_value() -> None:
    d = YamlDocument("a:\nb: 1\n")
    d.set("a", "x")
    assert d.text == "a: x\nb: 1\n"


# ------------------------------------------------------------------ structure edits


def test_new_keys_go_after_the_last_entry_at_its_column() -> None:
    d = doc()
    d.set("services.drv.ulimits.rtprio.soft", 99)
    assert (
        "    command: ros2 launch panther_bringup bringup.launch.py\n"
        "    ulimits:\n      rtprio:\n        soft: 99\n\n  other:" in d.text
    )


def test_new_service_is_separated_like_the_others() -> None:
    d = doc()
    d.set("services.gps", {"image": "husarion/nmea-gps", "<<": Alias("common"), "command": Block("a\n  b:=1\n", ">")})
    assert d.text.endswith(
        "    image: busybox\n\n  gps:\n    image: husarion/nmea-gps\n    <<: *common\n    command: >\n      a\n        b:=1\n"
    )
    assert d.get("services.gps.restart") == "always"
    d.delete("services.gps")
    assert d.text == COMPOSE


def test_merged_key_gets_an_explicit_override_and_the_anchor_stays() -> None:
    d = doc()
    assert d.set("services.drv.environment[1]", "B=3")
    assert d.get("services.drv.environment") == ["A=1", "B=3"]
    assert d.get("services.other.environment") == ["A=1", "B=2"]
    assert d.get("x-common.environment") == ["A=1", "B=2"]
    assert d.origin("services.drv.environment") == "own"
    assert "inherited from &common" in d.notes[0]
    assert "    environment:\n      - A=1\n      - B=3\n" in d.text
    assert "  environment:\n    - A=1\n    - B=2\n" in d.text


def test_editing_the_anchor_changes_every_merge() -> None:
    d = doc()
    d.set("x-common.restart", "no")
    assert d.get("services.drv.restart") == "no" and d.get("services.other.restart") == "no"
    assert d.text == COMPOSE.replace("restart: always", "restart: 'no'")


def test_deleting_an_inherited_key_is_refused() -> None:
    with pytest.raises(DocumentError) as err:
        doc().delete("services.drv.restart")
    assert "inherited from &common" in str(err.value)


def test_append_to_inherited_list_materialises() -> None:
    d = doc()
    d.append("services.other.environment", "C=3")
    assert d.get("services.other.environment") == ["A=1", "B=2", "C=3"]
    assert d.get("services.drv.environment") == ["A=1", "B=2"]


def test_materialize_and_alias_values() -> None:
    d = YamlDocument("a: &x [1, 2]\nb: *x\n")
    assert d.materialize("b") is True
    assert d.text == "a: &x [1, 2]\nb: [1, 2]\n"
    assert d.materialize("a") is False
    d2 = YamlDocument("a: &x {k: 1}\nb: *x\n")
    d2.set("b.k", 2)
    assert d2.get("a.k") == 1 and d2.get("b.k") == 2
    assert "alias of &x" in d2.notes[0]


@pytest.mark.parametrize(("text", "steps"), [
    pytest.param("hosts:\n  # NUC\n  - ip: 1\n    user: a\n  # UR5\n  - ip: 2\n    user: b\nz: 1\n",
                 [("hosts[1]", "hosts:\n  # NUC\n  - ip: 1\n    user: a\nz: 1\n"),
                  ("hosts[0]", "hosts: []\nz: 1\n")],
                 id="removes-lines-comments-and-separator"),
    pytest.param("hosts:\n  - ip: 1\n    user: a\n",
                 [("hosts[0].ip", "hosts:\n  - user: a\n"),
                  ("hosts[0].user", "hosts:\n  - {}\n")],
                 id="first-key-of-a-list-item"),
])
def test_delete_in_turn(text: str, steps: list[tuple[str, str]]) -> None:
    d = YamlDocument(text)
    for path, after in steps:
        d.delete(path)
        assert d.text == after, path


def test_delete_last_key_leaves_empty_mapping() -> None:
    d = YamlDocument("a:\n  b: 1\nc: 2\n")
    d.delete("a.b")
    assert d.text == "a: {}\nc: 2\n"
    assert d.delete("a.b") is False
    with pytest.raises(PathError):
        d.delete("a.b", missing_ok=False)


def test_flow_collections_are_edited_in_place() -> None:
    d = YamlDocument("m: { a: 1, b: 2 }\nl: [x, 'y']\ne: []\n")
    d.set("m.c", 3)
    d.append("l", "z")
    d.append("e", 1)
    d.set("l[1]", "w")
    assert d.text == "m: { a: 1, b: 2, c: 3 }\nl: [x, 'w', z]\ne: [1]\n"
    d.delete("m.a")
    d.delete("l[2]")
    assert d.text == "m: { b: 2, c: 3 }\nl: [x, 'w']\ne: [1]\n"


def test_multiline_flow_list_append_keeps_one_item_per_line() -> None:
    d = YamlDocument('command: [\n  "ros2",\n  "launch",\n]\n')
    d.append("command", Quoted("x:=1", '"'))
    assert d.text == 'command: [\n  "ros2",\n  "launch",\n  "x:=1",\n]\n'


def test_sequence_indentation_is_detected() -> None:
    d = YamlDocument("a:\n- 1\nb:\n    c: 1\n")
    assert (d.indentation.mapping, d.indentation.offset) == (4, 0)
    d.set("z", {"k": [1, 2]})
    assert d.text.endswith("z:\n    k:\n    - 1\n    - 2\n")
    assert (doc().indentation.mapping, doc().indentation.offset) == (2, 2)


def test_empty_document_and_missing_final_newline() -> None:
    d = YamlDocument("# only a comment\n")
    d.set("a.b", 1)
    assert d.text == "# only a comment\na:\n  b: 1\n"
    d2 = YamlDocument("a: 1")
    d2.set("b", 2)
    assert d2.text == "a: 1\nb: 2\n"
    assert d2.diff().endswith("+b: 2\n")


def test_markers_render_styles() -> None:
    d = YamlDocument("a: 1\n")
    d.set("f", Flow([1, "x"]))
    d.set("l", Block("x\ny\n"))
    d.set("g", Block("x\ny", ">"))
    d.set("q", Quoted("1", '"'))
    assert d.text == 'a: 1\nf: [1, x]\nl: |\n  x\n  y\ng: >-\n  x\n  y\nq: "1"\n'
    assert d.get("l") == "x\ny\n" and d.get("g") == "x y" and d.get("q") == "1"
    with pytest.raises(ValueError, match=r"is '\|' or '>', not '\|-'"):
        Block("x", "|-")


def test_cannot_descend_into_a_scalar_or_past_the_end() -> None:
    d = YamlDocument("a: 1\nl: [1]\n")
    with pytest.raises(PathError):
        d.set("a.b", 1)
    with pytest.raises(PathError):
        d.set("l[3]", 1)


def test_replace_span_is_verified() -> None:
    d = YamlDocument("a: x y\nb: 1\n")
    with pytest.raises(DocumentError):
        d.replace_span(0, 6, "a: x\nb: 2", path="a", expected="x")
    assert d.text == "a: x y\nb: 1\n"
    assert d.replace_span(3, 6, "x z", path="a", expected="x z")
    assert d.text == "a: x z\nb: 1\n"


def test_plain_ok_and_float_format() -> None:
    assert plain_ok("husarion/panther:humble-2.1.1")
    assert not plain_ok("on") and not plain_ok("~") and not plain_ok("1:20")
    assert not plain_ok("a,b", flow=True) and plain_ok("a,b")
    assert format_float(5.4e-5) == "5.4e-05" and format_float(3.0) == "3.0"
