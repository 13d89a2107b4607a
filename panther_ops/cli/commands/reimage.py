"""`panther-ops reimage`: flash and verify a robot's card on this machine (the card in a reader)."""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Annotated, Any, Optional

import typer

from panther_ops.cli import context
from panther_ops.cli.context import Fleet
from panther_ops.cli.options import READ, Json, shared, sudo_password

app = typer.Typer(help="OS reimage: write and verify a robot's card on this machine.", no_args_is_help=True)

ImageArg = Annotated[str, typer.Argument(help="Disk image: .img, .img.xz or .img.gz.")]
Device = Annotated[str, typer.Option("--device", "-d", help="The card's whole block device, e.g. /dev/sdb.")]
Sha256 = Annotated[
    Optional[str],  # noqa: UP045
    typer.Option("--sha256", help="The image file's expected sha256 (default: IMAGE.sha256 beside it)."),
]


BmapOpt = Annotated[
    Optional[str],  # noqa: UP045
    typer.Option("--bmap", help="The image's block map (bmaptool's .bmap; default: IMAGE.bmap etc. beside it, "
                 "else computed from the image)."),
]
Full = Annotated[bool, typer.Option("--full", help="Write (or compare) every byte of the image, without a block map.")]


@app.command("flash")
def flash(
    image: ImageArg,
    device: Device,
    sha256: Sha256 = None,
    bmap: BmapOpt = None,
    full: Full = False,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Erase the device without asking.")] = False,
    json_out: Json = False,
) -> int:
    """Write IMAGE to the card in this machine's reader, then read it back and check it.

    Only the image's mapped blocks are written and read back: the map is a bmaptool .bmap
    (--bmap, or IMAGE.bmap beside it), else computed from the image's partition table and its
    ext4 and FAT file systems (anything else is mapped whole, and said so). The image's sha256
    (--sha256 or IMAGE.sha256; or the .bmap's range checksums) is checked as it is read: a
    mismatch stops the write before the partition table is written (the card does not boot),
    exit 3. --full writes every byte (the image's sha256 then checked first, exit 2).
    The device must be a whole block device, unmounted, not holding this machine's root, at
    least the image's size. Exit 2: refused, nothing written; exit 3: the card does not read
    back as the image, or the image did not match its checksum.

    \b
    Example:
      panther-ops reimage flash panther-2.1.1.img.xz --device /dev/sdb --yes
    """
    from panther_ops.cli.render import emit_json, error
    from panther_ops.cli.views.reimage import progress
    from panther_ops.core.reimage.device import describe
    from panther_ops.core.reimage.flash import check_sha256, eligible_device, flash, inspect_image
    from panther_ops.errors import ExitCode

    if full:
        if bmap:
            from panther_ops.errors import UsageError

            raise UsageError("--bmap and --full: give one (--full writes every byte, without a map)")
        with progress(json_out) as step:
            # the image first (its checksum, then its size), whatever the device: then the device
            img = inspect_image(image, sha256, require_checksum=True, progress=step)
            file_sha = check_sha256(img, step)
            facts = eligible_device(device, img)
            what = f"{image} ({img.size} bytes, sha256 {file_sha} checked against {img.checksum_from})"
            _confirm(yes, what, describe(facts), image)
            context.info(f"writing {what} to {describe(facts)}")
            done = flash(img, facts, file_sha, step)
        v = done.verdict
        if json_out:
            emit_json({"schema": 1, "command": "reimage flash", "ok": v.ok, "mode": "full", **done.to_json()})
        else:
            w = done.write
            io = "direct I/O" if w.direct else "buffered I/O (the device refused O_DIRECT)"
            typer.echo(f"wrote {w.bytes_written} bytes to {device} in {w.seconds:.1f} s "
                       f"({w.bytes_written / (1 << 20) / max(w.seconds, 1e-9):.1f} MiB/s, {io})")
            typer.echo(("verified: " if v.ok else "VERIFY FAILED: ") + v.message)
        return 0 if v.ok else int(ExitCode.PARTIAL)
    return _flash_mapped(image, device, sha256, bmap, yes, json_out, error)


