"""Vectors: timed two-party transcripts, their schema, loading and writing.

A vector file (TOML, one case per file) says who the IUT is, which parameters apply, what
the tester does and what the IUT must do, step by step, with time windows written in terms
of the timers (``CDT``, ``ADT``...) so that one vector serves every timer setting. The
schema is documented in ``vectors/README.md``; :func:`load_vector` reports a broken file
with its path, the field and what is wrong.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import re
import threading
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

from .model.hexbytes import parse_hex
from .procedure import ProcedureError
from .registry import by_id, by_name
from .rules import for_procedure

# ------------------------------------------------------------------ time expressions
#: Names every time expression may use: CHAR is one character time of the profile's frame;
#: STARTUP is how long the harness waits for a freshly started IUT (set by the runner). Each
#: procedure adds the names of its timers (Procedure.time_names); a name is written in
#: capitals, and a vector may use only its procedure's (checked when it is loaded or built).
BASE_TIME_NAMES = ("CHAR", "STARTUP")
_TIME_NAME = re.compile(r"^[A-Z][A-Z0-9_]*$")

_UNIT = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?)\s*(ms|s)\b")


class ExprError(ValueError):
    pass


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


def timer_env(vector: "Vector", params: Any = None, startup: float = 0.0) -> dict[str, float]:
    """Values of the names in ``vector``'s time expressions, with ``params`` (default: the
    vector's own)."""
    env = dict(vector.proc.timer_env(vector.params if params is None else params))
    env["STARTUP"] = startup
    return env


def names_in(expr: "Expr") -> set[str]:
    return {n.id for n in ast.walk(expr._tree()) if isinstance(n, ast.Name) and not n.id.startswith("_")}


ZERO = Expr("0")

# ------------------------------------------------------------------ steps
#: the step kinds of every procedure; a procedure adds its own (Procedure.macro_steps), which
#: it expands into these before a run
STEP_KINDS = ("send", "send_error", "break", "wait", "expect", "silence", "partner")
#: the step kinds whose value is bytes (the others' is a duration)
DATA_KINDS = ("send", "send_error", "expect")
SINCE = ("previous", "sent", "mark")
GRADES = ("pass", "non-strict", "informational")
#: the keys a step of each of STEP_KINDS may have besides its kind (a procedure's own step
#: kinds name theirs, :attr:`ptpcert.procedure.MacroStep.keys`)
STEP_KEYS = {
    "send": {"at", "gap", "note", "mark"},
    "send_error": {"at", "note", "mark"},
    "break": {"at", "note", "mark"},
    "wait": {"note", "mark"},
    "silence": {"note", "mark"},
    "partner": {"note"},
    "expect": {"after", "within", "max_gap", "partial", "optional", "absent_grade", "or",
               "or_grade", "since", "note", "mark", "resume", "skip"},
}


