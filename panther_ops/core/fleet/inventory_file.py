"""The inventory file(s) read and checked: every key, value and reference, with the file,
line and key named in each refusal (docs/inventory.md)."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.hostspec import JUMP_FORMS, HostSpecError, parse_jump
from panther_ops.core.fleet.inventory import _SCALAR_FIELDS, DEFAULT_FORKS, Inventory, Robot, UserComputer
from panther_ops.core.fleet.inventory_desired import DesiredError, check_desired
from panther_ops.core.fleet.inventory_values import (
    DEFAULT_KEYS,
    GROUP_KEYS,
    HOST,
    NAME,
    ROBOT_KEYS,
    SETTINGS_KEYS,
    USER_COMPUTER_KEYS,
    BadValue,
    address_value,
    check_secrets,
    merge_desired,
    plain,
    port_value,
    positive_seconds,
    relative_to,
    user_value,
)
from panther_ops.core.yaml.located import LineDict, LineList, as_located, load_yaml, load_yaml_file
from panther_ops.errors import InventoryError

ENV_VAR = "PANTHER_OPS_INVENTORY"


DEFAULT_DIR = "inventory"


def find_inventory(explicit: str | None) -> tuple[Path, str]:
    """Which inventory to use, and why (shown to the operator)."""
    if explicit:
        return Path(explicit), "-i"
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env), f"${ENV_VAR}"
    return Path(DEFAULT_DIR), f"./{DEFAULT_DIR}/ (default)"


def load_inventory(explicit: str | None = None) -> Inventory:
    """Find, read and validate the inventory."""
    path, origin = find_inventory(explicit)
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.suffix in (".yaml", ".yml") and p.is_file())
        if not files:
            raise InventoryError("no *.yaml files in the inventory directory", path=str(path),
                                 hint="create one, or run `panther-ops demo init` for a demo fleet")
    elif path.exists():
        files = [path]
        ansible = _ansible_document(path)
        if ansible is not None:
            from panther_ops.core.fleet.inventory_ansible import in_ansible_terms

            try:
                return inventory_from_documents(path, origin, [(path, ansible)])
            except InventoryError as exc:
                raise in_ansible_terms(exc, path) from None
    else:
        raise InventoryError(
            f"inventory not found (from {origin})", path=str(path),
            hint=f"pass -i FILE, set ${ENV_VAR}, or create ./{DEFAULT_DIR}/",
        )
    return _Loader(path, origin).load(files)


_NATIVE = re.compile(r"^(robots|version|settings|defaults):", re.MULTILINE)


def _ansible_document(path: Path) -> dict[str, Any] | None:
    """The file as a panther-ops inventory document when it is an Ansible inventory (INI, YAML
    or ``ansible-inventory --list`` JSON: core/fleet/inventory_ansible.py), else None."""
    from panther_ops.core.fleet.inventory_ansible import ansible_document
    from panther_ops.errors import InputError

    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InventoryError("not a UTF-8 text file", path=str(path)) from None
    if _NATIVE.search(text):
        return None  # a panther-ops inventory: read once, by the loader
    try:
        parsed = load_yaml(text, str(path))
    except InputError:
        parsed = None  # an INI inventory is not YAML; a broken YAML one is refused by the loader
    return ansible_document(path, text, plain(parsed))


def inventory_from_documents(path: Path, origin: str, docs: list[tuple[Path, dict[str, Any]]]) -> Inventory:
    """An inventory from documents already read (an Ansible inventory's, a host's variables),
    through the same checks as a file's."""
    loader = _Loader(path, origin)
    for f, doc in docs:
        loader.read_doc(as_located(doc), f)
    return loader.finish([f for f, _ in docs])


