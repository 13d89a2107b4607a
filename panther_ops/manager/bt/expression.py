"""A small, safe evaluator for BehaviorTree.CPP v4 scripts and preconditions.

Supports what the Panther trees use and a little more: numbers (``1``, ``2.5``, ``0x10``),
strings (``'a'`` or ``"a"``), ``true``/``false``, blackboard names (``@name`` for the root
blackboard), parentheses, ``!`` and unary ``-``, ``* /``, ``+ -``, ``..`` (string concat),
comparisons ``== != < <= > >=``, ``&&``, ``||``, ``cond ? a : b``, assignments
``= := += -= *= /=`` and ``;`` between statements. A backslash before a line break (as in
the shipped XML) is a continuation. Nothing is ever passed to Python's ``eval``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Protocol

from panther_ops.manager.errors import ScriptError

Value = Any


class Env(Protocol):
    """Where names live: a tree's blackboard (through a scope)."""

    def get(self, name: str) -> Value: ...

    def set(self, name: str, value: Value) -> None: ...

    def exists(self, name: str) -> bool: ...


_TOKEN = re.compile(
    r"""
    (?P<space>(?:\s|\\)+)
  | (?P<number>0[xX][0-9a-fA-F]+|(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)
  | (?P<string>'[^']*'|"[^"]*")
  | (?P<name>@?[A-Za-z_][A-Za-z0-9_]*)
  | (?P<op>:=|\+=|-=|\*=|/=|==|!=|<=|>=|&&|\|\||\.\.|[-+*/<>=!()?:;])
    """,
    re.VERBOSE,
)
_ASSIGN_OPS = {"=", ":=", "+=", "-=", "*=", "/="}
_COMPARE_OPS = {"==", "!=", "<", "<=", ">", ">="}


@dataclass(frozen=True)
class Token:
    kind: str
    text: str
    pos: int


def tokenize(source: str) -> list[Token]:
    """Split a script into tokens; raise ScriptError at the first character that fits none."""
    tokens: list[Token] = []
    pos = 0
    while pos < len(source):
        match = _TOKEN.match(source, pos)
        if match is None:
            raise ScriptError(f"unexpected character {source[pos]!r} at {pos} in {source!r}")
        kind = match.lastgroup or ""
        if kind != "space":
            tokens.append(Token(kind, match.group(), pos))
        pos = match.end()
    return tokens


# ---------------------------------------------------------------- values


def to_number(value: Value) -> float | int | None:
    """A number for comparisons and arithmetic, or None when `value` is not numeric."""
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int | float):
        return value
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return None
    return None


def truthy(value: Value) -> bool:
    """BT.CPP's cast to bool: booleans, numbers (non-zero) and "true"/"false" strings."""
    if isinstance(value, bool):
        return value
    if isinstance(value, int | float):
        return value != 0
    if isinstance(value, str) and value.strip().lower() in {"true", "false", "1", "0"}:
        return value.strip().lower() in {"true", "1"}
    raise ScriptError(f"{value!r} is not a boolean")


def compare(op: str, left: Value, right: Value) -> bool:
    """Compare like BT.CPP: numbers numerically, strings as text, mixed via the number."""
    if isinstance(left, str) and isinstance(right, str):
        a: Any = left
        b: Any = right
    else:
        a, b = to_number(left), to_number(right)
        if a is None or b is None:
            raise ScriptError(f"cannot compare {left!r} with {right!r}")
    if op == "==":
        return bool(a == b)
    if op == "!=":
        return bool(a != b)
    if op == "<":
        return bool(a < b)
    if op == "<=":
        return bool(a <= b)
    if op == ">":
        return bool(a > b)
    return bool(a >= b)


def _arith(op: str, left: Value, right: Value) -> Value:
    if op == "..":
        return f"{format_value(left)}{format_value(right)}"
    a, b = to_number(left), to_number(right)
    if a is None or b is None:
        raise ScriptError(f"'{op}' needs numbers, got {left!r} and {right!r}")
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if b == 0:
        raise ScriptError("division by zero")
    return a / b


def format_value(value: Value) -> str:
    """A value as text (booleans as true/false)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def coerce_like(value: Value, existing: Value) -> Value:
    """Keep an entry's type on assignment, as a typed BT.CPP blackboard entry would."""
    if existing is None or type(value) is type(existing):
        return value
    if isinstance(existing, bool):
        return truthy(value)
    if isinstance(existing, int):
        number = to_number(value)
        if number is not None and float(number).is_integer():
            return int(number)
        return value
    if isinstance(existing, float):
        number = to_number(value)
        return float(number) if number is not None else value
    if isinstance(existing, str):
        return format_value(value)
    return value


# ---------------------------------------------------------------- syntax tree


class Node(Protocol):
    def eval(self, env: Env) -> Value: ...


@dataclass(frozen=True)
class Literal:
    value: Value

    def eval(self, env: Env) -> Value:
        return self.value


@dataclass(frozen=True)
class Name:
    name: str

    def eval(self, env: Env) -> Value:
        return env.get(self.name)


@dataclass(frozen=True)
class Unary:
    op: str
    operand: Node

    def eval(self, env: Env) -> Value:
        value = self.operand.eval(env)
        if self.op == "!":
            return not truthy(value)
        number = to_number(value)
        if number is None:
            raise ScriptError(f"unary '-' needs a number, got {value!r}")
        return -number


