"""Shell snippets for backups on the robot (``~/.panther-ops/backups/<id>/``).

Arguments only ever arrive as positional parameters.
"""

from __future__ import annotations

BACKUP_ROOT = "~/.panther-ops/backups"

SAVE = (
    'r="${PANTHER_OPS_ROOT:-}"; d="$1"; shift; case "$d" in "~/"*) d="$HOME/${d#"~/"}";; esac; '
    'mkdir -p -- "$r$d/files" || exit 1; i=0; '
    'for p in "$@"; do case "$p" in "~/"*) p="$HOME/${p#"~/"}";; esac; '
    'if [ -e "$r$p" ]; then cp -p -- "$r$p" "$r$d/files/$i" || exit 1; fi; i=$((i+1)); done; '
    'cat > "$r$d/manifest.json.tmp" && mv -f -- "$r$d/manifest.json.tmp" "$r$d/manifest.json" && sync'
)
"""$1 = backup dir; $2.. = files to save as files/0, files/1, ...; stdin = manifest.json."""

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
