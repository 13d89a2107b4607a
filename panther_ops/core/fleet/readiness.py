"""When a recreated service is up: a pure decision over samples of its container's state.

The signals the real stack gives (checked against Husarion's releases):

- docker's container state: ``State.Status`` / ``State.Running``, ``State.Restarting``,
  ``State.ExitCode``, ``State.StartedAt`` and ``RestartCount``. Upstream's compose files run
  the driver with ``restart: always`` (husarion/husarion_ugv_ros@2.2.2 and @2.3.2:
  docker/demo/compose.hardware.yaml, husarion/panther-docker@2.1.1:demo/compose.minimal-setup.yaml),
  so a driver that crashes is started again by docker: it shows as ``Restarting``, a
  ``RestartCount`` above 0 (a recreated container starts at 0) or a new ``StartedAt``.
- A healthcheck: none. No upstream compose file (husarion_ugv_ros 2.2.x/2.3.x
  docker/demo/*.yaml, panther-docker 2.0.x/2.1.x demo/*.yaml) declares ``healthcheck:`` and
  no Dockerfile of the releases (docker/Dockerfile.hardware) declares ``HEALTHCHECK``, so
  ``State.Health`` is absent on a stock robot; when an operator's compose adds one, its
  status counts (``starting`` waits, ``unhealthy`` fails, ``healthy`` is ready at once).
- The stack's own readiness (controller_manager's log lines, a topic) is not read: it takes
  ``docker logs`` or a ROS 2 CLI in the container per robot, several seconds of a Python
  start in the real image, more than the window below.

A container is *ready* when every sample since the first one that saw it running shows it
running, not restarting, never restarted, with the same ``StartedAt``, over at least
``MIN_STABLE_S`` seconds (or healthy, where it has a healthcheck). The caller's ``--settle``
is the upper bound: a container still waiting then counts as up, as the fixed wait did.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

MIN_STABLE_S = 2.0
"""How long a recreated container must stay up, unrestarted, before it counts as ready.

From facts: the lab's driver stand-in (tests/lab/data/ros2-standin.sh) exits at once on a file
it refuses, and a crashed container is back in ``Restarting``/``RestartCount`` 1 within docker's
first restart delay (100 ms, doubling); the stand-in's exit at once follows the real launch,
which fails on a ``*_path:=`` file that does not exist (the stand-in's header states the rule it
copies). Two seconds are four polls of the
watch (``POLL_S``): a crash at start is seen several times over, and a robot whose driver is
up finishes 3 s before the default ``--settle`` of 5 s. A driver that dies later than this
(a slow launch on the Built-in Computer, a controller that fails after loading) is NOT caught:
the watch has ended. No release states how long the real launch takes to fail; where it may
take longer, a healthcheck in compose.yaml (honoured: ready only once healthy) is the signal
to add. Open question of issue #29 (docs/configuration.md)."""

POLL_S = 0.5
"""Seconds between two looks at the containers."""

READY, WAIT, FAILED = "ready", "wait", "failed"


def stable_for(settle_s: float) -> float:
    """How long a container that is ready was seen up: the window, bounded by ``--settle``."""
    return min(settle_s, MIN_STABLE_S)


@dataclass(frozen=True)
class Sample:
    """One look at a container (``docker inspect``), at ``at`` seconds of the client's clock."""

    at: float
    status: str
    restarting: bool = False
    restart_count: int = 0
    started_at: str = ""
    exit_code: int | None = None
    health: str | None = None


def sample_of(attrs: Mapping[str, Any], at: float) -> Sample:
    """The sample of a container's ``docker inspect`` document."""
    state = attrs.get("State", {}) or {}
    health = state.get("Health") or {}
    return Sample(at, str(state.get("Status", "?")), bool(state.get("Restarting")),
                  int(attrs.get("RestartCount", 0) or 0), str(state.get("StartedAt", "")),
                  state.get("ExitCode"), health.get("Status") if isinstance(health, Mapping) else None)


def _last_exit(samples: Sequence[Sample]) -> str:
    """The exit code of the crash a container restarted from, as far as the looks saw it: docker
    sets ``State.ExitCode`` to 0 when it starts the container again, so a running container's is
    not its crash's; a look that saw it exited or restarting holds the real one."""
    for s in reversed(samples):
        if s.status not in ("running", "created") or s.restarting:
            return f"exit code {s.exit_code}"
    return "running again: its exit code is gone once docker starts it; `driver logs` shows why it stopped"


def judge(samples: Sequence[Sample], min_stable_s: float = MIN_STABLE_S) -> tuple[str, str]:
    """``(READY|WAIT|FAILED, problem)`` for a container's samples, oldest first."""
    if not samples:
        return WAIT, ""
    last = samples[-1]
    if last.status not in ("running", "created") or last.restarting:
        return FAILED, f"container {last.status} (exit code {last.exit_code}) after recreate"
    if last.restart_count > 0:  # a recreated container starts at 0; restart: always hides crashes
        return FAILED, f"container restarted {last.restart_count} time(s) after recreate ({_last_exit(samples)})"
    if last.health == "unhealthy":
        return FAILED, "container unhealthy after recreate"
    running = [s for s in samples if s.status == "running"]
    if any(s.started_at != last.started_at for s in running):
        return FAILED, f"container started again after recreate ({_last_exit(samples)})"
    if last.status != "running":
        return WAIT, ""
    if last.health == "healthy":
        return READY, ""
    if last.health is None and last.at - running[0].at >= min_stable_s:
        return READY, ""
    return WAIT, ""
