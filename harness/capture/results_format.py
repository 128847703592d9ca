"""The results format: a capture as the transcript of a case in a results object (what
``ptpcert run --json`` writes, schema ``ptpcert-results/1``), and back. Reading takes one
case, or a whole run laid out on one timeline with a mark where each case starts; writing
makes a results object with one case (verdict ``not-run``) that ``ptpcert report`` draws.
It sits between the capture's model and :mod:`ptpcert.results`, which it imports only
inside the functions that need it. Specified in ``docs/capture-formats.md`` ("Results
JSON").
"""

from __future__ import annotations

import datetime as _dt
import json
from pathlib import Path
from typing import Any, Iterable

from ptpcert.capture.json_format import LINE_DEFAULTS, line_from_dict, line_to_dict
from ptpcert.capture.model import (MODEM_LINES, WITH_DATA, Capture, CaptureError, Chunk, Cond, Mark, capture_time,
                                   iso_time, parse_start)
from ptpcert.capture.timing import Timing, run_timing
from ptpcert.model.line import LineSettings

#: Transcript directions of the seats in a capture ``ptpcert run`` wrote.
TRANSCRIPT_DIR = {"a": "tester", "b": "iut"}
RUN_SEATS = {"a": "tester", "b": "IUT"}
#: The group of the one case of a results object written from a capture.
CAPTURE_GROUP = "capture"
#: The note of a capture of a run that names the run's procedure (its title: "RK 512"),
#: so that ``analyze`` can tell a capture judged under another procedure's profile.
PROCEDURE_NOTE = "procedure: "
#: The mark (a whole run: where a case's parameters differ from the previous case's) or note
#: (one case) that carries a case's parameters as compact JSON, so that a reader of the
#: capture (the Wireshark dissector) knows the procedure's settings without the profile.
PARAMS_TAG = "parameters "
#: Whole-run captures from a results object: the gap between cases whose clocks overlap.
CASE_GAP = 1.0


_WIRE_KINDS = ("byte", "char_error", "break", "modem", "overrun", "lost")


def from_transcript(transcript: Iterable[dict[str, Any]], *, seats: dict[str, str] | None = None,
                    line: LineSettings | None = None, start: _dt.datetime | None = None,
                    notes: Iterable[str] = (), offset: float = 0.0, source: str = "") -> Capture:
    """A capture of a case's transcript (``CaseResult.transcript``): the tester is seat a,
    the IUT seat b. Bytes of one sender logged at the same instant form one chunk; every
    other byte keeps its own time. ``offset`` is added to every time. The harness's notes
    become marks (``start``: "the steps start"; ``mark``: its text); ``window`` notes
    only extend the end of the recording."""
    chunks, marks, end = _transcript_items(list(transcript), offset, source)
    return Capture(chunks, seats or dict(RUN_SEATS), line, start, end, list(notes), marks)


