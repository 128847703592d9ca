"""The one results object of a run. JSON is its own format; JUnit, HTML and the console
summary are views of it (:mod:`ptpcert.report`)."""

from __future__ import annotations

import base64
import json
import math
import os
import re
import secrets
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any, Iterable

PASS = "pass"
FAIL = "fail"
NON_STRICT = "non-strict"
INFORMATIONAL = "informational"
UNSUPPORTED = "unsupported"
XFAIL = "xfail"
XPASS = "xpass"
ERROR = "error"
NOT_RUN = "not-run"

VERDICTS = (FAIL, XPASS, ERROR, NON_STRICT, INFORMATIONAL, PASS, XFAIL, UNSUPPORTED, NOT_RUN)
#: Verdicts that make the run fail (exit status 1); ERROR makes it exit 2.
FAILING = (FAIL, XPASS)
#: Grades of a passing case, mildest first.
GRADE_ORDER = (PASS, INFORMATIONAL, NON_STRICT)

#: The results format. 2: the bytes of a transcript are stored as runs (one entry per burst
#: of one side, its bytes in base64 and, where they differ, each byte's time) and bounded
#: by the flood limit; 1 had one entry per byte. ``ptpcert report`` reads both.
SCHEMA = "ptpcert-results/2"
SCHEMA_V1 = "ptpcert-results/1"
SCHEMAS = (SCHEMA, SCHEMA_V1)


#: The fields of a frame in :attr:`CaseResult.frames` (what
#: :meth:`ptpcert.procedure.Procedure.describe_frames` returns; the reports draw them).
#: Times are seconds on the case's clock, as in the transcript.
FRAME_FIELDS = {
    "dir": 'who sent the frame: "tester" or "iut"',
    "t0": "where the frame begins (its first character, or the answer that opened it)",
    "t1": "where it ends (its last character)",
    "label": 'the frame decoded, for people: "SEND DB10 DW0 200 bytes, accepted (DLE)"',
    "frame": "optional: the frame's content in hex (without the link's framing)",
    "marks": 'optional: named instants inside it, a list of {"t": seconds, "name": str} '
             '(e.g. an end character "ETX")',
    "windows": 'optional: named spans that belong to it, a list of {"t0", "t1", "name"} '
               '(e.g. the "CDT" after its last character)',
    "diverged": "optional: true when the case's first divergence falls in this frame",
    "expected": "optional: the label of the frame the case expected in its place",
}


def divergence_frame(c: "CaseResult") -> dict[str, Any] | None:
    """The frame the case's first divergence falls in, or None: the one the run marked
    ``diverged``; for results without the mark, the IUT's frame (else the tester's) whose
    span holds the divergence's time."""
    if c.divergence is None:
        return None
    for f in c.frames:
        if f.get("diverged"):
            return f
    t = float(c.divergence.time)
    hits = [f for f in c.frames if _is(f.get("t0"), (int, float)) and _is(f.get("t1"), (int, float))
            and float(f["t0"]) - 1e-6 <= t <= float(f["t1"]) + 1e-6]
    hits.sort(key=lambda f: f.get("dir") != "iut")
    return hits[0] if hits else None


def divergence_frame_text(c: "CaseResult") -> str:
    """The divergence's frame in words: 'in the IUT's frame "response REATEL 0Ch -> ...",
    expected "response REATEL 14h -> ..."' ('during the tester's frame "..."' when it
    falls in one of the tester's); '' when it falls in no frame."""
    f = divergence_frame(c)
    if f is None:
        return ""
    where = "in the IUT's" if f.get("dir") == "iut" else "during the tester's"
    text = f"{where} frame \"{f.get('label', '?')}\""
    exp = f.get("expected")
    if exp and exp != f.get("label"):
        text += f", expected \"{exp}\""
    return text


def worse_grade(a: str, b: str) -> str:
    return a if GRADE_ORDER.index(a) >= GRADE_ORDER.index(b) else b


@dataclass
class Divergence:
    """The first point where the IUT did not do what the vector expects."""

    step: int              # index into the expanded steps (-1: prologue/epilogue)
    time: float            # seconds since the case started
    expected: str          # what the step expected, in words and hex
    observed: str          # what happened instead
    window: tuple[float, float] | None = None  # the window that applied (case time)


