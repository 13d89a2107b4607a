"""The launch arguments a release declares, read from its launch files with ``ast``.

Nothing upstream wrote is run: each ``*.launch.py`` is parsed, its ``DeclareLaunchArgument``
calls are collected, and its ``IncludeLaunchDescription`` calls are followed when they name
a package of the same repository (``FindPackageShare("pkg")`` -> the directory whose
``package.xml`` names ``pkg``); includes of other repositories (``joy2twist``...) are listed,
not followed.

A default is a tree of launch substitutions. `Evaluator` computes its value the way launch
would, in a *context* (the values of the other arguments; every environment variable
unset, so ``EnvironmentVariable(X, default_value=d)`` is ``d``): ``FindPackageShare(p)``
is written ``$(find p)``, ``PathJoinSubstitution`` joins, ``PythonExpression`` is evaluated
by `pyexpr` (a safe subset), ``LaunchConfiguration(x)`` is the context's ``x`` or the
default of ``x`` (the first declaration in launch order: the entry file's own, then its
includes in the order they appear). While evaluating it records what the value was read
from (``find:pkg``, ``env:NAME``, ``arg:name``), which `classify_source` turns into where
the default comes from: the image (``$(find ...)``), the ``~/config`` tree
(``common_dir_path`` set: the value changes with it), an environment variable, another
argument or a literal.
"""

from __future__ import annotations

import ast
import posixpath
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

from panther_ops.conformance.pyexpr import Unevaluable, evaluate

CONTEXTS: dict[str, dict[str, str]] = {
    "image": {},
    "tree": {"common_dir_path": "/config"},
    "variant": {"common_dir_path": "/config", "wheel_type": "WH02", "robot_model": "lynx",
                "localization_mode": "enu", "fuse_gps": "True"},
}
"""The contexts a default is evaluated in: every argument at its default (``image``: no
``common_dir_path``), the ``~/config`` tree mounted as on a 2.2 robot (``tree``), and other
values of the arguments defaults are built from (``variant``), so that a default which
follows ``wheel_type`` is told from one that names a fixed file."""


@dataclass(frozen=True)
class Declaration:
    """One ``DeclareLaunchArgument`` call."""

    name: str
    file: str
    default: ast.expr | None
    choices: tuple[str, ...] | None
    line: int


@dataclass(frozen=True)
class Include:
    """One ``IncludeLaunchDescription`` call: the launch file expression and the arguments passed."""

    file: str
    target: ast.expr
    arguments: dict[str, ast.expr]
    line: int


@dataclass
class LaunchFile:
    """What one launch file declares and includes, and its simple assignments (``x = ...``)."""

    path: str
    scope: dict[str, list[tuple[int, ast.expr]]] = field(default_factory=dict)
    declarations: list[Declaration] = field(default_factory=list)
    includes: list[Include] = field(default_factory=list)
    unused: list[str] = field(default_factory=list)

    def lookup(self, name: str, line: int) -> ast.expr | None:
        """The value last assigned to ``name`` before ``line`` (else its last assignment)."""
        bindings = self.scope.get(name)
        if not bindings:
            return None
        before = [expr for at, expr in bindings if at < line]
        return before[-1] if before else bindings[-1][1]


def _call_name(node: ast.expr) -> str:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return f"{_call_name(node.value)}.{node.attr}" if isinstance(node.value, (ast.Name, ast.Attribute)) \
            else node.attr
    return ""


def _kw(call: ast.Call, name: str, position: int | None = None) -> ast.expr | None:
    for kw in call.keywords:
        if kw.arg == name:
            return kw.value
    if position is not None and len(call.args) > position:
        return call.args[position]
    return None


