"""Launch arguments written into compose.yaml (validated, cross-checked), and carried across a stack change."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from panther_ops.core.kinds.arg_catalogue import _ALIAS_NOTES, _BY_NAME, ArgSpec
from panther_ops.core.robot.launch_args import (
    LaunchArgError,
    UnknownArgError,
    ValidatedArg,
    canonical_args,
    check_args,
    raise_for_errors,
    spec,
    validate_arg,
)
from panther_ops.core.stack import Stack

if TYPE_CHECKING:
    from panther_ops.core.robot.compose import ComposeFile


@dataclass(frozen=True)
class ArgMigration:
    """What moving a command from one stack to another does to its arguments."""

    renamed: dict[str, str]
    dropped: tuple[str, ...]


def migrate_args(source: Stack, target: Stack, args: Mapping[str, str]) -> ArgMigration:
    """Names to rename and args to drop when the driver image changes version.

    ``led_config_file`` -> ``animations_config_path`` (2.1 -> 2.2), ``ekf_config_path`` dropped
    (2.0.1 -> 2.0.2), the manual alias ``user_animations_file`` -> the declared name.
    """
    renamed: dict[str, str] = {}
    dropped: list[str] = []
    for name in args:
        s = _BY_NAME.get(name) or (_ALIAS_NOTES[name][0] if name in _ALIAS_NOTES else None)
        if s is None:
            continue
        if not s.available(target):
            dropped.append(name)
        elif s.name_for(target) != name:
            renamed[name] = s.name_for(target)
    return ArgMigration(renamed, tuple(dropped))


@dataclass(frozen=True)
class ArgChange:
    """Result of `set_launch_args` / `unset_launch_arg`."""

    changed: bool
    args: tuple[ValidatedArg, ...]
    warnings: tuple[str, ...]


_SAID_BY_THE_ARG = {"battery-sim-only": "battery_config_path"}
"""Cross rules whose warning the argument's own check (``validate_arg``) already gives."""


def set_launch_args(
    compose: ComposeFile,
    values: Mapping[str, str],
    *,
    force: bool = False,
    service: str | None = None,
    robot_model: str | None = None,
) -> ArgChange:
    """Validate and write launch arguments into the driver command of ``compose``.

    Each value is validated for the driver's stack (`validate_arg`), then the cross rules
    run over the resulting command; errors refuse the whole change (nothing written)
    unless ``force``. Names of other versions or aliases already in the command for the
    same argument are replaced by the declared name. Each value is checked against the
    command as it will be (``wheel_type WH05`` with ``robot_model lynx`` in the same change);
    ``robot_model``: the robot's model when the command has none (see `check_args`).

    Raises:
        LaunchArgError: a refused argument, value or combination.
    """
    stack = compose.stack()
    cmd = compose.command(service)
    current = dict(cmd.args)
    validated: list[ValidatedArg] = []
    warnings: list[str] = []
    prospective = dict(current)
    stale: list[str] = []
    context = canonical_args(stack, {**current, **values})
    if robot_model is not None:
        context.setdefault("robot_model", robot_model)
    given: dict[str, str] = {}  # the argument's catalogue key -> the name it was given as
    for key, value in values.items():
        found = _BY_NAME.get(key) or (_ALIAS_NOTES[key][0] if key in _ALIAS_NOTES else None)
        if found is not None:  # one argument under two of its names (a rename, the manual's alias)
            if found.key in given:
                first = given[found.key]
                raise LaunchArgError(f"{first}={values[first]} and {key}={value} both set the launch argument "
                                     f"{found.name_for(stack)}", hint="keep one of them")
            given[found.key] = key
        va = validate_arg(stack, key, value, force=force, context=context)
        validated.append(va)
        warnings.extend(va.warnings)
        if va.spec is not None:
            for other in (*va.spec.all_names(), *(a for a, _ in va.spec.aliases)):
                if other != va.name and other in prospective:
                    stale.append(other)
                    prospective.pop(other)
                    warnings.append(f"replaced {other} (not declared on {stack.label()}) by {va.name}")
        prospective[va.name] = va.value
    volumes = compose.list_volumes(service)
    said = {v.name for v in validated if v.warnings}  # a rule that says it again in other words is left out
    findings = [
        f for f in check_args(stack, prospective, volumes=volumes, robot_model=robot_model)
        if (set(f.keys) & {v.name for v in validated}
        or f.level == "error") and not (f.rule in _SAID_BY_THE_ARG and _SAID_BY_THE_ARG[f.rule] in said)
    ]
    warnings.extend(raise_for_errors(findings, force=force))
    changed = False
    for name in stale:
        changed = compose.unset_arg(name, service) or changed
    for va in validated:
        changed = compose.set_arg(va.name, va.value, service) or changed
    return ArgChange(changed, tuple(validated), tuple(dict.fromkeys(warnings)))


def unset_launch_arg(compose: ComposeFile, key: str, *, service: str | None = None) -> ArgChange:
    """Remove an argument (every name it has had, and its aliases) from the command.

    The stack's default applies afterwards. Unknown keys are removed as written.
    """
    try:
        s: ArgSpec | None = spec(key)
    except UnknownArgError:
        s = None
    names = (key,) if s is None else (*s.all_names(), *(a for a, _ in s.aliases))
    changed = False
    for name in names:
        changed = compose.unset_arg(name, service) or changed
    return ArgChange(changed, (), ())