def _transcript_items(tr: list[dict[str, Any]], offset: float,
                      source: str) -> tuple[list[Chunk], list[Mark], float | None]:
    from ptpcert.results import unpack_transcript   # results.json keeps bytes as runs (schema 2)
    try:
        tr = unpack_transcript(tr)
    except (TypeError, ValueError, KeyError, AttributeError) as exc:
        raise CaptureError(f"a transcript run cannot be read ({exc})", source) from None
    dirs = {"tester": "a", "iut": "b", "a": "a", "b": "b"}
    wire: list[tuple[float, int, dict]] = []
    marks: list[Mark] = []
    end: float | None = None
    watched = -1.0
    for i, e in enumerate(tr):
        if not isinstance(e, dict):
            raise CaptureError(f"transcript entry {i + 1} is not an object", source)
        kind = e.get("kind")
        try:
            if kind in _WIRE_KINDS:
                if "t" not in e:
                    continue
                if e.get("dir") not in dirs:
                    raise CaptureError(f"direction {e.get('dir')!r} is neither tester nor iut")
                wire.append((capture_time(e["t"]) + offset, i, e))
            elif kind == "start" and "t" in e:
                marks.append(Mark(capture_time(e["t"]) + offset, "the steps start"))
            elif kind == "mark":
                marks.append(Mark(capture_time(e["t"]) + offset, str(e.get("text", ""))))
            elif kind == "end":
                end = capture_time(e["t"]) + offset
            elif kind == "window" and "t1" in e:
                watched = max(watched, capture_time(e["t1"], "window end") + offset)
        except CaptureError as exc:
            raise CaptureError(f"transcript entry {i + 1}: {exc.message}", source) from None
    wire.sort(key=lambda x: x[0])
    chunks: list[Chunk] = []
    pending: dict | None = None

    def flush() -> None:
        nonlocal pending
        if pending is not None:
            chunks.append(Chunk(pending["t"], pending["seat"], bytes(pending["data"]), pending["cond"]))
            pending = None

    for t, i, e in wire:
        seat = dirs[e["dir"]]
        kind = e["kind"]
        try:
            if kind in ("byte", "char_error"):
                cond = None if kind == "byte" else (Cond.FRAMING if e.get("error") == "framing" else Cond.PARITY)
                b = e.get("byte")
                unknown = kind == "char_error" and e.get("byte_unknown")
                if not unknown and (isinstance(b, bool) or not isinstance(b, int) or not 0 <= b <= 255):
                    raise CaptureError(f"byte {b!r} is not 0..255")
                if pending is not None and (pending["seat"], pending["cond"], pending["t"]) == (seat, cond, t) \
                        and not unknown and not pending["unknown"]:
                    pending["data"].append(b)
                    continue
                flush()
                pending = {"t": t, "seat": seat, "cond": cond, "data": bytearray([] if unknown else [b]),
                           "unknown": bool(unknown)}
                if unknown:
                    flush()
                continue
            flush()
            if kind == "break":
                chunks.append(Chunk(t, seat, condition=Cond.BREAK, duration=e.get("duration")))
            elif kind == "modem":
                chunks.append(Chunk(t, seat, condition=Cond.MODEM, lines=frozenset(e.get("lines", ()))))
            else:
                chunks.append(Chunk(t, seat, condition=Cond(kind)))
        except CaptureError as exc:
            raise CaptureError(f"transcript entry {i + 1}: {exc.message}", source) from None
    flush()
    if end is None and watched >= 0:
        last = chunks[-1].t if chunks else 0.0
        end = max(watched, last, max((m.t for m in marks), default=0.0))
    return chunks, marks, end


def to_transcript(cap: Capture) -> list[dict[str, Any]]:
    """The capture as a transcript (``CaseResult.transcript`` entries): one entry per byte,
    seat a as ``tester`` and b as ``iut``; marks and the end as ``dir: "note"`` entries."""
    out: list[tuple[float, int, dict[str, Any]]] = []
    for m in cap.marks:
        out.append((m.t, 0, {"t": m.t, "dir": "note", "kind": "mark", "text": m.text}))
    for c in cap.chunks:
        d = TRANSCRIPT_DIR[c.seat]
        if c.condition is None:
            for b in c.data:
                out.append((c.t, 1, {"t": c.t, "dir": d, "kind": "byte", "byte": b}))
        elif c.condition in WITH_DATA:
            extra = {"error": "framing"} if c.condition is Cond.FRAMING else {}
            if not c.data:
                out.append((c.t, 1, {"t": c.t, "dir": d, "kind": "char_error", "byte": 0,
                                     "byte_unknown": True, **extra}))
            for b in c.data:
                out.append((c.t, 1, {"t": c.t, "dir": d, "kind": "char_error", "byte": b, **extra}))
        elif c.condition is Cond.BREAK:
            e = {"t": c.t, "dir": d, "kind": "break"}
            if c.duration is not None:
                e["duration"] = c.duration
            out.append((c.t, 1, e))
        elif c.condition is Cond.MODEM:
            out.append((c.t, 1, {"t": c.t, "dir": d, "kind": "modem",
                                 "lines": sorted(c.lines or (), key=MODEM_LINES.index)}))
        else:
            out.append((c.t, 1, {"t": c.t, "dir": d, "kind": c.condition.value}))
    out.sort(key=lambda x: (x[0], x[1]))
    res = [e for _, _, e in out]
    if cap.end is not None:
        res.append({"t": cap.end, "dir": "note", "kind": "end"})
    return res


def params_text(params: dict[str, Any]) -> str:
    """The text of the mark or note that carries a case's parameters (``PARAMS_TAG``, then
    the parameters as compact JSON, keys sorted)."""
    return PARAMS_TAG + json.dumps(params, sort_keys=True, separators=(",", ":"))


def _line_of_params(params: dict[str, Any]) -> LineSettings | None:
    if not params or "data_bits" not in params:
        return None
    try:
        return line_from_dict({k: params.get(k) for k in LINE_DEFAULTS})
    except CaptureError:
        return None


