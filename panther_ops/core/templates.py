"""Where the shipped templates live: beside the package when installed, else the repo root."""

from __future__ import annotations

from functools import cache
from pathlib import Path


@cache
def templates_dir() -> Path:
    here = Path(__file__).resolve().parent.parent  # panther_ops/
    for candidate in (here / "templates", here.parent / "templates"):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError("panther-ops templates/ directory not found (broken installation)")


def template_path(*parts: str) -> Path:
    """Path of a shipped template, e.g. ``template_path("compose", "panther-2.1.1.yaml")``."""
    return templates_dir().joinpath(*parts)