def _const_str(node: ast.expr | None) -> str | None:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def parse_launch_file(path: str, text: str) -> LaunchFile:
    """Parse one launch file (``SyntaxError`` propagates: the file is not Python)."""
    module = ast.parse(text, filename=path)
    out = LaunchFile(path)
    assigned: dict[int, str] = {}  # id(call) -> variable it is assigned to
    for node in ast.walk(module):
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            out.scope.setdefault(node.targets[0].id, []).append((node.lineno, node.value))
            assigned[id(node.value)] = node.targets[0].id
    loads = {n.id for n in ast.walk(module) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}
    for node in ast.walk(module):
        if not isinstance(node, ast.Call):
            continue
        kind = _call_name(node.func).rsplit(".", 1)[-1]
        if kind not in ("DeclareLaunchArgument", "IncludeLaunchDescription"):
            continue
        variable = assigned.get(id(node))
        if variable is not None and variable not in loads:
            out.unused.append(f"{kind} {variable} (line {node.lineno}) is never added to the launch description")
            continue
        if kind == "DeclareLaunchArgument":
            name = _const_str(_kw(node, "name", 0))
            if name is None:
                out.unused.append(f"DeclareLaunchArgument at line {node.lineno}: the name is not a literal")
                continue
            choices_node = _kw(node, "choices")
            choices = None
            if isinstance(choices_node, (ast.List, ast.Tuple)):
                choices = tuple(c for c in (_const_str(e) for e in choices_node.elts) if c is not None)
            out.declarations.append(Declaration(name, path, _kw(node, "default_value", 1), choices, node.lineno))
        else:
            source = _kw(node, "launch_description_source", 0)
            if isinstance(source, ast.Call) and _call_name(source.func).endswith("LaunchDescriptionSource") \
                    and source.args:
                source = source.args[0]
            if source is None:
                continue
            out.includes.append(Include(path, source, _launch_arguments(_kw(node, "launch_arguments")),
                                        node.lineno))
    out.declarations.sort(key=lambda d: d.line)
    out.includes.sort(key=lambda i: i.line)
    return out


def _launch_arguments(node: ast.expr | None) -> dict[str, ast.expr]:
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "items":
        node = node.func.value
    out: dict[str, ast.expr] = {}
    if isinstance(node, ast.Dict):
        for key, value in zip(node.keys, node.values, strict=True):
            name = _const_str(key)
            if name is not None:
                out[name] = value
    elif isinstance(node, (ast.List, ast.Tuple)):
        for item in node.elts:
            if isinstance(item, ast.Tuple) and len(item.elts) == 2 and (name := _const_str(item.elts[0])):
                out[name] = item.elts[1]
    return out


