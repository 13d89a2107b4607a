"""An Ansible inventory read as a panther-ops inventory, and a panther-ops inventory written as
one (docs/ansible.md, "Inventory").

Three forms are read, told apart by their content: ``ansible-inventory --list`` output (JSON
with ``_meta``/``all``), a YAML inventory (``all:`` with ``hosts``/``children``/``vars``) and an
INI inventory (``[group]`` sections, ``host key=value`` lines, ``[group:vars]``,
``[group:children]``). Each host becomes a robot; its variables, merged as Ansible merges them
(``all`` < parent groups < child groups < host), map onto the robot's keys:

    inventory_hostname            -> the robot's name (and its host when ansible_host is absent)
    ansible_host / ansible_port / ansible_user / ansible_ssh_private_key_file
                                  -> host / port / user / identity_file
    panther_ops_<key>             -> the robot key <key> (namespace, stack, jump, desired, ...)
    panther_ops_known_hosts       -> settings.known_hosts (host keys verified strictly)
    panther_ops_forks             -> settings.forks

Every other variable lands in the robot's free-form ``vars``. The values then go through the
inventory's own checks (inventory_file.py); what only an Ansible inventory can get wrong (an
unknown ``panther_ops_`` variable, a malformed line, a host pattern) is refused here, naming the
file and the key.
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.inventory import Inventory
from panther_ops.core.fleet.inventory_values import ROBOT_KEYS
from panther_ops.errors import InventoryError

CONNECTION_VARS = {
    "ansible_host": "host", "ansible_ssh_host": "host",
    "ansible_port": "port", "ansible_ssh_port": "port",
    "ansible_user": "user", "ansible_ssh_user": "user",
    "ansible_ssh_private_key_file": "identity_file",
}
"""Ansible's connection variables and the robot key each sets."""

PREFIX = "panther_ops_"
SETTING_VARS = {"panther_ops_known_hosts": "known_hosts", "panther_ops_forks": "forks"}
ROBOT_VARS = sorted(f"{PREFIX}{k}" for k in ROBOT_KEYS if k not in ("host", "port", "user", "identity_file", "groups"))
_PATTERN = re.compile(r"\[[^\]]*:[^\]]*\]")  # host ranges: www[01:50]


def _bad(msg: str, path: Path, key: str, hint: str | None = None) -> InventoryError:
    return InventoryError(msg, path=str(path), key=key, hint=hint)


def robot_entry(name: str, hostvars: Mapping[str, Any], where: str | Path) -> dict[str, Any]:
    """One host's merged variables as a robot entry of a panther-ops inventory."""
    entry: dict[str, Any] = {}
    free: dict[str, Any] = {}
    for var, value in hostvars.items():
        if var in CONNECTION_VARS:
            key = CONNECTION_VARS[var]
            entry[key] = _port(value) if key == "port" else value
        elif var in SETTING_VARS:
            continue
        elif var.startswith(PREFIX):
            if var not in ROBOT_VARS:
                raise _bad(f"unknown variable {var!r}", Path(where), f"{name}.{var}",
                           hint="allowed: " + ", ".join([*ROBOT_VARS, *SETTING_VARS]))
            entry[var[len(PREFIX):]] = value
        elif not var.startswith("ansible_"):
            free[var] = value
    entry.setdefault("host", name)
    if free:
        entry["vars"] = {**free, **(entry.get("vars") or {})}
    return entry


def in_ansible_terms(exc: InventoryError, path: str | Path) -> InventoryError:
    """A refusal of the inventory's checks (``[robots.r01.port]``) naming the Ansible variable the
    value came from (``[r01.ansible_port]``) in ``path``."""
    parts = (exc.key or "").split(".")
    if len(parts) < 3 or parts[0] != "robots":
        return exc
    name, key = parts[1], parts[2]
    var = {"host": "ansible_host", "port": "ansible_port", "user": "ansible_user",
           "identity_file": "ansible_ssh_private_key_file"}.get(key, PREFIX + key)
    where = (exc.path or "") + (f":{exc.line}" if exc.line else "") + (f" [{exc.key}]" if exc.key else "")
    message = exc.message.removeprefix(f"{where}: ") if where else exc.message
    out = InventoryError(message, path=str(path), key=".".join([name, var, *parts[3:]]), hint=exc.hint)
    return out


def _port(value: Any) -> Any:
    """An INI inventory's ``ansible_port=2201`` is text: ASCII digits become the number (anything
    else is left for the port's check to refuse)."""
    if isinstance(value, str) and value.isascii() and value.isdigit():
        return int(value)
    return value