@dataclass(frozen=True)
class Binary:
    op: str
    left: Node
    right: Node

    def eval(self, env: Env) -> Value:
        if self.op == "&&":
            return truthy(self.left.eval(env)) and truthy(self.right.eval(env))
        if self.op == "||":
            return truthy(self.left.eval(env)) or truthy(self.right.eval(env))
        left, right = self.left.eval(env), self.right.eval(env)
        if self.op in _COMPARE_OPS:
            return compare(self.op, left, right)
        return _arith(self.op, left, right)


@dataclass(frozen=True)
class Ternary:
    condition: Node
    then: Node
    otherwise: Node

    def eval(self, env: Env) -> Value:
        return self.then.eval(env) if truthy(self.condition.eval(env)) else self.otherwise.eval(env)


@dataclass(frozen=True)
class Assign:
    name: str
    op: str
    value: Node

    def eval(self, env: Env) -> Value:
        new = self.value.eval(env)
        if self.op == ":=":
            env.set(self.name, new)
            return new
        if not env.exists(self.name):
            raise ScriptError(f"'{self.name}' does not exist: use ':=' to create it")
        old = env.get(self.name)
        if self.op != "=":
            new = _arith(self.op[0], old, new)
        new = coerce_like(new, old)
        env.set(self.name, new)
        return new


@dataclass(frozen=True)
class Script:
    """A parsed script: statements, and the names it reads and writes."""

    source: str
    statements: tuple[Node, ...]
    reads: frozenset[str] = field(default_factory=frozenset)
    writes: frozenset[str] = field(default_factory=frozenset)

    def run(self, env: Env) -> Value:
        """Run every statement; return the value of the last one."""
        result: Value = None
        for statement in self.statements:
            result = statement.eval(env)
        return result

    def test(self, env: Env) -> bool:
        """Run and cast the result to bool (preconditions, ScriptCondition)."""
        return truthy(self.run(env))


# ---------------------------------------------------------------- parser


class _Parser:
    def __init__(self, source: str) -> None:
        self.source = source
        self.tokens = tokenize(source)
        self.i = 0
        self.reads: set[str] = set()
        self.writes: set[str] = set()

    def peek(self) -> Token | None:
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def take(self, text: str | None = None) -> Token:
        token = self.peek()
        if token is None or (text is not None and token.text != text):
            wanted = f"'{text}'" if text else "more input"
            found = f"'{token.text}' at {token.pos}" if token else "the end"
            raise ScriptError(f"expected {wanted}, found {found} in {self.source!r}")
        self.i += 1
        return token

    def at(self, *texts: str) -> bool:
        token = self.peek()
        return token is not None and token.kind == "op" and token.text in texts

    def script(self) -> Script:
        statements: list[Node] = []
        while self.peek() is not None:
            if self.at(";"):
                self.take()
                continue
            statements.append(self.statement())
            if self.peek() is not None:
                self.take(";")
        if not statements:
            raise ScriptError("empty script")
        return Script(self.source, tuple(statements), frozenset(self.reads),
                      frozenset(self.writes))

    def statement(self) -> Node:
        token = self.peek()
        nxt = self.tokens[self.i + 1] if self.i + 1 < len(self.tokens) else None
        if token and token.kind == "name" and nxt and nxt.kind == "op" and nxt.text in _ASSIGN_OPS:
            self.i += 2
            self.writes.add(token.text)
            if nxt.text not in {"=", ":="}:
                self.reads.add(token.text)
            return Assign(token.text, nxt.text, self.expression())
        return self.expression()

    def expression(self) -> Node:
        condition = self.binary(0)
        if self.at("?"):
            self.take()
            then = self.expression()
            self.take(":")
            return Ternary(condition, then, self.expression())
        return condition

    _LEVELS: tuple[frozenset[str], ...] = (
        frozenset({"||"}),
        frozenset({"&&"}),
        frozenset(_COMPARE_OPS),
        frozenset({"+", "-", ".."}),
        frozenset({"*", "/"}),
    )

    def binary(self, level: int) -> Node:
        if level == len(self._LEVELS):
            return self.unary()
        left = self.binary(level + 1)
        while self.at(*self._LEVELS[level]):
            op = self.take().text
            left = Binary(op, left, self.binary(level + 1))
        return left

    def unary(self) -> Node:
        if self.at("!", "-"):
            op = self.take().text
            return Unary(op, self.unary())
        return self.primary()

    def primary(self) -> Node:
        token = self.take()
        if token.kind == "number":
            text = token.text
            if text.lower().startswith("0x"):
                return Literal(int(text, 16))
            return Literal(float(text) if any(c in text for c in ".eE") else int(text))
        if token.kind == "string":
            return Literal(token.text[1:-1])
        if token.kind == "name":
            if token.text in {"true", "false"}:
                return Literal(token.text == "true")
            self.reads.add(token.text)
            return Name(token.text)
        if token.text == "(":
            inner = self.expression()
            self.take(")")
            return inner
        raise ScriptError(f"unexpected '{token.text}' at {token.pos} in {self.source!r}")


_cache: dict[str, Script] = {}


def parse(source: str) -> Script:
    """Parse a script or precondition (results are cached by source text)."""
    script = _cache.get(source)
    if script is None:
        script = _Parser(source).script()
        _cache[source] = script
    return script
