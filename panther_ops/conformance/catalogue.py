"""The launch-argument catalogue (core/kinds/arg_catalogue.py) against what a release declares.

The catalogue writes a default in its own notation; `catalogue_default` evaluates it in the
same contexts as upstream's (`launch.CONTEXTS`):

- ``$(find pkg)/rel``: the image's file (the same in every context);
- ``<common_dir_path>/dir/rel (common_dir_path set; else $(find pkg)/rel)``:
  ``<common_dir_path>/dir/rel`` when the ``~/config`` tree is mounted (``common_dir_path``
  set), else the image's ``$(find pkg)/rel``;
- ``{name}``: the value of argument ``name`` (the context's, else the catalogue default);
- a default by robot model (`ArgSpec.model_defaults`): the one of the context's ``robot_model``
  (else the catalogue's default model);
- ``[_with_gps]``: present when ``fuse_gps`` is true (`OPTIONAL`);
- anything else: the literal value.

`compare` then checks, for one argument: the kind (bool / choice / free text), the
choices (a choice argument: the same set; a bool: the words panther-ops writes are among
upstream's), the default in every context, where it is read from (image or ``~/config``
tree), and, for a default taken from an environment variable, that the catalogue's
description names it.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from panther_ops.conformance.launch import CONTEXTS
from panther_ops.core.kinds.arg_catalogue import ArgSpec, ArgType
from panther_ops.core.robot.launch_args import args_for, bool_word
from panther_ops.core.stack import Stack

_TREE = re.compile(r"^<common_dir_path>/(?P<tree>\S+) \(common_dir_path set; else (?P<image>\$\(find \w+\)/\S+)\)$")
OPTIONAL = {"_with_gps": "fuse_gps"}
"""Optional segments of the catalogue's notation: ``[segment]`` -> the argument that turns it on."""
_BOOL = frozenset({"true", "false"})


def declared(stack: Stack) -> dict[str, ArgSpec]:
    """The catalogue's arguments on ``stack``, by the name the stack declares."""
    return {s.name_for(stack): s for s in args_for(stack)}


def catalogue_source(spec: ArgSpec, stack: Stack) -> str:
    text = spec.default_for(stack)
    if _TREE.match(text):
        return "tree"
    return "image" if text.startswith("$(find ") else "literal"


def catalogue_default(spec: ArgSpec, stack: Stack, context: Mapping[str, str], _seen: frozenset[str] = frozenset(),
                      ) -> str:
    """The catalogue's default of ``spec`` in ``context`` (see the module docstring)."""
    by_name = declared(stack)

    def value(name: str) -> str:
        if name in context:
            return context[name]
        other = by_name.get(name)
        if other is None or name in _seen:
            return "{" + name + "}"
        return catalogue_default(other, stack, context, _seen | {spec.key})

    model = value("robot_model") if spec.model_dependent(stack) else None
    text = spec.default_for(stack, model)
    m = _TREE.match(text)
    if m:
        common = context.get("common_dir_path", "")
        text = f"{common}/{m['tree']}" if common else m["image"]

    def optional(o: re.Match[str]) -> str:
        switch = OPTIONAL.get(o[1])
        return o[1] if switch is not None and value(switch).lower() == "true" else ("" if switch else o[0])

    text = re.sub(r"\[(\w+)\]", optional, text)
    return re.sub(r"\{(\w+)\}", lambda o: value(o[1]), text)


def _kind(spec: ArgSpec) -> str:
    if spec.type is ArgType.BOOL:
        return "bool"
    return "choice" if spec.type is ArgType.CHOICE else "text"


def _same(kind: str, a: str, b: str) -> bool:
    if kind == "bool" and a.lower() in _BOOL and b.lower() in _BOOL:
        return a.lower() == b.lower()
    return a == b


def compare(row: Mapping[str, Any], spec: ArgSpec, stack: Stack) -> list[str]:
    """What the catalogue says differently from upstream's ``row`` (empty: they agree)."""
    problems: list[str] = []
    kind = _kind(spec)
    if kind != row["kind"]:
        problems.append(f"kind: upstream {row['kind']}, catalogue {spec.type.value}")
    choices = row.get("choices")
    if kind == "choice" and choices is not None:
        ours = set(spec.choices_for(stack))
        if ours != set(choices):
            missing, extra = sorted(set(choices) - ours), sorted(ours - set(choices))
            problems.append("choices: " + "; ".join(
                p for p in (f"upstream also accepts {', '.join(missing)}" if missing else "",
                            f"upstream refuses {', '.join(extra)}" if extra else "") if p))
    if kind == "bool" and choices is not None:
        refused = [w for w in (bool_word(stack, True), bool_word(stack, False)) if w not in choices]
        if refused:
            problems.append(f"panther-ops writes {'/'.join(refused)}; upstream accepts only {', '.join(choices)}")
    candidates = [(row["default"], row["source"], "")] + [
        (o["default"], o["source"], f" (as {o['file']} declares it)") for o in row.get("other_defaults", [])]
    best: list[str] | None = None
    for defaults, source, where in candidates:
        found = _default_problems(spec, stack, kind, defaults, source, where)
        if best is None or len(found) < len(best):
            best = found
    problems.extend(best or [])
    envs = row["source"][4:].split(",") if row["source"].startswith("env:") else []
    unnamed = [e for e in envs if e not in spec.description]
    if unnamed:
        problems.append(f"default: upstream reads env {', '.join(unnamed)}; the catalogue does not say so")
    return problems


def _default_problems(spec: ArgSpec, stack: Stack, kind: str, defaults: Mapping[str, str | None], source: str,
                      where: str) -> list[str]:
    problems: list[str] = []
    ours_source = catalogue_source(spec, stack)
    if source in ("tree", "image") and ours_source in ("tree", "image") and source != ours_source:
        words = {"tree": "the ~/config tree (common_dir_path), else the image", "image": "the image"}
        problems.append(f"read from: upstream {words[source]}{where}; catalogue {words[ours_source]}")
    for ctx_name, ctx in CONTEXTS.items():
        upstream = defaults.get(ctx_name)
        ours = catalogue_default(spec, stack, {k: v for k, v in ctx.items() if k != spec.key})
        if upstream is None:
            problems.append(f"default ({ctx_name}): upstream's is not evaluated by this tool")
        elif not _same(kind, upstream, ours):
            problems.append(f"default ({ctx_name}{_describe(ctx, spec.key)}): upstream {upstream!r}{where}, "
                            f"catalogue {ours!r}")
    return problems


def _describe(ctx: Mapping[str, str], own: str) -> str:
    shown = ", ".join(f"{k}={v}" for k, v in ctx.items() if k != own)
    return f": {shown}" if shown else ""
