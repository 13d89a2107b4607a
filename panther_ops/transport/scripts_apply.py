"""The shell side of a change: one session that stages, then commits on the go-ahead.

APPLY checks that every file is still what the plan read (sha256), backs the files up beside
the manifest, stages each new content in a temp file beside its target (same file system),
fsyncs all of them, optionally asks the robot's own ``docker compose`` about a staged compose
file, and prints ``STAGED_MARK``. It then waits for one line on stdin: ``go`` renames every
staged file into place (each rename atomic) and records the status; anything else, or the
end of the input (the connection died), removes the staged files and renames nothing.

Nothing user-given is ever part of the script text: paths and values come as positional
parameters, contents as bytes on stdin, each read with ``head -c SIZE`` (which reads no
further than its count, so the go-ahead stays in the pipe for ``read``). Every step is a
builtin but one process per real action (sha256sum, cp, head, chmod, sync, mv): this runs
on every robot of a fleet at once.
"""

from __future__ import annotations

CHANGED_EXIT = 3
"""A file changed on the robot since the plan read it: nothing written."""
REFUSED_EXIT = 5
"""The robot's docker compose refused the staged compose file: nothing written."""
ABANDONED_EXIT = 4
"""No go-ahead came (the caller said stop, or the connection died): nothing renamed."""

STAGED_MARK = b"@@staged\n"

_EACH = (
    'k=0; for a in "$@"; do case $k in 0) p=$a;; 1) want=$a;; 2) mode=$a;; 3) size=$a; '
    'case "$p" in "~/"*) p="$HOME/${p#"~/"}";; esac; f="$r$p"; @BODY@ ;; esac; k=$(((k+1)%4)); done; '
)

_APPLY_FN = "apply_() { " + (
    "trap '' HUP PIPE; nl='\n'; tab='\t'; r=\"${PANTHER_OPS_ROOT:-}\"; "
    'b="$1"; case "$b" in "~/"*) b="$HOME/${b#"~/"}";; esac; w="$r$b"; '
    'sfx="$2"; st="$3"; msize="$4"; val="$5"; shift 5; umask 077; '
    'staged=""; syncs=""; vt=""; '
    'drop() { IFS="$nl"; set -f; for l in $staged; do [ "${l%%"$tab"*}" = - ] || rm -f -- "${l%%"$tab"*}"; done; }; '
    'fail() { drop; rm -rf -- "$w"; printf "%s\\n" "$2" >&2; exit "$1"; }; '
    'mkdir -p -- "$w/files" || exit 1; i=0; '
    + _EACH.replace("@BODY@", (
        'if [ "$want" = - ]; then [ -e "$f" ] && fail 3 "$p appeared on the robot since it was read"; '
        'else got=$(sha256sum < "$f" 2>/dev/null); [ "${got%% *}" = "$want" ] || '
        'fail 3 "$p changed on the robot since it was read"; '
        'cp -p -- "$f" "$w/files/$i" || fail 1 "cannot back up $p"; syncs="$syncs$w/files/$i$nl"; fi; '
        'i=$((i+1))'
    ))
    + 'i=0; '
    + _EACH.replace("@BODY@", (
        'if [ "$size" = - ]; then staged="$staged-$tab$f$nl"; else '
        'd="${f%/*}"; t="$d/.${f##*/}.panther-ops.$sfx"; '
        'if [ ! -d "$d" ]; then umask 022; mkdir -p -- "$d" || fail 1 "cannot create ${p%/*}"; umask 077; fi; '
        'staged="$staged$t$tab$f$nl"; syncs="$syncs$t$nl"; [ "$i" = "$val" ] && vt="$t"; '
        'head -c "$size" > "$t" || fail 1 "cannot write beside $p"; '
        'if [ "$mode" != - ]; then chmod "$mode" "$t"; elif [ -e "$f" ]; then chmod --reference="$f" "$t"; '
        'else chmod 644 "$t"; fi '
        '|| fail 1 "cannot set the mode of the staged $p"; fi; '
        'i=$((i+1))'
    ))
    + 'head -c "$msize" > "$w/manifest.json" || fail 1 "cannot write the backup manifest"; '
    'IFS="$nl"; set -f; sync -- "$w/manifest.json" $syncs 2>/dev/null || sync; '
    'if [ -n "$vt" ] && [ -z "$r" ] && command -v docker >/dev/null 2>&1 && docker compose version >/dev/null 2>&1; '
    'then if ! err=$(cd "${vt%/*}" && docker compose -f "$vt" config -q 2>&1); then drop; '
    '  printf "refused: %s\\n" "$err" > "$w/status"; printf "%s\\n" "$err" >&2; exit 5; fi; fi; '
    'printf "@@staged\\n"; go=""; read -r go; '
    'if [ "$go" != go ]; then drop; printf "abandoned: no go-ahead (%s)\\n" "${go:-connection closed}" > "$w/status"; '
    '  exit 4; fi; '
    'dirs=""; for l in $staged; do t="${l%%"$tab"*}"; f="${l#*"$tab"}"; '
    '  if [ "$t" = - ]; then rm -f -- "$f" || exit 1; else mv -f -- "$t" "$f" || exit 1; fi; dirs="$dirs${f%/*}$nl"; '
    'done; sync -- $dirs 2>/dev/null; '
    'if [ -n "$st" ]; then printf "%s\\n" "$st" > "$w/status"; fi; exit 0'
) + "; }; "

APPLY = _APPLY_FN + 'apply_ "$@"'
"""$1 backup dir, $2 unique suffix, $3 status to record once renamed (empty: later), $4 size
of the manifest, $5 index of the file to validate with docker compose (``-``: none), then per
file: path, sha256 it must have now (``-``: must not exist), octal mode (``-``: keep), size of
the new content (``-``: remove the file). Stdin: each new content in order, then the manifest,
then (after ``STAGED_MARK``) the go-ahead line."""

WRITE_KEY = "write"
"""The key a kept read of compose.yaml is held under (see ``Transport.run_kept``)."""

READ_KEPT = (
    'r="${PANTHER_OPS_ROOT:-}"; p="$1"; case "$p" in "~/"*) p="$HOME/${p#"~/"}";; esac; '
    'printf "%s\\n" "$HOME"; if [ -f "$r$p" ]; then cat -- "$r$p" || exit 1; '
    'else echo "no such file: $p" >&2; exit 44; fi; printf "%s\\n" "$2"; '
    'IFS= read -r req || exit 0; [ "$req" = apply ] || exit 0; IFS= read -r n || exit 0; set --; '
    'while [ "$n" -gt 0 ]; do IFS= read -r a || exit 0; set -- "$@" "$a"; n=$((n-1)); done; '
) + _APPLY_FN + 'apply_ "$@"'
"""Read compose.yaml as ``READ_WITH_HOME`` does ($1; $HOME on the first line), print the mark
$2, then wait: a request ``apply``, the number of arguments and one per line, then the bytes
APPLY reads, carries out the write in this same session; the end of input ends it."""


def apply_request(args: list[str]) -> bytes:
    """The input that turns a kept ``READ_KEPT`` into ``APPLY args`` (arguments hold no newline)."""
    if any("\n" in a for a in args):
        raise ValueError("an argument of the write holds a newline")
    return ("apply\n" + f"{len(args)}\n" + "".join(a + "\n" for a in args)).encode()
