"""Run the manager's Lights and Safety trees at 10 Hz on the simulated Panther, in real time.

Reports CPU use (% of one core, during the run), resident memory and tick times.
Target: <= 1 % CPU and <= 60 MB RSS.

    .venv/bin/python bench/manager_bench.py [--seconds 30] [--trees python|xml] [--scenario PATH]
"""

from __future__ import annotations

import argparse
import itertools
import resource
import statistics
import sys
import time
from pathlib import Path

from panther_ops.manager.clock import MonotonicClock
from panther_ops.manager.paths import SCENARIOS, default_lights_project, default_safety_project
from panther_ops.manager.runtime import TreeSource
from panther_ops.manager.sim import Simulation, load_scenario


def rss_mb() -> float:
    """Current resident set size (VmRSS) in MB."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--trees", choices=("python", "xml"), default="python")
    parser.add_argument("--scenario", type=Path, default=SCENARIOS / "charging.yaml")
    args = parser.parse_args()

    trees = (TreeSource.projects(str(default_lights_project()), str(default_safety_project()))
             if args.trees == "xml" else TreeSource.python())
    scenario = load_scenario(args.scenario)
    simulation = Simulation(scenario, trees=trees, clock=MonotonicClock())
    setup_rss = rss_mb()

    wall0, cpu0 = time.monotonic(), time.process_time()
    tick_times: list[float] = []
    cpu_marks: list[float] = []
    calls = 0
    for snapshot in simulation.run(args.seconds):
        tick_times.append(time.perf_counter())
        cpu_marks.append(time.process_time())
        calls += len(snapshot.calls)
    wall, cpu = time.monotonic() - wall0, time.process_time() - cpu0
    half = len(cpu_marks) // 2
    steady = ((cpu_marks[-1] - cpu_marks[half]) / (tick_times[-1] - tick_times[half])
              if len(cpu_marks) > 20 else float("nan"))
    simulation.close()

    periods = [b - a for a, b in itertools.pairwise(tick_times)]
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"scenario          {scenario.name} ({args.trees} trees)")
    print(f"ticks             {len(tick_times)} in {wall:.1f} s "
          f"(mean period {statistics.mean(periods) * 1000:.1f} ms)" if periods else "")
    print(f"service calls     {calls}")
    print(f"CPU               {cpu / wall * 100:.2f} % of one core ({cpu * 1000:.0f} ms)")
    print(f"CPU per tick      {cpu / max(1, len(tick_times)) * 1000:.3f} ms "
          f"(second half alone: {steady * 100:.2f} % of one core)")
    print(f"RSS               {rss_mb():.1f} MB now, {peak:.1f} MB peak ({setup_rss:.1f} MB after setup)")
    ok = cpu / wall <= 0.01 and peak <= 60
    print(f"target (<= 1 % CPU, <= 60 MB RSS): {'met' if ok else 'NOT met'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
