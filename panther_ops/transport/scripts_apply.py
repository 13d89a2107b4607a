"""Shell snippets that carry out a change in two round trips: stage, then commit.

STAGE_ALL checks that every file is still what the plan read (sha256), backs the files up
with the manifest, and stages each new content beside its target; it prints the staged
names. COMMIT_ALL renames the staged files into place (each rename atomic) and records the
attempt's status. Nothing user-given is ever part of the script text: paths and values come
as positional parameters, contents as a tar archive on stdin.
"""

from __future__ import annotations

_RESOLVE = 'res() { case "$1" in "~/"*) printf "%s" "$HOME/${1#"~/"}";; *) printf "%s" "$1";; esac; }; '

CHANGED_EXIT = 3

STAGE_ALL = (
    'r="${PANTHER_OPS_ROOT:-}"; ' + _RESOLVE
    + 'b=$(res "$1"); sfx="$2"; shift 2; w="$r$b"; '
    'mkdir -p -- "$w/files" "$w/new" || exit 1; '
    'tar -x -f - -C "$w/new" || { echo "cannot unpack the upload" >&2; exit 1; }; '
    'i=0; : > "$w/new/todo"; '
    'while [ $# -ge 4 ]; do p=$(res "$1"); want="$2"; mode="$3"; new="$4"; shift 4; '
    '  if [ "$want" = "-" ]; then '
    '    if [ -e "$r$p" ]; then echo "$p appeared on the robot since it was read" >&2; exit 3; fi; '
    '  else '
    '    got=$(sha256sum < "$r$p" 2>/dev/null | cut -d" " -f1); '
    '    if [ "$got" != "$want" ]; then echo "$p changed on the robot since it was read" >&2; exit 3; fi; '
    '    cp -p -- "$r$p" "$w/files/$i" || exit 1; '
    '  fi; '
    '  printf "%s\\t%s\\t%s\\t%s\\n" "$i" "$mode" "$new" "$p" >> "$w/new/todo"; i=$((i+1)); '
    'done; '
    'mv -f -- "$w/new/manifest.json" "$w/manifest.json" || exit 1; : > "$w/staged"; '
    'tab=$(printf "\\t"); '
    'while IFS="$tab" read -r i mode new p; do '
    '  if [ "$new" = 1 ]; then '
    '    d=$(dirname -- "$r$p"); t="$d/.$(basename -- "$p").panther-ops.$sfx"; '
    '    if ! { mkdir -p -- "$d" && cp -- "$w/new/$i" "$t"; }; then '
    '      while read -r s; do rm -f -- "$s"; done < "$w/staged"; rm -f -- "$t"; exit 1; fi; '
    '    echo "$t" >> "$w/staged"; '
    '    if [ "$mode" != "-" ]; then chmod "$mode" "$t"; '
    '    elif [ -e "$r$p" ]; then chmod --reference="$r$p" "$t" 2>/dev/null; else chmod 644 "$t"; fi; '
    '    printf "%s\\n" "$t"; '
    '  else printf -- "-\\n"; fi; '
    'done < "$w/new/todo"; '
    'sync -- "$w/manifest.json" "$w"/files/* 2>/dev/null; while read -r s; do sync -- "$s"; done < "$w/staged"; '
    'rm -rf -- "$w/new" "$w/staged"'
)
"""$1 backup dir, $2 unique suffix, then per file: path, sha256 it must have now (``-``:
must not exist), octal mode (``-``: keep), 1 if it gets new content (0: removed). Stdin: a
tar of ``manifest.json`` and ``<index>`` files. Exit 3: a file changed since it was read."""

COMMIT_ALL = (
    'r="${PANTHER_OPS_ROOT:-}"; ' + _RESOLVE
    + 'b=$(res "$1"); st="$2"; shift 2; '
    'while [ $# -ge 2 ]; do t="$1"; p=$(res "$2"); shift 2; '
    '  if [ "$t" = "-" ]; then rm -f -- "$r$p" || exit 1; else mv -f -- "$t" "$r$p" || exit 1; fi; '
    '  sync -- "$(dirname -- "$r$p")" 2>/dev/null; '
    'done; '
    'if [ -n "$st" ]; then printf "%s\\n" "$st" > "$r$b/status"; fi; exit 0'
)
"""$1 backup dir, $2 status to record (empty: later), then pairs: staged file (``-``: remove
the target), target path."""