@dataclass
class CaseResult:
    id: str
    title: str
    reference: str
    rule: str
    group: str
    iut_role: str
    verdict: str = NOT_RUN
    message: str = ""
    divergence: Divergence | None = None
    expected_status: str = ""          # what the IUT must raise (description)
    expected_status_codes: list[list[str]] = field(default_factory=list)
    tester_status: str = ""            # what a CP 341 in the tester's seat raises
    observed_status: list[str] = field(default_factory=list)  # reported by the IUT
    status_checked: bool = False
    transcript: list[dict[str, Any]] = field(default_factory=list)
    #: frames the procedure found in the transcript, for reports: dicts with the fields of
    #: :data:`FRAME_FIELDS` (``dir``, ``t0``, ``t1``, ``label`` always; the rest optional)
    frames: list[dict[str, Any]] = field(default_factory=list)
    steps: list[dict[str, Any]] = field(default_factory=list)  # expanded steps, for reports
    origin: float = 0.0                # the transport clock at the case's time 0 (monotonic)
    duration: float = 0.0              # wall time of the case, seconds
    case_time: float = 0.0             # time on the case's clock (virtual for sim:)
    forced_wait: float = 0.0           # time the protocol itself forces the case to take
    attempts: int = 1
    stderr_tail: str = ""
    readings: list[str] = field(default_factory=list)
    source: str = ""
    params: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    rules: list[str] = field(default_factory=list)  # ids of the manual's rules the case checks
    device: str = ""                   # the IUT of a pool (--iut given several times) that ran the case

    @property
    def failed(self) -> bool:
        return self.verdict in FAILING


@dataclass
class RunResult:
    tool_version: str
    started: str
    finished: str = ""
    iut: str = ""
    #: the procedure, for people ("3964/3964R", "RK 512", "ASCII driver")
    procedure: str = ""
    profile: dict[str, Any] = field(default_factory=dict)
    profile_path: str = ""
    vector_set: str = ""
    vector_set_hash: str = ""
    cases: list[CaseResult] = field(default_factory=list)
    interrupted: bool = False
    wall_time: float = 0.0
    html_path: str = ""
    #: the harness's scheduling class for the run (:mod:`ptpcert.priority`), for people
    harness_scheduling: str = ""
    schema: str = SCHEMA
    #: the failures grouped by root cause (see :func:`root_causes`); empty while a run is
    #: under way (the views then compute them), filled in the JSON so that a re-rendered
    #: report shows the groups the run found
    root_causes: list[dict[str, Any]] = field(default_factory=list)

    def deviations(self) -> list[dict[str, Any]]:
        """The distinct deviations: the stored groups, or those of the cases as they stand."""
        return self.root_causes or root_causes(self.cases)

    def counts(self) -> dict[str, int]:
        out = {v: 0 for v in VERDICTS}
        for c in self.cases:
            out[c.verdict] = out.get(c.verdict, 0) + 1
        return out

    @property
    def verdict(self) -> str:
        n = self.counts()
        if n[FAIL] or n[XPASS]:
            return FAIL
        if n[ERROR] or self.interrupted:
            return ERROR
        return PASS

    def exit_status(self) -> int:
        v = self.verdict
        return 1 if v == FAIL else 2 if v == ERROR else 0

    # -- JSON -------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["root_causes"] = self.deviations()
        d["counts"] = self.counts()
        d["verdict"] = self.verdict
        return d

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1)

    def write_json(self, path: str | Path) -> None:
        write_atomic(path, self.to_json())

    @classmethod
    def from_dict(cls, d: Any) -> "RunResult":
        """A results object from its JSON form (either schema). Raises :class:`ResultsError`
        naming the key and what is allowed, so that no saved file can make a view fail."""
        _check_run(d)
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
        fields_ = {k: v for k, v in d.items() if k in cls.__dataclass_fields__ and k != "cases"}
        fields_["schema"] = SCHEMA
        return cls(cases=cases, **fields_)

    @classmethod
    def read_json(cls, path: str | Path) -> "RunResult":
        import stat
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
            data = json.loads(raw.decode("utf-8"))
        except UnicodeDecodeError as exc:
            raise ResultsError(f"{path}: is not UTF-8 text (byte {exc.start}); "
                               "expected the JSON that ptpcert run --json writes") from None
        except (json.JSONDecodeError, RecursionError) as exc:
            raise ResultsError(f"{path}: not JSON: {exc}") from None
        try:
            return cls.from_dict(data)
        except ResultsError as exc:
            raise ResultsError(f"{path}: {exc}") from None


