"""An Ansible host (its inventory_hostname and connection variables) as a panther-ops robot of a
one-robot inventory, its values checked by the inventory's own rules (core/fleet/inventory_ansible.py)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.inventory import Inventory, Robot
from panther_ops.core.fleet.inventory_ansible import in_ansible_terms, robot_entry
from panther_ops.core.fleet.inventory_file import inventory_from_documents
from panther_ops.errors import InventoryError


def robot_from_hostvars(name: str, hostvars: Mapping[str, Any], *, source: str = "ansible") -> tuple[Inventory, Robot]:
    """The robot ``name`` (inventory_hostname) with ``hostvars`` mapped onto its entry:
    ansible_host -> host, ansible_port -> port, ansible_user -> user,
    ansible_ssh_private_key_file -> identity_file, panther_ops_* -> the robot key of that name;
    ``panther_ops_known_hosts`` names the known_hosts file (host keys are always verified
    strictly: a host not in it is refused, never added). Bad values: exit-2 errors naming the
    variable."""
    settings: dict[str, Any] = {}
    known = hostvars.get("panther_ops_known_hosts")
    if known is not None:
        settings["known_hosts"] = known
    doc = {"settings": settings, "robots": {name: robot_entry(name, hostvars, source)}}
    try:
        inv = inventory_from_documents(Path(source), "ansible", [(Path(source), doc)])
    except InventoryError as exc:
        raise in_ansible_terms(exc, source) from None
    return inv, inv.robots[name]
