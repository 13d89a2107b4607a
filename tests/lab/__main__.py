"""CLI of the simulated robot lab (run as root from the repository root).

    python -m tests.lab up N [--docker | --no-docker] [--images 2.0,2.1.1,2.2] [--prefix P]
                             [--jump [R:J]] [--rtt MS [--jitter MS] [--relay-trace]] [--rate 20mbit]
    python -m tests.lab down [--prefix P | --all]
    python -m tests.lab status [--prefix P] [--json]
    python -m tests.lab leftovers [--prefix P]
    python -m tests.lab bench [--sizes 5,30] [--repeat 3] [--docker] [--rtt MS] [--images ...]

`up` prints the paths of the inventory and ssh config it wrote (`inventory: PATH` and
`ssh_config: PATH` on stdout); progress goes to stderr.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from ._sys import LabError
from .lab import Lab, lab_memory, lab_status, robot_name
from .state import DEFAULT_BASE, LabState, all_states
from .teardown import bare_state, leftovers, orphans, teardown


def _jumps(specs: list[str] | None, n: int) -> dict[str, str]:
    out: dict[str, str] = {}
    for spec in specs or []:
        if spec == "auto":
            if n < 2:
                raise SystemExit("--jump needs at least 2 robots")
            out[robot_name(n, n)] = robot_name(1, n)
            continue
        hidden, sep, jump = spec.partition(":")
        if not sep:
            raise SystemExit(f"--jump {spec!r}: expected ROBOT:JUMP, e.g. r05:r01")
        out[hidden] = jump
    return out


def cmd_up(a: argparse.Namespace) -> int:
    images = [i for i in a.images.split(",") if i.strip()]
    t0 = time.monotonic()
    lab = Lab(
        a.n,
        docker=a.docker,
        images=images,
        prefix=a.prefix,
        jumps=_jumps(a.jump, a.n),
        base=a.base,
        log=(lambda m: print(m, file=sys.stderr)) if a.verbose else None,
        rtt_ms=a.rtt,
        jitter_ms=a.jitter,
        rate=a.rate,
        relay_trace=a.relay_trace,
    )
    lab.up()
    net = f", RTT {a.rtt:g} ms" if a.rtt else ""
    net += f" ± {a.jitter:g} ms" if a.jitter else ""
    net += f", {a.rate}" if a.rate else ""
    print(
        f"lab {lab.st.prefix}: {a.n} robots up in {time.monotonic() - t0:.2f} s "
        f"({lab.status()['subnet']}, docker {'on' if a.docker else 'off'}{net}); "
        f"ssh -F {lab.ssh_config_path} {lab.names[0]}",
        file=sys.stderr,
    )
    print(f"inventory: {lab.inventory_path}")
    print(f"ssh_config: {lab.ssh_config_path}")
    return 0


def _select(a: argparse.Namespace) -> list[LabState]:
    states = all_states(Path(a.base))
    if getattr(a, "all", False):
        return states
    if a.prefix:
        chosen = [s for s in states if s.prefix == a.prefix]
        if not chosen:
            raise LabError(f"no lab {a.prefix!r} under {a.base}")
        return chosen
    return states


def cmd_down(a: argparse.Namespace) -> int:
    base = Path(a.base)
    if a.prefix and not (base / a.prefix / "state.json").is_file():
        # state file gone (crash, removed by hand): what carries the lab's names
        if not leftovers(a.prefix, base):
            print(f"no lab {a.prefix!r} under {a.base}, and nothing of it left", file=sys.stderr)
            return 0
        t0 = time.monotonic()
        teardown(bare_state(a.prefix, base))
        print(f"lab {a.prefix} (no state file): removed by name in {time.monotonic() - t0:.2f} s", file=sys.stderr)
        return _report_leftovers(a.prefix, base)
    states = _select(a)
    if not a.prefix and not a.all and len(states) > 1:
        names = ", ".join(s.prefix for s in states)
        print(f"several labs are up ({names}): use --prefix P or --all", file=sys.stderr)
        return 2
    if not states:
        print("no lab to tear down", file=sys.stderr)
        return 0
    code = 0
    for st in states:
        t0 = time.monotonic()
        teardown(st)
        print(f"lab {st.prefix}: down in {time.monotonic() - t0:.2f} s", file=sys.stderr)
        code |= _report_leftovers(st.prefix, Path(a.base))
    return code


def _report_leftovers(prefix: str, base: Path) -> int:
    left = leftovers(prefix, base)
    for item in left:
        print(f"lab {prefix}: left behind: {item}", file=sys.stderr)
    return 1 if left else 0


def cmd_leftovers(a: argparse.Namespace) -> int:
    """What is left on this machine: of lab P, or of labs no live lab claims. Exit 1 if any."""
    base = Path(a.base)
    if a.prefix:
        if any(s.prefix == a.prefix for s in all_states(base)):
            print(f"lab {a.prefix} is up (python -m tests.lab down --prefix {a.prefix})")
            return 1
        found = {a.prefix: leftovers(a.prefix, base)}
    else:
        found = orphans(base)
    found = {p: items for p, items in found.items() if items}
    for prefix, items in sorted(found.items()):
        for item in items:
            print(f"{prefix}: {item}")
    if not found:
        print("nothing left behind")
    return 1 if found else 0


def cmd_status(a: argparse.Namespace) -> int:
    states = [{**lab_status(s), "memory": lab_memory(s)} for s in _select(a)]
    if a.json:
        print(json.dumps(states, indent=2))
        return 0
    if not states:
        print("no lab is up")
        return 0
    for s in states:
        owner = "" if s["owner"] is None else f", owner pid {s['owner']}"
        if s["owner"] is not None and not s["owner_alive"]:
            owner += " (gone: leftover)"
        net = f", RTT {s['rtt_ms']:g} ms" if s.get("rtt_ms") else ""
        print(f"lab {s['prefix']}: {s['subnet']}, docker {'on' if s['docker'] else 'off'}{net}{owner}")
        m = s["memory"]
        print(f"  processes: {m['processes']}, RSS {m['rss_mb']:.0f} MB, PSS {m['pss_mb']:.0f} MB "
              f"({m['pss_mb'] / max(1, len(s['robots'])):.2f} MB per robot)")
        print(f"  inventory: {s['inventory']}")
        print(f"  ssh_config: {s['ssh_config']}")
        for name, r in s["robots"].items():
            state = "running" if r["running"] else "DOWN"
            sshd = "sshd" if r["sshd"] else "no sshd"
            dockerd = "" if r["dockerd"] is None else (", dockerd" if r["dockerd"] else ", NO dockerd")
            jump = f" via {r['jump']}" if r["jump"] else ""
            print(f"  {name} {r['ip']}{jump} stack {r['image']}: {state}, {sshd}{dockerd}")
    return 0


def cmd_bench(a: argparse.Namespace) -> int:
    """Median wall time of Lab.up()/Lab.down() (in-process, interpreter start excluded)."""
    import statistics

    images = [i for i in a.images.split(",") if i.strip()]
    for n in (int(x) for x in a.sizes.split(",")):
        ups, downs = [], []
        for _ in range(a.repeat):
            lab = Lab(n, docker=a.docker, images=images, base=a.base, rtt_ms=a.rtt)
            lab.up()
            lab.down()
            ups.append(lab.timings["up"])
            downs.append(lab.timings["down"])
        print(
            f"N={n} docker={'on' if a.docker else 'off'} rtt={a.rtt:g} images={a.images}: "
            f"up {statistics.median(ups):.2f} s (min {min(ups):.2f}, max {max(ups):.2f}), "
            f"down {statistics.median(downs):.2f} s (min {min(downs):.2f}, max {max(downs):.2f}) "
            f"[{a.repeat} runs]"
        )
    return 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m tests.lab", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--base", default=str(DEFAULT_BASE), help="directory of the labs")
    sub = p.add_subparsers(dest="cmd", required=True)
    up = sub.add_parser("up", help="bring up N simulated robots")
    up.add_argument("n", type=int, help="robots: r01..r99, or r001.. for 100 and more (up to 960)")
    up.add_argument("--docker", action=argparse.BooleanOptionalAction, default=False,
                    help="dockerd + compose stack per robot (default: --no-docker, sshd and files only)")
    up.add_argument("--images", default="2.1.1", help="stack versions cycled: 2.0,2.1.1,2.2")
    up.add_argument("--prefix", help="lab name (default: first free plN)")
    up.add_argument(
        "--jump",
        nargs="?",
        const="auto",
        action="append",
        metavar="ROBOT:JUMP",
        help="robot reachable only through JUMP (no value: the last robot behind r01)",
    )
    up.add_argument("--rtt", type=float, default=0.0, metavar="MS",
                    help="round trip to each robot's sshd through a delay relay (default 0: none)")
    up.add_argument("--jitter", type=float, default=0.0, metavar="MS", help="± jitter of each one-way delay")
    up.add_argument("--rate", metavar="RATE", help="tc tbf bandwidth limit per robot, e.g. 20mbit")
    up.add_argument("--relay-trace", action="store_true",
                    help="with --rtt: each relay logs every chunk to <robot dir>/relay.trace")
    up.add_argument("-v", "--verbose", action="store_true")
    up.set_defaults(func=cmd_up)
    down = sub.add_parser("down", help="tear a lab down (only what it owns)")
    down.add_argument("--prefix")
    down.add_argument("--all", action="store_true", help="every lab under --base")
    down.set_defaults(func=cmd_down)
    status = sub.add_parser("status", help="labs and their robots")
    status.add_argument("--prefix")
    status.add_argument("--json", action="store_true")
    status.set_defaults(func=cmd_status)
    left = sub.add_parser("leftovers", help="what is left of lab P, or of labs no live lab claims (exit 1 if any)")
    left.add_argument("--prefix")
    left.set_defaults(func=cmd_leftovers)
    bench = sub.add_parser("bench", help="measure up/down times")
    bench.add_argument("--sizes", default="5,30")
    bench.add_argument("--repeat", type=int, default=3)
    bench.add_argument("--docker", action=argparse.BooleanOptionalAction, default=False)
    bench.add_argument("--rtt", type=float, default=0.0, metavar="MS")
    bench.add_argument("--images", default="2.0,2.1.1,2.2")
    bench.set_defaults(func=cmd_bench)
    a = p.parse_args(argv)
    try:
        return int(a.func(a))
    except (LabError, ValueError) as exc:
        print(f"lab: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
