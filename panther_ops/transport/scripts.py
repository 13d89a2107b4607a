"""Fixed shell snippets run on robots. User input only ever arrives as positional
parameters ("$1", "$2"), never inside the script text.

Paths may start with ``~/`` (the robot user's home). ``PANTHER_OPS_ROOT`` is empty on a
real robot; the local (demo) transport sets it to the directory standing in for the robot's
file system.
"""

from __future__ import annotations

RESOLVE = 'r="${PANTHER_OPS_ROOT:-}"; p="$1"; case "$p" in "~/"*) p="$HOME/${p#"~/"}";; esac; '

READ = RESOLVE + 'if [ -f "$r$p" ]; then exec cat -- "$r$p"; else echo "no such file: $p" >&2; exit 44; fi'
"""Print a file; exit 44 when it does not exist."""

MISSING_EXIT = 44

READ_WITH_HOME = RESOLVE + (
    'printf "%s\\n" "$HOME"; if [ -f "$r$p" ]; then exec cat -- "$r$p"; else echo "no such file: $p" >&2; exit 44; fi'
)
"""$HOME on the first line, then the file (exit 44 when it does not exist): one round trip."""

EXISTS = RESOLVE + '[ -e "$r$p" ]'
