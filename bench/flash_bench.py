"""Card flashing throughput: `panther-ops reimage flash` (write + read-back verify) against
`dd bs=4M oflag=direct` followed by `cmp`, the same image on the same loop device.

Needs root (losetup). The loop device and its backing file are made here, in a temporary
directory under --dir, and detached/removed at the end; no other block device is touched.

    sudo .venv/bin/python bench/flash_bench.py                      # 256 MiB, 5 runs each
    sudo .venv/bin/python bench/flash_bench.py --size-mib 1024 --repeat 3 --json

Three kinds of loop device: `card` (as `direct`, both commands run in a block-I/O cgroup
limiting the loop device to an SD card's speed in a USB 3 reader: --card-write-mbs 40,
--card-read-mbs 90 MB/s), `direct` (losetup --direct-io=on: the backing file is written and
read with O_DIRECT, so the data goes to this machine's disk) and `cached` (the default loop
device: the backing file stays in the page cache; the work is CPU-bound).
Throughput is image bytes / wall time of the whole command (both phases); the ratio is
dd+cmp's time / panther-ops's time (>= 1: panther-ops is as fast or faster).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import lzma
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

MIB = 1 << 20


def sh(*argv: str) -> str:
    return subprocess.run(argv, check=True, capture_output=True, text=True).stdout


def timed(cmd: str, cgroup: Path | None = None) -> float:
    """Wall time of ``cmd`` (in ``cgroup``'s block-I/O limits when given)."""
    argv = ["sh", "-c", cmd]
    if cgroup is not None:
        argv = ["sh", "-c", f'echo $$ > {shlex.quote(str(cgroup / "cgroup.procs"))} && exec sh -c "$0"', cmd]
    start = time.monotonic()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return time.monotonic() - start


def card_cgroup(dev: str, write_bps: int, read_bps: int) -> Path:
    """A cgroup limiting ``dev`` to a card's bandwidth (cgroup v1 blkio throttle, else v2 io.max)."""
    st = os.stat(dev)
    devno = f"{os.major(st.st_rdev)}:{os.minor(st.st_rdev)}"
    v1 = Path("/sys/fs/cgroup/blkio")
    if (v1 / "blkio.throttle.write_bps_device").exists():
        cg = v1 / f"flash-bench-{os.getpid()}"
        cg.mkdir()
        (cg / "blkio.throttle.write_bps_device").write_text(f"{devno} {write_bps}\n")
        (cg / "blkio.throttle.read_bps_device").write_text(f"{devno} {read_bps}\n")
        return cg
    for root in (Path("/sys/fs/cgroup"), Path("/sys/fs/cgroup/unified")):
        if "io" in (root / "cgroup.controllers").read_text().split() if (root / "cgroup.controllers").exists() else ():
            (root / "cgroup.subtree_control").write_text("+io\n")
            cg = root / f"flash-bench-{os.getpid()}"
            cg.mkdir()
            (cg / "io.max").write_text(f"{devno} rbps={read_bps} wbps={write_bps}\n")
            return cg
    raise SystemExit("flash_bench: no block-I/O cgroup controller here for the `card` mode (--modes direct,cached)")


def make_image(path: Path, size: int) -> None:
    """Half random bytes (incompressible, as file contents), half zeros (free space), in 1 MiB runs."""
    with open(path, "wb") as fh:
        for i in range(size // MIB):
            fh.write(os.urandom(MIB) if i % 2 else bytes(MIB))
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    Path(f"{path}.sha256").write_text(f"{digest}  {path.name}\n")


def make_card_image(path: Path, size: int, used_mib: int) -> None:
    """A card image as a Panther's: a DOS table, a 64 MiB FAT32 boot partition, an ext4 root
    holding ``used_mib`` MiB of files (random bytes) in the rest; the rest is free space."""
    tmp = path.parent / "card-tree"
    (tmp / "usr").mkdir(parents=True)
    for i in range(max(1, used_mib // 8)):
        (tmp / "usr" / f"f{i}").write_bytes(os.urandom(8 * MIB))
    with open(path, "wb") as fh:
        fh.truncate(size)
    subprocess.run(["sfdisk", "--quiet", str(path)], check=True, capture_output=True,
                   input=b"label: dos\nstart=2048, size=131072, type=c\nstart=133120, type=83\n")
    subprocess.run(["mkfs.vfat", "-F", "32", "--offset", "2048", str(path), "65536"], check=True, capture_output=True)
    subprocess.run(["mkfs.ext4", "-q", "-F", "-E", f"offset={133120 * 512}", "-d", str(tmp), str(path),
                    f"{(size // 512 - 133120) // 2}k"], check=True, capture_output=True)
    shutil.rmtree(tmp)
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    Path(f"{path}.sha256").write_text(f"{digest}  {path.name}\n")


def panther_ops() -> str:
    exe = Path(sys.executable).with_name("panther-ops")
    return str(exe) if exe.exists() else shutil.which("panther-ops") or "panther-ops"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size-mib", type=int, default=256)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--dir", default="/var/tmp", help="where the image and the loop device's backing file go")
    ap.add_argument("--modes", default="card,direct,cached")
    ap.add_argument("--card-write-mbs", type=float, default=40.0)
    ap.add_argument("--card-read-mbs", type=float, default=90.0)
    ap.add_argument("--xz", action="store_true", help="also the .img.xz (xz -dc | dd ..., xz -dc | cmp)")
    ap.add_argument("--card-image", action="store_true",
                    help="also a sparse card image (FAT boot + ext4 root with --used-mib of files): block-mapped "
                         "panther-ops flash against dd + cmp and bmaptool copy (with its .bmap from bmaptool create)")
    ap.add_argument("--used-mib", type=int, default=64)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    if os.geteuid() != 0:
        print("flash_bench: needs root (losetup)", file=sys.stderr)
        return 2
    size = args.size_mib * MIB
    rows = []
    with tempfile.TemporaryDirectory(prefix="flash-bench-", dir=args.dir) as tmp:
        img = Path(tmp) / "bench.img"
        make_image(img, size)
        xz = Path(tmp) / "bench.img.xz"
        if args.xz:
            xz.write_bytes(lzma.compress(img.read_bytes(), preset=1))
            Path(f"{xz}.sha256").write_text(f"{hashlib.sha256(xz.read_bytes()).hexdigest()}  {xz.name}\n")
        card = Path(tmp) / "card.img"
        if args.card_image:
            make_card_image(card, size, args.used_mib)
            subprocess.run(["bmaptool", "create", "-o", f"{tmp}/card.bmaptool.bmap", str(card)], check=True)
        backing = Path(tmp) / "card.bin"
        with open(backing, "wb") as fh:
            fh.truncate(size + 64 * MIB)
        po = panther_ops()
        for mode in args.modes.split(","):
            dev = sh("losetup", "--find", "--show", f"--direct-io={'off' if mode == 'cached' else 'on'}",
                     str(backing)).strip()
            cg = None
            try:
                if mode == "card":
                    cg = card_cgroup(dev, int(args.card_write_mbs * 1e6), int(args.card_read_mbs * 1e6))
                q = shlex.quote
                cases = [("img", f"{q(po)} reimage flash {q(str(img))} --device {dev} --yes",
                          f"dd if={q(str(img))} of={dev} bs=4M oflag=direct status=none && "
                          f"cmp -n {size} {q(str(img))} {dev}")]
                if args.card_image:
                    theirs = f"{tmp}/card.bmaptool.bmap"
                    cases.append(("card.img (mapped)", f"{q(po)} reimage flash {q(str(card))} --device {dev} --yes",
                                  f"dd if={q(str(card))} of={dev} bs=4M oflag=direct status=none && "
                                  f"cmp -n {size} {q(str(card))} {dev}"))
                    cases.append(("card.img vs bmaptool", f"{q(po)} reimage flash {q(str(card))} --device {dev} --yes",
                                  f"bmaptool -q copy --bmap {q(theirs)} {q(str(card))} {dev}"))
                if args.xz:
                    cases.append(("img.xz", f"{q(po)} reimage flash {q(str(xz))} --device {dev} --yes",
                                  f"xz -dc {q(str(xz))} | dd of={dev} bs=4M iflag=fullblock oflag=direct "
                                  f"status=none && xz -dc {q(str(xz))} | cmp -n {size} - {dev}"))
                for kind, ours, theirs in cases:
                    t_po, t_dd = [], []
                    for i in range(args.repeat):  # alternate which goes first
                        for which in ((0, 1) if i % 2 == 0 else (1, 0)):
                            (t_po if which == 0 else t_dd).append(timed(ours if which == 0 else theirs, cg))
                    po_s, dd_s = statistics.median(t_po), statistics.median(t_dd)
                    rows.append({"mode": mode, "image": kind, "mib": args.size_mib, "repeat": args.repeat,
                                 "panther_ops_s": round(po_s, 3), "dd_cmp_s": round(dd_s, 3),
                                 "panther_ops_mib_s": round(size / MIB / po_s, 1),
                                 "dd_cmp_mib_s": round(size / MIB / dd_s, 1), "ratio": round(dd_s / po_s, 2),
                                 "panther_ops_cmd": ours, "dd_cmp_cmd": theirs,
                                 "panther_ops_runs": [round(t, 3) for t in t_po],
                                 "dd_cmp_runs": [round(t, 3) for t in t_dd]})
            finally:
                subprocess.run(["losetup", "-d", dev], check=False)
                if cg is not None:
                    cg.rmdir()
    if args.json:
        print(json.dumps({"rows": rows}, indent=2))
        return 0
    print("| loop device | image | size | panther-ops flash+verify | dd + cmp (bmaptool copy on its row) "
          "| ratio (their time / ours) |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['mode']} | .{r['image']} | {r['mib']} MiB | {r['panther_ops_s']:.2f} s "
              f"({r['panther_ops_mib_s']:.0f} MiB/s) | {r['dd_cmp_s']:.2f} s ({r['dd_cmp_mib_s']:.0f} MiB/s) "
              f"| {r['ratio']:.2f}x |")
    for r in rows:
        print(f"\n{r['mode']} .{r['image']}: panther-ops runs {r['panther_ops_runs']}, dd+cmp runs {r['dd_cmp_runs']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
