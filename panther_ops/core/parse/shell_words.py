"""Shell words of a command line, with their positions, and the script of ``bash -c "..."``.

A compose ``command:`` string is split into words shell-style (quotes removed, nothing
expanded); a ``bash -c SCRIPT`` command hands its SCRIPT to the shell, which splits it again.
Husarion's compose files run the gamepad that way (husarion/panther-docker@2.0.4 and
@2.1.1:demo/compose.minimal-setup.yaml: ``bash -c "ros2 launch joy2twist ...
joy2twist_params_file:=$(ros2 pkg prefix joy2twist)/share/... namespace:=panther"``), so the
container's ``Cmd`` is ``["bash", "-c", "<script>"]`` and its launch words are the script's.

``$(...)`` (a shell command substitution, or a launch ``$(find pkg)`` substitution) is kept
as part of its word even though it holds spaces, as a shell keeps it; ``${VAR}`` is left as
written.
"""

from __future__ import annotations

import posixpath
from collections.abc import Sequence
from dataclasses import dataclass

from panther_ops.errors import InputError

SHELLS = frozenset({"bash", "sh"})
"""Shells whose ``-c SCRIPT`` is read as a command line (by the base name of argv[0])."""
OPERATORS = frozenset(";&|<>`")
"""Characters that, unquoted in a script, make it more than one simple command (so does a
newline between two words)."""


class CommandSyntaxError(InputError):
    """The command cannot be split into words (e.g. an unclosed quote)."""


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


def _word(text: str, start: int, operators: list[str] | None = None) -> Token:
    """The word starting at ``start`` (not a blank); unquoted `OPERATORS` go to ``operators``."""
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
        if depth == 0 and c in OPERATORS and operators is not None:
            operators.append(c)
        buf.append(c)
        i += 1
    if depth:
        raise CommandSyntaxError(f"unclosed $( in command: {text.strip()!r}")
    raw = text[start:i]
    whole = quoted_parts == 1 and raw[:1] in "'\"" and raw[-1:] == raw[:1]
    return Token("".join(buf), start, i, quote, whole)


def _tokens(text: str, operators: list[str] | None = None) -> list[Token]:
    tokens: list[Token] = []
    i, n = 0, len(text)
    while i < n:
        newline = False
        while i < n and text[i] in " \t\r\n":
            newline = newline or text[i] == "\n"
            i += 1
        if i >= n:
            break
        if newline and tokens and operators is not None:  # a shell ends a command at a newline
            operators.append("\n")
        token = _word(text, i, operators)
        tokens.append(token)
        i = token.end
    return tokens


def shell_tokens(text: str) -> list[Token]:
    """Split ``text`` into words like compose (go-shellwords) does, with positions.

    Raises:
        CommandSyntaxError: an unclosed quote or ``$(``.
    """
    return _tokens(text)


def shell_script(argv: Sequence[str]) -> str | None:
    """The SCRIPT of an argv ``bash -c SCRIPT`` (or ``sh``, by path too); None for any other argv."""
    if len(argv) == 3 and posixpath.basename(argv[0]) in SHELLS and argv[1] == "-c":
        return argv[2]
    return None


def script_words(script: str) -> list[str]:
    """The words of a ``-c`` script that runs one simple command.

    Raises:
        CommandSyntaxError: an unclosed quote or ``$(``, or an unquoted ``;``, ``&``, ``|``,
            ``<``, ``>``, backquote or newline between words (more than one command: not read
            as one command line).
    """
    operators: list[str] = []
    tokens = _tokens(script, operators)
    if operators:
        raise CommandSyntaxError(
            f"the bash -c script holds {operators[0]!r} (more than one command): {script.strip()[:80]!r}",
            hint="panther-ops reads a bash -c script that is one `ros2 launch ...` command",
        )
    return [t.value for t in tokens]


def command_words(argv: Sequence[str]) -> tuple[tuple[str, ...], list[str]]:
    """``(shell, words)``: for ``bash -c SCRIPT`` ``(("bash", "-c"), words of SCRIPT)``, else
    ``((), argv)``. A container's ``Cmd`` and a compose command are compared this way.

    Raises:
        CommandSyntaxError: the script cannot be read as one command (`script_words`).
    """
    script = shell_script(argv)
    if script is None:
        return (), list(argv)
    return (argv[0], argv[1]), script_words(script)


def has_word(argv: Sequence[str], word: str) -> bool:
    """``word`` is one of the words ``argv`` runs (inside a ``bash -c`` script too)."""
    if word in argv:
        return True
    try:
        return word in command_words(argv)[1]
    except CommandSyntaxError:
        return False
