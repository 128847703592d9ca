"""The hex log (``.hexlog``, ``.log``, ``.txt``): a capture as plain text, one line per chunk,
for people to read, write by hand and diff. :class:`HexLogWriter` writes one as it goes
(``ptpcert monitor``), :func:`write_hexlog` / :func:`hexlog_text` a whole capture, and
:func:`read_hexlog` reads one tolerantly, reporting a wrong line by its number. Built on the
capture's model; specified in ``docs/capture-formats.md`` ("Hex log").
"""

from __future__ import annotations

import io
import re
from typing import IO, Any

from ptpcert.capture.model import (LINE_ALIASES, MODEM_LINES, SEATS, WITH_DATA, Capture, CaptureError, Chunk, Cond,
                                   Mark, capture_time, checked_line, hex_text, iso_time, parse_start)
from ptpcert.capture.timing import Timing
from ptpcert.model.line import LineSettings

HEXLOG_MAGIC = "ptpcert-hexlog"
HEXLOG_VERSION = 1

_COND_WORDS = {c.value.upper(): c for c in Cond}
_HEADER_KEYS = ("start", "line", "timing", "a", "b", "note")
_TIME_RE = re.compile(r"(\d+(?:\.\d*)?|\.\d+)(s|ms|us)?", re.IGNORECASE)
_HEXBYTE = re.compile(r"(?:[0-9A-Fa-f]{2})+")


def _fmt_dur(d: float) -> str:
    return f"{d * 1000:.3f}ms"


class HexLogWriter:
    """Writes a hex log line by line (for a recorder that writes as it goes). The header
    comes from ``meta`` (its seats, line, start and notes; its chunks are not written)."""

    def __init__(self, fp: IO[str], meta: Capture):
        self.fp, self.meta = fp, meta
        fp.write(f"# {HEXLOG_MAGIC} {HEXLOG_VERSION}\n")
        if meta.start is not None:
            fp.write(f"# start: {iso_time(meta.start)}\n")
        if meta.line is not None:
            fp.write(f"# line: {meta.line}\n")
        if meta.timing is not None:
            fp.write(f"# timing: {meta.timing.text()}\n")
        for s in SEATS:
            fp.write(f"# {s}: {meta.seats[s]}\n")
        for n in meta.notes:
            fp.write(f"# note: {n}\n")
        fp.write("# time (s) seat bytes in hex, or a line condition\n")

    def chunk(self, c: Chunk) -> None:
        if c.condition is None:
            rest = hex_text(c.data)
        else:
            rest = c.condition.value.upper()
            if c.data:
                rest += " " + hex_text(c.data)
            if c.duration is not None:
                rest += " " + _fmt_dur(c.duration)
            if c.lines:
                rest += " " + " ".join(sorted(c.lines, key=MODEM_LINES.index))
        self.fp.write(f"{c.t:.6f} {c.seat} {rest}\n")

    def mark(self, m: Mark) -> None:
        self.fp.write(f"{m.t:.6f} - MARK {m.text}\n")

    def close(self, end: float | None = None) -> None:
        if end is not None:
            self.fp.write(f"{capture_time(end, 'end'):.6f} - END\n")
        self.fp.flush()


def write_hexlog(cap: Capture, fp: IO[str]) -> None:
    """Write the whole capture as a hex log: header, then marks and chunks in time order
    (a mark before a chunk at the same time), then the end."""
    w = HexLogWriter(fp, cap)
    items: list[tuple[float, int, Any]] = [(m.t, 0, m) for m in cap.marks] + [(c.t, 1, c) for c in cap.chunks]
    items.sort(key=lambda x: (x[0], x[1]))
    for _, _, x in items:
        (w.mark if isinstance(x, Mark) else w.chunk)(x)
    w.close(cap.end)


def hexlog_text(cap: Capture) -> str:
    """The capture as the text of a hex log file."""
    buf = io.StringIO()
    write_hexlog(cap, buf)
    return buf.getvalue()


def _parse_time(tok: str, what: str) -> float:
    m = _TIME_RE.fullmatch(tok)
    if not m:
        raise CaptureError(f"{what} {tok!r} is not a number of seconds (e.g. 0.012500)")
    v = float(m.group(1))
    unit = (m.group(2) or "s").lower()
    return v / {"s": 1, "ms": 1e3, "us": 1e6}[unit]


def parse_line(text: str) -> LineSettings:
    """Line settings from the header's ``line:`` value, ``BAUD DATABITS PARITY STOPBITS``
    as in ``9600 8E1`` (``-`` for no baud rate); a :class:`CaptureError` otherwise."""
    try:
        line = LineSettings.parse(text)
    except ValueError as exc:
        raise CaptureError(str(exc)) from None
    return checked_line(line)