@dataclass(frozen=True)
class Step:
    """One step of a transcript.

    * ``send``: the tester sends ``data`` (``at``: delay before the first byte after the
      reference point; ``gap``: pause between characters on top of the character time).
    * ``send_error``: each byte of ``data`` arrives at the IUT with a parity/framing error.
    * ``break``: the tester holds the line in the space state for ``duration``.
    * ``wait``: the tester does nothing for ``duration``; what arrives is kept for later.
    * ``expect``: the IUT sends ``data``; its first byte arrives in [``after``, ``within``]
      after the reference point and each further byte within ``max_gap`` of the previous
      one. ``partial``: the IUT may stop anywhere in ``data`` (it was interrupted);
      ``optional``: it may send nothing (graded ``absent_grade``); ``alternatives``: other
      byte strings accepted in the same window (graded ``alt_grade``). ``resume``: the
      bytes continue those of the last ``partial`` step with the same data: only what it
      did not receive is expected (an IUT that was stopped and goes on).
    * ``silence``: the IUT sends nothing for ``duration``.
    * a procedure's own kind (:attr:`ptpcert.procedure.Procedure.macro_steps`): a whole
      exchange with the payload ``data`` (e.g. the tester delivers it as a conforming sender,
      from ``at`` after the reference point, or receives it from the IUT within a window),
      expanded into the steps above by :func:`expand`.
    * ``partner``: for at most ``duration``, the tester plays a conforming station with the
      vector's ``tester_params``, answering whatever the IUT sends, until both are idle and
      the line is quiet (used where the exact bytes depend on timing, e.g. a configuration
      mismatch).

    The reference point of a step is the end of the previous one: after the last byte sent,
    the last byte received, or the end of a wait, silence or break. An expect step with
    ``since = "sent"`` measures from the end of the tester's last byte instead, and with
    ``since = "mark"`` from the end of the last step marked ``mark = true``.
    """

    kind: str
    data: bytes = b""
    at: Expr = ZERO
    gap: Expr = ZERO
    duration: Expr = ZERO
    after: Expr = ZERO
    within: Expr = ZERO
    max_gap: Expr = Expr("CDT")
    partial: bool = False
    optional: bool = False
    absent_grade: str = "pass"
    alternatives: tuple[bytes, ...] = ()
    alt_grade: str = "pass"
    since: str = "previous"
    mark: bool = False
    resume: bool = False
    note: str = ""
    #: an optional expect that sees nothing skips this many of the following steps (the
    #: rest of a macro step it begins, e.g. the tester's replies to a block not sent)
    skip: int = 0

    @property
    def is_macro(self) -> bool:
        """A procedure's own step kind (expanded before a run)."""
        return self.kind not in STEP_KINDS

    def to_toml(self) -> dict[str, Any]:
        d: dict[str, Any] = {}
        if self.kind in DATA_KINDS or self.is_macro:
            d[self.kind] = vector_hex(self.data)
        else:
            d[self.kind] = str(self.duration)
        if self.at != ZERO and (self.kind in ("send", "send_error", "break") or self.is_macro):
            d["at"] = str(self.at)
        if self.kind == "send" and self.gap != ZERO:
            d["gap"] = str(self.gap)
        if self.kind == "expect" or (self.is_macro and self.within != ZERO):
            if self.since != "previous":
                d["since"] = self.since
            if self.after != ZERO:
                d["after"] = str(self.after)
            d["within"] = str(self.within)
            if self.kind == "expect" and self.max_gap != Expr("CDT"):
                d["max_gap"] = str(self.max_gap)
            if self.partial:
                d["partial"] = True
            if self.optional:
                d["optional"] = True
                if self.absent_grade != "pass":
                    d["absent_grade"] = self.absent_grade
            if self.skip:
                d["skip"] = self.skip
            if self.alternatives:
                d["or"] = [vector_hex(a) for a in self.alternatives]
                if self.alt_grade != "pass":
                    d["or_grade"] = self.alt_grade
            if self.resume:
                d["resume"] = True
        if self.mark:
            d["mark"] = True
        if self.note:
            d["note"] = self.note
        return d


# ------------------------------------------------------------------ vectors
IUT_ROLES = ("receiver", "sender", "both", "idle")
STARTS = ("idle", "power-on")
#: capabilities any vector may require; a procedure adds its own (Procedure.requirements)
BASE_REQUIREMENTS = ("line_conditions", "restart")


@dataclass(frozen=True)
class StatusSpec:
    """Expected STATUS events: each entry of ``required`` is a set of alternatives of which
    at least one must be raised; anything raised must be in ``allowed``. Each entry of
    ``soft`` is what a conforming IUT raises under the reading the model takes of an open
    point of the manual: missing, it grades the case informational, never failed."""

    required: tuple[frozenset[int], ...] = ()
    optional: frozenset[int] = frozenset()
    soft: tuple[frozenset[int], ...] = ()

    @property
    def allowed(self) -> frozenset[int]:
        out = set(self.optional)
        for group in self.required + self.soft:
            out |= group
        return frozenset(out)

    def soft_missing(self, observed: Iterable[int]) -> list[str]:
        """The ``soft`` entries none of whose codes was raised."""
        seen = set(observed)
        return [" or ".join(f"16#{c:04X}" for c in sorted(g)) for g in self.soft if not g & seen]

    def judge(self, observed: Iterable[int]) -> list[str]:
        """Problems with ``observed`` (empty: acceptable)."""
        seen = list(observed)
        problems = []
        for group in self.required:
            if not group & set(seen):
                problems.append("missing " + " or ".join(f"16#{c:04X}" for c in sorted(group)))
        extra = sorted({c for c in seen if c not in self.allowed})
        if extra:
            problems.append("unexpected " + ", ".join(f"16#{c:04X}" for c in extra))
        return problems

    def to_toml(self) -> list[str]:
        return ["|".join(f"16#{c:04X}" for c in sorted(g)) for g in self.required]

    def describe(self) -> str:
        req = self.to_toml()
        s = ", ".join(req) if req else "none"
        if self.soft:
            s += " (by the model's reading of an open point also " + ", ".join(
                "|".join(f"16#{c:04X}" for c in sorted(g)) for g in self.soft) + ")"
        if self.optional:
            s += " (may also raise " + ", ".join(f"16#{c:04X}" for c in sorted(self.optional)) + ")"
        return s