def _confirm(yes: bool, what: str, dev: str, image: str) -> None:
    """Go on only with --yes or the operator's yes (exit 2 when nobody can answer, 5 declined)."""
    from panther_ops.cli.mutate import require

    require(f"Erase {dev} and write {image}?", yes,
            f"writing {what} would erase {dev}: pass --yes; nothing was written", "nothing was written")


def _flash_mapped(image: str, device: str, sha256: str | None, bmap: str | None, yes: bool, json_out: bool,
                  error: Callable[[str], None]) -> int:
    import time

    from panther_ops.cli.render import emit_json, human_bytes
    from panther_ops.cli.views.reimage import progress
    from panther_ops.core.reimage.device import describe
    from panther_ops.core.reimage.flash import eligible_device, inspect_image
    from panther_ops.core.reimage.mapflash import find_bmap, flash_mapped, read_map
    from panther_ops.errors import ExitCode, UsageError

    started = time.monotonic()
    bmap_path = find_bmap(image, bmap)
    with progress(json_out) as step:
        # the image's name, format, checksum file and map first, whatever the device
        img = inspect_image(image, sha256, require_checksum=bmap_path is None, progress=step, check_now=False)
        plan = read_map(img, bmap_path, step)
        if img.expected_sha256 is None and not plan.kind:
            raise UsageError(f"{image}: no checksum to check it against ({bmap_path} has no range checksums): "
                             f"give --sha256 HASH or put {os.path.basename(image)}.sha256 beside it")
        facts = eligible_device(device, img)
        checked = " and ".join(x for x in (
            f"sha256 from {img.checksum_from}" if img.expected_sha256 else "",
            f"{plan.kind} of each range from the map" if plan.kind else "") if x)
        what = (f"{image} ({img.size} bytes; {human_bytes(plan.mapped_bytes)} mapped in {len(plan.spans)} "
                f"ranges; checked as it is read: {checked})")
        _confirm(yes, what, describe(facts), image)
        if not json_out:
            context.info(f"map: {plan.source}")
            for note in plan.notes:
                context.info(f"note: {note}")
            context.info(f"writing {what} to {describe(facts)}")
        done = flash_mapped(img, facts, plan, step)
    total = time.monotonic() - started
    v = done.verdict
    ok = done.stopped is None and v is not None and v.ok
    if json_out:
        emit_json({"schema": 1, "command": "reimage flash", "ok": ok, "mode": "mapped", **done.to_json(),
                   "seconds": round(total, 3)})
    elif done.stopped is not None:
        error(f"STOPPED: {done.stopped}: the write was stopped before the partition table was written; "
              f"{device} is NOT bootable. Flash it again with a good image.")
    else:
        w = done.write
        assert w is not None and v is not None
        io = "direct I/O" if w.direct else "buffered I/O (the device refused O_DIRECT)"
        typer.echo(f"wrote {w.bytes_written} of {img.size} bytes ({100 * w.bytes_written / img.size:.1f}%) "
                   f"to {device} in {w.seconds:.1f} s ({w.bytes_written / (1 << 20) / max(w.seconds, 1e-9):.1f} "
                   f"MiB/s, {io}); the rest of the card was left as it was")
        typer.echo(("verified: " if v.ok else "VERIFY FAILED: ") + v.message + f"; {total:.1f} s in all")
    return 0 if ok else int(ExitCode.PARTIAL)


