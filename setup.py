"""The templates ship inside the package: ``templates/`` (kept at the top of the repository)
is installed as ``panther_ops/templates`` (found at run time with importlib.resources, see
panther_ops/core/fleet/templates.py). Everything else is in pyproject.toml."""

from __future__ import annotations

from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py


class BuildWithTemplates(build_py):  # type: ignore[misc]
    """build_py, plus the templates as package data of ``panther_ops``.

    An editable install reads them from the checkout instead (the same files).
    """

    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        source = Path(__file__).resolve().parent / "templates"
        self.copy_tree(str(source), str(Path(self.build_lib) / "panther_ops" / "templates"))


setup(cmdclass={"build_py": BuildWithTemplates})