@dataclass(frozen=True)
class Expected:
    iut_status: StatusSpec = StatusSpec()
    tester_status: StatusSpec = StatusSpec()
    delivered: tuple[bytes, ...] = ()   # blocks the IUT delivers to its application, in order
    sent: tuple[bytes, ...] = ()        # blocks the IUT's send jobs complete (DONE), in order
    echo_after: tuple[bytes, ...] = ()  # blocks an echo IUT sends back after the steps


@dataclass(frozen=True)
class Vector:
    id: str
    title: str
    reference: str
    rule: str
    group: str
    iut_role: str
    params: Any                          # the procedure's parameters
    steps: tuple[Step, ...]
    expected: Expected = Expected()
    start: str = "idle"
    requires: frozenset[str] = frozenset()
    readings: tuple[str, ...] = ()       # ambiguities (A-numbers) the vector depends on
    provenance: str = ""                 # [S] stated, [F] figure, [I] inferred, [O] open point
    notes: str = ""
    source: str = ""                     # file the vector was loaded from
    #: parameters the vector's bytes depend on; a profile must match them to run it
    binds: tuple[str, ...] = ("procedure",)
    #: tester-side parameters when they differ from the IUT's (e.g. configuration mismatch)
    tester_params: Any | None = None
    #: the case works close to a timer's edge: a failure is confirmed by a second run
    timing_sensitive: bool = False
    #: the procedure (its id, :attr:`ptpcert.procedure.Procedure.id`); see ptpcert.registry
    procedure: str = field(kw_only=True)
    #: the IUT setup the case needs (a name of [iut.setups] and its arguments), or None
    setup: tuple[str, dict[str, Any]] | None = None
    #: procedure-specific data (e.g. RK 512 requests and results), a TOML table
    extra: dict[str, Any] = field(default_factory=dict)
    #: ids of the manual's rules the vector checks (the procedure's catalogue, ptpcert.rules)
    rules: tuple[str, ...] = ()

    @property
    def proc(self):
        """The procedure's description (:class:`ptpcert.procedure.Procedure`)."""
        return by_id(self.procedure)

    @property
    def needs(self) -> frozenset[str]:
        """Capabilities the vector needs: declared plus those its steps imply."""
        out = set(self.requires)
        if any(s.kind in ("send_error", "break") for s in self.steps):
            out.add("line_conditions")
        if self.start == "power-on":
            out.add("restart")
        return frozenset(out)

    def digest(self) -> str:
        return hashlib.sha256(repr(self.to_toml()).encode()).hexdigest()[:12]

    # -------------------------------------------------------------- writing
    def to_toml(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "id": self.id, "title": self.title, "reference": self.reference, "rule": self.rule,
            "group": self.group, "iut_role": self.iut_role,
        }
        if self.start != "idle":
            d["start"] = self.start
        if self.requires:
            d["requires"] = sorted(self.requires)
        if self.rules:
            d["rules"] = list(self.rules)
        if self.readings:
            d["readings"] = list(self.readings)
        if self.provenance:
            d["provenance"] = self.provenance
        if self.notes:
            d["notes"] = self.notes
        if self.binds != ("procedure",):
            d["binds"] = list(self.binds)
        if self.timing_sensitive:
            d["timing_sensitive"] = True
        params = self.proc.params_table(self.params)
        if params.get("procedure") not in self.proc.names:   # the parameters do not name it
            d["procedure"] = self.proc.names[0]
        if self.setup is not None:
            name, args = self.setup
            d["setup"] = {"name": name, **args} if args else name
        d["params"] = params
        if self.tester_params is not None:
            d["tester_params"] = self.proc.params_table(self.tester_params)
        if self.extra:
            d["extra"] = dict(self.extra)
        e = self.expected
        exp: dict[str, Any] = {"iut_status": e.iut_status.to_toml()}
        if e.iut_status.optional:
            exp["iut_status_optional"] = [f"16#{c:04X}" for c in sorted(e.iut_status.optional)]
        if e.iut_status.soft:
            exp["iut_status_soft"] = ["|".join(f"16#{c:04X}" for c in sorted(g)) for g in e.iut_status.soft]
        exp["tester_status"] = e.tester_status.to_toml()
        if e.tester_status.optional:
            exp["tester_status_optional"] = [f"16#{c:04X}" for c in sorted(e.tester_status.optional)]
        for name in ("delivered", "sent", "echo_after"):
            v = getattr(e, name)
            if v:
                exp[name] = [vector_hex(x) for x in v]
        d["expected"] = exp
        d["steps"] = [s.to_toml() for s in self.steps]
        return d


