"""`panther-ops estop trigger --all` on N lab robots (docker on, stacks 2.0/2.1.1/2.2 mixed):
the wall time of the whole command as an operator runs it (a fresh process, start to exit).

Issue #14's budget: 30 robots in <= 1.5 s. Run it on a quiet machine (the robots' sshd,
dockerd and containers share its cores), as root, from the repository root:

    sudo .venv/bin/python bench/estop_bench.py --robots 30 --repeat 5

Prints one JSON document: every run's wall time, the median, the best and the load average.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robots", type=int, default=30)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--prefix", default=None, help="lab name (default: the first free)")
    args = ap.parse_args()
    sys.path.insert(0, str(REPO))
    from tests.lab import Lab, missing_requirements

    why = missing_requirements(docker=True)
    if why:
        print("cannot run the lab here: " + "; ".join(why), file=sys.stderr)
        return 2
    lab = Lab(args.robots, docker=True, images=("2.0", "2.1.1", "2.2"), prefix=args.prefix, ephemeral=True)
    walls: list[float] = []
    try:
        lab.up()
        po = [sys.executable, "-m", "panther_ops.cli.app", "-i", str(lab.inventory_path)]
        for _ in range(args.repeat):
            subprocess.run([*po, "estop", "reset", "--all", "--yes", "--json"], check=True, capture_output=True)
            start = time.monotonic()
            cp = subprocess.run([*po, "estop", "trigger", "--all", "--json"], check=False, capture_output=True,
                                text=True)
            walls.append(time.monotonic() - start)
            doc = json.loads(cp.stdout)
            stopped = sum(r["outcome"] == "changed" for r in doc["robots"])
            if cp.returncode != 0 or stopped != args.robots:
                print(f"run failed: {stopped}/{args.robots} e-stopped, exit {cp.returncode}", file=sys.stderr)
                return 1
    finally:
        lab.down()
    print(json.dumps({"robots": args.robots, "walls_s": [round(w, 3) for w in walls],
                      "median_s": round(statistics.median(walls), 3), "best_s": round(min(walls), 3),
                      "load_average_1m": round(os.getloadavg()[0], 2), "budget_s": 1.5}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
