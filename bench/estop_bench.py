"""`panther-ops estop trigger --all` on N lab robots (docker on, stacks 2.0/2.1.1/2.2 mixed):
the wall time of the whole command as an operator runs it (a fresh process, start to exit).

Issue #14's budget: 30 robots in <= 1.5 s. Run it on a quiet machine (the robots' sshd,
dockerd and containers share its cores), as root, from the repository root:

    sudo .venv/bin/python bench/estop_bench.py --robots 30 --repeat 5

Prints one JSON document: every run's wall time, the median, the best and the load average,
and the CPU seconds of each run: the command's own (its process, every thread) and the
machine's (every process: the command, the robots' sshd, shells, curl, dockerd,
containerd, runc and containers; on a busy machine other work too).

A paired comparison with another checkout (e.g. main: ``git worktree add /tmp/main main``):

    sudo .venv/bin/python bench/estop_bench.py --repeat 10 --against /tmp/main

runs this checkout and that one in turn on the same lab (alternating which goes first), so
both see the same load, and reports each one's numbers.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]


def machine_cpu_s() -> float:
    """CPU seconds the machine spent so far, every core and process (/proc/stat, idle and
    iowait left out)."""
    fields = Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]
    ticks = [int(x) for x in fields]
    busy = sum(ticks) - ticks[3] - (ticks[4] if len(ticks) > 4 else 0)
    return busy / os.sysconf("SC_CLK_TCK")


def children_cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def one_run(checkout: Path, inventory: Path, robots: int) -> dict[str, float]:
    """Reset every robot, then one timed `estop trigger --all --json` with ``checkout``'s code."""
    env = {**os.environ, "PYTHONPATH": str(checkout)}
    po = [sys.executable, "-m", "panther_ops.cli.app", "-i", str(inventory)]
    # cwd "/": `python -m` would put the current directory's panther_ops first
    subprocess.run([*po, "estop", "reset", "--all", "--yes", "--json"], check=True, capture_output=True, env=env,
                   cwd="/")
    cpu0, machine0, start = children_cpu_s(), machine_cpu_s(), time.monotonic()
    cp = subprocess.run([*po, "estop", "trigger", "--all", "--json"], check=False, capture_output=True, text=True,
                        env=env, cwd="/")
    wall = time.monotonic() - start
    cpu, machine = children_cpu_s() - cpu0, machine_cpu_s() - machine0
    doc = json.loads(cp.stdout)
    stopped = sum(r["outcome"] == "changed" for r in doc["robots"])
    if cp.returncode != 0 or stopped != robots:
        raise RuntimeError(f"{checkout}: {stopped}/{robots} e-stopped, exit {cp.returncode}\n{cp.stderr[-2000:]}")
    return {"wall_s": wall, "command_cpu_s": cpu, "machine_cpu_s": machine}


def summary(runs: list[dict[str, float]]) -> dict[str, Any]:
    walls = [r["wall_s"] for r in runs]
    return {
        "walls_s": [round(w, 3) for w in walls],
        "median_s": round(statistics.median(walls), 3),
        "best_s": round(min(walls), 3),
        "command_cpu_s_median": round(statistics.median(r["command_cpu_s"] for r in runs), 3),
        "machine_cpu_s_median": round(statistics.median(r["machine_cpu_s"] for r in runs), 3),
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robots", type=int, default=30)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--prefix", default=None, help="lab name (default: the first free)")
    ap.add_argument("--against", type=Path, default=None,
                    help="another checkout, run in turn with this one on the same lab (a paired comparison)")
    args = ap.parse_args()
    sys.path.insert(0, str(REPO))
    from tests.lab import Lab, missing_requirements

    why = missing_requirements(docker=True)
    if why:
        print("cannot run the lab here: " + "; ".join(why), file=sys.stderr)
        return 2
    checkouts = {"this": REPO}
    if args.against is not None:
        if not (args.against / "panther_ops" / "__init__.py").is_file():
            print(f"--against {args.against}: not a checkout of panther-ops (no panther_ops/__init__.py)",
                  file=sys.stderr)
            return 2
        checkouts["against"] = args.against.resolve()
    lab = Lab(args.robots, docker=True, images=("2.0", "2.1.1", "2.2"), prefix=args.prefix, ephemeral=True)
    runs: dict[str, list[dict[str, float]]] = {k: [] for k in checkouts}
    try:
        lab.up()
        for i in range(args.repeat):
            for name in list(checkouts)[:: 1 if i % 2 == 0 else -1]:
                runs[name].append(one_run(checkouts[name], lab.inventory_path, args.robots))
    except RuntimeError as exc:
        print(f"run failed: {exc}", file=sys.stderr)
        return 1
    finally:
        lab.down()
    doc: dict[str, Any] = {"robots": args.robots, **summary(runs["this"]),
                           "load_average_1m": round(os.getloadavg()[0], 2), "budget_s": 1.5}
    if args.against is not None:
        doc["against"] = {"checkout": str(checkouts["against"]), **summary(runs["against"])}
    print(json.dumps(doc, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