class Evaluator:
    """Values of substitution trees in one context (see the module docstring)."""

    def __init__(self, files: Mapping[str, LaunchFile], order: list[Declaration], context: Mapping[str, str]):
        self.files = files
        self.first: dict[str, Declaration] = {}
        for decl in order:
            self.first.setdefault(decl.name, decl)
        self.context = dict(context)
        self._active: set[str] = set()

    def argument(self, name: str, marks: set[str]) -> str:
        """The value of launch argument ``name`` in this context."""
        if name in self.context:
            return self.context[name]
        decl = self.first.get(name)
        if decl is None:
            raise Unevaluable(f"argument {name} is not declared")
        if decl.default is None:
            raise Unevaluable(f"argument {name} has no default")
        if name in self._active:
            raise Unevaluable(f"argument {name}'s default refers to itself")
        self._active.add(name)
        try:
            return self.value(decl.default, self.files[decl.file], decl.line, marks)
        finally:
            self._active.discard(name)

    def value(self, node: ast.expr, where: LaunchFile, line: int, marks: set[str]) -> str:
        """The string a substitution tree ``node`` of ``where`` gives."""
        if isinstance(node, ast.Constant):
            return node.value if isinstance(node.value, str) else str(node.value)
        if isinstance(node, ast.Name):
            bound = where.lookup(node.id, line)
            if bound is None:
                raise Unevaluable(f"{node.id} is not assigned in {where.path}")
            return self.value(bound, where, line, marks)
        if isinstance(node, (ast.List, ast.Tuple)):
            return "".join(self.value(e, where, line, marks) for e in node.elts)
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
            return self.value(node.left, where, line, marks) + self.value(node.right, where, line, marks)
        if isinstance(node, ast.JoinedStr):
            return "".join(self._formatted(part, where, line, marks) for part in node.values)
        if not isinstance(node, ast.Call):
            raise Unevaluable(f"{ast.unparse(node)!r} is not a substitution")
        name = _call_name(node.func)
        short = name.rsplit(".", 1)[-1]
        if short == "LaunchConfiguration":
            arg = _const_str(_kw(node, "variable_name", 0))
            if arg is None:
                raise Unevaluable("LaunchConfiguration of a computed name")
            marks.add(f"arg:{arg}")
            return self.argument(arg, marks)
        if short == "EnvironmentVariable" or name in ("os.environ.get", "os.getenv"):
            env = self.value(_kw(node, "name", 0) or ast.Constant(""), where, line, marks)
            marks.add(f"env:{env}")
            default = _kw(node, "default_value", 1)
            return "" if default is None else self.value(default, where, line, marks)
        if short in ("FindPackageShare", "FindPackagePrefix"):
            package = self.value(_kw(node, "package", 0) or ast.Constant(""), where, line, marks)
            marks.add(f"find:{package}")
            return f"$(find {package})"
        if short == "PathJoinSubstitution":
            parts = _kw(node, "substitutions", 0)
            elts = parts.elts if isinstance(parts, (ast.List, ast.Tuple)) else [parts] if parts else []
            return posixpath.join(*(self.value(e, where, line, marks) for e in elts)) if elts else ""
        if short == "PythonExpression":
            text = self.value(_kw(node, "expression", 0) or ast.Constant(""), where, line, marks)
            result = evaluate(text)
            return str(result)
        if short == "TextSubstitution":
            return self.value(_kw(node, "text", 0) or ast.Constant(""), where, line, marks)
        raise Unevaluable(f"{name}(...) is not evaluated")

    def _formatted(self, part: ast.expr, where: LaunchFile, line: int, marks: set[str]) -> str:
        if isinstance(part, ast.Constant):
            return str(part.value)
        if isinstance(part, ast.FormattedValue):
            inner = part.value
            if isinstance(inner, ast.Name) and (bound := where.lookup(inner.id, line)) is not None:
                inner = bound
            try:
                literal: Any = ast.literal_eval(inner)
            except ValueError:
                return self.value(inner, where, line, marks)
            return str(literal)
        raise Unevaluable(f"{ast.unparse(part)!r} in an f-string")


def classify_source(values: Mapping[str, str | None], marks: set[str]) -> str:
    """Where a default is read from: ``tree``, ``image``, ``arg:<names>``, ``env:<names>`` or ``literal``."""
    image, tree = values.get("image"), values.get("tree")
    if image is not None and tree is not None and image != tree:
        return "tree"
    if image is not None and image.startswith("$(find "):
        return "image"
    args = sorted(m[4:] for m in marks if m.startswith("arg:") and m != "arg:common_dir_path")
    if args:
        return "arg:" + ",".join(args)
    envs = sorted(m[4:] for m in marks if m.startswith("env:"))
    if envs:
        return "env:" + ",".join(envs)
    return "literal"


@dataclass
class Traversal:
    """The launch files reached from an entry file, in launch order."""

    files: dict[str, LaunchFile] = field(default_factory=dict)
    order: list[Declaration] = field(default_factory=list)
    external: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)