class _Loader:
    def __init__(self, path: Path, origin: str) -> None:
        self.path = path
        self.origin = origin
        self.settings: dict[str, Any] = {}
        self.defaults: dict[str, Any] = {}
        self.raw_robots: dict[str, tuple[LineDict, Path]] = {}
        self.groups: dict[str, dict[str, Any]] = {}
        self.default_group_at: tuple[Path, LineDict] | None = None

    def err(self, msg: str, file: Path, doc: LineDict | LineList | None, key: str, sub: str | None = None,
            hint: str | None = None) -> InventoryError:
        line = None
        if isinstance(doc, LineDict):
            line = doc.line_of(sub) if sub is not None else doc.line
        elif isinstance(doc, LineList):
            line = doc.line
        return InventoryError(msg, path=str(file), line=line, key=key, hint=hint)

    def load(self, files: list[Path]) -> Inventory:
        for f in files:
            self.read_file(f)
        return self.finish(files)

    def finish(self, files: list[Path]) -> Inventory:
        if not self.raw_robots:
            raise InventoryError("the inventory defines no robots", path=str(self.path),
                                 hint="add a `robots:` mapping (docs/inventory.md)")
        robots = {name: self.robot(name, doc, f) for name, (doc, f) in self.raw_robots.items()}
        for r in robots.values():
            if r.jump and r.jump not in robots:
                try:
                    parse_jump(r.jump)
                except HostSpecError as exc:
                    doc, f = self.raw_robots[r.name]
                    raise self.err(f"{exc}: neither a robot of the inventory nor user@host[:port]",
                                   f, doc, f"robots.{r.name}.jump", "jump", hint=f"allowed: {JUMP_FORMS}") from None
            self.check_groups(r)
        inv = Inventory(
            path=self.path, origin=self.origin, robots=robots, groups=self.groups,
            ssh_config=self.settings.get("ssh_config"),
            known_hosts=tuple(self.settings.get("known_hosts", ())),
            forks=int(self.settings.get("forks", DEFAULT_FORKS)),
            command_timeout=float(self.settings.get("command_timeout", 120.0)),
            files=tuple(files),
            default_group=self.settings.get("default_group"),
        )
        if inv.default_group is not None and inv.default_group not in self.groups:
            assert self.default_group_at is not None
            f, s = self.default_group_at
            raise self.err(f"default_group {inv.default_group!r} is not a group of the inventory", f, s,
                           "settings.default_group", "default_group",
                           hint=f"groups: {', '.join(self.groups) or '(none defined)'}")
        for r in robots.values():
            if r.jump in robots:
                inv.endpoint(r)  # raises on loops
        return inv

    def read_file(self, f: Path) -> None:
        self.read_doc(load_yaml_file(f), f)

    def read_doc(self, doc: Any, f: Path) -> None:
        if doc is None:
            return
        if not isinstance(doc, LineDict):
            raise InventoryError("the inventory must be a mapping with `robots:`", path=str(f), line=1)
        allowed = {"version", "settings", "defaults", "robots", "groups"}
        for key in doc:
            if key not in allowed:
                raise self.err(f"unknown top-level key {key!r}", f, doc, key, key,
                               hint=f"allowed: {', '.join(sorted(allowed))}")
        if doc.get("version", 1) != 1:
            raise self.err("unsupported inventory version", f, doc, "version", "version", hint="allowed: 1")
        check_secrets(doc, f, "")
        if "settings" in doc:
            self.read_settings(doc["settings"], f, doc)
        if "defaults" in doc:
            d = self.mapping(doc["defaults"], f, doc, "defaults")
            for k in d:
                if k not in DEFAULT_KEYS:
                    raise self.err(f"{k!r} cannot be a fleet-wide default", f, d, f"defaults.{k}", k,
                                   hint=f"allowed: {', '.join(sorted(DEFAULT_KEYS))}")
            self.defaults.update(self.fields(d, f, "defaults"))
        self.read_groups(doc, f)
        robots = self.mapping(doc.get("robots", LineDict()), f, doc, "robots")
        for name, rdoc in robots.items():
            self.check_name(name, f, robots, f"robots.{name}")
            if name in self.raw_robots:
                raise self.err(f"robot {name!r} is defined twice (also in {self.raw_robots[name][1]})",
                               f, robots, f"robots.{name}", name)
            self.raw_robots[name] = (self.mapping(rdoc, f, robots, f"robots.{name}"), f)

    def read_groups(self, doc: LineDict, f: Path) -> None:
        for name, gdoc in self.mapping(doc.get("groups", LineDict()), f, doc, "groups").items():
            g = self.mapping(gdoc if gdoc is not None else LineDict(), f, doc["groups"], f"groups.{name}")
            self.check_name(name, f, doc["groups"], f"groups.{name}")
            for k in g:
                if k not in GROUP_KEYS:
                    raise self.err(f"unknown group key {k!r}", f, g, f"groups.{name}.{k}", k,
                                   hint=f"allowed: {', '.join(sorted(GROUP_KEYS))}")
            self.groups[name] = dict(g)
            if "desired" in g:
                self.groups[name]["desired"] = self.check_desired(g["desired"], f, g, f"groups.{name}.desired")

    def read_settings(self, value: Any, f: Path, parent: LineDict) -> None:
        s = self.mapping(value, f, parent, "settings")
        for k, v in s.items():
            if k not in SETTINGS_KEYS:
                raise self.err(f"unknown setting {k!r}", f, s, f"settings.{k}", k,
                               hint=f"allowed: {', '.join(sorted(SETTINGS_KEYS))}")
            if k == "ssh_config":
                self.settings[k] = str(relative_to(f, str(v)))
            elif k == "known_hosts":
                items = v if isinstance(v, list) else [v]
                self.settings[k] = [str(relative_to(f, str(i))) for i in items]
            elif k == "forks":
                if not isinstance(v, int) or isinstance(v, bool) or not 1 <= v <= 500:
                    raise self.err("forks must be a whole number from 1 to 500", f, s, "settings.forks", k)
                self.settings[k] = v
            elif k == "command_timeout":
                if not positive_seconds(v):
                    raise self.err(f"command_timeout {v!r} is not allowed", f, s, f"settings.{k}", k,
                                   hint="a finite number of seconds > 0, e.g. 120")
                self.settings[k] = float(v)
            elif k == "default_group":
                if not isinstance(v, str) or not v:
                    raise self.err("default_group must be a group name", f, s, f"settings.{k}", k)
                self.settings[k] = v
                self.default_group_at = (f, s)

    def mapping(self, value: Any, f: Path, parent: LineDict | LineList, key: str) -> LineDict:
        if value is None:
            out = LineDict()
            out.key_lines = {}
            out.line = parent.line
            return out
        if not isinstance(value, LineDict):
            sub = key.rsplit(".", 1)[-1]
            raise self.err(f"must be a mapping, got {type(value).__name__}", f, parent, key,
                           sub if isinstance(parent, LineDict) else None)
        return value

    def check_name(self, name: str, f: Path, parent: LineDict, key: str) -> None:
        if not NAME.match(name):
            raise self.err(f"name {name!r} is not allowed", f, parent, key, name,
                           hint="letters, digits, '.', '_' and '-', starting with a letter or digit")

    def fields(self, d: LineDict, f: Path, prefix: str) -> dict[str, Any]:
        """Validate the robot fields present in ``d``; returns them normalised."""
        out: dict[str, Any] = {}
        for k, v in d.items():
            if k not in ROBOT_KEYS:
                raise self.err(f"unknown key {k!r}", f, d, f"{prefix}.{k}", k, hint=", ".join(sorted(ROBOT_KEYS)))
            try:
                out[k] = self.field(k, v, f, d, f"{prefix}.{k}")
            except BadValue as bad:
                raise self.err(bad.message, f, d, f"{prefix}.{k}", k, hint=bad.hint) from None
        return out

    def field(self, k: str, v: Any, f: Path, d: LineDict, key: str) -> Any:
        """One robot field, checked and normalised (raises BadValue)."""
        if k in ("host", "jump", "identity_file", "compose_file", "description", "root"):
            if not isinstance(v, str) or not v.strip():
                raise BadValue(f"{k} must be a non-empty string")
            if k in ("host", "jump"):
                return address_value(k, v)
            return str(relative_to(f, v.strip())) if k in ("identity_file", "root") else v.strip()
        if k == "vars":
            return dict(self.mapping(v, f, d, key))
        if k == "desired":
            return self.check_desired(v, f, d, key)
        if k == "user_computer":
            return self.user_computer(v, f, d, key)
        return _SCALAR_FIELDS[k](v)

    def user_computer(self, v: Any, f: Path, parent: LineDict, key: str) -> UserComputer:
        d = self.mapping(v, f, parent, key)
        out: dict[str, Any] = {}
        for k, value in d.items():
            if k not in USER_COMPUTER_KEYS:
                raise self.err(f"unknown key {k!r}", f, d, f"{key}.{k}", k, hint=", ".join(sorted(USER_COMPUTER_KEYS)))
            try:
                if k == "host":
                    if not isinstance(value, str) or not HOST.match(value):
                        raise BadValue(f"host {value!r} is not a host name or IP address",
                                   "letters, digits, '.', ':', '_' and '-', not starting with '-' (e.g. 10.15.20.3)")
                    out[k] = value
                elif k == "key":
                    if not isinstance(value, str) or not value.strip():
                        raise BadValue("key must be a path to a private key")
                    out[k] = str(relative_to(f, value.strip()))
                else:
                    out[k] = (user_value if k == "user" else port_value)(value)
            except BadValue as bad:
                raise self.err(bad.message, f, d, f"{key}.{k}", k, hint=bad.hint) from None
        return UserComputer(**out)

    def check_desired(self, value: Any, f: Path, parent: LineDict, key: str) -> dict[str, Any]:
        """One layer's ``desired:`` block, checked whole (`inventory_desired`); its values as
        the commands read them."""
        d = self.mapping(value, f, parent, key)
        try:
            return check_desired(plain(d))
        except DesiredError as bad:
            doc, sub = _located(d, bad.path)
            raise self.err(bad.message, f, doc, f"{key}.{bad.key}", sub, hint=bad.hint) from None

    def check_merged(self, name: str, doc: LineDict, f: Path, desired: dict[str, Any], groups: Any) -> None:
        """The robot's desired block as merged from its layers, checked whole again: two names
        of one setting may come from different layers (a group's ``led_config_file``, the
        robot's ``animations_config_path``), and neither replaces the other."""
        try:
            check_desired(desired)
        except DesiredError as bad:
            layers = [("defaults", self.defaults.get("desired", {}))]
            layers += [(f"groups.{g}", self.groups.get(g, {}).get("desired", {})) for g in groups]
            layers.append((f"robots.{name}", doc.get("desired") or {}))
            where = [f"{layer}.desired.{'.'.join(map(str, path))}" for path in (bad.other, bad.path) if path
                     for layer, block in layers if _holds(block, path)]
            raise self.err(f"{bad.message} (merged from {', '.join(where)})", f, doc,
                           f"robots.{name}.desired.{bad.key}", "desired" if "desired" in doc else None,
                           hint="one name in every layer (a later layer then replaces an earlier one's value)"
                           if bad.other else bad.hint) from None

    def check_groups(self, robot: Robot) -> None:
        """Every group a robot names is declared under ``groups:`` (a typo would silently
        drop that group's settings)."""
        import difflib

        for g in robot.groups:
            if g in self.groups:
                continue
            doc, f = self.raw_robots[robot.name]
            close = difflib.get_close_matches(g, list(self.groups), n=1)
            raise self.err(
                f"group {g!r} is not declared under `groups:`" + (f"; did you mean {close[0]!r}?" if close else ""),
                f, doc, f"robots.{robot.name}.groups", "groups" if "groups" in doc else None,
                hint=f"declared groups: {', '.join(self.groups) or '(none)'}; declare it "
                f"(`groups: {{{g}: {{}}}}`) if it is a new group",
            )

    def robot(self, name: str, doc: LineDict, f: Path) -> Robot:
        own = self.fields(doc, f, f"robots.{name}")
        merged: dict[str, Any] = {**self.defaults, **own}
        groups = merged.get("groups", ())
        desired: dict[str, Any] = merge_desired({}, self.defaults.get("desired", {}))
        vars_: dict[str, Any] = dict(self.defaults.get("vars", {}))
        for g in groups:
            gd = self.groups.get(g, {})
            desired = merge_desired(desired, plain(gd.get("desired", {})))
            vars_.update(plain(gd.get("vars", {})))
        desired = merge_desired(desired, own.get("desired", {}))
        vars_.update(own.get("vars", {}))
        self.check_merged(name, doc, f, desired, groups)
        transport = merged.get("transport", "ssh")
        if transport == "local":
            if "root" not in merged:
                raise self.err("a local robot needs `root:` (its stand-in directory)", f, doc,
                               f"robots.{name}.root")
            host = merged.get("host", "localhost")
        else:
            if "host" not in merged:
                raise self.err("missing `host:` (IP or hostname of the Built-in Computer)", f, doc,
                               f"robots.{name}.host",
                               hint="every Panther's internal address is 10.15.20.2: reach a fleet "
                               "by per-robot hostnames (e.g. Husarnet), a jump host or a forwarded port")
            host = merged["host"]
        return Robot(
            name=name, host=host, port=merged.get("port"), user=merged.get("user", "husarion"),
            identity_file=merged.get("identity_file"), jump=merged.get("jump"),
            namespace=merged.get("namespace"), stack=merged.get("stack", "auto"), groups=tuple(groups),
            vars=vars_, desired=desired, transport=transport,
            root=Path(merged["root"]) if "root" in merged else None,
            compose_file=merged.get("compose_file", "~/compose.yaml"),
            connect_timeout=merged.get("connect_timeout", 10.0),
            source=f"{f}:{doc.line}", user_computer=merged.get("user_computer"),
        )


def _located(doc: LineDict, path: tuple[str | int, ...]) -> tuple[LineDict | LineList, str | None]:
    """The innermost mapping or list on ``path`` below ``doc`` that holds the next step, and
    that step's key (for its line)."""
    node: LineDict | LineList = doc
    for i, step in enumerate(path):
        last = i == len(path) - 1
        if isinstance(node, LineDict) and isinstance(step, str) and step in node:
            child = node[step]
            if last or not isinstance(child, (LineDict, LineList)):
                return node, step
            node = child
        elif isinstance(node, LineList) and isinstance(step, int) and 0 <= step < len(node):
            child = node[step]
            if last or not isinstance(child, (LineDict, LineList)):
                return child if isinstance(child, (LineDict, LineList)) else node, None
            node = child
        else:
            break
    return node, None


def _holds(block: Any, path: tuple[str | int, ...]) -> bool:
    """Whether a layer's desired block gives the key at ``path``."""
    node = block
    for step in path:
        if not isinstance(node, (dict, list)):
            return False
        try:
            node = node[step]  # type: ignore[index]
        except (KeyError, IndexError, TypeError):
            return False
    return True