# ------------------------------------------------------------------ root causes
#: names of the control characters in the signatures' words
_STEERING = {0x02: "STX", 0x10: "DLE", 0x15: "NAK"}
_HEX = re.compile(r"^(?:[0-9A-F]{2}(?:\*\d+)?)(?: [0-9A-F]{2}(?:\*\d+)?)*$")


def _bytes_word(data: bytes) -> str:
    """Up to three bytes in hex; a longer run (a block, whose data differ from case to case)
    as "a block"."""
    if not data:
        return "nothing"
    if len(data) <= 3:
        return " ".join(f"{b:02X}" for b in data)
    return "a block"


def _stimulus_word(c: CaseResult, until: float) -> str:
    """What the tester sent last before ``until`` (case time), as a class that survives other
    payloads: NAK, STX, DLE (the characters that steer the procedure), BREAK, a corrupted
    character, a block (more than one byte at once), any other character; "" at the start."""
    last = None
    for t, d, kind, value, _ in wire_runs(c.transcript):
        if t > until + 1e-9:
            break
        if d == "tester":
            last = (kind, value)
    if last is None:
        return ""
    kind, value = last
    if kind == "break":
        return "BREAK"
    if kind == "char_error":
        return "corrupted character"
    data = bytes(value)
    if len(data) == 1:
        return _STEERING.get(data[0], "character")
    return "block"


def _words(text: str) -> str:
    """Free text without what changes from run to run: times, counts and positions."""
    text = re.sub(r"^step \d+: ", "", text)
    text = re.sub(r" \(reported: .*$", "", text)
    text = re.sub(r"-?\d+(?:\.\d+)? ?(?:ms|s)\b", "T", text)
    return re.sub(r"(?<![#\w])\d+(?![#\w])", "N", text).strip()


def failure_signature(c: CaseResult) -> tuple[str, str, str]:
    """The signature of a failed case's first divergence, as (context, expected, observed):
    what the tester had last sent, what the IUT was expected to send and what it sent
    instead, in words that survive other payloads and other timings (a block is "a
    block", a byte position inside a block's data is not kept, times are not kept).
    Cases with the same signature fail for one root cause."""
    d = c.divergence
    if d is None:
        return "", "", _words(c.message)
    step = c.steps[d.step] if 0 <= d.step < len(c.steps) else {}
    raw = str(step.get("data", "")) if step.get("kind") == "expect" else ""
    try:
        want = bytes.fromhex(raw) if raw else b""
    except ValueError:
        want = b""
    expected = _bytes_word(want) if want else _words(d.expected)
    obs = d.observed
    if d.expected.endswith("block(s) from the IUT"):   # the echo the epilogue waits for
        intact = re.match(r"^received (\d+) intact block", obs)
        return "", "its echo of the block", (
            "sends no intact block" if intact and intact.group(1) == "0" else
            "sends fewer intact blocks" if intact else _words(obs))
    m = re.match(r"^received ([0-9A-F]{2})$", obs)
    n = re.match(r"^([0-9A-F]{2}) came .* too (late|early)$", obs)
    k = re.match(r"^byte (\d+) is ([0-9A-F]{2}) \(after .*\)$", obs)
    if m:
        observed = f"sends {m.group(1)}"
    elif n:
        observed = f"sends {n.group(1)} too {n.group(2)}"
    elif k:
        pos, byte = int(k.group(1)), k.group(2)
        from_end = len(want) - pos if want else -1
        if len(want) <= 3:
            observed = f"sends {byte} as byte {pos}"
        elif from_end == 0:
            observed = "sends the block with another last byte (its BCC or end)"
        elif 0 < from_end <= 2:
            observed = f"sends the block with another byte {from_end + 1} from its end"
        else:
            observed = "sends the block with other data"
    elif obs == "nothing received":
        observed = "sends nothing"
    elif obs.startswith("got ") and ", then nothing" in obs:
        observed = "stops in the middle"
    elif obs.startswith("it still sent "):
        observed = "goes on sending after it must stop"
    elif obs.startswith("it sent "):
        observed = "sends " + _bytes_word(bytes.fromhex(obs[8:].replace("…", "").strip()) if _HEX.match(
            obs[8:].strip()) and "*" not in obs else b"\x00" * 4)
    else:
        observed = _words(obs)
    if n:   # the right byte at the wrong time: the IUT's timer, whatever the tester sent before
        return "", expected, observed
    return _stimulus_word(c, d.time), expected, observed


