"""pytest fixtures of the simulated robot lab (tests/lab; see docs/lab.md).

Fixtures:
    lab          session: 5 robots, docker on, stacks 2.0/2.1.1/2.2 cycling, r05 behind r01.
    lab_factory  session: make(n, docker=..., images=..., jumps=...) -> Lab for other shapes
                 (same shape -> same lab; all torn down at the end of the session).
    lab_ready    function: only checks that a lab (without docker) can run here, for tests
                 that build and tear down their own `Lab`.

Tests using these fixtures get the `lab` marker. Without root or a required binary they
are skipped with the reason; with the environment variable CI=true they fail instead.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path

import pytest

_ROOT = Path(__file__).resolve().parents[1]
if str(_ROOT) not in sys.path:  # `pytest` without `python -m`: make `tests.lab` importable
    sys.path.insert(0, str(_ROOT))

from tests.lab import Lab, missing_requirements  # noqa: E402

pytest_plugins = ["tests.fixtures"]  # the demo fleet fixtures every feature folder uses

LAB_FIXTURES = frozenset({"lab", "lab_factory", "lab_ready"})
DEFAULT_IMAGES = ("2.0", "2.1.1", "2.2")

LabFactory = Callable[..., Lab]


def _ci() -> bool:
    return os.environ.get("CI", "").strip().lower() == "true"


def lab_unavailable(docker: bool = True) -> str | None:
    """Why the lab cannot run here, or None."""
    why = missing_requirements(docker)
    return "; ".join(why) if why else None


def skip_or_fail(reason: str) -> None:
    """Skip a lab test, or fail it when CI=true (lab tests must run in CI)."""
    msg = f"simulated robot lab unavailable: {reason}"
    if _ci():
        pytest.fail(f"{msg} (CI=true: lab tests must not be skipped)", pytrace=False)
    pytest.skip(msg)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        if LAB_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.lab)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Iterator[None]:
    outcome = yield
    rep = outcome.get_result()  # type: ignore[attr-defined]
    if _ci() and rep.skipped and item.get_closest_marker("lab") is not None and not hasattr(rep, "wasxfail"):
        reason = rep.longrepr[2] if isinstance(rep.longrepr, tuple) else str(rep.longrepr)
        rep.outcome = "failed"
        rep.longrepr = f"lab test skipped under CI=true (lab tests must run): {reason}"


@pytest.fixture(scope="session")
def lab_factory() -> Iterator[LabFactory]:
    """make(n=5, docker=True, images=("2.0", "2.1.1", "2.2"), jumps=None, rtt_ms=0, jitter_ms=0) -> Lab.

    ``rtt_ms`` > 0: each robot's sshd behind a delay relay (a realistic network, docs/lab.md)."""
    labs: dict[tuple[object, ...], Lab] = {}

    def make(
        n: int = 5,
        *,
        docker: bool = True,
        images: Sequence[str] = DEFAULT_IMAGES,
        jumps: Mapping[str, str] | None = None,
        rtt_ms: float = 0.0,
        jitter_ms: float = 0.0,
    ) -> Lab:
        key = (n, docker, tuple(images), tuple(sorted((jumps or {}).items())), rtt_ms, jitter_ms)
        cached = labs.get(key)
        if cached is not None and cached.state is not None:
            return cached
        reason = lab_unavailable(docker)
        if reason:
            skip_or_fail(reason)
        lab = Lab(n, docker=docker, images=images, jumps=jumps, ephemeral=True, rtt_ms=rtt_ms, jitter_ms=jitter_ms)
        labs[key] = lab
        lab.up()
        return lab

    yield make
    errors = []
    for lab in labs.values():
        try:
            lab.down()
        except Exception as exc:  # keep tearing the others down
            errors.append(exc)
    if errors:
        raise errors[0]


@pytest.fixture
def lab_ready() -> None:
    """Skip (fail under CI=true) unless a lab without docker can run on this machine."""
    reason = lab_unavailable(docker=False)
    if reason:
        skip_or_fail(reason)


@pytest.fixture(scope="session")
def lab(lab_factory: LabFactory) -> Lab:
    """5 robots with docker, stacks 2.0.4/2.1.1/2.2.2 cycling; r05 reachable only via r01."""
    return lab_factory(5, docker=True, images=DEFAULT_IMAGES, jumps={"r05": "r01"})


@pytest.fixture
def jazzy_lab(lab_factory: LabFactory) -> Lab:
    """2 robots with docker: r01 on husarion_ugv 2.2.2, r02 on 2.3.2 (ROS 2 Jazzy)."""
    return lab_factory(2, docker=True, images=("2.2", "2.3.2"))
