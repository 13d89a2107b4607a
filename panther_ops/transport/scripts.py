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

STAGE = (
    RESOLVE
    + 'd=$(dirname -- "$r$p"); mkdir -p -- "$d" || exit 1; '
    + 't="$d/.$(basename -- "$p").panther-ops.$2"; '
    + 'umask 077; cat > "$t" || { rm -f -- "$t"; exit 1; }; '
    + 'if [ -n "$3" ]; then chmod "$3" "$t"; elif [ -e "$r$p" ]; then '
    + 'chmod --reference="$r$p" "$t" 2>/dev/null || true; else chmod 644 "$t"; fi; '
    + 'sync -- "$t" 2>/dev/null || sync; printf %s "$t"'
)
"""Upload stdin to a temp file beside the target (same file system), fsync it, print its name.
$2 is a unique suffix, $3 an optional octal mode."""

COMMIT = (
    'r="${PANTHER_OPS_ROOT:-}"; t="$1"; p="$2"; case "$p" in "~/"*) p="$HOME/${p#"~/"}";; esac; '
    + 'mv -f -- "$t" "$r$p" || exit 1; sync -- "$(dirname -- "$r$p")" 2>/dev/null; exit 0'
)
"""Rename a staged temp file over its target (atomic on POSIX file systems)."""

DISCARD = 'rm -f -- "$1"'
