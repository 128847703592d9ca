"""Reading a saved results object back: the schema names, the file read as JSON, the checks
that let no saved file make a view fail (each problem a :class:`ResultsError` naming the
key and what is allowed), and the cases rebuilt from their JSON form, schema 1's
transcripts (one entry per byte) packed into runs as a run keeps them.

Part of :mod:`ptpcert.results`: :meth:`ptpcert.results.run.RunResult.from_dict` and
``read_json`` call it; writing is :meth:`~ptpcert.results.run.RunResult.to_json`.
"""

from __future__ import annotations

import json
import math
import stat
import sys
from dataclasses import Field, fields
from pathlib import Path
from typing import Any, Iterable

from ptpcert.results.cases import NOT_RUN, VERDICTS, CaseResult, Divergence
from ptpcert.results.transcripts import BYTE_KINDS, RUN_KINDS, pack_transcript, run_bytes

#: The results format. 2: the bytes of a transcript are stored as runs (one entry per burst
#: of one side, its bytes in base64 and, where they differ, each byte's time) and bounded
#: by the flood limit; 1 had one entry per byte. ``ptpcert report`` reads both.
SCHEMA = "ptpcert-results/2"
SCHEMA_V1 = "ptpcert-results/1"
SCHEMAS = (SCHEMA, SCHEMA_V1)


class ResultsError(ValueError):
    """A saved results object that ptpcert cannot read; the message names the key."""


def parse_json(text: str) -> Any:
    """``text`` as JSON; a ``ValueError`` that says what is wrong (no traceback) for text
    that is no JSON, JSON nested too deep for the reader, and a number of more digits than
    Python converts (both of which ``json`` raises as other errors)."""
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"not JSON: {exc}") from None
    except RecursionError:
        raise ValueError("not readable JSON: arrays or objects nested too deep") from None
    except ValueError as exc:     # int('9' * 5000): the digit limit of int()
        if "digits" in str(exc):
            raise ValueError(f"not readable JSON: a number of more than {sys.get_int_max_str_digits()} "
                             "digits") from None
        raise ValueError(f"not JSON: {exc}") from None


def read_document(path: str | Path) -> Any:
    """The JSON a results file holds, not yet checked. Raises :class:`ResultsError` naming
    the file when it is no file, cannot be read, or is not UTF-8 JSON."""
    try:
        mode = Path(path).stat().st_mode
        if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISSOCK(mode):   # /dev/zero: never ends
            raise ResultsError(f"{path}: is a device, not a results file")
        raw = Path(path).read_bytes()
    except IsADirectoryError:
        raise ResultsError(f"{path}: is a directory, not a results file") from None
    except OSError as exc:
        raise ResultsError(f"{path}: cannot be read: {exc.strerror}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ResultsError(f"{path}: is not UTF-8 text (byte {exc.start}); "
                           "expected the JSON that ptpcert run --json writes") from None
    try:
        return parse_json(text)
    except ValueError as exc:
        raise ResultsError(f"{path}: {exc}") from None


def cases_from_dict(d: dict[str, Any]) -> list[CaseResult]:
    """The cases of a results object that passed :func:`check_run`, keys unknown to
    :class:`CaseResult` left out; a schema 1 transcript is packed into runs."""
    if d["schema"] == SCHEMA_V1:   # one entry per byte: packed into runs as a run keeps them
        d = dict(d, cases=[dict(c, transcript=pack_transcript(c.get("transcript", []))) for c in d["cases"]])
    names = {f.name for f in fields(CaseResult)}
    cases = []
    for c in d["cases"]:
        c = {k: v for k, v in c.items() if k in names}
        div = c.pop("divergence", None)
        if div is not None:
            div = {k: v for k, v in div.items() if k in Divergence.__dataclass_fields__}
            if div.get("window") is not None:
                div["window"] = tuple(div["window"])
            div = Divergence(**div)
        cases.append(CaseResult(divergence=div, **c))
    return cases


# ------------------------------------------------------------------ checking saved results
def _kind_of(annotation: str) -> tuple[type, ...]:
    a = str(annotation)
    if a.startswith("list"):
        return (list,)
    if a.startswith("dict"):
        return (dict,)
    return {"str": (str,), "float": (int, float), "int": (int,), "bool": (bool,)}.get(a, (object,))


def _type_name(types: tuple[type, ...]) -> str:
    return {list: "a list", dict: "an object", str: "a string", int: "an integer", float: "a number",
            bool: "true or false"}.get(types[-1], "a value")


def is_kind(value: Any, types: tuple[type, ...]) -> bool:
    """Whether a JSON value is of one of ``types``: true or false is no number unless
    ``bool`` is among them, and NaN or an infinity is no number at all."""
    if isinstance(value, bool) and bool not in types:
        return False
    if isinstance(value, float) and float in types and not math.isfinite(value):
        return False
    return isinstance(value, types)