class VectorError(ValueError):
    """A vector file is broken. ``path``, ``field`` and the message say where and what."""

    def __init__(self, path: str, fld: str, message: str):
        self.path, self.field, self.message = path, fld, message
        super().__init__(f"{path}: {fld}: {message}" if fld else f"{path}: {message}")


_ID = re.compile(r"^[A-Z0-9][A-Z0-9.\-_]*$")
_TOP_KEYS = {"id", "title", "reference", "rule", "rules", "group", "iut_role", "start", "requires",
             "readings", "provenance", "notes", "binds", "params", "tester_params", "expected", "steps",
             "timing_sensitive", "procedure", "setup", "extra"}
_EXPECTED_KEYS = {"iut_status", "iut_status_optional", "iut_status_soft", "tester_status",
                  "tester_status_optional", "delivered", "sent", "echo_after"}


def load_vector(path: str | Path) -> Vector:
    path = Path(path)
    try:
        text = path.read_text("utf-8")
    except UnicodeDecodeError:
        raise VectorError(str(path), "", "is not UTF-8 text (save the vector as UTF-8)") from None
    except OSError as exc:
        raise VectorError(str(path), "", f"cannot be read: {exc.strerror}") from None
    return load_vector_text(text, str(path))


def load_vector_text(text: str, source: str) -> Vector:
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise VectorError(source, "", f"not valid TOML: {exc}") from None
    return vector_from_dict(raw, source)


def vector_from_dict(raw: dict[str, Any], source: str = "<vector>") -> Vector:
    def err(fld: str, msg: str) -> VectorError:
        return VectorError(source, fld, msg)

    if not isinstance(raw, dict):
        raise err("", "must be a TOML table of keys")
    unknown = sorted(set(raw) - _TOP_KEYS)
    if unknown:
        raise err(unknown[0], "unknown key (known: " + ", ".join(sorted(_TOP_KEYS)) + ")")
    for key in ("id", "title", "reference", "rule", "group", "iut_role", "params", "steps"):
        if key not in raw:
            raise err(key, "missing (required)")
    for key in ("id", "title", "reference", "rule"):
        if not isinstance(raw[key], str) or not raw[key].strip():
            raise err(key, "must be a non-empty string")
    if not _ID.match(raw["id"]):
        raise err("id", f"{raw['id']!r}: use upper-case letters, digits, '.', '-' and '_'")
    # the procedure: named at the top, else by the parameters (a procedure whose parameters
    # name its variant, e.g. procedure = "3964R")
    pname = raw.get("procedure")
    if pname is None and isinstance(raw["params"], dict):
        pname = raw["params"].get("procedure")
    if pname is None:
        raise err("procedure", "missing: name the procedure at the top (procedure = \"...\") or in [params]")
    try:
        proc = by_name(pname)
    except ProcedureError as exc:
        raise err("procedure", str(exc).split(": ", 1)[1]) from None
    if raw["group"] not in proc.groups:
        raise err("group", f"{raw['group']!r}: allowed values are {', '.join(proc.groups)}")
    if raw["iut_role"] not in IUT_ROLES:
        raise err("iut_role", f"{raw['iut_role']!r}: allowed values are {', '.join(IUT_ROLES)}")
    start = raw.get("start", "idle")
    if start not in STARTS:
        raise err("start", f"{start!r}: allowed values are {', '.join(STARTS)}")
    known_req = BASE_REQUIREMENTS + tuple(proc.requirements)
    requires = raw.get("requires", [])
    if not isinstance(requires, list) or any(r not in known_req for r in requires):
        raise err("requires", f"{requires!r}: a list of {', '.join(known_req)}")
    params = _params(proc, raw["params"], "params", err)
    tester_params = _params(proc, raw["tester_params"], "tester_params", err) if "tester_params" in raw else None
    names = proc.param_names()
    binds = raw.get("binds", ["procedure"] if "procedure" in names else [])
    if not isinstance(binds, list) or any(b not in names for b in binds):
        raise err("binds", f"{binds!r}: a list of parameter names ({', '.join(sorted(names))})")
    if not isinstance(raw["steps"], list) or not raw["steps"]:
        raise err("steps", "must be a non-empty list of steps")
    steps = tuple(_step(s, f"steps[{i}]", err, proc) for i, s in enumerate(raw["steps"]))
    expected = _expected(raw.get("expected", {}), err)
    readings = raw.get("readings", [])
    if not isinstance(readings, list) or any(r not in proc.readings for r in readings):
        bad = next((r for r in readings if r not in proc.readings), readings) if isinstance(readings, list) else readings
        raise err("readings", f"{bad!r}: a list of the manual's open points this procedure has readings for "
                  f"({proc.readings[0]}..{proc.readings[-1]})" if proc.readings else "this procedure has no readings")
    rules = raw.get("rules", [])
    if not isinstance(rules, list) or any(not isinstance(r, str) for r in rules):
        raise err("rules", "a list of rule ids such as [\"3964.RX.BCC-CHECK\"] (ptpcert rules lists them)")
    unknown_rules = for_procedure(proc).unknown(rules)
    if unknown_rules:
        raise err("rules", f"{unknown_rules[0]!r} is not a rule of the {proc.title} catalogue "
                  "(ptpcert rules lists them)")
    for key in ("provenance", "notes"):
        if key in raw and not isinstance(raw[key], str):
            raise err(key, "must be a string")
    if not isinstance(raw.get("timing_sensitive", False), bool):
        raise err("timing_sensitive", "must be true or false")
    setup = _setup(raw.get("setup"), proc, err)
    extra = raw.get("extra", {})
    if not isinstance(extra, dict):
        raise err("extra", "must be a table")
    v = Vector(
        id=raw["id"], title=raw["title"].strip(), reference=raw["reference"].strip(),
        rule=raw["rule"].strip(), group=raw["group"], iut_role=raw["iut_role"], params=params,
        steps=steps, expected=expected, start=start, requires=frozenset(requires),
        readings=tuple(readings), provenance=raw.get("provenance", ""),
        notes=raw.get("notes", "").strip(), source=source, binds=tuple(binds),
        tester_params=tester_params, timing_sensitive=raw.get("timing_sensitive", False),
        procedure=proc.id, setup=setup, extra=dict(extra), rules=tuple(rules),
    )
    check_times(v, err)
    return v