class _Tree:
    """Groups (hosts, vars, children) and host variables, from any of the three forms."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.hosts: dict[str, dict[str, Any]] = {}
        self.groups: dict[str, dict[str, Any]] = {}

    def group(self, name: str) -> dict[str, Any]:
        if _PATTERN.search(name):
            raise _bad(f"group pattern {name!r} is not supported", self.path, name)
        return self.groups.setdefault(name, {"hosts": [], "vars": {}, "children": []})

    def host(self, group: str, name: str, hostvars: Mapping[str, Any] | None, key: str) -> None:
        if _PATTERN.search(name):
            raise _bad(f"host range {name!r} is not supported", self.path, key,
                       hint="write each robot on its own line (panther-ops names every robot)")
        self.hosts.setdefault(name, {}).update(hostvars or {})
        if name not in self.group(group)["hosts"]:
            self.group(group)["hosts"].append(name)

    def ancestors(self) -> dict[str, list[str]]:
        """Each host's groups, parents before children (the order Ansible merges their vars in)."""
        parents: dict[str, list[str]] = {}
        for g, d in self.groups.items():
            for c in d["children"]:
                parents.setdefault(c, []).append(g)

        def depth(g: str, seen: tuple[str, ...] = ()) -> int:
            if g in seen:
                raise _bad(f"group {g!r} is its own child", self.path, f"{g}.children")
            return 1 + max((depth(p, (*seen, g)) for p in parents.get(g, [])), default=0)

        out: dict[str, list[str]] = {h: [] for h in self.hosts}
        for g in self.groups:
            for h in self._members(g, ()):
                out[h].append(g)
        return {h: sorted(set(gs), key=lambda g: (depth(g), g)) for h, gs in out.items()}

    def _members(self, g: str, seen: tuple[str, ...]) -> list[str]:
        if g in seen:
            raise _bad(f"group {g!r} is its own child", self.path, f"{g}.children")
        d = self.groups.get(g, {"hosts": [], "children": []})
        return [*d["hosts"], *(h for c in d["children"] for h in self._members(c, (*seen, g)))]

    def document(self) -> dict[str, Any]:
        """The panther-ops inventory document: robots, their groups, settings."""
        if not self.hosts:
            raise _bad("the Ansible inventory defines no hosts", self.path, "all.hosts",
                       hint="each robot is a host of the inventory (docs/ansible.md)")
        all_vars = self.groups.get("all", {}).get("vars", {})
        robots: dict[str, Any] = {}
        settings: dict[str, Any] = {}
        member = self.ancestors()
        for h, own in self.hosts.items():
            merged: dict[str, Any] = dict(all_vars)
            for g in member[h]:
                merged.update(self.groups[g]["vars"])
            merged.update(own)
            for var, setting in SETTING_VARS.items():
                if var in merged:
                    value = merged[var] if setting == "known_hosts" else _port(merged[var])
                    if settings.setdefault(setting, value) != value:
                        raise _bad(f"{var} differs between hosts ({settings[setting]!r}, {value!r})", self.path,
                                   f"{h}.{var}", hint="one value for the whole inventory: set it in all.vars")
            entry = robot_entry(h, merged, self.path)
            groups = [g for g in member[h] if g not in ("all", "ungrouped")]
            if groups:
                entry["groups"] = groups
            robots[h] = entry
        groups_doc: dict[str, Any] = {g: {} for g in self.groups if g not in ("all", "ungrouped")}
        return {"settings": settings, "groups": groups_doc, "robots": robots}


def _from_json(doc: dict[str, Any], path: Path) -> _Tree:
    tree = _Tree(path)
    hostvars = (doc.get("_meta") or {}).get("hostvars") or {}
    for g, d in doc.items():
        if g == "_meta":
            continue
        if not isinstance(d, dict):
            raise _bad(f"group {g!r} must be a mapping (hosts, vars, children)", path, g)
        tree.group(g)["vars"].update(d.get("vars") or {})
        tree.group(g)["children"].extend(d.get("children") or [])
        for h in d.get("hosts") or []:
            tree.host(g, h, hostvars.get(h), f"{g}.hosts.{h}")
    return tree


def _from_yaml(doc: dict[str, Any], path: Path) -> _Tree:
    tree = _Tree(path)

    def walk(g: str, d: Any, key: str) -> None:
        if d is None:
            d = {}
        if not isinstance(d, dict):
            raise _bad(f"group {g!r} must be a mapping (hosts, vars, children)", path, key)
        unknown = set(d) - {"hosts", "vars", "children"}
        if unknown:
            raise _bad(f"unknown key {sorted(unknown)[0]!r} in group {g!r}", path, f"{key}.{sorted(unknown)[0]}",
                       hint="allowed: hosts, vars, children")
        tree.group(g)["vars"].update(d.get("vars") or {})
        for h, hv in (d.get("hosts") or {}).items():
            if hv is not None and not isinstance(hv, dict):
                raise _bad(f"host {h!r} must map to its variables", path, f"{key}.hosts.{h}")
            tree.host(g, str(h), hv, f"{key}.hosts.{h}")
        for c, cd in (d.get("children") or {}).items():
            if c not in tree.group(g)["children"]:
                tree.group(g)["children"].append(c)
            walk(c, cd, f"{key}.children.{c}")

    for g, d in doc.items():
        walk(str(g), d, str(g))
    return tree