def read_hexlog(text: str | IO[str], source: str = "") -> Capture:
    """A capture from a hex log (docs/capture-formats.md, "Hex log"). Raises
    :class:`CaptureError` with the line number and what is wrong."""
    if not isinstance(text, str):
        text = text.read()
    seats = {"a": "a", "b": "b"}
    line: LineSettings | None = None
    timing: Timing | None = None
    start = None
    notes: list[str] = []
    chunks: list[Chunk] = []
    marks: list[Mark] = []
    end: float | None = None
    in_header = True
    names: dict[str, str] = {}

    for no, raw in enumerate(text.splitlines(), 1):
        s = raw.strip()
        if not s:
            continue
        try:
            if s.startswith("#"):
                body = s[1:].strip()
                if no == 1 or (in_header and body.lower().startswith(HEXLOG_MAGIC)):
                    m = re.fullmatch(re.escape(HEXLOG_MAGIC) + r"\s+(\d+)", body, re.IGNORECASE)
                    if m and int(m.group(1)) > HEXLOG_VERSION:
                        raise CaptureError(f"hex log version {m.group(1)} is newer than this ptpcert reads "
                                           f"(version {HEXLOG_VERSION})")
                    if m:
                        continue
                key, sep, value = body.partition(":")
                key = key.strip().lower()
                if in_header and sep and key in _HEADER_KEYS:
                    value = value.strip()
                    if key == "start":
                        start = parse_start(value)
                    elif key == "line":
                        line = parse_line(value)
                    elif key == "timing":
                        timing = Timing.parse(value)
                    elif key == "note":
                        notes.append(value)
                    else:
                        if not value:
                            raise CaptureError(f"seat {key} needs a name after '{key}:'")
                        seats[key] = value
                continue
            if in_header:
                in_header = False
                for s_, n in seats.items():
                    names[n.lower()] = s_
                names.update({"a": "a", "b": "b"})
            fields_ = s.split()
            if "#" in s and len(fields_) > 2 and fields_[2].upper() != "MARK":
                # after bytes or a condition, a word starting with '#' begins a comment
                cut = next((i for i, f in enumerate(fields_) if f.startswith("#")), len(fields_))
                fields_ = fields_[:cut]
            if len(fields_) < 2:
                raise CaptureError(f"expected a time, a seat and bytes or a condition; got {s!r}")
            t = _parse_time(fields_[0], "time")
            who, rest = fields_[1], fields_[2:]
            if who == "-":
                word = rest[0].upper() if rest else ""
                if word == "END" and len(rest) == 1:
                    end = capture_time(t, "end")
                elif word == "MARK":
                    marks.append(Mark(t, s.split(None, 3)[3] if len(rest) > 1 else ""))
                else:
                    raise CaptureError(f"a line with seat '-' is '- MARK text' or '- END', not {' '.join(rest)!r}")
                continue
            seat = names.get(who.lower())
            if seat is None:
                known = ", ".join(dict.fromkeys(["a", "b", seats["a"], seats["b"]]))
                raise CaptureError(f"seat {who!r} is not one of {known} (or '-' for MARK/END)")
            if not rest:
                raise CaptureError("no bytes and no condition after the seat")
            word = rest[0].upper()
            if word in _COND_WORDS:
                chunks.append(_parse_condition(t, seat, _COND_WORDS[word], rest[1:]))
                continue
            data = bytearray()
            for tok in rest:
                if not _HEXBYTE.fullmatch(tok):
                    if re.fullmatch(r"[0-9A-Fa-f]+", tok):
                        raise CaptureError(f"{tok!r} has an odd number of hex digits (bytes are two digits each)")
                    raise CaptureError(f"{tok!r} is neither hex bytes nor a condition "
                                       f"({', '.join(_COND_WORDS)})")
                data += bytes.fromhex(tok)
            chunks.append(Chunk(t, seat, bytes(data)))
        except CaptureError as exc:
            raise CaptureError(exc.message, source, no) from None
    try:
        return Capture(chunks, seats, line, start, end, notes, marks, timing)
    except CaptureError as exc:
        raise CaptureError(exc.message, source) from None


def _parse_condition(t: float, seat: str, cond: Cond, args: list[str]) -> Chunk:
    if cond is Cond.BREAK:
        if len(args) > 1:
            raise CaptureError(f"BREAK takes at most a duration (e.g. 50ms), not {' '.join(args)!r}")
        dur = _parse_time(args[0], "BREAK duration") if args else None
        return Chunk(t, seat, condition=cond, duration=dur)
    if cond in WITH_DATA:
        data = bytearray()
        for tok in args:
            if not _HEXBYTE.fullmatch(tok):
                raise CaptureError(f"{cond.value.upper()} takes the character(s) in hex, not {tok!r}")
            data += bytes.fromhex(tok)
        return Chunk(t, seat, bytes(data), cond)
    if cond is Cond.MODEM:
        lines = {LINE_ALIASES.get(x.upper(), x.upper()) for x in args}
        bad = sorted(lines - set(MODEM_LINES))
        if bad:
            raise CaptureError(f"{bad[0]!r} is not a modem line (MODEM lists the lines asserted: "
                               f"{', '.join(MODEM_LINES)})")
        return Chunk(t, seat, condition=cond, lines=frozenset(lines))
    if args:
        raise CaptureError(f"{cond.value.upper()} takes no arguments, not {' '.join(args)!r}")
    return Chunk(t, seat, condition=cond)

