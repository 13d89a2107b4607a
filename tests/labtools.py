"""What the lab test modules share: robots by stack, their containers, and
putting every robot back as it was (compose.yaml, ~/config, backups, the running stack)."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
import yaml

from tests.lab import Lab, missing_requirements
from tests.lab.computers import ComputerSpec

COMPOSE = "/home/husarion/compose.yaml"


def robot_of(lab: Any, version: str, index: int = 0) -> str:
    """The name of the `index`-th directly reachable robot on stack `version`."""
    return str([r.name for r in lab.robots if version in r.image and not r.jump][index])


def containers(lab: Any, name: str) -> dict[str, dict[str, Any]]:
    """Every container on the robot by name: id, image reference, state, command, restarts, mounts."""
    ids = lab.docker(name, "ps", "-aq", check=True).stdout.split()
    if not ids:
        return {}
    docs = json.loads(lab.docker(name, "inspect", *ids, check=True).stdout)
    return {d["Name"].lstrip("/"): {"id": d["Id"], "image": d["Config"]["Image"], "state": d["State"]["Status"],
                                    "cmd": d["Config"]["Cmd"], "restarts": d["RestartCount"],
                                    "mounts": {m["Destination"]: m["Source"] for m in d["Mounts"]}} for d in docs}


@contextmanager
def robots_put_back(lab: Any, recreate: Callable[[str, bool], bool] | None = None) -> Iterator[None]:
    """After the block, every robot's compose.yaml, ~/config and ~/.panther-ops as before it.

    The stack is then recreated where ``recreate(name, compose_changed)`` says so (always
    when no ``recreate`` is given)."""
    saved = {r.name: lab.read(r.name, COMPOSE) for r in lab.robots}
    for r in lab.robots:
        lab.sh(r.name, "rm -rf /tmp/cfg-save && cp -a /home/husarion/config /tmp/cfg-save 2>/dev/null; true")
    yield
    for r in lab.robots:
        changed = lab.read(r.name, COMPOSE) != saved[r.name]
        lab.write(r.name, COMPOSE, saved[r.name])
        lab.sh(r.name, "rm -rf /home/husarion/config /home/husarion/.panther-ops; "
                       "[ -d /tmp/cfg-save ] && cp -a /tmp/cfg-save /home/husarion/config; true")
        if recreate is None or recreate(r.name, changed):
            lab.compose(r.name, "up", "-d", "--force-recreate", "--remove-orphans")


@contextmanager
def computers_lab(*computers: ComputerSpec, images: tuple[str, ...] = ("2.1.1",)) -> Iterator[Lab]:
    """Two robots without docker (``images``: their stacks, cycled) and these User Computers behind
    them; torn down after the block."""
    why = missing_requirements(docker=False)
    if why:  # a lab test: a failure under CI=true
        pytest.skip("simulated robot lab unavailable: " + "; ".join(why))
    lab = Lab(2, docker=False, images=images, ephemeral=True).up()
    try:
        lab.add_computers(list(computers))
        yield lab
    finally:
        lab.down()


def user_computer_inventory(lab: Lab, path: Path, computers: dict[str, str], *, user: str | None = None,
                            computer_keys: bool = True) -> Path:
    """The lab's inventory written to `path` (absolute paths), `user_computer` set on robots.

    ``computers``: robot -> computer; its host is the computer's address, its key the lab's
    identity file, its user `user` when given. ``computer_keys``: the computers' host keys known."""
    doc = yaml.safe_load(lab.inventory_path.read_text())
    doc["settings"]["known_hosts"] = [str(lab.known_hosts_path)] + (
        [str(lab.computers_known_hosts_path)] if computer_keys else [])
    doc["settings"]["ssh_config"] = str(lab.ssh_config_path)
    doc["defaults"]["identity_file"] = str(lab.identity_file)
    for robot, computer in computers.items():
        entry = {"host": lab.computer(computer).ip, "key": str(lab.identity_file)}
        doc["robots"][robot]["user_computer"] = entry | ({"user": user} if user else {})
    path.write_text(yaml.safe_dump(doc))
    return path
