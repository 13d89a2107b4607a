"""Catalogue of the driver's launch arguments per stack version, with validation.

Facts: panther-stack.md section 1.1 (bringup.launch.py and the per-package launch files of
panther_ros 2.0.0-2.1.x and husarion_ugv_ros 2.2.x, Humble).

Each argument has a catalogue key (its panther_ros 2.0/2.1 name, or its own name when it
only exists on 2.2) and, per version, the name the stack declares:
``led_config_file`` is ``animations_config_path`` on 2.2 and ``user_led_animations_file`` is
``user_led_animations_path``. Any of those names is accepted as input; the manual's
``user_animations_file`` (never a declared argument) is accepted as an alias with a note.

`validate_arg` checks one value (type, allowed values, availability on the robot's
version) and returns the name and the normalised value to write; `check_args` runs the
cross-argument rules (`RULES`) over a whole command; `set_launch_args` does both and edits
a `ComposeFile`.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from panther_ops.core.kinds.arg_catalogue import (
    _ALIAS_NOTES,
    _BY_NAME,
    _V2_2,
    CATALOGUE,
    PATH_CHARACTERS,
    ArgSpec,
    ArgType,
    _ugv,
    arg_text_problem,
)
from panther_ops.core.parse import ros_names
from panther_ops.core.stack import Stack
from panther_ops.errors import UsageError

if TYPE_CHECKING:  # validating a value needs no YAML editor (ruamel loads when a compose file is edited)
    pass


class LaunchArgError(UsageError):
    """A launch argument or value that the robot's stack does not accept."""


class UnknownArgError(LaunchArgError):
    """No such launch argument in the catalogue."""


class UnavailableArgError(LaunchArgError):
    """The argument exists, but not on the robot's stack version."""


class InvalidArgValueError(LaunchArgError):
    """The value is not allowed for the argument (the message lists what is)."""


class ArgConflictError(LaunchArgError):
    """A combination of arguments that cannot work (cross-argument rule)."""


@dataclass(frozen=True)
class ValidatedArg:
    """A launch argument ready to be written.

    Attributes:
        key: catalogue key.
        name: the name to write on this stack (``animations_config_path`` on 2.2).
        value: the normalised value (booleans as the stack spells them).
        warnings: things the operator should know (forced values, aliases, sim-only).
    """

    key: str
    name: str
    value: str
    warnings: tuple[str, ...] = ()
    spec: ArgSpec | None = field(default=None, compare=False, repr=False)




_TRUE = frozenset({"true", "1"})


_FALSE = frozenset({"false", "0"})


_INTERPOLATION = re.compile(r"\$\{[^}]*\}|\$[A-Za-z_][A-Za-z0-9_]*")


_FIND = re.compile(r"^\$\((?:find|find-pkg-share) [A-Za-z0-9_]+\)")
"""A launch substitution of a package's share directory, as the catalogue's defaults use it."""


_PATH_CHAR = re.compile(r"[A-Za-z0-9_.+/-]")


def spec(key: str) -> ArgSpec:
    """The catalogue entry for a key, a per-version name or an alias.

    Raises:
        UnknownArgError: not in the catalogue (the message suggests close names).
    """
    found = _BY_NAME.get(key) or (_ALIAS_NOTES[key][0] if key in _ALIAS_NOTES else None)
    if found is None:
        names = sorted({*_BY_NAME, *_ALIAS_NOTES})
        close = difflib.get_close_matches(key, names, n=3)
        hint = f"did you mean {', '.join(close)}?" if close else "see docs/configuration.md for the table"
        raise UnknownArgError(f"unknown launch argument {key!r}", hint=hint)
    return found


def args_for(stack: Stack) -> list[ArgSpec]:
    """Arguments the stack declares."""
    return [s for s in CATALOGUE if s.available(stack)]


GAMEPAD_ALWAYS_ON = (2, 3, 2)
"""From husarion_ugv 2.3.2 bringup always runs the gamepad: husarion_ugv_ros@2.3.2:husarion_ugv_bringup/launch/
bringup.launch.py includes husarion_ugv_teleop/launch/teleop.launch.py with ``{"launch_gamepad": "True"}``, which
overrides the command line's value (an include's launch_arguments win over the global one)."""


