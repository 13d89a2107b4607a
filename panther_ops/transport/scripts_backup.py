"""Shell snippets for backups on the robot (``~/.panther-ops/backups/<id>/``).

Arguments only ever arrive as positional parameters.
"""

from __future__ import annotations

BACKUP_ROOT = "~/.panther-ops/backups"

LIST = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'for m in "$r$d"/*/manifest.json; do [ -f "$m" ] || continue; cat -- "$m"; echo; echo "@@status"; '
    's="${m%/manifest.json}/status"; [ -f "$s" ] && cat -- "$s"; echo; echo "@@@"; done'
)
"""Print every manifest and its status line, each record ended by a ``@@@`` line."""

MARK = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'printf "%s\\n" "$2" > "$r$d/status"'
)
"""Record how an attempt ended: $1 = backup dir, $2 = ``applied`` / ``rolled-back: reason`` / ..."""

READ_BACKUP = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'cat -- "$r$d/$2"'
)
