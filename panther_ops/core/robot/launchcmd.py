"""The ``ros2 launch`` command line of a compose service, as tokens and ``name:=value`` args.

Compose splits a string ``command:`` shell-style (quotes removed, no expansion); a list
``command:`` is the argv itself. The words are split by `panther_ops.core.parse.shell_words`,
which keeps each token's position (so one argument can be rewritten in place); this module
parses the argv into package, launch file and ordered arguments, and quotes new values.

``$(...)`` launch substitutions (``$(find panther_description)/config/WH01.yaml``) are kept
as one word even though they contain a space, like a shell keeps a command substitution in
one word; values that need it are written single-quoted (``name:='$(find pkg)/x.yaml'``).
``${VAR}`` is compose's own interpolation and is left as written.

The launch command may also be the one script of ``bash -c "ros2 launch ..."``, as
husarion/panther-docker@2.0.4 and @2.1.1:demo/compose.minimal-setup.yaml run the gamepad
(its ``joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/share/...`` needs the shell). Its
arguments are the script's words (`launch_words`); they are edited inside the script's quotes
(`script_span`, `put_arg`, `remove_args`), and a new word that the quotes would not keep as
written (``"``, ``$``, backquote, backslash inside ``"..."``; ``'`` inside ``'...'``) is
refused (`check_script_word`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import Enum

from panther_ops.core.parse.shell_words import (
    CommandSyntaxError,
    Token,
    command_words,
    shell_tokens,
)
from panther_ops.errors import InputError

__all__ = [
    "CommandForm",
    "CommandSyntaxError",
    "LaunchCommand",
    "Token",
    "arg_word",
    "check_script_word",
    "launch_words",
    "parse_launch_argv",
    "put_arg",
    "remove_args",
    "remove_word",
    "script_span",
    "shell_quote",
    "shell_tokens",
    "split_arg",
]

# ros2 launch options that take a value
_OPTIONS_WITH_VALUE = frozenset({"--launch-prefix", "--launch-prefix-filter"})
_LAUNCH_FILE = re.compile(r".*\.(?:launch\.)?(?:py|xml|ya?ml)$")
_SAFE_WORD = re.compile(r"^[A-Za-z0-9_@%+=:,./~{}-]+$")


class CommandForm(str, Enum):
    """How the ``command:`` of a service is written."""

    STRING = "string"
    """A one-line string (plain or quoted)."""
    BLOCK = "block"
    """A folded ``>`` / literal ``|`` block, or a plain scalar over several lines."""
    LIST = "list"
    """A list (flow ``[...]`` or block ``- ...``): one item per argv word."""


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
        argv: the words compose gives the container (``bash``, ``-c``, the script for a
            command run by the shell).
        package: launch package (None when a launch file path is given).
        launch_file: launch file name or path.
        args: ``name -> value`` in command order (the last one wins for repeats).
        options: other words after ``ros2 launch`` (``-d``, ...).
        line: 1-based line of the command in the compose file.
        shell: ``("bash", "-c")`` when the launch command is the script of a shell, else ``()``.
        words: the ``ros2 launch`` words (the script's words for a shell; else ``argv``).
    """

    form: CommandForm
    style: str | None
    argv: tuple[str, ...]
    package: str | None
    launch_file: str
    args: dict[str, str] = field(default_factory=dict)
    options: tuple[str, ...] = ()
    line: int | None = None
    shell: tuple[str, ...] = ()
    words: tuple[str, ...] = ()

    def arg_names(self) -> list[str]:
        return list(self.args)