@app.command("verify")
def verify(image: ImageArg, device: Device, sha256: Sha256 = None, bmap: BmapOpt = None, full: Full = False,
           json_out: Json = False) -> int:
    """Read DEVICE back and compare it with IMAGE.

    With a block map (--bmap, IMAGE.bmap beside it, else computed from the image): each mapped
    range of the card is hashed and compared with the map's checksum (or the image's bytes);
    the first differing byte is named. --full: every byte, both sides hashed. The image's own
    sha256 is checked first, before the device, when --sha256 or IMAGE.sha256 gives one.
    Exit 3 when the device differs.

    \b
    Example:
      panther-ops reimage verify panther-2.1.1.img.xz --device /dev/sdb
    """
    from panther_ops.cli.render import emit_json
    from panther_ops.cli.views.reimage import progress
    from panther_ops.core.reimage.flash import inspect_image, verify
    from panther_ops.core.reimage.mapflash import find_bmap, read_map, verify_mapped
    from panther_ops.errors import ExitCode, UsageError

    if full and bmap:
        raise UsageError("--bmap and --full: give one (--full compares every byte, without a map)")
    with progress(json_out) as step:
        img = inspect_image(image, sha256, require_checksum=False, progress=step)  # checked when a hash is given
        if full:
            v = verify(img, device, step)
            doc: dict[str, Any] = {"mode": "full", "verify": v.to_json()}
            ok, message = v.ok, v.message
        else:
            plan = read_map(img, find_bmap(image, bmap), step)
            mv = verify_mapped(img, device, plan, step)
            doc = {"mode": "mapped", "map": plan.to_json(img.size), "verify": mv.to_json()}
            ok, message = mv.ok, mv.message
    if json_out:
        emit_json({"schema": 1, "command": "reimage verify", "image": img.to_json(), "ok": ok, **doc})
    else:
        typer.echo(("verified: " if ok else "VERIFY FAILED: ") + message)
    return 0 if ok else int(ExitCode.PARTIAL)


@app.command("bmap")
def bmap_cmd(
    image: ImageArg,
    out: Annotated[
        Optional[str],  # noqa: UP045
        typer.Option("--out", "-o", help="Where to write it (default: beside the image, IMAGE.bmap without .xz/.gz)."),
    ] = None,
    json_out: Json = False,
) -> int:
    """Write IMAGE's block map, in bmaptool's format (version 2.0, sha256 of each range).

    Computed from the image's partition table and its ext4 and FAT file systems (anything
    else is mapped whole, and said so); a sparse image's holes are left out. Map a fleet's
    image once; `reimage flash` (and `bmaptool copy`) then find it beside the image.

    \b
    Example:
      panther-ops reimage bmap panther-2.1.1.img.xz
    """
    from pathlib import Path

    from panther_ops.cli.render import emit_json, human_bytes
    from panther_ops.cli.views.reimage import progress
    from panther_ops.core.reimage.bmap import render_bmap
    from panther_ops.core.reimage.flash import inspect_image
    from panther_ops.core.reimage.mapflash import build_bmap, default_bmap_path
    from panther_ops.transport.localfile import write_atomic

    target = out or default_bmap_path(image)
    with progress(json_out) as step:
        img = inspect_image(image, None, require_checksum=False, progress=step)
        bm, plan = build_bmap(img, step)
    write_atomic(Path(target), render_bmap(bm).encode())
    if json_out:
        emit_json({"schema": 1, "command": "reimage bmap", "ok": True, "image": img.to_json(), "bmap": target,
                   "map": plan.to_json(img.size)})
    else:
        for note in plan.notes:
            context.info(f"note: {note}")
        typer.echo(f"{target}: {human_bytes(bm.mapped_bytes)} of {human_bytes(img.size)} mapped "
                   f"({100 * bm.mapped_bytes / img.size:.1f}%) in {len(bm.ranges)} ranges")
    return 0


@app.command("plan")
@shared(*READ)
def plan(fleet: Fleet) -> int:
    """List what `reimage backup` would carry from each robot (read only).

    The compose file, the config tree, every file the driver mounts from the robot, the
    shutdown hosts file, the robot's SSH key pair, known_hosts and authorized_keys, the
    deployed manager, and the inventory's desired: block; per file its mode, owner, size and
    whether it is a secret.

    \b
    Example:
      panther-ops reimage plan -r panther-01
    """
    from panther_ops.cli.views.reimage import print_carried
    from panther_ops.core.reimage.tasks import plan_task

    return fleet.run("reimage plan", plan_task, lambda f: print_carried(f, title="reimage plan"), read_only=True)


@app.command("backup")
@shared(*READ)
def backup(
    fleet: Fleet,
    out: Annotated[str, typer.Option("--out", "-o", help="Directory for the archives (created 0700).")] = "backups",
) -> int:
    """Back up each robot into one archive (OUT/ROBOT-TIME.tar.gz, mode 0600) with a manifest.

    Read over the robot's one connection; robots are read in parallel. The manifest names the
    robot, model, serial, stack and version, OS build, host key fingerprint, and per file its
    path, mode, owner, sha256 and whether it is a secret (private keys, shutdown secrets).

    \b
    Example:
      panther-ops reimage backup --all --out backups/
    """
    from panther_ops.cli.render import print_results
    from panther_ops.core.reimage.archive import out_dir
    from panther_ops.core.reimage.tasks import backup_task

    directory = out_dir(out)
    return fleet.run("reimage backup", backup_task(directory), lambda f: print_results(f, title="reimage backup"))


