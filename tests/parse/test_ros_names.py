"""The one parser of ROS names (core/parse/ros_names.py) against rcl's and rmw's rules."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from panther_ops.core.parse.ros_names import RosNameError, namespace, service_name, topic_name

# the design article's examples, and what rcl_validate_topic_name accepts
VALID_TOPICS = ["foo", "abc123", "_foo", "Foo", "BAR", "~", "foo/bar", "~/foo", "{node}_bar", "foo/{ns}/bar",
                "foo/_bar", "/foo", "/bar/baz", "/_private/thing", "hardware/e_stop_reset", "cmd_vel",
                "/panther/cmd_vel", "a{node}b", "foo__bar"]
INVALID_TOPICS = {
    "": "non-empty",
    "123abc": "starts with a digit",
    "foo/1bar": "starts with a digit",
    "foo bar": "' ' is not allowed",
    " ": "' ' is not allowed",
    "foo//bar": "'//'",
    "foo/": "ends with '/'",
    "/": "'/' alone",
    "~foo": "'~' must be followed by '/'",
    "foo~": "'~' is allowed only as the first character",
    "foo~/bar": "'~'",
    "foo/~bar": "'~'",
    "/~": "'~'",
    "foo/~/bar": "'~'",
    "hardware/e-stop-reset": "'-' is not allowed",
    "a;b": "';' is not allowed",
    "é": "'é' is not allowed",
    "foo/{bar": "without its '}'",
    "foo}": "without its '{'",
    "{{node}}": "inside a {substitution}",
    "{no/de}": "'/' inside",
    "{4node}": "substitution starts with a digit",
    "{robot}/x": "unknown substitution {robot}",
    "{}": "unknown substitution {}",
    "x" * 248: "longer than 247",
}


@pytest.mark.parametrize("name", VALID_TOPICS)
def test_valid_topic_and_service_names(name: str) -> None:
    assert topic_name(name) == name
    assert service_name(name) == name


@pytest.mark.parametrize(("name", "why"), INVALID_TOPICS.items(), ids=repr)
def test_invalid_topic_names_say_why(name: str, why: str) -> None:
    with pytest.raises(RosNameError, match="topic name") as exc:
        topic_name(name)
    assert why in str(exc.value)
    with pytest.raises(RosNameError, match="service name"):
        service_name(name)


@pytest.mark.parametrize("value", [None, 3, True, ["a"]])
def test_a_name_is_a_text(value: object) -> None:
    with pytest.raises(RosNameError):
        topic_name(value)
    with pytest.raises(RosNameError):
        namespace(value)


@pytest.mark.parametrize("ns", ["", "/", "panther", "/panther", "fleet/panther_01", "/fleet/panther_01", "_hidden"])
def test_valid_namespaces(ns: str) -> None:
    assert namespace(ns) == ns


@pytest.mark.parametrize(("ns", "why"), [
    ("1robot", "starts with a digit"), ("fleet/2", "starts with a digit"), ("panther/", "ends with '/'"),
    ("a//b", "'//'"), ("//a", "'//'"), ("e-stop", "'-' is not allowed"), ("~/x", "'~' is not allowed in a namespace"),
    ("{node}", "'{' is not allowed"), ("pan ther", "' ' is not allowed"), ("x" * 245, "longer than 245"),
], ids=repr)
def test_invalid_namespaces(ns: str, why: str) -> None:
    with pytest.raises(RosNameError, match="namespace") as exc:
        namespace(ns)
    assert why in str(exc.value)


def test_namespace_length_counts_the_leading_slash() -> None:
    assert namespace("x" * 244) == "x" * 244
    assert namespace("/" + "x" * 244) == "/" + "x" * 244


def test_bt_service_names_are_ros_names(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 23 item 5: a literal service_name port of a BT project (bt validate, config push --as bt-*)."""
    from panther_ops.cli.app import main
    from panther_ops.core.kinds.bt import service_name_findings

    trees = Path(__file__).resolve().parents[2] / "templates" / "behavior_trees"
    shutil.copytree(trees, tmp_path / "proj")
    project = tmp_path / "proj" / "PantherLightsBT.btproj"
    assert service_name_findings(project) == []
    lights = tmp_path / "proj" / "lights.xml"
    text = lights.read_text()
    lights.write_text(text.replace('service_name="lights/set_animation"', 'service_name="lights/set-animation"', 1)
                      .replace('service_name="lights/set_animation"', 'service_name="{my_service}"', 1))
    [found] = service_name_findings(project)
    assert found.code == "bt-service-name" and "lights.xml: Lights" in found.where
    assert found.message.startswith("<CallSetLedAnimationService> service_name='lights/set-animation': not a valid")
    capsys.readouterr()
    assert main(["bt", "validate", str(project)]) == 2
    out = " ".join(capsys.readouterr().out.split())
    assert "service_name='lights/set-animation': not a valid ROS service name: '-' is not allowed" in out
