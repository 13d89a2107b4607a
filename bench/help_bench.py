"""Benchmark: wall time of `panther-ops --help` (start-up cost of the CLI).

    .venv/bin/python bench/help_bench.py [--runs 21]

Prints the median and spread; the budget is a median <= 0.15 s (docs/performance.md).
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--runs", type=int, default=21)
    args = ap.parse_args()
    exe = shutil.which("panther-ops", path=str(Path(sys.executable).parent)) or "panther-ops"
    # bytecode as an installed package has it (an editable install under PYTHONDONTWRITEBYTECODE has none)
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(Path(__file__).resolve().parents[1] / "panther_ops")],
                   check=True, stdout=subprocess.DEVNULL)
    times = []
    for _ in range(args.runs):
        t = time.perf_counter()
        subprocess.run([exe, "--help"], stdout=subprocess.DEVNULL, check=True)
        times.append(time.perf_counter() - t)
    times.sort()
    print(f"panther-ops --help: median {statistics.median(times):.3f} s, min {times[0]:.3f} s, "
          f"max {times[-1]:.3f} s over {args.runs} runs ({sys.version.split()[0]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