def from_results(run: Any, case: str | None = None, source: str = "") -> Capture:
    """A capture of a results object (a :class:`~ptpcert.results.RunResult`, its JSON
    object, or a path): the case ``case``, or with ``case=None`` the only case or else the
    whole run on one timeline (docs/capture-formats.md, "Results JSON")."""
    from ptpcert import results as R

    if isinstance(run, (str, Path)):
        source = source or str(run)
        try:
            run = R.RunResult.read_json(run)
        except ValueError as exc:
            raise CaptureError(str(exc)) from None
    elif isinstance(run, dict):
        try:
            run = R.RunResult.from_dict(run)
        except (ValueError, KeyError, TypeError) as exc:
            raise CaptureError(f"not a ptpcert results object ({exc})", source) from None
    start = None
    try:
        start = parse_start(run.started, "the run's start")
    except CaptureError:
        pass
    if case is not None:
        found = [c for c in run.cases if c.id == case]
        if not found:
            near = [c.id for c in run.cases if case.lower() in c.id.lower()][:5]
            hint = f"; did you mean {', '.join(near)}" if near else ""
            raise CaptureError(f"no case {case!r} among the {len(run.cases)} cases of the results{hint}", source)
        cases = found
    else:
        cases = list(run.cases)
    if len(cases) == 1:
        c = cases[0]
        line = _line_of_params(c.params)
        notes = [f"case {c.id}: {c.title}" + (f" ({c.reference})" if c.reference else ""),
                 f"verdict: {c.verdict}" + (f": {c.message}" if c.message else "")]
        if run.iut:
            notes.append(f"IUT: {run.iut}")
        if run.procedure:
            notes.append(PROCEDURE_NOTE + run.procedure)
        if c.params:
            notes.append(params_text(c.params))
        notes += [n for n in c.notes if "\n" not in n]
        timing = _run_timing(run.iut, line)
        if c.group == CAPTURE_GROUP:
            # a results object written from a capture: its notes as they were, and its timing
            notes = [n for n in c.notes if not n.startswith(_TIMING_NOTE)]
            said = [n[len(_TIMING_NOTE):] for n in c.notes if n.startswith(_TIMING_NOTE)]
            timing = Timing.parse(said[0]) if said else None
        cap = from_transcript(c.transcript, line=line, start=start, notes=notes, source=source)
        cap.timing = timing
        return cap
    chunks: list[Chunk] = []
    marks: list[Mark] = []
    lines = {_line_of_params(c.params) for c in cases if c.transcript}
    line = lines.pop() if len(lines) == 1 else None
    notes = [f"run of {len(cases)} cases" + (f" against {run.iut}" if run.iut else "")]
    if run.procedure:
        notes.append(PROCEDURE_NOTE + run.procedure)
    if len(lines) > 1:
        notes.append("the cases ran with different line settings; none is given")
    first_origin = next((c.origin for c in cases if c.transcript), 0.0)
    prev_end = -CASE_GAP
    said = None
    for c in cases:
        if not c.transcript:
            continue
        offset = round(max(c.origin - first_origin, prev_end + CASE_GAP), 6)
        cs, ms, end = _transcript_items(c.transcript, offset, source)
        chunks += cs
        marks.append(Mark(offset, f"case {c.id} ({c.verdict})" + (f" {c.reference}" if c.reference else "")))
        if c.params and c.params != said:
            marks.append(Mark(offset, params_text(c.params)))
            said = c.params
        marks += ms
        prev_end = max([offset] + [x.t for x in cs] + [m.t for m in ms] + ([end] if end is not None else []))
    return Capture(chunks, dict(RUN_SEATS), line, start, prev_end if chunks or marks else None, notes, marks,
                   _run_timing(run.iut, line))


#: the note of a results object written from a capture that keeps the capture's timing
_TIMING_NOTE = "capture timing: "


def _run_timing(iut: str, line: LineSettings | None) -> Timing | None:
    """How a run's transcript times were taken (None when the results do not name the IUT)."""
    if not iut:
        return None
    return run_timing(iut, line.char_time if line is not None and line.baud_rate else None)


def to_results(cap: Capture, case_id: str = "capture"):
    """A results object with one case whose transcript is the capture (verdict
    ``not-run``), for ``ptpcert report`` to draw."""
    from ptpcert import __version__
    from ptpcert import results as R

    c = R.CaseResult(case_id, "a capture converted to a transcript", "", "", CAPTURE_GROUP, "",
                     verdict=R.NOT_RUN, message="not judged: converted from a capture")
    c.transcript = to_transcript(cap)
    c.params = {} if cap.line is None else line_to_dict(cap.line)
    c.notes = list(cap.notes) + ([] if cap.timing is None else [_TIMING_NOTE + cap.timing.text()])
    return R.RunResult(tool_version=__version__, started=iso_time(cap.start) or "", iut=cap.seats["b"],
                       cases=[c])