def describe_signature(sig: tuple[str, str, str], count: int) -> str:
    context, expected, observed = sig
    head = f"{count} case{'s' if count != 1 else ''}: "
    if not expected:
        return head + observed
    where = f"after the tester's {context}, " if context else ""
    return head + f"{where}the IUT {observed} where {expected} is due"


def root_causes(cases: Iterable[CaseResult]) -> list[dict[str, Any]]:
    """The failed cases grouped by the signature of their first divergence
    (:func:`failure_signature`): one group per distinct deviation, the largest first, each
    with its description, the number of cases it explains and their ids."""
    groups: dict[tuple[str, str, str], list[str]] = {}
    for c in cases:
        if c.verdict == FAIL:
            groups.setdefault(failure_signature(c), []).append(c.id)
    ordered = sorted(groups.items(), key=lambda kv: -len(kv[1]))
    return [{"signature": list(sig), "description": describe_signature(sig, len(ids)), "count": len(ids),
             "cases": ids} for sig, ids in ordered]


def root_cause_of(run: "RunResult") -> dict[str, int]:
    """Each failed case's group number (1-based) in the run's deviations."""
    return {cid: i + 1 for i, g in enumerate(run.deviations()) for cid in g.get("cases", [])}


class ResultsError(ValueError):
    """A saved results object that ptpcert cannot read; the message names the key."""


# ------------------------------------------------------------------ transcripts
#: Entries of the bytes on the line: one per byte (the runner's log, and schema 1) and
#: their runs (schema 2).
BYTE_KINDS = {"byte": "bytes", "char_error": "char_errors"}
RUN_KINDS = {run: one for one, run in BYTE_KINDS.items()}


