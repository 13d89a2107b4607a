"""The collection's modules: their options (checked here, the way the CLI checks its own) and, per
module, the change the CLI makes for the same command (its label, planner and applier)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.changes import Planner
from panther_ops.errors import UsageError


class ArgumentError(UsageError):
    """A module option that is unknown, missing, of the wrong type or not one of its choices."""


@dataclass(frozen=True)
class Option:
    type: type = str
    required: bool = False
    choices: tuple[str, ...] = ()
    default: Any = None


@dataclass(frozen=True)
class Change:
    """What the CLI hands fleet.change for the same command."""

    label: str
    planner: Planner
    restart: bool | None = None
    """The command decides whether anything is recreated (estop reset: never), else the option."""


COMMON = {"restart": Option(bool, default=True), "settle": Option(float, default=5.0)}
"""--no-restart and --settle: how a change is applied (config set/push, apply)."""

MODULES: dict[str, dict[str, Option]] = {
    "config": {"state": Option(str, choices=("set", "push"), default="set"), "key": Option(str),
               "value": Option(str), "src": Option(str), "as": Option(str), "force": Option(bool, default=False),
               **COMMON},
    "apply": {"force": Option(bool, default=False), **COMMON},
    "gps": {"state": Option(str, choices=("enabled", "disabled"), default="enabled"),
            "port": Option(int, default=5000), "ip": Option(str, default="10.15.20.2"), **COMMON},
    "shutdown_hosts": {"src": Option(str, required=True), "force": Option(bool, default=False), **COMMON},
    "driver": {"state": Option(str, choices=("updated", "restarted"), required=True), "tag": Option(str),
               "pull": Option(bool, default=False), "force": Option(bool, default=False), **COMMON},
    "estop": {"state": Option(str, choices=("triggered", "reset"), default="triggered")},
}
"""Each module's options (docs/ansible.md)."""


def check_arguments(module: str, args: Mapping[str, Any]) -> dict[str, Any]:
    """The options given, checked and with their defaults: an unknown module or option, a
    missing one or a wrong type is an :class:`ArgumentError` naming it and what is allowed."""
    if module not in MODULES:
        raise ArgumentError(f"unknown module {module!r}", hint="allowed: " + ", ".join(MODULES))
    spec = MODULES[module]
    out: dict[str, Any] = {}
    for name in args:
        if name not in spec:
            raise ArgumentError(f"{module}: unknown option {name!r}", hint="allowed: " + ", ".join(spec))
    for name, opt in spec.items():
        value = args.get(name)
        if value is None:
            if opt.required:
                raise ArgumentError(f"{module}: option {name!r} is required")
            out[name] = opt.default
            continue
        out[name] = _typed(module, name, opt, value)
    return out


def _typed(module: str, name: str, opt: Option, value: Any) -> Any:
    where = f"{module}: option {name!r}"
    if opt.type is bool:
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.lower() in ("true", "yes", "false", "no"):
            return value.lower() in ("true", "yes")
        raise ArgumentError(f"{where}: {value!r} is not a boolean", hint="true or false")
    if opt.type in (int, float):
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise ArgumentError(f"{where}: {value!r} is not a number")
        from panther_ops.core.parse.numbers import NumberError, ascii_int, decimal

        try:
            return ascii_int(str(value)) if opt.type is int else float(decimal(str(value)))
        except NumberError as exc:
            raise ArgumentError(f"{where}: {exc}") from None
    text = value if isinstance(value, str) else str(value)
    if opt.choices and text not in opt.choices:
        raise ArgumentError(f"{where}: {text!r} is not allowed", hint="allowed: " + ", ".join(opt.choices))
    return text


def _config(a: dict[str, Any]) -> Change:
    force = a["force"]
    if a["state"] == "push":
        if not a["src"] or not a["as"]:
            raise ArgumentError("config: state=push needs src (the file) and as (what it is)")
        from panther_ops.core.robot.push import push_kind, read_bundle

        kind = push_kind(a["as"])
        bundle = read_bundle(kind, Path(a["src"]), force=force)

        def push(c: Any) -> Any:
            from panther_ops.core.config.read import read_and_plan_push

            return read_and_plan_push(c, kind, bundle, force=force)

        return Change(f"config push {Path(a['src']).name} --as {kind.value}", push)
    if not a["key"] or a["value"] is None:
        raise ArgumentError("config: state=set needs key and value")
    from panther_ops.core.config.checks import parse_value, precheck

    key, value = a["key"], a["value"]
    parsed = parse_value(value) if key.startswith("controller.") else value
    precheck({key: parsed}, force=force)

    def set_(c: Any) -> Any:
        from panther_ops.core.config.read import read_and_plan_args, read_and_plan_controller

        if key.startswith("controller."):
            return read_and_plan_controller(c, {key: parsed}, force=force)
        return read_and_plan_args(c, {key: value}, [], force=force)

    return Change(f"config set {key} {value}", set_)


def _apply(a: dict[str, Any]) -> Change:
    from panther_ops.core.apply.read import read_and_plan_desired

    return Change("apply", lambda c: read_and_plan_desired(c, force=a["force"]))


def _gps(a: dict[str, Any]) -> Change:
    from panther_ops.core.gps.plan import GpsOptions
    from panther_ops.core.gps.read import read_and_plan_disable, read_and_plan_enable

    if a["state"] == "disabled":
        return Change("gps disable", read_and_plan_disable)
    opts = GpsOptions(port=a["port"], ip=a["ip"])
    return Change("gps enable", lambda c: read_and_plan_enable(c, opts))


def _shutdown_hosts(a: dict[str, Any]) -> Change:
    from panther_ops.core.kinds import FileKind

    return _config({**a, "state": "push", "as": FileKind.SHUTDOWN_HOSTS.value})


def _driver(a: dict[str, Any]) -> Change:
    from panther_ops.core.driver import read as driver_read

    if a["state"] == "restarted":
        return Change("driver restart", driver_read.read_and_plan_restart)
    if not a["tag"]:
        raise ArgumentError("driver: state=updated needs tag (the driver image's tag)")
    from panther_ops.core.driver.images import parse_target

    target = parse_target(a["tag"], force=a["force"])
    return Change(f"driver update {a['tag']}",
                  lambda c: driver_read.read_and_plan_update(c, target, force=a["force"], pull=a["pull"]))


def _estop_reset(a: dict[str, Any]) -> Change:
    from panther_ops.core.remote.estop.calls import read_and_plan_reset

    return Change("estop reset", read_and_plan_reset, restart=False)


CHANGES: dict[str, Callable[[dict[str, Any]], Change]] = {
    "config": _config, "apply": _apply, "gps": _gps, "shutdown_hosts": _shutdown_hosts, "driver": _driver,
    "estop": _estop_reset,
}
"""Each module's change through the pipeline (estop: its reset; a trigger is an action: run.py)."""
