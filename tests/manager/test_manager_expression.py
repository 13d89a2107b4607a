from __future__ import annotations

from typing import Any

import pytest

from panther_ops.manager.bt.expression import parse
from panther_ops.manager.errors import ScriptError


class DictEnv(dict[str, Any]):
    def get(self, name: str, default: Any = None) -> Any:  # type: ignore[override]
        if name not in self:
            raise ScriptError(f"'{name}' is not on the blackboard")
        return self[name]

    def set(self, name: str, value: Any) -> None:
        self[name] = value

    def exists(self, name: str) -> bool:
        return name in self


@pytest.fixture
def env() -> DictEnv:
    return DictEnv(battery_status=1, POWER_SUPPLY_STATUS_CHARGING=1, POWER_SUPPLY_STATUS_FULL=4,
                   cpu_temp=71.5, CPU_FAN_ON_TEMP=70.0, fan_state=False, e_stop_state=True,
                   current_anim_id=-1, ERROR_ANIM_ID=2, round="0.700000", shown="0.600000")


@pytest.mark.parametrize(("source", "expected"), [
    ("battery_status == POWER_SUPPLY_STATUS_CHARGING", True),
    ("battery_status != POWER_SUPPLY_STATUS_CHARGING && battery_status != POWER_SUPPLY_STATUS_FULL",
     False),
    ("cpu_temp > CPU_FAN_ON_TEMP || fan_state", True),
    ("!fan_state", True),
    ("!e_stop_state || current_anim_id == ERROR_ANIM_ID", False),
    ("(1 + 2) * 3 == 9", True),
    ("10 / 4 == 2.5", True),
    ("-1 < 0", True),
    ("0x10 == 16", True),
    ("round == '0.700000'", True),
    ('round != "0.700000"', False),
    ("round == shown", False),
    ("round > 0.5", True),
    ("true && !false", True),
    ("cpu_temp >= 71.5 ? 'hot' : 'cold'", "hot"),
    ("'a' .. 1", "a1"),
])
def test_expressions_evaluate_like_bt_cpp(env: DictEnv, source: str, expected: Any) -> None:
    assert parse(source).run(env) == expected


def test_backslash_line_continuations_of_the_shipped_xml(env: DictEnv) -> None:
    assert parse("battery_status != POWER_SUPPLY_STATUS_CHARGING \\\n&& fan_state").test(env) is False
    assert parse("fan_state \\ || e_stop_state").test(env) is True


def test_assignment_keeps_the_entry_type_and_reports_names(env: DictEnv) -> None:
    script = parse("shown = round; current_anim_id = ERROR_ANIM_ID")
    script.run(env)
    assert env["shown"] == "0.700000"
    assert env["current_anim_id"] == 2 and isinstance(env["current_anim_id"], int)
    assert script.reads == {"round", "ERROR_ANIM_ID"}
    assert script.writes == {"shown", "current_anim_id"}


def test_plain_assignment_needs_an_existing_entry_but_colon_equals_creates(env: DictEnv) -> None:
    with pytest.raises(ScriptError, match="does not exist"):
        parse("new_entry = 1").run(env)
    parse("new_entry := 1; new_entry += 2").run(env)
    assert env["new_entry"] == 3


@pytest.mark.parametrize("source", [
    "__import__('os').system('true')",
    "cpu_temp.__class__",
    "open('x')",
    "fan_state &&",
    "a = = b",
    "",
    "1 +",
])
def test_anything_beyond_the_language_is_rejected_not_evaluated(env: DictEnv, source: str) -> None:
    with pytest.raises(ScriptError):
        parse(source).run(env)


def test_unknown_names_and_bad_comparisons_are_script_errors(env: DictEnv) -> None:
    with pytest.raises(ScriptError, match="not on the blackboard"):
        parse("missing > 1").test(env)
    with pytest.raises(ScriptError, match="cannot compare"):
        parse("'abc' < 1").test(env)
    with pytest.raises(ScriptError, match="not a boolean"):
        parse("'maybe' && true").test(env)