def pack_transcript(log: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """A transcript with one entry per byte as runs: consecutive bytes of one side, kind
    and step become one entry ``{"t", "dir", "kind": "bytes" | "char_errors", "step",
    "base64": "AhA=", "times": [...]}`` (the bytes in base64, RFC 4648: a flood's 20000
    bytes take 27 kB, not 40 kB as hex), ``times`` only where the bytes' times differ from
    ``t``. Every other entry (BREAK, windows, marks) is kept as it is."""
    out: list[dict[str, Any]] = []
    cur: dict[str, Any] | None = None
    data = bytearray()
    times: list[float] = []

    def flush() -> None:
        nonlocal cur
        if cur is not None:
            cur["base64"] = base64.b64encode(bytes(data)).decode("ascii")
            if any(t != times[0] for t in times):
                cur["times"] = list(times)
            out.append(cur)
            cur = None

    for e in log:
        kind = e.get("kind")
        if kind in BYTE_KINDS:
            run = BYTE_KINDS[kind]
            d, step = e.get("dir", "tester"), e.get("step", 0)
            if cur is None or cur["kind"] != run or cur["dir"] != d or cur["step"] != step:
                flush()
                cur = {"t": e["t"], "dir": d, "kind": run, "step": step}
                data, times = bytearray(), []
            data.append(int(e["byte"]) & 0xFF)
            times.append(e["t"])
        else:
            flush()
            out.append(dict(e))
    flush()
    return out


def unpack_transcript(transcript: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """Inverse of :func:`pack_transcript`: one entry per byte again (entries of schema 1
    pass unchanged), for tools that read a transcript byte by byte."""
    out: list[dict[str, Any]] = []
    for e in transcript:
        kind = e.get("kind")
        if kind not in RUN_KINDS:
            out.append(e)
            continue
        one, data = RUN_KINDS[kind], run_bytes(e)
        times = e.get("times") or [e["t"]] * len(data)
        base = {k: v for k, v in e.items() if k not in ("kind", "base64", "times", "t")}
        out.extend({**base, "t": times[i], "kind": one, "byte": b} for i, b in enumerate(data))
    return out


def run_bytes(e: dict[str, Any]) -> bytes:
    """The bytes of a run entry."""
    text = e.get("base64")
    if not isinstance(text, str):
        raise TypeError("base64 missing")
    return base64.b64decode(text, validate=True)


def wire_runs(transcript: Iterable[dict[str, Any]]) -> list[tuple[float, str, str, Any, int]]:
    """The bytes, character errors and BREAKs of a transcript (runs, or one entry per byte)
    as ``(t, dir, kind, value, step)`` in time order (equal times keep the log's order):
    ``kind`` "byte" or "char_error" with ``value`` the bytes that arrived together at ``t``
    (a run whose bytes share one time stays whole), or "break" with its duration."""
    out: list[tuple[float, str, str, Any, int]] = []
    for e in transcript:
        kind = e.get("kind")
        if kind in RUN_KINDS:
            one, d, step = RUN_KINDS[kind], e.get("dir", "tester"), int(e.get("step", 0))
            data = run_bytes(e)
            times = e.get("times")
            if times:
                out.extend((float(x), d, one, data[i:i + 1], step) for i, x in enumerate(times))
            elif data:
                out.append((float(e["t"]), d, one, data, step))
        elif kind in BYTE_KINDS and "t" in e:
            out.append((float(e["t"]), e.get("dir", "tester"), kind, bytes([int(e.get("byte", 0)) & 0xFF]),
                        int(e.get("step", 0))))
        elif kind == "break" and "t" in e:
            out.append((float(e["t"]), e.get("dir", "tester"), "break", float(e.get("duration", 0.0)),
                        int(e.get("step", 0))))
    out.sort(key=lambda x: x[0])
    return out


def wire_events(transcript: Iterable[dict[str, Any]]) -> list[tuple[float, str, str, Any, int]]:
    """As :func:`wire_runs`, one entry per byte: ``value`` is the byte (an int)."""
    out: list[tuple[float, str, str, Any, int]] = []
    for t, d, kind, value, step in wire_runs(transcript):
        if kind == "break":
            out.append((t, d, kind, value, step))
        else:
            out.extend((t, d, kind, b, step) for b in value)
    return out


def dropped_note(e: dict[str, Any]) -> str:
    """The words for a ``dropped`` entry: bytes the transcript does not keep."""
    who = "the IUT" if e.get("dir") == "iut" else "the tester"
    return (f"{e.get('bytes', 0)} more byte(s) from {who} not kept: the transcript keeps the first "
            f"{e.get('kept', 0)} (flood limit)")


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


def _is(value: Any, types: tuple[type, ...]) -> bool:
    if isinstance(value, bool) and bool not in types:
        return False
    if isinstance(value, float) and float in types and not math.isfinite(value):
        return False
    return isinstance(value, types)


def _check_run(d: Any) -> None:
    if not isinstance(d, dict):
        what = "an array" if isinstance(d, list) else f"a {type(d).__name__}"
        raise ResultsError(f"not a ptpcert results object: the JSON is {what}, not an object with "
                           f"\"schema\": \"{SCHEMA}\"")
    if d.get("schema") not in SCHEMAS:
        raise ResultsError(f"schema: {d.get('schema')!r} is not a ptpcert results object "
                           f"(readable: {', '.join(SCHEMAS)})")
    for f in fields(RunResult):
        if f.name in d and f.name != "cases" and not _is(d[f.name], _kind_of(f.type)):
            raise ResultsError(f"{f.name}: must be {_type_name(_kind_of(f.type))}")
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
            if f.name in c and f.name != "divergence" and not _is(c[f.name], _kind_of(f.type)):
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
        if not _is(div.get(key), types):
            raise ResultsError(f"{where}.divergence.{key}: must be {_type_name(types)}")
    w = div.get("window")
    if w is not None and not (isinstance(w, list) and len(w) == 2 and all(_is(x, (int, float)) for x in w)):
        raise ResultsError(f"{where}.divergence.window: must be null or [from, to] in seconds")


def _check_frame(f: dict[str, Any], where: str) -> None:
    """A frame's fields (:data:`FRAME_FIELDS`) have their types."""
    for key in ("t0", "t1"):
        if not _is(f.get(key), (int, float)):
            raise ResultsError(f"{where}.{key}: must be a number (seconds)")
    if f.get("dir") not in ("tester", "iut"):
        raise ResultsError(f"{where}.dir: {f.get('dir')!r} (allowed: tester, iut)")
    for key, times in (("marks", ("t",)), ("windows", ("t0", "t1"))):
        items = f.get(key, [])
        if not isinstance(items, list):
            raise ResultsError(f"{where}.{key}: must be a list of objects")
        for k, m in enumerate(items):
            if not isinstance(m, dict) or not all(_is(m.get(t), (int, float)) for t in times):
                raise ResultsError(f"{where}.{key}[{k}]: must be an object with "
                                   + ", ".join(f"\"{t}\"" for t in times) + " (seconds) and \"name\"")


def _check_entry(e: dict[str, Any], where: str) -> None:
    for key in ("t", "t0", "t1", "duration"):
        if key in e and not _is(e[key], (int, float)):
            raise ResultsError(f"{where}.{key}: must be a number (seconds)")
    if "step" in e and not _is(e["step"], (int,)):
        raise ResultsError(f"{where}.step: must be an integer")
    kind = e.get("kind")
    if kind in BYTE_KINDS or kind in RUN_KINDS or kind == "break":
        if "t" not in e:
            raise ResultsError(f"{where}.t: missing")
        if e.get("dir") not in ("tester", "iut"):
            raise ResultsError(f"{where}.dir: {e.get('dir')!r} (allowed: tester, iut)")
    if kind in BYTE_KINDS and not (_is(e.get("byte"), (int,)) and 0 <= e["byte"] <= 255):
        raise ResultsError(f"{where}.byte: must be an integer 0..255")
    if kind in RUN_KINDS:
        try:
            n = len(run_bytes(e))
        except (TypeError, ValueError):
            raise ResultsError(f"{where}.base64: must be the run's bytes in base64, such as \"AhA=\"") from None
        times = e.get("times")
        if times is not None and not (isinstance(times, list) and len(times) == n
                                      and all(_is(x, (int, float)) for x in times)):
            raise ResultsError(f"{where}.times: must be a list of {n} times (seconds), one per byte")


# ------------------------------------------------------------------ writing reports
def write_atomic(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` whole or not at all: into a temporary file in the same
    directory, renamed over ``path`` when complete; the temporary file is removed whatever
    goes wrong."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.parent / f".{p.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
    try:
        with open(tmp, "x", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, p)
    except BaseException:
        try:
            tmp.unlink()
        except OSError:
            pass
        raise


def report_path_problem(path: str | Path) -> str | None:
    """Why a report cannot be written to ``path``, or None when it can. Checked before a
    run starts, so that no run ends without its reports: missing directories are created,
    and a file is created and removed in the target directory."""
    text = str(path)
    if not text.strip():
        return "is empty; give a file name"
    p = Path(path)
    if p.is_dir():
        return "is a directory; give a file name in it"
    if p.exists() and not p.is_file():
        return "exists and is not a regular file"
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return f"its directory {p.parent} cannot be created ({exc.strerror})"
    probe = p.parent / f".{p.name}.{os.getpid()}.{secrets.token_hex(4)}.probe"
    try:
        with open(probe, "x", encoding="utf-8"):
            pass
    except OSError as exc:
        return f"no file can be written in {p.parent} ({exc.strerror})"
    try:
        probe.unlink()
    except OSError:
        pass
    return None