def _setup(raw: Any, proc, err) -> tuple[str, dict[str, Any]] | None:
    if raw is None:
        return None
    if isinstance(raw, str):
        name, args = raw, {}
    elif isinstance(raw, dict) and isinstance(raw.get("name"), str):
        name, args = raw["name"], {k: v for k, v in raw.items() if k != "name"}
    else:
        raise err("setup", "a setup name, or a table { name = \"...\", argument = value, ... }")
    if name not in proc.setups:
        raise err("setup", f"{name!r}: known setups of {proc.title}: {', '.join(proc.setups) or 'none'}")
    return name, args


def check_times(v: Vector, err) -> None:
    """Every time expression of ``v`` names only what its procedure knows, and evaluates to
    a finite number for the vector's parameters (a window that cannot be computed would
    otherwise be found only at run time, or pass silently as NaN)."""
    import math

    allowed = set(BASE_TIME_NAMES) | set(v.proc.time_names)
    env = timer_env(v)
    for i, s in enumerate(v.steps):
        for key in ("at", "gap", "duration", "after", "within", "max_gap"):
            e = getattr(s, key)
            bad = names_in(e) - allowed
            if bad:
                raise err(f"steps[{i}].{key}", f"{e.text!r}: unknown name {sorted(bad)[0]!r}, not a timer of "
                          f"{v.proc.title} (allowed: {', '.join(sorted(allowed))})")
            try:
                value = e.eval(env)
            except (ZeroDivisionError, OverflowError):
                raise err(f"steps[{i}].{key}", f"{e.text!r} cannot be computed (division by zero or overflow)") from None
            if not math.isfinite(value):
                raise err(f"steps[{i}].{key}", f"{e.text!r} is not a finite duration")
            if key in ("duration", "gap", "max_gap") and value < 0:
                raise err(f"steps[{i}].{key}", f"{e.text!r} is negative")
            if key == "within" and value < 0:
                raise err(f"steps[{i}].{key}", f"{e.text!r}: a window cannot close before the reference point")
            if key == "within" and value < getattr(s, "after").eval(env):
                raise err(f"steps[{i}].{key}", f"{e.text!r} closes the window before 'after' opens it")


