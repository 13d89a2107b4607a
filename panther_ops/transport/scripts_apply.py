"""The shell side of a change: one session that stages, then commits on the go-ahead (the
robot's half of :class:`panther_ops.transport.session.Session`).

APPLY reads its arguments from its input (one per line, so it can be started before the
write is known: a session opened beside the plan's read costs no round trip), unpacks one
tar archive holding the backup (manifest and the old contents) and every new content, each
staged in a temp file beside its target (same file system, so the rename is atomic), fsyncs
them, optionally asks the robot's own ``docker compose`` about a staged
compose file, and prints ``STAGED_MARK``. It then waits for one line on stdin:

- ``go``: takes the robot's write lock (``flock`` on ``~/.panther-ops/write.lock``), checks
  that every file is still what the plan read (sha256; exit 3 and nothing left behind when one
  changed), renames every staged file into place, fsyncs the directories and records the
  status, then lets the lock go: the check and the renames are one step to any other writer,
  which either waits and then finds the file changed, or finds it as it was;
- ``stop`` (the command will not go ahead: another robot's plan was refused, or the
  operator said no): removes all it made, backup included, and renames nothing;
- anything else, or the end of the input (the connection died): removes the staged files,
  records the attempt as abandoned beside the backup, and renames nothing.

The line may already wait behind the archive (a caller that has its go-ahead sends both in
one message): it is read only after everything is staged, synced and validated.

The check comes after the go-ahead, right before the renames, so a write staged early
(while the rest of the fleet is still being planned) is still checked against the robot's
file as it is at the moment it is replaced.

Nothing user-given is ever part of the script text: paths and values come as the lines of
the request (absolute paths: the caller resolved ``~``), contents as the archive after it,
read with ``head -c SIZE`` (which reads no further than its count, so the go-ahead stays in
the pipe for ``read``; tar itself would drain the pipe). Every process counts, since this
runs on every robot of a fleet at once: a one-file change runs head, tar and sync before
the go-ahead and sha256sum, mv and sync after it, and chmod only when the caller does not
know the file's mode.
"""

from __future__ import annotations

import io
import tarfile
import time
from dataclasses import dataclass

from panther_ops.transport.scripts import MISSING_EXIT, RESOLVE

CHANGED_EXIT = 3
"""A file changed on the robot since the plan read it: nothing written."""
REFUSED_EXIT = 5
"""The robot's docker compose refused the staged compose file: nothing written."""
ABANDONED_EXIT = 4
"""No go-ahead came (the caller said stop, or the connection died): nothing renamed."""

STAGED_MARK = b"@@staged\n"

_EACH = (
    'k=0; for a in "$@"; do case $k in 0) p=$a; f="$r$a";; 1) want=$a;; 2) t=$a;; 3) ref=$a; '
    '@BODY@ ;; esac; k=$(((k+1)%4)); done; '
)

_CHECK = _EACH.replace("@BODY@", (
    'if [ "$want" = - ]; then if [ -e "$f" ]; then '
    '  printf "%s appeared on the robot since it was read\\n" "$p" >&2; unmake; exit 3; fi; '
    'else got=$(sha256sum < "$f" 2>/dev/null); if [ "${got%% *}" != "$want" ]; then '
    '  printf "%s changed on the robot since it was read\\n" "$p" >&2; unmake; exit 3; fi; fi'
))

LOCK_NAME = "write.lock"
"""The lock file every write on a robot takes (``~/.panther-ops/write.lock``, beside the
backups): held with ``flock`` from the check that each file is what the plan read until every
rename is done, so two writers never both pass the check."""
LOCK_WAIT_S = 60
"""How long a write waits for another write's check and renames (they take milliseconds)."""

_LOCK = (
    f'lk="${{w%/backups/*}}/{LOCK_NAME}"; '
    'if ! command -v flock >/dev/null 2>&1; then drop; '
    '  echo "flock (util-linux) is missing on the robot: a write cannot be made safe against another" >&2; exit 1; fi; '
    'if ! touch -- "$lk" 2>/dev/null || ! [ -w "$lk" ]; then drop; '
    'printf "cannot open the write lock %s\\n" "$lk" >&2; exit 1; fi; exec 9>>"$lk"; '
    f'if ! flock -w {LOCK_WAIT_S} 9; then drop; '
    f'  printf "another change held the write lock %s for {LOCK_WAIT_S} s; nothing written\\n" "$lk" >&2; exit 1; fi; '
)
"""Take the robot's write lock (fd 9, released when the shell ends, renames done)."""

