"""What else names the robot's ROS namespace when ``config set namespace`` changes the driver's.

The driver's ``namespace:=`` launch argument is one of several places: the gamepad service
(``gamepad_controller``, ``husarion/joy2twist``) has its own ``namespace:=``, the compose
environment (2.0/2.1: ``ROBOT_NAMESPACE`` in the shared ``x-common-config``; 2.2: in the
``env_file`` ``/home/husarion/config/common/.env``) carries ``ROBOT_NAMESPACE``, and the
WebUI snap has ``ros.namespace``. Left on the old name they stop talking to the driver.

:func:`follow_in_compose` and :func:`follow_in_env_file` find them in the compose file (in
memory) and the env file's text, and either change them (``everywhere``) or return one
warning per place that keeps the old name. The WebUI is a snap setting on the robot, not a
file: it is named with the command that changes it.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from panther_ops.core.robot.compose import ComposeFile
from panther_ops.errors import OpsError

ENV_KEY = "ROBOT_NAMESPACE"
WEBUI = "husarion-webui"
HINT = "add --everywhere to change them in the same plan"


@dataclass
class Followers:
    """The places that keep another namespace, and what was changed (``everywhere``)."""

    warnings: list[str] = field(default_factory=list)
    changed: list[str] = field(default_factory=list)
    services: list[str] = field(default_factory=list)
    """Services whose definition changed (to recreate with the driver)."""
    after: bytes | None = None
    """The env file's new content (:func:`follow_in_env_file`, when changed)."""


def follow_in_compose(compose: ComposeFile, driver: str, new: str, *, everywhere: bool) -> Followers:
    """The other services' ``namespace:=`` and the compose environment's ROBOT_NAMESPACE
    (changed in ``compose``, in memory, with ``everywhere``), and the WebUI's setting."""
    out = Followers()
    before = {svc: _seen(compose, svc) for svc in compose.services()}
    for svc in compose.services():
        if svc == driver:
            continue
        try:
            value = compose.command(svc).args.get("namespace")
        except OpsError:  # not a ros2 launch command: nothing to follow
            continue
        if value is not None and value != new:
            _one(out, everywhere, f"service {svc} (namespace:={value})", _set_arg(compose, svc, new))
    value = compose.get_env(ENV_KEY, driver)
    if value is not None and value != new:
        _one(out, everywhere, f"{ENV_KEY}={value} in compose.yaml's environment",
             lambda: compose.set_env(ENV_KEY, new, driver, shared=True))
    out.services = [svc for svc in compose.services() if svc != driver and _seen(compose, svc) != before.get(svc)]
    out.warnings.append(f"the WebUI ({WEBUI} snap) has its own ros.namespace: check it with "
                        f"`sudo snap get {WEBUI} ros.namespace`, change it with "
                        f"`sudo snap set {WEBUI} ros.namespace={new}`")
    return out


def follow_in_env_file(path: str, data: bytes, new: str, *, everywhere: bool) -> Followers:
    """ROBOT_NAMESPACE in an ``env_file`` (2.2: ``config/common/.env``): its line changed, or a warning."""
    out = Followers()
    text = data.decode(errors="replace")
    m = re.search(rf"^{ENV_KEY}=(.*)$", text, re.M)
    if m and m.group(1).strip().strip("'\"") != new:
        after = (text[:m.start(1)] + new + text[m.end(1):]).encode()

        def change() -> bool:
            out.after = after
            return True

        _one(out, everywhere, f"{ENV_KEY}={m.group(1).strip()} in {path}", change)
    return out


def _set_arg(compose: ComposeFile, svc: str, new: str) -> Callable[[], bool]:
    return lambda: compose.set_arg("namespace", new, svc)


def _seen(compose: ComposeFile, svc: str) -> tuple[object, ...]:
    try:
        args: object = compose.command(svc).args
    except OpsError:
        args = None
    return args, compose.environment(svc)


def _one(out: Followers, everywhere: bool, what: str, change: Callable[[], bool]) -> None:
    if everywhere:
        change()
        out.changed.append(what)
    else:
        out.warnings.append(f"{what} keeps the old namespace; {HINT}")
