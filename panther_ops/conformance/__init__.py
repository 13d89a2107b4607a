"""Conformance with Husarion's releases: the tool behind scripts/conformance.py and docs/conformance.md.

panther-ops must accept the robot's own files and know its launch arguments as the release
declares them. This package checks that against the upstream repositories themselves
(husarion/panther_ros 2.0-2.1, husarion/husarion_ugv_ros 2.2+, husarion/panther-docker for
the compose files), at a tag, read from a local git mirror. It is a development tool: nothing
in the product imports it (an import-linter contract says so).

Two halves:

*Online* (needs the mirror; `upstream`, `launch`, `distil`): read a release with ``git``
(`upstream.GitRelease`), parse bringup and the launch files of the same repository it
includes with ``ast`` (`launch`: nothing upstream wrote is run; ``PythonExpression`` texts
are evaluated by `pyexpr`, a safe subset), run each kind's validator on the release's
default files laid out as in the package share (`validate`), and distil all of it into the
release's *table*, ``tests/golden/upstream/<tag>.json`` (`distil`).

*Offline* (the tables and the project only; `checks`, `catalogue`, `report`): compare the
tables with the project's validators, launch-argument catalogue and templates, and render
docs/conformance.md. tests/conformance/test_conformance.py runs this half in CI.

What a table keeps, and why it is not a copy of upstream's files: per launch argument, the
facts the catalogue must state (name, declaring files, kind, choices, default in three
contexts, where it is read from); per upstream default file, its sha256, the key paths of
its content with each value's type and a 16-hex-digit hash of the value (`digest`), never
the value, and for a file of a panther-ops kind the validator's verdict when the table was
made; the files the image copies into the ``~/config`` tree. A template is compared with
upstream's file through the hashes, which tell which key differs and how (missing, extra,
``int`` for ``float``, another value) without holding the values. When a template equals
the upstream file, the offline check runs the validator again on the template (the same
parsed content); otherwise the verdict recorded by the last online run stands, so a change
to a validator is followed by re-running the script.

Known failures are listed with the finding that fixes them in `known`; a template's
deliberate difference from upstream is listed with its reason in `reasons`.
"""