def _params(proc, raw: Any, fld: str, err):
    if not isinstance(raw, dict):
        raise err(fld, "must be a table of parameters")
    try:
        return proc.params_from_table(raw)
    except ProcedureError as exc:
        raise err(f"{fld}.{exc.key}" if exc.key else fld, str(exc).split(": ", 1)[-1]) from None


_REPEAT = re.compile(r"^([0-9A-Fa-f]{2})\*(\d+)$")
#: the longest run one ``XX*N`` token may stand for (2 x 1024 bytes and a frame's few more:
#: the longest frame a procedure of the CP 341 puts on the line, its data doubled), and the
#: most one step may hold
MAX_REPEAT = 2 * 1024 + 8
MAX_STEP_BYTES = 64 * 1024


def parse_vector_hex(text: str) -> bytes:
    """Hex bytes as in the figures (``"02 10"``), where a token ``XX*N`` stands for the
    byte XX repeated N times (``"41*1024"``)."""
    out = bytearray()
    for token in text.split():
        m = _REPEAT.match(token)
        if m:
            n = int(m.group(2))
            if n > MAX_REPEAT:
                raise ValueError(f"{token!r}: at most {MAX_REPEAT} repetitions (the longest block on the line)")
            out += bytes([int(m.group(1), 16)]) * n
        elif re.fullmatch(r"[A-Za-z_]\w*", token) and not re.fullmatch(r"[0-9A-Fa-f]+", token):
            raise ValueError(f"{token!r}: names are not allowed here; write the bytes in hex "
                             "(e.g. 02 for STX, 10 for DLE)")
        else:
            out += parse_hex(token)
        if len(out) > MAX_STEP_BYTES:
            raise ValueError(f"more than {MAX_STEP_BYTES} bytes in one step")
    return bytes(out)


def vector_hex(data: bytes) -> str:
    """Inverse of :func:`parse_vector_hex`, compressing runs of 8 or more equal bytes."""
    parts, i = [], 0
    while i < len(data):
        j = i
        while j < len(data) and data[j] == data[i]:
            j += 1
        n = j - i
        parts.append(f"{data[i]:02X}*{n}" if n >= 8 else " ".join([f"{data[i]:02X}"] * n))
        i = j
    return " ".join(parts)


def brief_hex(data: bytes, limit: int = 24) -> str:
    """Bytes for messages: as :func:`vector_hex`, long ones cut to their head and tail."""
    text = vector_hex(data)
    toks = text.split()
    if len(toks) <= limit:
        return text
    return " ".join(toks[: limit - 6]) + " … " + " ".join(toks[-4:]) + f" ({len(data)} bytes)"


def _hex(value: Any, fld: str, err) -> bytes:
    if not isinstance(value, str):
        raise err(fld, "must be a string of hex bytes such as \"02 10\"")
    try:
        return parse_vector_hex(value)
    except ValueError as exc:
        raise err(fld, str(exc)) from None


def _expr(value: Any, fld: str, err, duration: bool = True) -> Expr:
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0:
        value = "0"
    if not isinstance(value, str):
        raise err(fld, "must be a time expression in quotes, such as \"CDT + 2*CHAR\"")
    try:
        e = Expr(value)
    except ExprError as exc:
        raise err(fld, str(exc)) from None
    if duration and value.strip() != "0" and not is_duration(e):
        raise err(fld, f"{value!r} is a bare number; give a unit (ms, s) or a timer name")
    return e