_APPLY_FN = "apply_() { " + (
    "trap '' HUP PIPE; nl='\n'; tab='\t'; r=\"${PANTHER_OPS_ROOT:-}\"; "
    'w="$r$1"; st="$2"; size="$3"; val="$4"; shift 4; '
    + 'staged=""; syncs="$w/manifest.json$nl"; vt=""; i=0; '
    'drop() { IFS="$nl"; set -f; for l in $staged; do [ "${l%%"$tab"*}" = - ] || rm -f -- "${l%%"$tab"*}"; done; }; '
    'unmake() { drop; rm -rf -- "$w"; rmdir -- "${w%/*}" "${w%/*/*}" 2>/dev/null; }; '
    + _EACH.replace("@BODY@", (
        'if [ "$t" = - ]; then staged="$staged-$tab$f$nl"; else staged="$staged$r$t$tab$f$nl"; '
        '  syncs="$syncs$r$t$nl"; [ "$i" = "$val" ] && vt="$r$t"; fi; '
        '[ "$want" = - ] || syncs="$syncs$w/files/$i$nl"; i=$((i+1))'
    ))
    + 'if ! head -c "$size" | tar -x -p --no-same-owner --no-overwrite-dir -f - -C "${r:-/}"; then '
    '  unmake; echo "cannot unpack the upload" >&2; exit 1; fi; '
    + 'i=0; ' + _EACH.replace("@BODY@", (
        'if [ "$ref" = 1 ] && [ -e "$f" ]; then if [ "$t" = - ]; then chmod --reference="$f" -- "$w/files/$i"; '
        '  else chmod --reference="$f" -- "$r$t" "$w/files/$i"; fi || { unmake; '
        '  printf "cannot give %s its mode\\n" "$p" >&2; exit 1; }; fi; i=$((i+1))'
    ))
    + 'IFS="$nl"; set -f; sync -- $syncs 2>/dev/null || sync; '
    'if [ -n "$vt" ] && [ -z "$r" ] && command -v docker >/dev/null 2>&1 && docker compose version >/dev/null 2>&1; '
    'then if ! err=$(cd "${vt%/*}" && docker compose -f "$vt" config -q 2>&1); then drop; '
    '  printf "refused: %s\\n" "$err" > "$w/status"; printf "%s\\n" "$err" >&2; exit 5; fi; fi; '
    'printf "@@staged\\n"; go=""; read -r go; '
    'if [ "$go" = stop ]; then unmake; exit 4; fi; '
    'if [ "$go" != go ]; then drop; printf "abandoned: no go-ahead (%s)\\n" "${go:-connection closed}" > "$w/status"; '
    '  exit 4; fi; '
    + _LOCK + 'unset IFS; set +f; ' + _CHECK + 'IFS="$nl"; set -f; '
    'dirs=""; for l in $staged; do t="${l%%"$tab"*}"; f="${l#*"$tab"}"; '
    '  if [ "$t" = - ]; then rm -f -- "$f" || exit 1; else mv -f -- "$t" "$f" || exit 1; fi; dirs="$dirs${f%/*}$nl"; '
    'done; sync -- $dirs 2>/dev/null; '
    'if [ -n "$st" ]; then printf "%s\\n" "$st" > "$w/status"; fi; exit 0'
) + "; }; "

READ_MARK = b"@@read\n"
"""Ends the read a session makes first (``APPLY`` given a path, :meth:`Session.read`)."""

_READ_FIRST = (
    'if [ $# -gt 0 ]; then ' + RESOLVE + 'if [ -f "$r$p" ]; then printf "@@home 0 %s\\n" "$HOME"; '
    f'base64 -- "$r$p" || exit 1; else printf "@@home {MISSING_EXIT} %s\\n" "$HOME"; fi; printf "@@read\\n"; fi; '
)

APPLY = _READ_FIRST + (
    'IFS= read -r n || exit 0; case "$n" in ""|*[!0-9]*) echo "the write request is not a count" >&2; exit 1;; esac; '
    'set --; while [ "$n" -gt 0 ]; do IFS= read -r a || exit 0; set -- "$@" "$a"; n=$((n-1)); done; '
) + _APPLY_FN + 'apply_ "$@"'
"""Given a path (``$1``, ``~/`` for the home), it first prints ``@@home 0 $HOME`` and the file in
base64 (whose alphabet has no ``@``; ``@@home 44 $HOME`` alone when there is no such file), then
``READ_MARK``: the
read a plan makes of the file it will write, on the session's own command (one exec session
per robot, :meth:`panther_ops.transport.session.Session.read`).
Stdin: the request (:func:`request`: the number of arguments, then one per line), the archive
(:func:`archive`), then, after ``STAGED_MARK``, ``GO`` or ``STOP``; the end of the input before
the request ends it with nothing made. Arguments: $1 backup dir (absolute), $2 status to record
once renamed (empty: later), $3 size of the archive, $4 index of the file to validate with docker
compose (``-``: none), then per file: absolute path, sha256 it must have when renamed over
(``-``: must not exist), its staged temp file (``-``: remove the file), ``1`` to give the staged
file and the backup the target's mode with chmod (``0``: the archive has it). Exit 3: a file
changed since it was read; 4: no go-ahead; 5: docker compose refused. The arguments come on the
input, not the command line, so the session can be started before the write is known."""

GO = b"go\n"
"""The go-ahead: check, rename, record."""
STOP = b"stop\n"
"""No go-ahead: remove everything the staging made."""


@dataclass(frozen=True)
class Member:
    """One file the archive creates on the robot (an absolute path)."""

    path: str
    data: bytes | None
    """None: a directory."""
    mode: int
    mtime: float | None = None


def archive(members: list[Member]) -> bytes:
    """A tar archive of ``members``, paths relative to ``/`` (APPLY unpacks it there)."""
    buf = io.BytesIO()
    now = time.time()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.GNU_FORMAT) as tar:
        for m in members:
            info = tarfile.TarInfo(m.path.lstrip("/"))
            info.mode = m.mode
            info.mtime = int(m.mtime if m.mtime is not None else now)
            if m.data is None:
                info.type = tarfile.DIRTYPE
                tar.addfile(info)
            else:
                info.size = len(m.data)
                tar.addfile(info, io.BytesIO(m.data))
    return buf.getvalue()


def request(args: list[str]) -> bytes:
    """The first input of ``APPLY``: its arguments (none may hold a newline)."""
    if any("\n" in a for a in args):
        raise ValueError("an argument of the write holds a newline")
    return (f"{len(args)}\n" + "".join(a + "\n" for a in args)).encode()
