"""Simulated robot test lab of panther-ops (see docs/lab.md).

    from tests.lab import Lab
    with Lab(5, docker=True, images=["2.0", "2.1.1", "2.2"], jumps={"r05": "r01"}) as lab:
        lab.ssh("r01", "hostname")

CLI: python -m tests.lab up N [--docker] [--images 2.0,2.1.1,2.2] [--prefix P] [--jump]
"""

from __future__ import annotations

from ._sys import LabError
from .lab import Lab, Robot, missing_requirements
from .state import DEFAULT_BASE

__all__ = ["DEFAULT_BASE", "Lab", "LabError", "Robot", "missing_requirements"]