def _ini_value(text: str) -> Any:
    """An INI variable's value as Ansible reads it: a Python literal when it is one, else text."""
    import ast

    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError, TypeError, MemoryError, RecursionError):  # not a literal: the text
        return text


def _from_ini(text: str, path: Path) -> _Tree:
    import shlex

    tree = _Tree(path)
    group, kind = "ungrouped", "hosts"
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        if line.startswith("["):
            if not line.endswith("]"):
                raise InventoryError(f"malformed section header {line!r}", path=str(path), line=n)
            group, _, kind = line[1:-1].partition(":")
            kind = kind or "hosts"
            if kind not in ("hosts", "vars", "children"):
                raise InventoryError(f"unknown section kind {kind!r}", path=str(path), line=n,
                                     hint="[group], [group:vars] or [group:children]")
            tree.group(group)
            continue
        try:
            words = shlex.split(line, comments=True)
        except ValueError as exc:
            raise InventoryError(f"cannot split the line: {exc}", path=str(path), line=n) from None
        if kind == "children":
            tree.group(group)["children"].append(words[0])
            tree.group(words[0])
            continue
        pairs = words[1:] if kind == "hosts" else words
        hostvars: dict[str, Any] = {}
        for w in pairs:
            k, eq, v = w.partition("=")
            if not eq or not k:
                raise InventoryError(f"expected key=value, got {w!r}", path=str(path), line=n,
                                     key=f"{group}.{words[0]}" if kind == "hosts" else f"{group}:vars")
            hostvars[k] = _ini_value(v)
        if kind == "vars":
            tree.group(group)["vars"].update(hostvars)
        else:
            tree.host(group, words[0], hostvars, f"{group}.{words[0]}")
    return tree


def ansible_document(path: Path, text: str, parsed: Any) -> dict[str, Any] | None:
    """``text`` (``parsed``: its YAML, or None where it is not YAML) as a panther-ops inventory
    document when it is an Ansible inventory; None when it is not one (a panther-ops inventory)."""
    if isinstance(parsed, dict):
        if {"robots", "version", "settings", "defaults"} & set(parsed):
            return None
        if text.lstrip().startswith("{") and ("_meta" in parsed or "all" in parsed):
            return _from_json(json.loads(text), path).document()
        if parsed and all(isinstance(v, dict | type(None)) and set(v or {}) <= {"hosts", "vars", "children"}
                          for v in parsed.values()):
            return _from_yaml(dict(parsed), path).document()
        return None
    if re.search(r"^\s*\[[^\]]+\]\s*$", text, re.MULTILINE) or re.search(r"^\S+\s+\w+=", text, re.MULTILINE):
        return _from_ini(text, path).document()
    return None


def export_ansible(inv: Inventory) -> dict[str, Any]:
    """The inventory as an Ansible YAML inventory: each robot a host of ``all`` with its keys
    as variables, each group a child of ``all`` listing its robots (read back by
    :func:`ansible_document` to the same robots)."""
    hosts: dict[str, Any] = {}
    children: dict[str, Any] = {g: {"hosts": {}} for g in inv.groups}
    for r in inv.robots.values():
        hv: dict[str, Any] = {"ansible_host": r.host, "ansible_user": r.user}
        if r.port is not None:
            hv["ansible_port"] = r.port
        if r.identity_file:
            hv["ansible_ssh_private_key_file"] = r.identity_file
        for key, value, default in (("jump", r.jump, None), ("namespace", r.namespace, None),
                                    ("stack", r.stack, "auto"), ("compose_file", r.compose_file, "~/compose.yaml"),
                                    ("transport", r.transport, "ssh"),
                                    ("root", str(r.root) if r.root else None, None)):
            if value != default:
                hv[PREFIX + key] = value
        if r.desired:
            hv[PREFIX + "desired"] = r.desired
        hv.update(r.vars)
        hosts[r.name] = hv
        for g in r.groups:
            children[g]["hosts"][r.name] = None
    all_vars: dict[str, Any] = {}
    if inv.known_hosts:
        all_vars["panther_ops_known_hosts"] = list(inv.known_hosts)
    all_group: dict[str, Any] = {"hosts": hosts}
    if all_vars:
        all_group["vars"] = all_vars
    if children:
        all_group["children"] = children
    return {"all": all_group}
