"""Evaluate the text of a launch ``PythonExpression`` without running it.

Upstream builds file names and defaults with ``PythonExpression(["'", common_dir_path,
"/pkg' if '", common_dir_path, "' else '", FindPackageShare("pkg"), "'"])``. Once the parts
are substituted the text is a small Python expression; this module evaluates the subset
those expressions use (string and number constants, ``x if c else y``, ``and``/``or``/
``not``, comparisons, ``+``, dict/list/tuple literals and subscripts) over the ``ast``
of the text. Anything else (a call, a name, an attribute) is refused with
`Unevaluable`: nothing upstream wrote is executed.
"""

from __future__ import annotations

import ast
import operator
from collections.abc import Callable
from typing import Any

_COMPARE: dict[type[ast.cmpop], Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
    ast.Gt: operator.gt, ast.GtE: operator.ge, ast.In: lambda a, b: a in b, ast.NotIn: lambda a, b: a not in b,
}


class Unevaluable(ValueError):
    """The expression uses something outside the evaluated subset (or fails)."""


def evaluate(text: str) -> Any:
    """The value of ``text`` (a Python expression of the subset above).

    Raises:
        Unevaluable: a construct outside the subset, a syntax error or a failing operation.
    """
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise Unevaluable(f"not an expression: {text!r} ({exc.msg})") from None
    try:
        return _eval(tree.body)
    except (TypeError, KeyError, IndexError, ValueError, ZeroDivisionError) as exc:
        if isinstance(exc, Unevaluable):
            raise
        raise Unevaluable(f"{text!r}: {type(exc).__name__}: {exc}") from None


def _eval(node: ast.expr) -> Any:
    if isinstance(node, ast.Constant) and isinstance(node.value, (str, int, float, bool, type(None))):
        return node.value
    if isinstance(node, ast.IfExp):
        return _eval(node.body) if _eval(node.test) else _eval(node.orelse)
    if isinstance(node, ast.BoolOp):
        return _bool_op(node)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.Not, ast.USub)):
        operand = _eval(node.operand)
        return (not operand) if isinstance(node.op, ast.Not) else -operand
    if isinstance(node, ast.Compare):
        return _compare(node)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        return _eval(node.left) + _eval(node.right)
    if isinstance(node, ast.Dict):
        return {_eval(k): _eval(v) for k, v in zip(node.keys, node.values, strict=True) if k is not None}
    if isinstance(node, (ast.List, ast.Tuple)):
        return [_eval(e) for e in node.elts]
    if isinstance(node, ast.Subscript):
        return _eval(node.value)[_eval(node.slice)]
    raise Unevaluable(f"{ast.unparse(node)!r} is outside the evaluated subset")


def _bool_op(node: ast.BoolOp) -> Any:
    values = iter(node.values)
    result = _eval(next(values))
    for value in values:
        if isinstance(node.op, ast.And) and not result:
            return result
        if isinstance(node.op, ast.Or) and result:
            return result
        result = _eval(value)
    return result


def _compare(node: ast.Compare) -> bool:
    left = _eval(node.left)
    for op, right_node in zip(node.ops, node.comparators, strict=True):
        compare = _COMPARE.get(type(op))
        if compare is None:
            raise Unevaluable(f"comparison {type(op).__name__} is not evaluated")
        right = _eval(right_node)
        if not compare(left, right):
            return False
        left = right
    return True