def bool_word(stack: Stack, value: bool) -> str:
    """``True``/``False`` on panther_ros 2.0-2.1 (some args only accept these), ``true``/``false`` on 2.2."""
    word = "true" if value else "false"
    return word if _ugv(stack) else word.capitalize()


def unavailable_text(s: ArgSpec, stack: Stack) -> str:
    """Why ``stack`` has no argument ``s``: the releases that declare it, and the robot's."""
    family = "husarion_ugv" if s.since >= _V2_2 else "panther_ros"
    return f"{s.key} needs {family} {s.availability()}; this robot runs {stack.label()}"


def check_arg_text(key: str, value: str) -> None:
    """Refuse what can never be written into the driver's command, ``--force`` or not: a
    name that is not a launch argument name, a value holding a newline or another control
    character (it would split or corrupt the ``command:`` line of compose.yaml); the
    catalogue's rule (`arg_text_problem`), which the inventory's ``desired.launch_args`` uses too.

    Raises:
        InvalidArgValueError: naming the argument and the offending character.
    """
    problem = arg_text_problem(key, value)
    if problem is not None:
        raise InvalidArgValueError(problem[0], hint=problem[1])


def validate_arg(
    stack: Stack,
    key: str,
    value: str,
    *,
    force: bool = False,
    context: Mapping[str, str] | None = None,
    simulation: bool = False,
) -> ValidatedArg:
    """Check one launch argument for the robot's stack and normalise its value.

    Args:
        stack: the robot's stack.
        key: catalogue key, the per-version name or an accepted alias.
        value: the value as typed (``true``, ``WH02``, ``/config/x.yaml``...).
        force: turn refusals into warnings (unknown names, values out of the choices,
            unavailable on this version). Malformed values (empty choice...) still pass.
        context: the command's arguments as they will be (by catalogue key; for WH05 vs
            robot_model, with the robot's ROBOT_MODEL_NAME when the command has none); None
            when no robot is known yet (a pre-check): then WH05 is not checked against a model.
        simulation: the command runs in simulation (sim-only args are then fine).

    Returns:
        The name to write on this stack and the normalised value.

    Raises:
        UnknownArgError, UnavailableArgError, InvalidArgValueError: unless ``force``.
    """
    warnings: list[str] = []
    value = value.strip()
    check_arg_text(key, value)
    try:
        s = spec(key)
    except UnknownArgError:
        if not force:
            raise
        return ValidatedArg(key, key, value, (f"{key} is not in the catalogue; written as given (forced)",))
    if key in _ALIAS_NOTES:
        warnings.append(_ALIAS_NOTES[key][1] + f": {s.name_for(stack)}")
    name = s.name_for(stack)
    if key not in _ALIAS_NOTES and key != name:
        warnings.append(f"on {stack.label()} the argument is called {name}")
    if not s.available(stack):
        if not force:
            raise UnavailableArgError(unavailable_text(s, stack), hint=_replacement_hint(s, stack))
        warnings.append(unavailable_text(s, stack) + " (forced)")
    normalised = _normalise(s, stack, value, force=force, warnings=warnings)
    if s.key == "launch_gamepad" and normalised == bool_word(stack, False) and stack.version >= GAMEPAD_ALWAYS_ON:
        message = (f"launch_gamepad:={normalised} has no effect on {stack.label()}: bringup includes "
                   "husarion_ugv_teleop's teleop.launch.py with launch_gamepad True, so the gamepad always runs")
        if not force:
            raise InvalidArgValueError(message, hint="leave launch_gamepad out, or true (what 2.3.2 runs anyway); "
                                       "--force writes it all the same")
        warnings.append(message + " (forced)")
    if s.sim_only_until is not None and stack.version <= s.sim_only_until and not simulation and normalised:
        warnings.append(
            f"{name} only matters in simulation on {stack.label()} (Gazebo battery plugin); the robot ignores it"
        )
    if s.key == "wheel_type" and normalised == "WH05" and context is not None:  # None: no robot known yet
        model = context.get("robot_model")
        if model is None:
            warnings.append("WH05 is the Lynx wheel: this robot's model is not known here (robot_model:=, "
                            "ROBOT_MODEL_NAME)")
        elif model != "lynx":
            message = f"WH05 is the Lynx wheel; this robot's robot_model is {model}"
            if not force:
                raise InvalidArgValueError(
                    message,
                    hint="Panther wheels: WH01 (off-road), WH02 (mecanum), WH04 (small pneumatic), custom; "
                    "on a Lynx: robot_model:=lynx (or ROBOT_MODEL_NAME=lynx in /run/husarion/robot_config.env)",
                )
            warnings.append(message + " (forced)")
    return ValidatedArg(s.key, name, normalised, tuple(warnings), s)