@app.command("restore")
@shared("yes", "dry_run", "no_restart", "settle", "json_out")
def restore(
    fleet: Fleet,
    robot: Annotated[str, typer.Option("--robot", "-r", help="The robot the backup was taken from.")],
    from_: Annotated[str, typer.Option("--from", help="The robot's backup archive (reimage backup).")],
) -> int:
    """Put a backup back onto the robot after its OS was reinstalled.

    The archive is checked first, whole: its manifest, then every member exactly as the
    manifest lists it (no path outside the archive, no unlisted file or link, no hard link,
    device or fifo, nothing missing, twice or changed); else refused (exit 2, nothing written).
    The robot's new host key is shown beside the backup's and must be trusted first
    (`panther-ops trust ROBOT --replace` after checking it on the robot): never silently.
    Then, as one plan with diffs through the pipeline (confirm, backup on the robot, atomic
    writes, recreate, verify, roll back): every file of the backup under the robot user's
    home that differs (key pair, known_hosts, authorized_keys, config tree, mounted files,
    the deployed manager, compose.yaml byte-identical); then `apply` of the inventory's
    desired: block, and a doctor summary (which reports a default password still accepted).
    Onto a newer image of the same release line (2.1.1 -> 2.1.x) the new compose file and its
    image tags are kept and the backup's launch arguments, mounts and extra services are
    re-applied onto it; across release lines restore is refused (exit 2). --json: the restore's
    document, the apply's and the doctor's in it under "apply" and "doctor".

    \b
    Example:
      panther-ops reimage restore -r panther-01 --from backups/panther-01-20261124T031330Z.tar.gz
    """
    from panther_ops.cli.envelope import under
    from panther_ops.cli.views.status import print_doctor
    from panther_ops.core.apply.read import read_and_plan_desired
    from panther_ops.core.health.doctor import make_doctor_task
    from panther_ops.core.reimage.read import load_backup, read_and_plan_restore
    from panther_ops.errors import UsageError

    backup = load_backup(from_)
    inv = context.load(fleet.ctx)
    (target,) = inv.select([robot], [], False)[:1]
    context.check_keys(inv, [target])
    taken_from = backup.robot.get("name")
    if taken_from != target.name:
        raise UsageError(f"--from {from_}: the backup is of robot {taken_from!r}, not {target.name!r}")
    old_key = backup.robot.get("host_key") or "none recorded"
    if target.transport != "local":
        from panther_ops.core.fleet.plan_trust import trust_state
        from panther_ops.core.fleet.trust import read_offered_key

        trust = read_offered_key(inv, target)
        context.info(f"{target.name} offers host key {trust.key_type} {trust.fingerprint}; "
                     f"the backup recorded {old_key}")
        state = trust_state(trust.key_type, trust.fingerprint, trust.known)
        if state != "known":
            again = " --replace" if state == "changed" else ""
            raise UsageError(
                f"{target.name}: its host key {trust.fingerprint} is not trusted "
                f"({'changed' if again else 'new'}; the backup recorded {old_key}): refused, nothing was changed",
                hint=f"check it on the robot (ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub), "
                     f"then `panther-ops trust {target.name}{again}`",
            )
    code = fleet.change("reimage restore", lambda c: read_and_plan_restore(c, backup), on=(inv, [target]),
                        verb="Restore onto")
    if code != 0 or fleet.dry_run:
        return code
    if target.desired:
        with under("apply"):
            code = fleet.change("apply", read_and_plan_desired, on=(inv, [target]),
                                sudo_password=sudo_password(False))
    summary = context.run("doctor", inv, [target], make_doctor_task(password_check=target.transport != "local"),
                          json_out=fleet.json_out)
    with under("doctor"):
        fleet.show(summary, print_doctor)
    return code
