"""Where the shipped templates live: package data ``panther_ops/templates`` when installed
from a wheel (setup.py maps the repository's ``templates/`` there), else, in a checkout or
an editable install, the repository's ``templates/`` beside the package."""

from __future__ import annotations

from functools import cache
from pathlib import Path


@cache
def templates_dir() -> Path:
    from importlib.resources import files

    package = files("panther_ops")
    if isinstance(package, Path):  # an installed or checked-out package: real files
        for candidate in (package / "templates", package.parent / "templates"):
            if candidate.is_dir():
                return candidate
    raise FileNotFoundError(f"panther-ops templates not found in {package} (broken installation)")


def template_path(*parts: str) -> Path:
    """Path of a shipped template, e.g. ``template_path("compose", "panther-2.1.1.yaml")``."""
    return templates_dir().joinpath(*parts)


class TemplateNotFound(FileNotFoundError):
    """A template file panther-ops should ship is missing (broken installation)."""


def template_file(*parts: str) -> Path:
    """Like `template_path`, but the file must exist.

    Raises:
        TemplateNotFound: no such file in the templates directory.
    """
    path = template_path(*parts)
    if not path.is_file():
        raise TemplateNotFound(f"template {'/'.join(parts)} not found in {templates_dir()}")
    return path


def read_template(*parts: str) -> str:
    """Text (UTF-8) of a template file, e.g. ``read_template("config", "panther-2.1", ...)``."""
    return template_file(*parts).read_text(encoding="utf-8")