def _step(raw: Any, fld: str, err, proc=None) -> Step:
    if not isinstance(raw, dict):
        raise err(fld, "must be a table such as { send = \"02\" }")
    macros = dict(proc.macro_steps) if proc is not None else {}
    known = STEP_KINDS + tuple(macros)
    kinds = [k for k in known if k in raw]
    if len(kinds) != 1:
        raise err(fld, f"must have exactly one of {', '.join(known)} (has {', '.join(kinds) or 'none'})")
    kind = kinds[0]
    macro = macros.get(kind)
    allowed = macro.keys if macro is not None else STEP_KEYS[kind]
    extra = sorted(set(raw) - {kind} - allowed)
    if extra:
        raise err(f"{fld}.{extra[0]}", f"not allowed in a {kind} step (allowed: {', '.join(sorted(allowed))})")
    kw: dict[str, Any] = {"kind": kind, "note": raw.get("note", "")}
    if kind in DATA_KINDS or macro is not None:
        kw["data"] = _hex(raw[kind], f"{fld}.{kind}", err)
        if macro is None and not kw["data"]:
            raise err(f"{fld}.{kind}", "must not be empty")
        if macro is not None and not 1 <= len(kw["data"]) <= macro.max_data:
            raise err(f"{fld}.{kind}", f"a payload of 1..{macro.max_data} bytes")
    else:
        kw["duration"] = _expr(raw[kind], f"{fld}.{kind}", err)
    for key in ("at", "gap", "after", "within", "max_gap"):
        if key in raw:
            kw[key] = _expr(raw[key], f"{fld}.{key}", err)
    if "mark" in raw:
        if not isinstance(raw["mark"], bool):
            raise err(f"{fld}.mark", "must be true or false")
        kw["mark"] = raw["mark"]
    for key, text in (macro.defaults.items() if macro is not None else ()):
        if key not in raw:
            kw[key] = Expr(text)
    if kind == "expect" or "within" in allowed:
        if kind == "expect" and "within" not in raw:
            raise err(f"{fld}.within", "an expect step needs a window: within = \"...\"")
        if "skip" in raw:
            if not isinstance(raw["skip"], int) or isinstance(raw["skip"], bool) or raw["skip"] < 0:
                raise err(f"{fld}.skip", "the number of following steps skipped when the optional bytes do not come")
            kw["skip"] = raw["skip"]
        for key in ("partial", "optional", "resume"):
            if key in raw:
                if not isinstance(raw[key], bool):
                    raise err(f"{fld}.{key}", "must be true or false")
                kw[key] = raw[key]
        for key, target in (("absent_grade", "absent_grade"), ("or_grade", "alt_grade")):
            if key in raw:
                if raw[key] not in GRADES:
                    raise err(f"{fld}.{key}", f"{raw[key]!r}: allowed values are {', '.join(GRADES)}")
                kw[target] = raw[key]
        if "since" in raw:
            if raw["since"] not in SINCE:
                raise err(f"{fld}.since", f"{raw['since']!r}: allowed values are {', '.join(SINCE)}")
            kw["since"] = raw["since"]
        if "or" in raw:
            if not isinstance(raw["or"], list) or not raw["or"]:
                raise err(f"{fld}.or", "a non-empty list of hex strings")
            kw["alternatives"] = tuple(_hex(a, f"{fld}.or[{i}]", err) for i, a in enumerate(raw["or"]))
    return Step(**kw)


def _status_list(raw: Any, fld: str, err) -> list[frozenset[int]]:
    from .status import UnknownStatus, lookup
    if not isinstance(raw, list):
        raise err(fld, "a list of codes such as [\"16#0808\"] or alternatives [\"16#0703|16#0709\"]")
    out = []
    for i, item in enumerate(raw):
        if not isinstance(item, str):
            raise err(f"{fld}[{i}]", "must be a string such as \"16#0808\"")
        try:
            out.append(frozenset(lookup(p).code for p in item.split("|")))
        except UnknownStatus as exc:
            raise err(f"{fld}[{i}]", str(exc)) from None
    return out


def _expected(raw: Any, err) -> Expected:
    if not isinstance(raw, dict):
        raise err("expected", "must be a table")
    unknown = sorted(set(raw) - _EXPECTED_KEYS)
    if unknown:
        raise err(f"expected.{unknown[0]}", "unknown key (known: " + ", ".join(sorted(_EXPECTED_KEYS)) + ")")

    def spec(name: str) -> StatusSpec:
        req = _status_list(raw.get(name, []), f"expected.{name}", err)
        opt = _status_list(raw.get(name + "_optional", []), f"expected.{name}_optional", err)
        soft = _status_list(raw.get(name + "_soft", []), f"expected.{name}_soft", err) if name == "iut_status" else []
        return StatusSpec(tuple(req), frozenset().union(*opt) if opt else frozenset(), tuple(soft))

    def blocks(name: str) -> tuple[bytes, ...]:
        v = raw.get(name, [])
        if not isinstance(v, list):
            raise err(f"expected.{name}", "a list of hex payloads")
        return tuple(_hex(x, f"expected.{name}[{i}]", err) for i, x in enumerate(v))

    return Expected(spec("iut_status"), spec("tester_status"), blocks("delivered"),
                    blocks("sent"), blocks("echo_after"))