def _replacement_hint(s: ArgSpec, stack: Stack) -> str | None:
    if s.key == "ekf_config_path":
        return "from 2.0.2 use localization_config_path"
    if s.key == "simulation_engine":
        return "from 2.0.2 the simulator is chosen by the simulation launch files"
    if s.key == "launch_nmea_gps":
        return (f"on {stack.label()} the GPS runs as its own compose service (nmea-gps, from the manual), "
                "not a launch argument: panther-ops gps enable")
    if s.key == "launch_gamepad":
        return (f"on {stack.label()} the gamepad runs as its own compose service (gamepad_controller, "
                "husarion/joy2twist), not a launch argument: start or stop that service in compose.yaml; its "
                "parameters: panther-ops config push FILE --as joy2twist")
    return None


def _normalise(s: ArgSpec, stack: Stack, value: str, *, force: bool, warnings: list[str]) -> str:
    name = s.name_for(stack)
    if _INTERPOLATION.search(value) and s.type is not ArgType.PATH:
        warnings.append(f"{name}={value!r} uses compose interpolation; not checked")
        return value
    if s.type is ArgType.BOOL:
        low = value.lower()
        if low in _TRUE:
            return bool_word(stack, True)
        if low in _FALSE:
            return bool_word(stack, False)
        return _refuse(name, value, (bool_word(stack, True), bool_word(stack, False)), force, warnings)
    if s.type is ArgType.CHOICE:
        choices = s.choices_for(stack)
        for choice in choices:
            if value == choice or value.lower() == choice.lower():
                return choice
        return _refuse(name, value, choices, force, warnings)
    if s.type is ArgType.NAMESPACE:
        try:
            return ros_names.namespace(value)
        except ros_names.RosNameError as exc:  # no node starts under it: --force cannot help
            raise InvalidArgValueError(f"{name}={value!r}: {exc}", hint="the driver's nodes would not start "
                                       "(rcl refuses the name); --force does not write it") from None
    if s.type in (ArgType.PATH, ArgType.DIR):
        return _check_path(s, name, value, force, warnings)
    return value


def _check_path(s: ArgSpec, name: str, value: str, force: bool, warnings: list[str]) -> str:
    if value == "" or (s.allow_none and value == "None"):
        return value
    find = _FIND.match(value)
    rest = value[find.end():] if find else value
    plain = _INTERPOLATION.sub("x", rest)  # compose fills these in on the robot
    bad = next((c for c in plain if not _PATH_CHAR.match(c)), None)
    if bad is not None:  # --force or not: no config path has it, the driver would not find the file
        raise InvalidArgValueError(
            f"{name}={value!r}: {bad!r} is not a character of a config path; allowed: {PATH_CHARACTERS}"
            + (", after $(find <package>)" if find else ""),
            hint="name the file with those characters (config push writes file names of the same set)")
    if ".." in plain.split("/"):
        raise InvalidArgValueError(f"{name}={value!r} holds '..': name the file directly",
                                   hint="a path that climbs out of a mounted directory is not what the mount gives")
    absolute = value.startswith("/") or bool(_INTERPOLATION.match(value))
    if (rest == "" or rest.startswith("/")) if find else absolute:
        return value
    allowed: tuple[str, ...] = ("an absolute path inside the container (e.g. /config/...)", "$(find <package>)/...")
    if s.type is ArgType.DIR:
        allowed = ("an absolute directory inside the container (e.g. /config)", "''")
    if s.allow_none:
        allowed = (*allowed, "None")
    return _refuse(name, value, allowed, force, warnings, kind="a path launch can open")


def _refuse(
    name: str,
    value: str,
    allowed: Iterable[str],
    force: bool,
    warnings: list[str],
    *,
    kind: str = "an allowed value",
) -> str:
    listing = ", ".join(allowed)
    message = f"{name}={value!r} is not {kind}; allowed: {listing}"
    if not force:
        raise InvalidArgValueError(message)
    warnings.append(message + " (forced)")
    return value
