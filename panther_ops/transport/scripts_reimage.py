"""Robot-side script of `reimage plan`/`backup`: the files that make a robot itself, as one tar
stream. Paths arrive as positional parameters (absolute, ``~`` already resolved)."""

from __future__ import annotations

TAR = (
    'r="${PANTHER_OPS_ROOT:-}"; n=$#; i=0; '
    'while [ "$i" -lt "$n" ]; do p="$1"; shift; i=$((i + 1)); '
    'if [ -e "$r$p" ] || [ -L "$r$p" ]; then set -- "$@" "${p#/}"; fi; done; '
    '[ "$#" -eq 0 ] && exit 0; '
    'exec tar -C "${r:-/}" -cf - -- "$@"'
)
"""A tar of every path given that exists (files and whole directories); nothing when none does.
Unreadable files are named on stderr (tar goes on, exit 2)."""