def check_run(d: Any, run_fields: Iterable[Field]) -> None:
    """Check a results object's JSON form (either schema) before anything reads it:
    ``run_fields`` are the run's own fields (those of
    :class:`~ptpcert.results.run.RunResult`), each present one of its type; every case
    with its required keys, its fields' types, a known verdict, and well-formed divergence,
    transcript entries and frames. Raises :class:`ResultsError` naming the key."""
    if not isinstance(d, dict):
        what = "an array" if isinstance(d, list) else f"a {type(d).__name__}"
        raise ResultsError(f"not a ptpcert results object: the JSON is {what}, not an object with "
                           f"\"schema\": \"{SCHEMA}\"")
    if d.get("schema") not in SCHEMAS:
        raise ResultsError(f"schema: {d.get('schema')!r} is not a ptpcert results object "
                           f"(readable: {', '.join(SCHEMAS)})")
    for f in run_fields:
        if f.name in d and f.name != "cases" and not is_kind(d[f.name], _kind_of(f.type)):
            raise ResultsError(f"{f.name}: must be {_type_name(_kind_of(f.type))}")
    if any(not isinstance(v, str) for v in (d.get("iut_identity") or {}).values()):
        raise ResultsError("iut_identity: must be an object of strings (vendor, product, version, serial, text)")
    cases = d.get("cases")
    if not isinstance(cases, list):
        raise ResultsError("cases: missing, or not a list of cases")
    required = ("id", "title", "reference", "rule", "group", "iut_role")
    for i, c in enumerate(cases):
        where = f"cases[{i}]"
        if not isinstance(c, dict):
            raise ResultsError(f"{where}: must be an object")
        for key in required:
            if key not in c:
                raise ResultsError(f"{where}.{key}: missing")
        for f in fields(CaseResult):
            if f.name in c and f.name != "divergence" and not is_kind(c[f.name], _kind_of(f.type)):
                raise ResultsError(f"{where}.{f.name}: must be {_type_name(_kind_of(f.type))}")
        where = f"cases[{i}] ({c['id']})"
        if c.get("verdict", NOT_RUN) not in VERDICTS:
            raise ResultsError(f"{where}.verdict: {c['verdict']!r} is not a verdict (allowed: {', '.join(VERDICTS)})")
        _check_divergence(c.get("divergence"), where)
        for name in ("transcript", "frames", "steps"):
            for j, e in enumerate(c.get(name, [])):
                if not isinstance(e, dict):
                    raise ResultsError(f"{where}.{name}[{j}]: must be an object")
        for j, e in enumerate(c.get("transcript", [])):
            _check_entry(e, f"{where}.transcript[{j}]")
        for j, e in enumerate(c.get("frames", [])):
            _check_frame(e, f"{where}.frames[{j}]")
        for name in ("observed_status", "readings", "notes"):
            if any(not isinstance(x, str) for x in c.get(name, [])):
                raise ResultsError(f"{where}.{name}: must be a list of strings")


def _check_divergence(div: Any, where: str) -> None:
    if div is None:
        return
    if not isinstance(div, dict):
        raise ResultsError(f"{where}.divergence: must be an object or null")
    for key, types in (("step", (int,)), ("time", (int, float)), ("expected", (str,)), ("observed", (str,))):
        if not is_kind(div.get(key), types):
            raise ResultsError(f"{where}.divergence.{key}: must be {_type_name(types)}")
    w = div.get("window")
    if w is not None and not (isinstance(w, list) and len(w) == 2 and all(is_kind(x, (int, float)) for x in w)):
        raise ResultsError(f"{where}.divergence.window: must be null or [from, to] in seconds")


def _check_frame(f: dict[str, Any], where: str) -> None:
    """A frame's fields (:data:`FRAME_FIELDS`) have their types."""
    for key in ("t0", "t1"):
        if not is_kind(f.get(key), (int, float)):
            raise ResultsError(f"{where}.{key}: must be a number (seconds)")
    if f.get("dir") not in ("tester", "iut"):
        raise ResultsError(f"{where}.dir: {f.get('dir')!r} (allowed: tester, iut)")
    for key, times in (("marks", ("t",)), ("windows", ("t0", "t1"))):
        items = f.get(key, [])
        if not isinstance(items, list):
            raise ResultsError(f"{where}.{key}: must be a list of objects")
        for k, m in enumerate(items):
            if not isinstance(m, dict) or not all(is_kind(m.get(t), (int, float)) for t in times):
                raise ResultsError(f"{where}.{key}[{k}]: must be an object with "
                                   + ", ".join(f"\"{t}\"" for t in times) + " (seconds) and \"name\"")


def _check_entry(e: dict[str, Any], where: str) -> None:
    for key in ("t", "t0", "t1", "duration"):
        if key in e and not is_kind(e[key], (int, float)):
            raise ResultsError(f"{where}.{key}: must be a number (seconds)")
    if "step" in e and not is_kind(e["step"], (int,)):
        raise ResultsError(f"{where}.step: must be an integer")
    kind = e.get("kind")
    if kind in BYTE_KINDS or kind in RUN_KINDS or kind == "break":
        if "t" not in e:
            raise ResultsError(f"{where}.t: missing")
        if e.get("dir") not in ("tester", "iut"):
            raise ResultsError(f"{where}.dir: {e.get('dir')!r} (allowed: tester, iut)")
    if kind in BYTE_KINDS and not (is_kind(e.get("byte"), (int,)) and 0 <= e["byte"] <= 255):
        raise ResultsError(f"{where}.byte: must be an integer 0..255")
    if kind in RUN_KINDS:
        try:
            n = len(run_bytes(e))
        except (TypeError, ValueError):
            raise ResultsError(f"{where}.base64: must be the run's bytes in base64, such as \"AhA=\"") from None
        times = e.get("times")
        if times is not None and not (isinstance(times, list) and len(times) == n
                                      and all(is_kind(x, (int, float)) for x in times)):
            raise ResultsError(f"{where}.times: must be a list of {n} times (seconds), one per byte")