def traverse(entry: str, read: Mapping[str, str], packages: Mapping[str, str]) -> Traversal:
    """Parse ``entry`` and every include of a package in ``packages`` (name -> directory).

    Args:
        entry: repository path of the entry launch file (bringup).
        read: repository path -> text, for every launch file of the release.
        packages: package name -> its directory in the repository.
    """
    out = Traversal()

    def visit(path: str) -> None:
        if path in out.files:
            return
        lf = parse_launch_file(path, read[path])
        out.files[path] = lf
        out.problems.extend(f"{path}: {u}" for u in lf.unused)
        out.order.extend(lf.declarations)
        for inc in lf.includes:
            evaluator = Evaluator(out.files, out.order, CONTEXTS["image"])
            try:
                target = evaluator.value(inc.target, lf, inc.line, set())
            except Unevaluable as exc:
                out.problems.append(f"{path}:{inc.line}: include not followed ({exc})")
                continue
            repo_path = _repo_path(target, packages)
            if repo_path is None or repo_path not in read:
                out.external.append(target.replace("$(find ", "").replace(")", "", 1))
                continue
            visit(repo_path)

    visit(entry)
    return out


def _repo_path(target: str, packages: Mapping[str, str]) -> str | None:
    if not target.startswith("$(find "):
        return None
    package, _, rest = target[len("$(find "):].partition(")")
    directory = packages.get(package)
    return None if directory is None else posixpath.normpath(posixpath.join(directory, rest.lstrip("/")))


def _defaults(trav: Traversal, decl: Declaration, notes: list[str]) -> tuple[dict[str, str | None], set[str]]:
    """A declaration's default in every context, and what it is read from (in ``image``)."""
    values: dict[str, str | None] = {}
    marks: set[str] = set()
    for ctx_name, ctx in CONTEXTS.items():
        evaluator = Evaluator(trav.files, trav.order, {k: v for k, v in ctx.items() if k != decl.name})
        ctx_marks: set[str] = set()
        try:
            values[ctx_name] = "" if decl.default is None else evaluator.value(
                decl.default, trav.files[decl.file], decl.line, ctx_marks)
        except Unevaluable as exc:
            values[ctx_name] = None
            notes.append(f"{decl.file}: {ctx_name}: not evaluated ({exc})")
        if ctx_name == "image":
            marks = ctx_marks
    return values, marks


def arguments(trav: Traversal) -> Iterator[dict[str, Any]]:
    """One row per declared argument: name, files, kind, choices, defaults per context, source.

    An argument declared by several files with different defaults (husarion_ugv 2.2's
    ``battery_config_path``: the simulated battery in controller.launch.py, the battery
    driver's parameters in battery.launch.py) has the first as ``default`` and each other
    in ``other_defaults``: which one a node sees depends on launch's scoping, so a
    catalogue default equal to any of them is taken as right (and the report says so).
    """
    by_name: dict[str, list[Declaration]] = {}
    for decl in trav.order:
        by_name.setdefault(decl.name, []).append(decl)
    for name, decls in by_name.items():
        first = decls[0]
        notes: list[str] = []
        values, marks = _defaults(trav, first, notes)
        others: list[dict[str, Any]] = []
        for decl in decls[1:]:
            other, other_marks = _defaults(trav, decl, notes)
            if other != values and all(o["default"] != other for o in others):
                others.append({"file": decl.file, "default": other, "source": classify_source(other, other_marks)})
        choices = _choices(decls)
        yield {
            "name": name,
            "declared_in": list(dict.fromkeys(d.file for d in decls)),
            "kind": _kind(choices, values.get("image")),
            "choices": None if choices is None else list(choices),
            "default": values,
            "source": classify_source(values, marks),
            "other_defaults": others,
            "notes": notes,
        }


_BOOL_WORDS = frozenset({"true", "false"})


def _choices(decls: list[Declaration]) -> tuple[str, ...] | None:
    """The values every declaration accepts (launch checks each declaration's choices)."""
    out: tuple[str, ...] | None = None
    for decl in decls:
        if decl.choices is None:
            continue
        out = decl.choices if out is None else tuple(c for c in out if c in decl.choices)
    return out


def _kind(choices: tuple[str, ...] | None, default: str | None) -> str:
    if choices is not None:
        return "bool" if {c.lower() for c in choices} <= _BOOL_WORDS else "choice"
    return "bool" if default is not None and default.lower() in _BOOL_WORDS else "text"