def parse_launch_argv(
    argv: Sequence[str], *, path: str | None = None, line: int | None = None
) -> tuple[str | None, str, dict[str, str], tuple[str, ...]]:
    """Package, launch file, args and options of a ``ros2 launch`` argv.

    Raises:
        InputError: the argv is not ``ros2 launch <package> <file> ...`` or
            ``ros2 launch <file path> ...`` (`launch_words` unwraps ``bash -c "..."`` first).
    """
    words = list(argv)
    if len(words) < 3 or words[0] != "ros2" or words[1] != "launch":
        shown = " ".join(words)[:80]
        raise InputError(
            f"command is not `ros2 launch ...`: {shown!r}",
            path=path,
            line=line,
            key="command",
            hint="panther-ops edits launch arguments in a `ros2 launch <pkg> <file> name:=value` command, "
            'written as it is or as the one command of `bash -c "..."`; edit this one by hand',
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


def launch_words(
    argv: Sequence[str], *, path: str | None = None, line: int | None = None
) -> tuple[tuple[str, ...], list[str]]:
    """``(shell, words)`` of a command: the script's words of ``bash -c SCRIPT``, else the argv.

    Raises:
        InputError: the script is not one command (an operator) or cannot be split.
    """
    try:
        return command_words(argv)
    except CommandSyntaxError as exc:
        raise InputError(exc.message, path=path, line=line, key="command", hint=exc.hint) from exc


def script_span(text: str, *, path: str | None = None, line: int | None = None) -> tuple[int, int, str]:
    """Where the SCRIPT of a command text ``bash -c "SCRIPT"`` is: the span between its quotes
    and the quote character.

    Raises:
        InputError: the script is not one quoted string, or (``"..."``) holds a backslash:
            its text is not the script as written, so it is not edited in place.
    """
    tokens = shell_tokens(text)
    tok = tokens[2] if len(tokens) == 3 else None
    if tok is None or not tok.whole_quoted or tok.quote is None or (
            tok.quote == '"' and "\\" in text[tok.start : tok.end]):
        raise InputError("the bash -c script is not one quoted string without backslashes: "
                         f"{text.strip()[:80]!r}", path=path, line=line, key="command",
                         hint='panther-ops edits a script written `bash -c "ros2 launch ..."`; edit this one by hand')
    return tok.start + 1, tok.end - 1, tok.quote


UNSAFE_IN_QUOTES = {'"': '"$`\\', "'": "'"}
"""Characters a new word may not hold inside a script quoted with the key: in ``"..."`` they
end the string or are expanded or escaped before the shell gets the script."""
_CHAR_NAMES = {'"': 'a double quote (")', "$": "a dollar sign ($)", "`": "a backquote (`)",
               "\\": "a backslash (\\)", "'": "a single quote (')"}
_QUOTE_NAMES = {'"': "double-quoted", "'": "single-quoted"}


def check_script_word(
    word: str, quote: str | None, *, name: str, value: str, path: str | None = None, line: int | None = None
) -> None:
    """Refuse a new word for a script in ``quote`` that the quotes would not keep as written.

    Raises:
        InputError: the word holds a character of `UNSAFE_IN_QUOTES` (names the value).
    """
    unsafe = UNSAFE_IN_QUOTES.get(quote or "", "")
    if not any(c in unsafe for c in word):
        return
    own = [c for c in unsafe if c in value]
    why = ("it holds " + ", ".join(_CHAR_NAMES[c] for c in own) if own else
           "quoted for the shell it needs " + ", ".join(_CHAR_NAMES[c] for c in unsafe if c in word))
    raise InputError(
        f"launch argument {name}: the value {value!r} cannot be written inside the "
        f"{_QUOTE_NAMES.get(quote or '', 'quoted')} bash -c script of this command: {why}",
        path=path, line=line, key="command",
        hint="use a value without " + ", ".join(_CHAR_NAMES[c] for c in unsafe)
             + (" or a single quote" if quote == '"' else "") + ", or edit the command by hand",
    )


def last_arg(tokens: list[Token], name: str) -> Token | None:
    """The last ``name:=`` word among ``tokens`` (a later one wins, as in ros2 launch)."""
    for tok in reversed(tokens):
        parsed = split_arg(tok.value)
        if parsed is not None and parsed[0] == name:
            return tok
    return None


def put_arg(text: str, name: str, word: Callable[[Token | None], str]) -> str:
    """``text`` with its last ``name:=`` word replaced by ``word(that token)``, or with
    ``word(None)`` added after its last word: on a line of its own at that word's indentation
    when the last word begins its line, else after one space."""
    tokens = shell_tokens(text)
    target = last_arg(tokens, name)
    if target is not None:
        return text[: target.start] + word(target) + text[target.end :]
    if not tokens:
        return word(None)
    last = tokens[-1]
    line_start = text.rfind("\n", 0, last.start) + 1
    lead = text[line_start : last.start]
    sep = "\n" + lead if line_start > 0 and not lead.strip() else " "
    return text[: last.end] + sep + word(None) + text[last.end :]


def remove_word(text: str, tok: Token) -> str:
    """Remove a word; its whole line when it is alone on a line that is not the first."""
    line_start = text.rfind("\n", 0, tok.start) + 1
    line_end = text.find("\n", tok.end)
    line_end = len(text) if line_end < 0 else line_end
    alone = not text[line_start : tok.start].strip() and not text[tok.end : line_end].strip()
    if alone and line_start > 0:
        return text[: line_start - 1] + text[line_end:]
    start = tok.start
    while start > line_start and text[start - 1] in " \t":
        start -= 1
    end = tok.end
    if start == line_start:
        while end < line_end and text[end] in " \t":
            end += 1
    return text[:start] + text[end:]


def remove_args(text: str, name: str) -> str:
    """``text`` without any ``name:=`` word (`remove_word`)."""
    for tok in reversed(shell_tokens(text)):
        parsed = split_arg(tok.value)
        if parsed is not None and parsed[0] == name:
            text = remove_word(text, tok)
    return text
