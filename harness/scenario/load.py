"""Loading vectors: from TOML text, files and directories, every field checked.

:func:`vector_from_dict` turns a TOML table into a :class:`ptpcert.scenario.vector.Vector`,
checking each key against the schema (``vectors/README.md``) and against what the vector's
procedure knows (its groups, parameters, macro steps, setups, readings, rules and timer
names); anything wrong raises :class:`VectorError` with the file, the field and what is
wrong. :func:`check_times` makes sure every time expression names only known timers and
evaluates to a usable duration. Around it, :func:`load_vector_text`, :func:`load_vector`
and :func:`load_dir` read text, a file and a directory tree, and :func:`load_vector_sets`
gathers the bundled golden vectors, those a procedure ships and the user's, with ids
unique across all of them.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Any, Mapping

from ..procedure import ProcedureError
from ..registry import by_name
from ..rules import for_procedure
from .expr import BASE_TIME_NAMES, Expr, ExprError, is_duration, names_in
from .hexnotation import parse_vector_hex
from .steps import DATA_KINDS, GRADES, SINCE, STEP_KEYS, STEP_KINDS, Step, unmarked_since
from .vector import BASE_REQUIREMENTS, IUT_ROLES, STARTS, Expected, StatusSpec, Vector, timer_env


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
    expected = _expected(raw.get("expected", {}), err, proc.byte_names)
    readings = raw.get("readings", [])
    if not isinstance(readings, list) or any(r not in proc.readings for r in readings):
        bad = next((r for r in readings if r not in proc.readings), readings) if isinstance(readings, list) else readings
        raise err("readings", f"{bad!r}: a list of the manual's open points this procedure has readings for "
                  f"({proc.readings[0]}..{proc.readings[-1]})" if proc.readings else "this procedure has no readings")
    rules = raw.get("rules", [])
    if not isinstance(rules, list) or any(not isinstance(r, str) for r in rules):
        raise err("rules", "a list of rule ids of the procedure's catalogue (ptpcert rules lists them)")
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
    unmarked = unmarked_since(steps)
    if unmarked is not None:
        raise err(f"steps[{unmarked}].since", "\"mark\" but no step before it sets mark = true")
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
            if e is None:   # the procedure's own default
                e = Expr(v.proc.max_gap)
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


def _hex(value: Any, fld: str, err, names: Mapping[str, int] | None = None) -> bytes:
    if not isinstance(value, str):
        raise err(fld, "must be a string of hex bytes such as \"02 10\"")
    try:
        return parse_vector_hex(value, names)
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
    byte_names = proc.byte_names if proc is not None else None
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
        kw["data"] = _hex(raw[kind], f"{fld}.{kind}", err, byte_names)
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
            kw["alternatives"] = tuple(_hex(a, f"{fld}.or[{i}]", err, byte_names) for i, a in enumerate(raw["or"]))
        if "or_end" in raw:
            if not isinstance(raw["or_end"], int) or isinstance(raw["or_end"], bool) or raw["or_end"] < 0:
                raise err(f"{fld}.or_end", "the number of further steps run before the case ends when an "
                                           "alternative came")
            if "or" not in raw:
                raise err(f"{fld}.or_end", "needs alternatives (or = [...]) to end on")
            kw["or_end"] = raw["or_end"]
    return Step(**kw)


def _status_list(raw: Any, fld: str, err) -> list[frozenset[int]]:
    from ..status import UnknownStatus, lookup
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


def _expected(raw: Any, err, names: Mapping[str, int] | None = None) -> Expected:
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
        return tuple(_hex(x, f"expected.{name}[{i}]", err, names) for i, x in enumerate(v))

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
    from ..paths import bundled_vectors
    from ..registry import procedures

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
