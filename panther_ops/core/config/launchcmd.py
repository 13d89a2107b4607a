"""The ``ros2 launch`` command line of a compose service, as tokens and ``name:=value`` args.

Compose splits a string ``command:`` shell-style (quotes removed, no expansion); a list
``command:`` is the argv itself. This module tokenises a command string keeping each
token's position (so one argument can be rewritten in place), parses the argv into package,
launch file and ordered arguments, and quotes new values.

``$(...)`` launch substitutions (``$(find panther_description)/config/WH01.yaml``) are kept
as one word even though they contain a space, like a shell keeps a command substitution in
one word; values that need it are written single-quoted (``name:='$(find pkg)/x.yaml'``).
``${VAR}`` is compose's own interpolation and is left as written.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import Enum

from panther_ops.errors import InputError

# ros2 launch options that take a value
_OPTIONS_WITH_VALUE = frozenset({"--launch-prefix", "--launch-prefix-filter"})
_LAUNCH_FILE = re.compile(r".*\.(?:launch\.)?(?:py|xml|ya?ml)$")
_SAFE_WORD = re.compile(r"^[A-Za-z0-9_@%+=:,./~{}-]+$")


class CommandSyntaxError(InputError):
    """The command cannot be split into words (e.g. an unclosed quote)."""


class CommandForm(str, Enum):
    """How the ``command:`` of a service is written."""

    STRING = "string"
    """A one-line string (plain or quoted)."""
    BLOCK = "block"
    """A folded ``>`` / literal ``|`` block, or a plain scalar over several lines."""
    LIST = "list"
    """A list (flow ``[...]`` or block ``- ...``): one item per argv word."""


@dataclass(frozen=True)
class Token:
    """One word of a command string.

    Attributes:
        value: the word after quote removal.
        start, end: its span in the tokenised text.
        quote: the first quote character used in the word (None when unquoted).
        whole_quoted: the word is one quoted string (``'name:=value'``).
    """

    value: str
    start: int
    end: int
    quote: str | None = None
    whole_quoted: bool = False


def _single_quoted(text: str, i: int) -> tuple[str, int]:
    j = text.find("'", i + 1)
    if j < 0:
        raise CommandSyntaxError(f"unclosed ' in command: {text.strip()!r}")
    return text[i + 1 : j], j + 1


def _double_quoted(text: str, i: int) -> tuple[str, int]:
    j, n = i + 1, len(text)
    part: list[str] = []
    while j < n and text[j] != '"':
        if text[j] == "\\" and j + 1 < n and text[j + 1] in '"\\$`':
            part.append(text[j + 1])
            j += 2
            continue
        part.append(text[j])
        j += 1
    if j >= n:
        raise CommandSyntaxError(f'unclosed " in command: {text.strip()!r}')
    return "".join(part), j + 1


def _word(text: str, start: int) -> Token:
    """The word starting at ``start`` (not a blank)."""
    i, n = start, len(text)
    buf: list[str] = []
    quote: str | None = None
    depth = 0
    quoted_parts = 0
    while i < n:
        c = text[i]
        if depth == 0 and c in " \t\r\n":
            break
        if depth == 0 and c in "'\"":
            part, i = _single_quoted(text, i) if c == "'" else _double_quoted(text, i)
            buf.append(part)
            quote = quote or c
            quoted_parts += 1
            continue
        if c == "\\" and depth == 0 and i + 1 < n:
            if text[i + 1] != "\n":
                buf.append(text[i + 1])
            i += 2
            continue
        if text.startswith("$(", i):
            depth += 1
            buf.append("$(")
            i += 2
            continue
        if depth and c in "()":
            depth += 1 if c == "(" else -1
        buf.append(c)
        i += 1
    if depth:
        raise CommandSyntaxError(f"unclosed $( in command: {text.strip()!r}")
    raw = text[start:i]
    whole = quoted_parts == 1 and raw[:1] in "'\"" and raw[-1:] == raw[:1]
    return Token("".join(buf), start, i, quote, whole)


def shell_tokens(text: str) -> list[Token]:
    """Split ``text`` into words like compose (go-shellwords) does, with positions.

    Raises:
        CommandSyntaxError: an unclosed quote or ``$(``.
    """
    tokens: list[Token] = []
    i, n = 0, len(text)
    while i < n:
        while i < n and text[i] in " \t\r\n":
            i += 1
        if i >= n:
            break
        token = _word(text, i)
        tokens.append(token)
        i = token.end
    return tokens


def shell_quote(value: str, quote: str | None = None) -> str:
    """``value`` as one word: bare when safe, else quoted (``'`` unless ``quote`` is ``"``)."""
    if quote is None and value and _SAFE_WORD.match(value):
        return value
    if quote == '"':
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return "'" + value.replace("'", "'\\''") + "'"


def arg_word(name: str, value: str, like: Token | None = None) -> str:
    """The word ``name:=value``, quoted like ``like`` (the word it replaces) when given.

    Raises:
        ValueError: a name or value with a control character (a newline would end the
            ``command:`` line): validate_arg refuses those first, naming the argument.
    """
    if any(ord(c) < 32 or ord(c) == 127 for c in name + value):
        raise ValueError(f"launch argument {name}: control character in {value!r}")
    if like is not None and like.whole_quoted and like.quote:
        return shell_quote(f"{name}:={value}", like.quote)
    if like is not None and like.quote:
        return f"{name}:=" + shell_quote(value, like.quote)
    return f"{name}:=" + shell_quote(value)


def split_arg(word: str) -> tuple[str, str] | None:
    """``name:=value`` -> (name, value); None for other words."""
    name, sep, value = word.partition(":=")
    if not sep or not name or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        return None
    return name, value


@dataclass(frozen=True)
class LaunchCommand:
    """A parsed ``ros2 launch`` command.

    Attributes:
        form: how the command is written in the compose file.
        style: its YAML style (None plain, ``'``, ``"``, ``>``, ``|``, ``flow``, ``block``).
        argv: the words.
        package: launch package (None when a launch file path is given).
        launch_file: launch file name or path.
        args: ``name -> value`` in command order (the last one wins for repeats).
        options: other words after ``ros2 launch`` (``-d``, ...).
        line: 1-based line of the command in the compose file.
    """

    form: CommandForm
    style: str | None
    argv: tuple[str, ...]
    package: str | None
    launch_file: str
    args: dict[str, str] = field(default_factory=dict)
    options: tuple[str, ...] = ()
    line: int | None = None

    def arg_names(self) -> list[str]:
        return list(self.args)


def parse_launch_argv(
    argv: Sequence[str], *, path: str | None = None, line: int | None = None
) -> tuple[str | None, str, dict[str, str], tuple[str, ...]]:
    """Package, launch file, args and options of a ``ros2 launch`` argv.

    Raises:
        InputError: the argv is not ``ros2 launch <package> <file> ...`` or
            ``ros2 launch <file path> ...`` (e.g. wrapped in ``bash -c``).
    """
    words = list(argv)
    if len(words) < 3 or words[0] != "ros2" or words[1] != "launch":
        shown = " ".join(words)[:80]
        raise InputError(
            f"command is not `ros2 launch ...`: {shown!r}",
            path=path,
            line=line,
            key="command",
            hint="panther-ops edits launch arguments only in a plain `ros2 launch <pkg> <file> name:=value` "
            "command (not wrapped in bash -c); edit this one by hand",
        )
    options: list[str] = []
    positional: list[str] = []
    args: dict[str, str] = {}
    i = 2
    while i < len(words):
        word = words[i]
        parsed = split_arg(word)
        if parsed is not None:
            args.pop(parsed[0], None)
            args[parsed[0]] = parsed[1]
        elif word.startswith("-") and not positional:
            options.append(word)
            if word in _OPTIONS_WITH_VALUE and i + 1 < len(words):
                options.append(words[i + 1])
                i += 1
        elif len(positional) < 2:
            positional.append(word)
        else:
            options.append(word)
        i += 1
    if not positional:
        raise InputError("`ros2 launch` without a launch file", path=path, line=line, key="command")
    if len(positional) == 1 or (_LAUNCH_FILE.match(positional[0]) and "/" in positional[0]):
        return None, positional[0], args, tuple(options + positional[1:])
    return positional[0], positional[1], args, tuple(options)
