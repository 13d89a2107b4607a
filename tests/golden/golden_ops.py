"""Apply a golden case (tests/golden/cases/*.yaml) and return the edited text.

A case names an input file (relative to the repository), the path it has on the robot
(for the diff headers), an operation and its arguments, and the expected unified diff:

    description: set wheel_type on a one-line command
    input: templates/compose/panther-2.1.1.yaml
    path: /home/husarion/compose.yaml
    op: compose.set_arg
    args: {name: wheel_type, value: WH02}
    notes: []            # optional: substrings expected in the edit notes / warnings
    expect: |
      --- a/home/husarion/compose.yaml
      ...

Operations: ``yaml.set|delete|append`` (args: path, value), ``compose.<method>`` (any
ComposeFile method, args as keywords), ``launch.set`` (args: values, force),
``controller.set`` (args: stack, wheel_type, key, value, force).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.robot import arg_edits
from panther_ops.core.robot.compose import ComposeFile
from panther_ops.core.robot.controller import ControllerConfig
from panther_ops.core.stack import stack_from_version
from panther_ops.core.yaml.document import Block, Flow, Quoted, YamlDocument

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "tests" / "golden" / "cases"


@dataclass
class Outcome:
    before: str
    after: str
    notes: list[str] = field(default_factory=list)


def _markers(value: Any) -> Any:
    """``{"$folded": "..."}`` / ``$literal`` / ``$flow`` / ``$quoted`` in case args -> markers."""
    if isinstance(value, dict):
        if set(value) == {"$folded"}:
            return Block(value["$folded"], ">")
        if set(value) == {"$literal"}:
            return Block(value["$literal"])
        if set(value) == {"$flow"}:
            return Flow(_markers(value["$flow"]))
        if set(value) == {"$quoted"}:
            return Quoted(value["$quoted"])
        return {k: _markers(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_markers(v) for v in value]
    return value


def apply_case(case: dict[str, Any]) -> Outcome:
    text = (ROOT / case["input"]).read_text(encoding="utf-8")
    path = case.get("path", case["input"])
    group, _, name = case["op"].partition(".")
    args = _markers(dict(case.get("args") or {}))
    if group == "yaml":
        doc = YamlDocument(text, path)
        getattr(doc, name)(args.pop("path"), *([args.pop("value")] if "value" in args else []), **args)
        return Outcome(text, doc.text, list(doc.notes))
    if group == "compose":
        compose = ComposeFile.parse(text, path)
        getattr(compose, name)(**args)
        return Outcome(text, compose.text(), list(compose.notes))
    if group == "launch":
        compose = ComposeFile.parse(text, path)
        change = arg_edits.set_launch_args(compose, args["values"], force=bool(args.get("force")))
        return Outcome(text, compose.text(), [*compose.notes, *change.warnings])
    if group == "controller":
        stack = stack_from_version(str(args["stack"]))
        config = ControllerConfig.parse(text, stack, args["wheel_type"], path=path)
        result = config.set(args["key"], args["value"], force=bool(args.get("force")))
        return Outcome(text, config.text(), [*config.doc.notes, *result.warnings])
    raise ValueError(f"unknown op {case['op']!r}")