def _toml_files(root, prefix: str) -> list[tuple[str, object]]:
    """(name for messages, file) of every ``*.toml`` under ``root``, a directory or an
    importlib.resources Traversable, sorted by path."""
    out = []
    for entry in sorted(root.iterdir(), key=lambda e: e.name):
        name = f"{prefix}/{entry.name}" if prefix else entry.name
        if entry.is_dir():
            if not entry.name.startswith((".", "__")):
                out += _toml_files(entry, name)
        elif entry.name.endswith(".toml"):
            out.append((name, entry))
    return out


def load_dir(root, label: str | None = None) -> list[Vector]:
    """Every ``*.toml`` vector under ``root`` (a directory or an importlib.resources
    Traversable; sorted by path); ids must be unique. ``label`` names the root in
    messages and in each vector's ``source`` (default: the path)."""
    if isinstance(root, str):
        root = Path(root)
    if not root.is_dir():
        raise VectorError(str(root), "", "is not a directory of vectors")
    base = str(root) if label is None else label
    out: list[Vector] = []
    seen: dict[str, str] = {}
    for rel, f in _toml_files(root, ""):
        where = f"{base}/{rel}"
        try:
            text = f.read_text("utf-8")
        except UnicodeDecodeError:
            raise VectorError(where, "", "is not UTF-8 text (save the vector as UTF-8)") from None
        except OSError as exc:
            raise VectorError(where, "", f"cannot be read: {exc.strerror}") from None
        v = load_vector_text(text, where)
        if v.id in seen:
            raise VectorError(where, "id", f"{v.id!r} is also the id of {seen[v.id]}")
        seen[v.id] = where
        out.append(v)
    return out


def load_vector_sets(extra=(), *, only: bool = False) -> list[Vector]:
    """The bundled golden vectors (ptpcert's, and those a procedure of another distribution
    ships, :meth:`ptpcert.procedure.Procedure.vectors_dir`) plus those of the directories
    ``extra``; with ``only``, just those of ``extra`` (or just the bundled ones when ``extra``
    is empty). Ids must be unique across all of them."""
    from .paths import bundled_vectors
    from .registry import procedures

    sets: list[list[Vector]] = []
    if not (only and extra):
        sets.append(load_dir(bundled_vectors(), "vectors"))
        for proc in procedures():
            own = proc.vectors_dir()
            if own is not None:
                sets.append(load_dir(own, f"vectors of {proc.title}"))
    for d in extra:
        sets.append(load_dir(Path(d)))
    out: list[Vector] = []
    seen: dict[str, str] = {}
    for vs in sets:
        for v in vs:
            if v.id in seen:
                raise VectorError(v.source, "id", f"{v.id!r} is also the id of {seen[v.id]}")
            seen[v.id] = v.source
            out.append(v)
    return out


# ------------------------------------------------------------------ expansion
def expand(vector: Vector) -> tuple[Step, ...]:
    """Replace the procedure's macro steps (e.g. ``prime``) by the send/expect steps they
    stand for."""
    out: list[Step] = []
    proc = vector.proc
    for s in vector.steps:
        if s.is_macro:
            out += proc.expand(s, vector.params)
        else:
            out.append(s)
    return tuple(out)



# ------------------------------------------------------------------ writing TOML
def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def dump_vector(vector: Vector, header: str = "") -> str:
    """The vector as a TOML file that :func:`load_vector` reads back unchanged."""
    d = vector.to_toml()
    lines = []
    if header:
        lines += ["# " + line if line else "#" for line in header.splitlines()]
        lines.append("")
    for key, value in d.items():
        if key in ("params", "tester_params", "expected", "steps", "extra"):
            continue
        lines.append(f"{key} = {_toml_value(value)}")
    lines.append("steps = [")
    for s in d["steps"]:
        lines.append(f"  {_toml_value(s)},")
    lines.append("]")
    for table in ("params", "tester_params", "expected", "extra"):
        if table in d:
            lines.append("")
            lines.append(f"[{table}]")
            for key, value in d[table].items():
                lines.append(f"{key} = {_toml_value(value)}")
    return "\n".join(lines) + "\n"


def vector_set_hash(vectors: Iterable[Vector]) -> str:
    h = hashlib.sha256()
    for v in sorted(vectors, key=lambda v: v.id):
        h.update(v.id.encode())
        h.update(v.digest().encode())
    return h.hexdigest()[:16]
