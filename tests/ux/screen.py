"""A small model of a terminal's screen, for what a live view leaves on it.

It handles what rich's ``Live`` and a terminal's own echo write: printable characters (with
the terminal's deferred wrap: a character in the last column puts the cursor in a "pending
wrap" state, and the next character goes to the next line), ``\\r``, ``\\n``, cursor up
(``ESC [ n A``), erase line (``ESC [ 2 K``); colours and cursor show/hide are ignored. The
screen grows downward without limit (a scrollback), so every line ever left is kept.
"""

from __future__ import annotations

import re

_CSI = re.compile(r"\x1b\[([0-9;?]*)([A-Za-z])|\x1b\][^\x07]*\x07")


class Screen:
    def __init__(self, cols: int) -> None:
        self.cols = cols
        self.lines: list[list[str]] = [[]]
        self.row = 0
        self.col = 0
        self.pending_wrap = False

    def feed(self, text: str) -> None:
        i = 0
        while i < len(text):
            m = _CSI.match(text, i)
            if m:
                self._control(m.group(1) or "", m.group(2) or "")
                i = m.end()
                continue
            self._char(text[i])
            i += 1

    def _control(self, arg: str, final: str) -> None:
        if final == "A":
            self.row = max(0, self.row - int(arg or 1))
            self.pending_wrap = False
        elif final == "K" and arg == "2":
            self.lines[self.row] = []

    def _line(self) -> list[str]:
        while len(self.lines) <= self.row:
            self.lines.append([])
        return self.lines[self.row]

    def _char(self, ch: str) -> None:
        if ch == "\r":
            self.col, self.pending_wrap = 0, False
        elif ch == "\n":
            self.row += 1
            self.pending_wrap = False
            self._line()
        elif ch == "\x1b" or ord(ch) < 32:
            return
        else:
            if self.pending_wrap:
                self.row, self.col, self.pending_wrap = self.row + 1, 0, False
            line = self._line()
            while len(line) < self.col:
                line.append(" ")
            if self.col < len(line):
                line[self.col] = ch
            else:
                line.append(ch)
            if self.col == self.cols - 1:
                self.pending_wrap = True
            else:
                self.col += 1

    def text(self) -> list[str]:
        return ["".join(line).rstrip() for line in self.lines]
