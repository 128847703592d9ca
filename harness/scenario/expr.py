"""Time expressions: the durations a vector's steps are timed by.

A step's windows and delays are written as expressions over the timers (``"CDT + 2*CHAR"``,
``"0.8*ADT"``, ``"150ms"``) so that one vector serves every timer setting. This module
parses them (once per text, under a lock, with their dimensions checked: a duration is
never added to a bare factor), evaluates them in an environment of timer values, and
lists the names they use. It knows no procedure: the names a vector may use are
:data:`BASE_TIME_NAMES` plus its procedure's (checked by :mod:`ptpcert.scenario.load`);
their values come from :func:`ptpcert.scenario.vector.timer_env`.
"""

from __future__ import annotations

import ast
import functools
import re
import threading
from dataclasses import dataclass

#: Names every time expression may use: CHAR is one character time of the profile's frame;
#: STARTUP is how long the harness waits for a freshly started IUT (set by the runner). Each
#: procedure adds the names of its timers (Procedure.time_names); a name is written in
#: capitals, and a vector may use only its procedure's (checked when it is loaded or built).
BASE_TIME_NAMES = ("CHAR", "STARTUP")
_TIME_NAME = re.compile(r"^[A-Z][A-Z0-9_]*$")

_UNIT = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?)\s*(ms|s)\b")


class ExprError(ValueError):
    """A time expression is malformed; the message quotes it and says what is wrong."""


#: CPython 3.11's ast module keeps its recursion count in one shared state: two threads
#: parsing at once (run --jobs) can fail with "SystemError: AST constructor recursion depth
#: mismatch" (python/cpython gh-106905). Each text is parsed once, under this lock; the
#: trees are only read afterwards.
_PARSE_LOCK = threading.Lock()


@functools.lru_cache(maxsize=4096)
def parse_expr(text: str) -> ast.AST:
    """The syntax tree of the time expression ``text``, its units rewritten as calls and its
    dimensions checked (:class:`ExprError` when it is not a valid duration or factor). Each
    text is parsed once (cached) and under ``_PARSE_LOCK``."""
    src = _UNIT.sub(lambda m: f"_{m.group(2)}({m.group(1)})", text)
    try:
        with _PARSE_LOCK:
            tree = ast.parse(src, mode="eval").body
    except SyntaxError:
        raise ExprError(f"{text!r} is not an arithmetic expression") from None
    _dimension(tree, text)
    return tree


@dataclass(frozen=True)
class Expr:
    """A duration such as ``"CDT + 2*CHAR"``, ``"0.8*ADT"`` or ``"150ms"``. Bare numbers
    are factors; a constant duration needs a unit (``ms`` or ``s``)."""

    text: str

    def __post_init__(self) -> None:
        self._tree()  # validate now

    def _tree(self) -> ast.AST:
        return parse_expr(self.text)

    def eval(self, env: dict[str, float]) -> float:
        return _eval(self._tree(), env)

    def __str__(self) -> str:
        return self.text


def _dimension(node: ast.AST, text: str) -> bool:
    """Check the expression and return True when it is a duration (False: a factor)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return False
    if isinstance(node, ast.Name):
        if not _TIME_NAME.match(node.id):
            raise ExprError(f"{text!r}: {node.id!r} is not a timer name (timers are named in capitals, "
                            "e.g. CDT, ADT, CHAR)")
        return True
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("_ms", "_s"):
        return True
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        return _dimension(node.operand, text)
    if isinstance(node, ast.BinOp):
        left, right = _dimension(node.left, text), _dimension(node.right, text)
        if isinstance(node.op, (ast.Add, ast.Sub)):
            if left != right:
                raise ExprError(f"{text!r}: adds a duration and a bare number (write 5ms, not 5)")
            return left
        if isinstance(node.op, ast.Mult):
            if left and right:
                raise ExprError(f"{text!r}: multiplies two durations")
            return left or right
        if isinstance(node.op, ast.Div):
            if right:
                raise ExprError(f"{text!r}: divides by a duration")
            return left
    raise ExprError(f"{text!r}: only + - * /, numbers, units ms/s and timer names are allowed")


def is_duration(expr: Expr) -> bool:
    """True when ``expr`` is a duration (``"CDT + 5ms"``), False when it is a bare factor
    (``"0.8"``)."""
    return _dimension(expr._tree(), expr.text)


def _eval(node: ast.AST, env: dict[str, float]) -> float:
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.Name):
        return env[node.id]
    if isinstance(node, ast.Call):
        v = float(node.args[0].value)
        return v / 1000.0 if node.func.id == "_ms" else v
    if isinstance(node, ast.UnaryOp):
        v = _eval(node.operand, env)
        return -v if isinstance(node.op, ast.USub) else v
    a, b = _eval(node.left, env), _eval(node.right, env)
    op = node.op
    return a + b if isinstance(op, ast.Add) else a - b if isinstance(op, ast.Sub) else a * b if isinstance(op, ast.Mult) else a / b


def names_in(expr: Expr) -> set[str]:
    """The timer names ``expr`` uses (``{"CDT", "CHAR"}`` for ``"CDT + 2*CHAR"``)."""
    return {n.id for n in ast.walk(expr._tree()) if isinstance(n, ast.Name) and not n.id.startswith("_")}


#: the zero duration, the default of every time field of a step
ZERO = Expr("0")
