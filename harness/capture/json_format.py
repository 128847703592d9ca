"""Capture JSON (format ``ptpcert-capture/1``, ``.json``): a capture as one JSON object that
carries every field of :class:`~ptpcert.capture.model.Capture`. :func:`to_dict` and
:func:`from_dict` convert; :mod:`ptpcert.capture.files` turns them into files. Also the
JSON form of a capture's line settings, which the results format shares
(:func:`line_to_dict`, :func:`line_from_dict`). The format is specified in
``docs/capture-formats.md`` ("Capture JSON").
"""

from __future__ import annotations

from typing import Any

from ptpcert.capture.model import (MODEM_LINES, Capture, CaptureError, Chunk, Mark, checked_line, hex_text,
                                   iso_time, parse_start)
from ptpcert.capture.timing import Timing
from ptpcert.model.line import LineSettings

JSON_FORMAT = "ptpcert-capture/1"

#: The JSON fields of line settings, each with the value a reader takes when a file omits
#: it: no baud rate and an 8N1 frame (not :class:`~ptpcert.model.line.LineSettings`' own
#: defaults, which are the reference profile's 9600 8E1).
LINE_DEFAULTS: dict[str, Any] = {"baud_rate": None, "data_bits": 8, "parity": "none", "stop_bits": 1}


def line_to_dict(line: LineSettings) -> dict[str, Any]:
    """Line settings as a JSON object (the fields of :data:`LINE_DEFAULTS`, in that order)."""
    return {k: getattr(line, k) for k in LINE_DEFAULTS}


def line_from_dict(d: Any) -> LineSettings:
    """Line settings from their JSON object, omitted fields as :data:`LINE_DEFAULTS` says;
    a :class:`CaptureError` when ``d`` is no object or the settings are no frame."""
    try:
        values = {k: d.get(k, v) for k, v in LINE_DEFAULTS.items()}
    except AttributeError:
        raise CaptureError(f"line settings must be an object, not {d!r}") from None
    return checked_line(LineSettings(**values))


def _unhex(text: Any, where: str) -> bytes:
    if not isinstance(text, str):
        raise CaptureError(f"{where}: bytes must be a hex string, not {text!r}")
    try:
        return bytes.fromhex(text)
    except ValueError:
        raise CaptureError(f"{where}: {text!r} is not hex bytes (pairs of hex digits)") from None


def chunk_to_dict(c: Chunk) -> dict[str, Any]:
    """One chunk as its JSON object: time and seat, and of the rest only what it has."""
    d: dict[str, Any] = {"t": c.t, "seat": c.seat}
    if c.condition is not None:
        d["condition"] = c.condition.value
    if c.data:
        d["data"] = hex_text(c.data)
    if c.duration is not None:
        d["duration"] = c.duration
    if c.lines is not None:
        d["lines"] = sorted(c.lines, key=MODEM_LINES.index)
    return d


def to_dict(cap: Capture) -> dict[str, Any]:
    """The capture as a JSON-ready object (format ``ptpcert-capture/1``)."""
    return {
        "format": JSON_FORMAT,
        "start": iso_time(cap.start),
        "end": cap.end,
        "line": None if cap.line is None else line_to_dict(cap.line),
        "seats": dict(cap.seats),
        "notes": list(cap.notes),
        "marks": [{"t": m.t, "text": m.text} for m in cap.marks],
        "timing": None if cap.timing is None else cap.timing.to_dict(),
        "chunks": [chunk_to_dict(c) for c in cap.chunks],
    }


def from_dict(d: Any, source: str = "") -> Capture:
    """A capture from its JSON object (format ``ptpcert-capture/1``)."""
    if not isinstance(d, dict) or d.get("format") != JSON_FORMAT:
        got = d.get("format") if isinstance(d, dict) else type(d).__name__
        raise CaptureError(f"not a ptpcert capture (format {got!r}, expected {JSON_FORMAT!r})", source)
    try:
        chunks = []
        for i, c in enumerate(d.get("chunks", [])):
            where = f"chunk {i + 1}"
            if not isinstance(c, dict):
                raise CaptureError(f"{where} is not an object")
            unknown = sorted(set(c) - {"t", "seat", "data", "condition", "duration", "lines"})
            if unknown:
                raise CaptureError(f"{where}: unknown field {unknown[0]!r}")
            try:
                chunks.append(Chunk(c.get("t"), c.get("seat"), _unhex(c.get("data", ""), where),
                                    c.get("condition"), c.get("duration"),
                                    None if c.get("lines") is None else frozenset(c["lines"])))
            except CaptureError as exc:
                raise CaptureError(f"{where}: {exc.message}") from None
        marks = [Mark(m.get("t"), str(m.get("text", ""))) for m in d.get("marks", [])]
        line = d.get("line")
        timing = d.get("timing")
        return Capture(chunks, d.get("seats") or {"a": "a", "b": "b"},
                       None if line is None else line_from_dict(line),
                       parse_start(d.get("start")), d.get("end"), list(d.get("notes", [])), marks,
                       None if timing is None else Timing.from_dict(timing))
    except CaptureError as exc:
        raise CaptureError(exc.message, source) from None
    except (TypeError, AttributeError) as exc:
        raise CaptureError(f"malformed capture: {exc}", source) from None

