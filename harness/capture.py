"""Captures of a serial link: what two stations put on the line, with timestamps, read and
written in four formats.

A :class:`Capture` is a time-ordered list of :class:`Chunk` s. Each chunk has a time, the
*seat* whose transmit line it was seen on (``"a"`` or ``"b"``; in a capture that
``ptpcert run`` wrote, a is the tester and b the IUT), and either bytes or one line
condition. Around the chunks: who sits in each seat, the line settings, the absolute time of
t = 0, when the recording ended, free-form notes, and marks (timed text, e.g. where a case
starts). The module is procedure-neutral: it knows bytes and line conditions, no protocol.

Time
    ``t`` is seconds since the capture's start, rounded to the microsecond (all four formats
    hold microseconds). A chunk's time is when its last character was complete: handed to
    the line (the tester's own bytes) or read from it (everything received). The bytes of one
    chunk count as completed together at ``t``, as the model's ``"bytes"`` line event takes
    them; a recorder that cannot tell characters apart in time (a monitor that reads a port
    in bursts) makes chunks of several bytes, and its timing resolution is its read
    granularity. Converting a ``ptpcert run`` transcript keeps every byte's own time: bytes
    form one chunk only when they were logged at the same instant.

Line conditions (:class:`Cond`), one per chunk
    ``break``    the line held at space longer than a character frame; ``duration`` in
                 seconds when known.
    ``parity``   a character received with a parity error; ``data`` is the character as it
                 was read (may be empty when the recorder does not say).
    ``framing``  a character with a framing error (no stop bit); ``data`` as for parity.
    ``overrun``  the receiver of the recording side lost characters (UART overflow).
    ``lost``     the recording itself lost data here (buffer full, a dropped read).
    ``modem``    a modem-line change: ``lines`` is the set of lines now asserted, of
                 CTS, DCD, DSR, RTS, DTR, RI, MBOK, as the seat's own UART sees them.

    A transcript's ``char_error`` (what ptpcert's tester sends: a character with the wrong
    parity) is a ``parity`` chunk; a ``framing`` chunk becomes ``char_error`` with
    ``"error": "framing"``. The 3964/3964R model treats both as an invalid character.

Formats (``load``/``save`` choose by extension, or by name: ``json``, ``results``,
``hexlog``, ``pcap``)

1. **Capture JSON** (``.json``)::

       {"format": "ptpcert-capture/1",
        "start": "2026-01-31T09:00:00.000000+00:00",  # or null: t = 0 is not tied to a date
        "end": 0.734512,                               # or null: the recording ends at its last chunk
        "line": {"baud_rate": 9600, "data_bits": 8, "parity": "even", "stop_bits": 1},  # or null
        "seats": {"a": "tester", "b": "IUT"},
        "notes": ["free text", ...],
        "marks": [{"t": 0.0, "text": "case 3964R.D08 starts"}, ...],
        "chunks": [{"t": 0.001146, "seat": "a", "data": "02"},
                   {"t": 0.013, "seat": "a", "condition": "break", "duration": 0.05},
                   {"t": 0.02, "seat": "b", "condition": "parity", "data": "41"},
                   {"t": 0.03, "seat": "a", "condition": "modem", "lines": ["DTR", "RTS"]}]}

   ``data`` is hex, spaces allowed. Every field is carried.

2. **Results JSON** (``.json`` holding ``"schema": "ptpcert-results/1"``, what
   ``ptpcert run --json`` writes). Reading: one case's transcript (``case=ID``), or, without
   a case id and with several cases, the whole run on one timeline (each case placed at its
   own start time, or after the previous case with a 1 s gap when the clocks overlap, as
   under ``sim:``) with a mark where each case starts. Seat a is the tester, b the IUT; the
   line settings come from the case's parameters. Writing: a results object with one case
   (verdict ``not-run``: nothing was judged) whose transcript is the capture, so that
   ``ptpcert report`` draws it. Marks, the end, modem changes, overruns and losses travel as
   transcript entries the reports ignore (kinds ``mark``, ``end``, ``modem``, ``overrun``,
   ``lost``); seat names are fixed (tester, IUT).

3. **Hex log** (``.hexlog``, ``.log``, ``.txt``): plain text, one line per chunk::

       # ptpcert-hexlog 1
       # start: 2026-01-31T09:00:00.000000+00:00
       # line: 9600 8E1
       # a: tester
       # b: IUT
       # note: free text (one line per note)
       0.001146 a 02
       0.003229 b 10
       0.012000 a 41 42 10 10 10 03 51
       0.013000 a BREAK 50.000ms
       0.020000 b PARITY 41
       0.020500 b FRAMING
       0.030000 a MODEM DTR RTS
       0.031000 b OVERRUN
       0.032000 b LOST
       0.000000 - MARK case 3964R.D08 starts
       0.734512 - END

   Fields are separated by blanks: the time in seconds (the writer gives six decimals; the
   reader takes any decimal number, optionally with ``s`` or ``ms``), the seat (``a``,
   ``b``, or the name the header gives it, any case; ``-`` for a line about the capture, not
   a seat), then either bytes in hex (two digits each, blanks between them optional) or a
   condition word with its arguments: ``BREAK [duration]`` (``50ms``, ``0.05s``,
   ``50000us``), ``PARITY [hex]``, ``FRAMING [hex]``, ``MODEM [lines asserted]``,
   ``OVERRUN``, ``LOST``. Capture lines: ``- MARK text`` and ``- END`` (when the recording
   ended). Header lines are ``# key: value`` comments before the first record (keys
   ``start``, ``line`` as ``BAUD DATABITS PARITY STOPBITS`` with parity N, O, E, M or S and
   ``-`` for no baud rate, ``a``, ``b``, ``note``); other comments and blank lines are
   ignored anywhere, and on a record line a word that starts with ``#`` begins a comment
   (except in a MARK's text). Lines may come in any time order; the capture sorts them
   (stably).
   Every field is carried. A wrong line raises :class:`CaptureError` naming the file, the
   line number and what is wrong.

4. **pcap** (``.pcap``), link type LINKTYPE_RTAC_SERIAL (250), which Wireshark and tshark
   dissect as "RTAC Serial". The file is classic pcap (microsecond timestamps, written
   little-endian; the reader also takes big-endian and nanosecond files). Every record's
   data starts with the 12-byte RTAC serial header, big-endian::

       offset 0  4 bytes  seconds since 1970-01-01 UTC  } the same time as the record header
       offset 4  4 bytes  microseconds                  }
       offset 8  1 byte   event type
       offset 9  1 byte   UART control lines: CTS 01, DCD 02, DSR 04, RTS 08, DTR 10, RING 20, MBOK 40
       offset 10 2 bytes  footer (reserved by the link type; see below)
       offset 12 ...      payload

   Direction is the event type: seat a's bytes are DATA_TX_START (0x01), seat b's
   DATA_RX_START (0x02), as the recording device sees its own transmit and receive lines
   (the reader takes DATA_TX_END 0x03 and DATA_RX_END 0x04 alike). Conditions have event
   types of their own: STATUS_CHANGE 0x00 (``modem``, lines in the control-line byte),
   CAPTURE_DATA_LOST 0x05 (``lost``), FRAMING_ERROR 0x07 and PARITY_ERROR 0x08 (payload: the
   character(s) as read), SERIAL_BREAK_EVENT 0x09 (payload: empty, or the duration in
   microseconds as 4 bytes big-endian), SERIAL_OVERFLOW_EVENT 0x0A (``overrun``). These event
   types carry no direction, so on condition records ptpcert puts the seat in the footer:
   0x0001 seat a, 0x0002 seat b (mirroring the data event types); data records keep footer
   0. A condition record with another footer (a file from another recorder) is read as the
   recording device would have seen it: errors, BREAK, overflow and losses on its receive
   line (seat b), a STATUS_CHANGE on its own UART (seat a). The control-line byte of every
   record carries seat a's current modem lines; a change on a data record of another
   writer's file becomes a ``modem`` chunk.

   The first record is a STATUS_CHANGE with no line asserted at t = 0, so that the file
   fixes its own zero: the reader takes the first record's time as t = 0 and does not
   turn that record into a chunk. When the capture has an end, the last record is
   CAPTURE_COMPLETE (0x06) at that time. A capture without a start date is written from
   1970-01-01 00:00:00 and read back without one. Data chunks longer than a record allows
   (65523 bytes) are split into records with the same time. Seats' names, line settings,
   notes and marks have no place in pcap and are not carried.

Programs: :func:`load` and :func:`save` (files), :func:`from_transcript` /
:func:`to_transcript`, :func:`from_results` / :func:`to_results`, :func:`read_hexlog` /
:func:`write_hexlog` with the streaming :class:`HexLogWriter`, :func:`read_pcap` /
:func:`write_pcap` with the streaming :class:`PcapWriter`, and :meth:`Capture.line_events`,
which gives a seat's chunks as the model's line events.
"""

from __future__ import annotations

import datetime as _dt
import enum
import io
import json
import math
import re
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any, Iterable

from .model.line import LineSettings

JSON_FORMAT = "ptpcert-capture/1"
HEXLOG_MAGIC = "ptpcert-hexlog"
HEXLOG_VERSION = 1
LINKTYPE_RTAC_SERIAL = 250

SEATS = ("a", "b")
#: Transcript directions of the seats in a capture ``ptpcert run`` wrote.
TRANSCRIPT_DIR = {"a": "tester", "b": "iut"}
RUN_SEATS = {"a": "tester", "b": "IUT"}

#: Names of the file formats, and the extensions that choose them.
FORMATS = ("json", "results", "hexlog", "pcap")
EXTENSIONS = {".json": "json", ".hexlog": "hexlog", ".log": "hexlog", ".txt": "hexlog",
              ".pcap": "pcap", ".cap": "pcap"}

#: Modem lines, in the bit order of the RTAC control-line byte (bit 0 = CTS).
MODEM_LINES = ("CTS", "DCD", "DSR", "RTS", "DTR", "RI", "MBOK")
_LINE_ALIASES = {"RING": "RI"}

EPOCH = _dt.datetime(1970, 1, 1, tzinfo=_dt.timezone.utc)
_US = _dt.timedelta(microseconds=1)

#: The group of the one case of a results object written from a capture.
CAPTURE_GROUP = "capture"
#: Whole-run captures from a results object: the gap between cases whose clocks overlap.
CASE_GAP = 1.0


class Cond(enum.StrEnum):
    """A line condition (the module docstring says what each means)."""

    BREAK = "break"
    PARITY = "parity"
    FRAMING = "framing"
    OVERRUN = "overrun"
    LOST = "lost"
    MODEM = "modem"


#: Conditions whose chunk may hold the character(s) concerned.
_WITH_DATA = (Cond.PARITY, Cond.FRAMING)
#: Conditions that say the recording may have missed something (no line event for a model).
GAPS = (Cond.OVERRUN, Cond.LOST)


class CaptureError(ValueError):
    """A capture that cannot be read or written. ``source`` is the file (or ""), ``line``
    the line number in a hex log or the record number in a pcap file (or None)."""

    def __init__(self, message: str, source: str = "", line: int | None = None):
        self.message, self.source, self.line = message, str(source), line
        if self.source:
            where = self.source + ("" if line is None else f":{line}") + ": "
        else:
            where = "" if line is None else f"line {line}: "
        super().__init__(where + message)


# ------------------------------------------------------------------ the model


def checked_line(line: LineSettings) -> LineSettings:
    """``line``, when it is a frame a UART can have (see
    :meth:`~ptpcert.model.line.LineSettings.problem`); else a :class:`CaptureError` saying
    what is wrong."""
    problem = line.problem()
    if problem is not None:
        raise CaptureError(problem)
    return line


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


def parse_line(text: str) -> LineSettings:
    """Line settings from the header's ``line:`` value, ``BAUD DATABITS PARITY STOPBITS``
    as in ``9600 8E1`` (``-`` for no baud rate); a :class:`CaptureError` otherwise."""
    try:
        line = LineSettings.parse(text)
    except ValueError as exc:
        raise CaptureError(str(exc)) from None
    return checked_line(line)


def _time(t: Any, what: str = "time") -> float:
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t):
        raise CaptureError(f"{what} {t!r} is not a number of seconds")
    if t < 0:
        raise CaptureError(f"{what} {t!r} is before the capture's start (negative)")
    return round(float(t), 6)


@dataclass(frozen=True)
class Chunk:
    """Bytes, or one line condition, seen on one seat's transmit line at time ``t``."""

    t: float
    seat: str
    data: bytes = b""
    condition: Cond | None = None
    duration: float | None = None          # BREAK: seconds held, when known
    lines: frozenset[str] | None = None    # MODEM: the lines asserted after the change

    def __post_init__(self) -> None:
        object.__setattr__(self, "t", _time(self.t))
        if self.seat not in SEATS:
            raise CaptureError(f"seat {self.seat!r} is neither a nor b")
        object.__setattr__(self, "data", bytes(self.data))
        if self.condition is None:
            if not self.data:
                raise CaptureError(f"a chunk at {self.t:.6f} s has neither bytes nor a line condition")
        else:
            try:
                object.__setattr__(self, "condition", Cond(self.condition))
            except ValueError:
                raise CaptureError(f"{self.condition!r} is not a line condition "
                                   f"(one of {', '.join(c.value for c in Cond)})") from None
            if self.data and self.condition not in _WITH_DATA:
                raise CaptureError(f"a {self.condition} chunk carries no bytes")
        if self.duration is not None:
            if self.condition is not Cond.BREAK:
                raise CaptureError("only a BREAK has a duration")
            object.__setattr__(self, "duration", _time(self.duration, "BREAK duration"))
        if self.condition is Cond.MODEM:
            lines = frozenset(_LINE_ALIASES.get(x.upper(), x.upper()) for x in (self.lines or ()))
            bad = sorted(lines - set(MODEM_LINES))
            if bad:
                raise CaptureError(f"{bad[0]!r} is not a modem line (one of {', '.join(MODEM_LINES)})")
            object.__setattr__(self, "lines", lines)
        elif self.lines is not None:
            raise CaptureError("only a MODEM chunk has lines")

    @property
    def is_data(self) -> bool:
        return self.condition is None


@dataclass(frozen=True)
class Mark:
    """Timed text about the capture (a case starts, an operator's remark)."""

    t: float
    text: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "t", _time(self.t, "mark time"))
        if "\n" in self.text or "\r" in self.text:
            raise CaptureError("a mark's text is one line")


def _merged(chunks: list[Chunk]) -> list[Chunk]:
    """Adjacent chunks of one seat at one instant, both bytes (or both characters with the
    same error), are one chunk: every format then gives back what it was given."""
    out: list[Chunk] = []
    for c in chunks:
        p = out[-1] if out else None
        if (p is not None and p.t == c.t and p.seat == c.seat and p.condition == c.condition
                and (c.condition is None or c.condition in _WITH_DATA) and p.data and c.data):
            out[-1] = Chunk(p.t, p.seat, p.data + c.data, p.condition)
        else:
            out.append(c)
    return out


@dataclass
class Capture:
    """A recording of both directions of one serial link (see the module docstring)."""

    chunks: list[Chunk] = field(default_factory=list)
    seats: dict[str, str] = field(default_factory=lambda: {"a": "a", "b": "b"})
    line: LineSettings | None = None
    start: _dt.datetime | None = None      # the absolute time of t = 0 (UTC)
    end: float | None = None               # when the recording ended; None: at its last chunk
    notes: list[str] = field(default_factory=list)
    marks: list[Mark] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.chunks = _merged(sorted(self.chunks, key=lambda c: c.t))  # stable: equal times keep their order
        self.marks = sorted(self.marks, key=lambda m: m.t)
        self.seats = dict(self.seats)
        if self.line is not None:
            checked_line(self.line)
        if set(self.seats) != set(SEATS):
            raise CaptureError(f"seats must name a and b, not {sorted(self.seats)}")
        for s, name in self.seats.items():
            if not isinstance(name, str) or not name.strip() or "\n" in name:
                raise CaptureError(f"seat {s}'s name {name!r} must be a non-empty line of text")
        if self.start is not None:
            if self.start.tzinfo is None:
                self.start = self.start.replace(tzinfo=_dt.timezone.utc)
            self.start = self.start.astimezone(_dt.timezone.utc)
        if self.end is not None:
            self.end = _time(self.end, "end")
            last = self.chunks[-1].t if self.chunks else 0.0
            if self.end < last:
                raise CaptureError(f"the recording cannot end at {self.end:.6f} s, "
                                   f"before its last chunk ({last:.6f} s)")
        self.notes = list(self.notes)
        for n in self.notes:
            if "\n" in n or "\r" in n:
                raise CaptureError("a note is one line of text")

    # -- views ----------------------------------------------------------------------------
    @property
    def duration(self) -> float:
        """How long the line was watched (the end, or the last chunk's time)."""
        if self.end is not None:
            return self.end
        return self.chunks[-1].t if self.chunks else 0.0

    def seat_of(self, name: str) -> str | None:
        """The seat ("a" or "b") of a seat letter or name (any case), or None."""
        low = name.strip().lower()
        if low in SEATS:
            return low
        for s, n in self.seats.items():
            if n.lower() == low:
                return s
        return None

    def line_events(self, seat: str | None = None) -> list[tuple[float, str, str, Any]]:
        """The chunks as the model's line events, in time order: ``(t, seat, kind, value)``
        with kind ``"bytes"`` (value: bytes), ``"invalid"`` (value: the character, 0 when
        the recording does not say; one event per character) or ``"break"`` (value: the
        duration or None). ``seat`` selects one seat's transmit line, i.e. what the station
        in the *other* seat receives. Modem changes, overruns and losses are not line events
        for a station; look at :attr:`chunks` (and :data:`GAPS`) for them."""
        out: list[tuple[float, str, str, Any]] = []
        for c in self.chunks:
            if seat is not None and c.seat != seat:
                continue
            if c.condition is None:
                out.append((c.t, c.seat, "bytes", c.data))
            elif c.condition in _WITH_DATA:
                for b in c.data or b"\x00":
                    out.append((c.t, c.seat, "invalid", b))
            elif c.condition is Cond.BREAK:
                out.append((c.t, c.seat, "break", c.duration))
        return out

    def wire_bytes(self, seat: str) -> bytes:
        """All data bytes one seat sent, concatenated (conditions left out)."""
        return b"".join(c.data for c in self.chunks if c.seat == seat and c.condition is None)


# ------------------------------------------------------------------ capture JSON


def _iso(d: _dt.datetime | None) -> str | None:
    return None if d is None else d.isoformat(timespec="microseconds")


def _parse_start(text: Any, where: str = "start") -> _dt.datetime | None:
    if text in (None, ""):
        return None
    try:
        d = _dt.datetime.fromisoformat(str(text).strip().replace("Z", "+00:00"))
    except ValueError:
        raise CaptureError(f"{where} {text!r} is not an ISO 8601 date and time "
                           "(e.g. 2026-01-31T09:00:00.000000+00:00)") from None
    return (d if d.tzinfo else d.replace(tzinfo=_dt.timezone.utc)).astimezone(_dt.timezone.utc)


def _hex(data: bytes) -> str:
    return data.hex(" ").upper()


def _unhex(text: Any, where: str) -> bytes:
    if not isinstance(text, str):
        raise CaptureError(f"{where}: bytes must be a hex string, not {text!r}")
    try:
        return bytes.fromhex(text)
    except ValueError:
        raise CaptureError(f"{where}: {text!r} is not hex bytes (pairs of hex digits)") from None


def chunk_to_dict(c: Chunk) -> dict[str, Any]:
    d: dict[str, Any] = {"t": c.t, "seat": c.seat}
    if c.condition is not None:
        d["condition"] = c.condition.value
    if c.data:
        d["data"] = _hex(c.data)
    if c.duration is not None:
        d["duration"] = c.duration
    if c.lines is not None:
        d["lines"] = sorted(c.lines, key=MODEM_LINES.index)
    return d


def to_dict(cap: Capture) -> dict[str, Any]:
    """The capture as a JSON-ready object (format ``ptpcert-capture/1``)."""
    return {
        "format": JSON_FORMAT,
        "start": _iso(cap.start),
        "end": cap.end,
        "line": None if cap.line is None else line_to_dict(cap.line),
        "seats": dict(cap.seats),
        "notes": list(cap.notes),
        "marks": [{"t": m.t, "text": m.text} for m in cap.marks],
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
        return Capture(chunks, d.get("seats") or {"a": "a", "b": "b"},
                       None if line is None else line_from_dict(line),
                       _parse_start(d.get("start")), d.get("end"), list(d.get("notes", [])), marks)
    except CaptureError as exc:
        raise CaptureError(exc.message, source) from None
    except (TypeError, AttributeError) as exc:
        raise CaptureError(f"malformed capture: {exc}", source) from None


# ------------------------------------------------------------------ transcripts (results.json)

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
    from .results import unpack_transcript   # results.json keeps bytes as runs (schema 2)
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
                wire.append((_time(e["t"]) + offset, i, e))
            elif kind == "start" and "t" in e:
                marks.append(Mark(_time(e["t"]) + offset, "the steps start"))
            elif kind == "mark":
                marks.append(Mark(_time(e["t"]) + offset, str(e.get("text", ""))))
            elif kind == "end":
                end = _time(e["t"]) + offset
            elif kind == "window" and "t1" in e:
                watched = max(watched, _time(e["t1"], "window end") + offset)
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
        elif c.condition in _WITH_DATA:
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
    whole run on one timeline (see the module docstring)."""
    from . import results as R

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
        start = _parse_start(run.started, "the run's start")
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
        notes = [f"case {c.id}: {c.title}" + (f" ({c.reference})" if c.reference else ""),
                 f"verdict: {c.verdict}" + (f": {c.message}" if c.message else "")]
        if run.iut:
            notes.append(f"IUT: {run.iut}")
        notes += [n for n in c.notes if "\n" not in n]
        if c.group == CAPTURE_GROUP:
            notes = list(c.notes)   # a results object written from a capture: its notes as they were
        return from_transcript(c.transcript, line=_line_of_params(c.params), start=start, notes=notes, source=source)
    chunks: list[Chunk] = []
    marks: list[Mark] = []
    lines = {_line_of_params(c.params) for c in cases if c.transcript}
    line = lines.pop() if len(lines) == 1 else None
    notes = [f"run of {len(cases)} cases" + (f" against {run.iut}" if run.iut else "")]
    if len(lines) > 1:
        notes.append("the cases ran with different line settings; none is given")
    first_origin = next((c.origin for c in cases if c.transcript), 0.0)
    prev_end = -CASE_GAP
    for c in cases:
        if not c.transcript:
            continue
        offset = round(max(c.origin - first_origin, prev_end + CASE_GAP), 6)
        cs, ms, end = _transcript_items(c.transcript, offset, source)
        chunks += cs
        marks.append(Mark(offset, f"case {c.id} ({c.verdict})" + (f" {c.reference}" if c.reference else "")))
        marks += ms
        prev_end = max([offset] + [x.t for x in cs] + [m.t for m in ms] + ([end] if end is not None else []))
    return Capture(chunks, dict(RUN_SEATS), line, start, prev_end if chunks or marks else None, notes, marks)


def to_results(cap: Capture, case_id: str = "capture"):
    """A results object with one case whose transcript is the capture (verdict
    ``not-run``), for ``ptpcert report`` to draw."""
    from . import __version__
    from . import results as R

    c = R.CaseResult(case_id, "a capture converted to a transcript", "", "", CAPTURE_GROUP, "",
                     verdict=R.NOT_RUN, message="not judged: converted from a capture")
    c.transcript = to_transcript(cap)
    c.params = {} if cap.line is None else line_to_dict(cap.line)
    c.notes = list(cap.notes)
    return R.RunResult(tool_version=__version__, started=_iso(cap.start) or "", iut=cap.seats["b"],
                       cases=[c])


# ------------------------------------------------------------------ hex log

_COND_WORDS = {c.value.upper(): c for c in Cond}
_HEADER_KEYS = ("start", "line", "a", "b", "note")
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
            fp.write(f"# start: {_iso(meta.start)}\n")
        if meta.line is not None:
            fp.write(f"# line: {meta.line}\n")
        for s in SEATS:
            fp.write(f"# {s}: {meta.seats[s]}\n")
        for n in meta.notes:
            fp.write(f"# note: {n}\n")
        fp.write("# time (s) seat bytes in hex, or a line condition\n")

    def chunk(self, c: Chunk) -> None:
        if c.condition is None:
            rest = _hex(c.data)
        else:
            rest = c.condition.value.upper()
            if c.data:
                rest += " " + _hex(c.data)
            if c.duration is not None:
                rest += " " + _fmt_dur(c.duration)
            if c.lines:
                rest += " " + " ".join(sorted(c.lines, key=MODEM_LINES.index))
        self.fp.write(f"{c.t:.6f} {c.seat} {rest}\n")

    def mark(self, m: Mark) -> None:
        self.fp.write(f"{m.t:.6f} - MARK {m.text}\n")

    def close(self, end: float | None = None) -> None:
        if end is not None:
            self.fp.write(f"{_time(end, 'end'):.6f} - END\n")
        self.fp.flush()


def write_hexlog(cap: Capture, fp: IO[str]) -> None:
    w = HexLogWriter(fp, cap)
    items: list[tuple[float, int, Any]] = [(m.t, 0, m) for m in cap.marks] + [(c.t, 1, c) for c in cap.chunks]
    items.sort(key=lambda x: (x[0], x[1]))
    for _, _, x in items:
        (w.mark if isinstance(x, Mark) else w.chunk)(x)
    w.close(cap.end)


def hexlog_text(cap: Capture) -> str:
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


def read_hexlog(text: str | IO[str], source: str = "") -> Capture:
    """A capture from a hex log (see the module docstring). Raises :class:`CaptureError`
    with the line number and what is wrong."""
    if not isinstance(text, str):
        text = text.read()
    seats = {"a": "a", "b": "b"}
    line: LineSettings | None = None
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
                        start = _parse_start(value)
                    elif key == "line":
                        line = parse_line(value)
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
                    end = _time(t, "end")
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
        return Capture(chunks, seats, line, start, end, notes, marks)
    except CaptureError as exc:
        raise CaptureError(exc.message, source) from None


def _parse_condition(t: float, seat: str, cond: Cond, args: list[str]) -> Chunk:
    if cond is Cond.BREAK:
        if len(args) > 1:
            raise CaptureError(f"BREAK takes at most a duration (e.g. 50ms), not {' '.join(args)!r}")
        dur = _parse_time(args[0], "BREAK duration") if args else None
        return Chunk(t, seat, condition=cond, duration=dur)
    if cond in _WITH_DATA:
        data = bytearray()
        for tok in args:
            if not _HEXBYTE.fullmatch(tok):
                raise CaptureError(f"{cond.value.upper()} takes the character(s) in hex, not {tok!r}")
            data += bytes.fromhex(tok)
        return Chunk(t, seat, bytes(data), cond)
    if cond is Cond.MODEM:
        lines = {_LINE_ALIASES.get(x.upper(), x.upper()) for x in args}
        bad = sorted(lines - set(MODEM_LINES))
        if bad:
            raise CaptureError(f"{bad[0]!r} is not a modem line (MODEM lists the lines asserted: "
                               f"{', '.join(MODEM_LINES)})")
        return Chunk(t, seat, condition=cond, lines=frozenset(lines))
    if args:
        raise CaptureError(f"{cond.value.upper()} takes no arguments, not {' '.join(args)!r}")
    return Chunk(t, seat, condition=cond)


# ------------------------------------------------------------------ pcap (LINKTYPE_RTAC_SERIAL)

#: RTAC serial event types (the link type's definition).
EV_STATUS_CHANGE = 0x00
EV_DATA_TX_START = 0x01
EV_DATA_RX_START = 0x02
EV_DATA_TX_END = 0x03
EV_DATA_RX_END = 0x04
EV_CAPTURE_DATA_LOST = 0x05
EV_CAPTURE_COMPLETE = 0x06
EV_FRAMING_ERROR = 0x07
EV_PARITY_ERROR = 0x08
EV_SERIAL_BREAK = 0x09
EV_SERIAL_OVERFLOW = 0x0A

_COND_EVENT = {Cond.MODEM: EV_STATUS_CHANGE, Cond.LOST: EV_CAPTURE_DATA_LOST, Cond.FRAMING: EV_FRAMING_ERROR,
               Cond.PARITY: EV_PARITY_ERROR, Cond.BREAK: EV_SERIAL_BREAK, Cond.OVERRUN: EV_SERIAL_OVERFLOW}
_EVENT_COND = {v: k for k, v in _COND_EVENT.items()}
#: The footer on condition records: the seat (mirrors the data event types).
_SEAT_FOOTER = {"a": 0x0001, "b": 0x0002}
_FOOTER_SEAT = {v: k for k, v in _SEAT_FOOTER.items()}

PCAP_MAGIC_US = 0xA1B2C3D4
PCAP_MAGIC_NS = 0xA1B23C4D
PCAPNG_MAGIC = 0x0A0D0D0A
SNAPLEN = 65535
RTAC_HEADER = struct.Struct(">IIBBH")
MAX_PAYLOAD = SNAPLEN - RTAC_HEADER.size
_GLOBAL = struct.Struct("<IHHiIII")
_RECORD = struct.Struct("<IIII")


def _lines_byte(lines: Iterable[str] | None) -> int:
    return sum(1 << MODEM_LINES.index(x) for x in (lines or ()))


def _byte_lines(v: int) -> frozenset[str]:
    return frozenset(name for i, name in enumerate(MODEM_LINES) if v >> i & 1)


def _start_us(start: _dt.datetime | None) -> int:
    return 0 if start is None else (start - EPOCH) // _US


class PcapWriter:
    """Writes a pcap file record by record (for a recorder that writes as it goes): the
    global header and the start record at once, then one or more records per chunk."""

    def __init__(self, fp: IO[bytes], start: _dt.datetime | None = None):
        self.fp = fp
        self.base = _start_us(start)
        if self.base < 0:
            raise CaptureError("pcap cannot hold times before 1970")
        self.lines_a = 0
        fp.write(_GLOBAL.pack(PCAP_MAGIC_US, 2, 4, 0, 0, SNAPLEN, LINKTYPE_RTAC_SERIAL))
        self._record(0.0, EV_STATUS_CHANGE, 0, _SEAT_FOOTER["a"], b"")

    def _record(self, t: float, event: int, ctrl: int, footer: int, payload: bytes) -> None:
        us = self.base + round(_time(t) * 1_000_000)
        sec, usec = divmod(us, 1_000_000)
        if sec > 0xFFFFFFFF:
            raise CaptureError("pcap cannot hold times after 2106")
        body = RTAC_HEADER.pack(sec, usec, event, ctrl, footer) + payload
        self.fp.write(_RECORD.pack(sec, usec, len(body), len(body)) + body)

    def chunk(self, c: Chunk) -> None:
        if c.condition is None:
            event = EV_DATA_TX_START if c.seat == "a" else EV_DATA_RX_START
            for i in range(0, len(c.data), MAX_PAYLOAD):
                self._record(c.t, event, self.lines_a, 0, c.data[i:i + MAX_PAYLOAD])
            return
        footer = _SEAT_FOOTER[c.seat]
        ctrl = self.lines_a
        payload = b""
        if c.condition is Cond.MODEM:
            ctrl = _lines_byte(c.lines)
            if c.seat == "a":
                self.lines_a = ctrl
        elif c.condition is Cond.BREAK and c.duration is not None:
            payload = struct.pack(">I", min(round(c.duration * 1_000_000), 0xFFFFFFFF))
        elif c.condition in _WITH_DATA:
            payload = c.data
        for i in range(0, max(len(payload), 1), MAX_PAYLOAD):
            self._record(c.t, _COND_EVENT[c.condition], ctrl, footer, payload[i:i + MAX_PAYLOAD])

    def close(self, end: float | None = None) -> None:
        if end is not None:
            self._record(end, EV_CAPTURE_COMPLETE, self.lines_a, 0, b"")
        self.fp.flush()


def write_pcap(cap: Capture, fp: IO[bytes]) -> None:
    w = PcapWriter(fp, cap.start)
    for c in cap.chunks:
        w.chunk(c)
    w.close(cap.end)


def pcap_bytes(cap: Capture) -> bytes:
    buf = io.BytesIO()
    write_pcap(cap, buf)
    return buf.getvalue()


def read_pcap(data: bytes, source: str = "") -> Capture:
    """A capture from a pcap file of link type LINKTYPE_RTAC_SERIAL (see the module
    docstring). Errors name the record number (1 = the first record)."""
    if len(data) < 24:
        raise CaptureError(f"too short for a pcap file ({len(data)} bytes; the file header alone is 24)", source)
    (magic_le,) = struct.unpack_from("<I", data)
    if magic_le == PCAPNG_MAGIC:
        raise CaptureError("this is pcapng; ptpcert reads classic pcap (in Wireshark: File > Save As, "
                           "format 'Wireshark/tcpdump/... - pcap')", source)
    order = ""
    for o in ("<", ">"):
        (m,) = struct.unpack_from(o + "I", data)
        if m in (PCAP_MAGIC_US, PCAP_MAGIC_NS):
            order, nano = o, m == PCAP_MAGIC_NS
    if not order:
        raise CaptureError(f"not a pcap file (magic number {data[:4].hex()})", source)
    _, major, minor, _, _, _, network = struct.unpack_from(order + "IHHiIII", data)
    if major != 2:
        raise CaptureError(f"pcap version {major}.{minor} is not 2.x", source)
    if network & 0xFFFF != LINKTYPE_RTAC_SERIAL:
        raise CaptureError(f"link type {network & 0xFFFF} is not LINKTYPE_RTAC_SERIAL ({LINKTYPE_RTAC_SERIAL}); "
                           "ptpcert reads serial-line captures of that link type only", source)
    rec = struct.Struct(order + "IIII")
    pos, n = 24, 0
    records: list[tuple[int, int, int, int, int, bytes]] = []
    chunks: list[Chunk] = []
    notes: list[str] = []
    end: float | None = None
    lines_a = 0
    while pos < len(data):
        n += 1
        if pos + rec.size > len(data):
            raise CaptureError(f"the file ends inside the header of record {n}", source)
        sec, frac, incl, orig = rec.unpack_from(data, pos)
        pos += rec.size
        if pos + incl > len(data):
            raise CaptureError(f"record {n} says {incl} bytes, but only {len(data) - pos} remain "
                               "(the file is cut short)", source)
        body = data[pos:pos + incl]
        pos += incl
        if incl < orig:
            raise CaptureError(f"record {n} was cut to {incl} of {orig} bytes when captured (snapshot length)",
                               source)
        if incl < RTAC_HEADER.size:
            raise CaptureError(f"record {n} has {incl} bytes, fewer than the 12-byte RTAC serial header", source)
        us = sec * 1_000_000 + (round(frac / 1000) if nano else frac)
        _, _, event, ctrl, footer = RTAC_HEADER.unpack_from(body)
        records.append((n, us, event, ctrl, footer, body[RTAC_HEADER.size:]))
    # t = 0 is the earliest record (the first one, unless another recorder wrote them out of order)
    first_us = min((r[1] for r in records), default=None)
    for n, us, event, ctrl, footer, payload in records:
        t = (us - first_us) / 1_000_000
        try:
            if n == 1 and event == EV_STATUS_CHANGE and ctrl == 0 and not payload:
                continue     # the start record (ours, or a recorder's with nothing asserted)
            if event in (EV_DATA_TX_START, EV_DATA_TX_END, EV_DATA_RX_START, EV_DATA_RX_END):
                if ctrl != lines_a:   # another recorder's lines changed on a data record
                    chunks.append(Chunk(t, "a", condition=Cond.MODEM, lines=_byte_lines(ctrl)))
                    lines_a = ctrl
                if payload:
                    seat = "a" if event in (EV_DATA_TX_START, EV_DATA_TX_END) else "b"
                    chunks.append(Chunk(t, seat, payload))
            elif event == EV_CAPTURE_COMPLETE:
                end = t
            elif event in _EVENT_COND:
                cond = _EVENT_COND[event]
                default = "a" if cond is Cond.MODEM else "b"
                seat = _FOOTER_SEAT.get(footer, default)
                if cond is Cond.MODEM:
                    chunks.append(Chunk(t, seat, condition=cond, lines=_byte_lines(ctrl)))
                    if seat == "a":
                        lines_a = ctrl
                elif cond is Cond.BREAK:
                    dur = None
                    if len(payload) == 4:
                        dur = struct.unpack(">I", payload)[0] / 1_000_000
                    elif payload:
                        notes.append(f"record {n}: a BREAK with {len(payload)} payload bytes; duration not read")
                    chunks.append(Chunk(t, seat, condition=cond, duration=dur))
                elif cond in _WITH_DATA:
                    chunks.append(Chunk(t, seat, payload, cond))
                else:
                    chunks.append(Chunk(t, seat, condition=cond))
            else:
                notes.append(f"record {n}: event type 0x{event:02X} is unknown; skipped")
        except CaptureError as exc:
            raise CaptureError(f"record {n}: {exc.message}", source) from None
    start = None if not first_us else EPOCH + _dt.timedelta(microseconds=first_us)
    if end is not None and chunks and end < max(c.t for c in chunks):
        notes.append(f"CAPTURE_COMPLETE at {end:.6f} s comes before the last chunk; ignored")
        end = None
    return Capture(chunks, {"a": "a", "b": "b"}, None, start, end, notes)


# ------------------------------------------------------------------ files


def format_of(path: str | Path, given: str | None = None) -> str:
    """The format a path stands for: ``given`` when set, else by extension (``.json`` is
    ``json``; :func:`load` then tells a results object from a capture by its content)."""
    if given:
        if given not in FORMATS:
            raise CaptureError(f"unknown format {given!r} (one of {', '.join(FORMATS)})")
        return given
    ext = Path(str(path)).suffix.lower()
    if ext not in EXTENSIONS:
        raise CaptureError(f"cannot tell the format of {str(path)!r} from its extension; name it with "
                           f"--from/--to ({', '.join(FORMATS)}) or use one of {', '.join(EXTENSIONS)}")
    return EXTENSIONS[ext]


def loads_json(text: str, source: str = "", case: str | None = None) -> Capture:
    """A capture JSON, a results object (``case`` selects a case) or a bare transcript."""
    try:
        d = json.loads(text)
    except json.JSONDecodeError as exc:
        raise CaptureError(f"not JSON: {exc}", source) from None
    if isinstance(d, dict) and d.get("format") == JSON_FORMAT:
        if case is not None:
            raise CaptureError("a case id selects a case of a results object; this is a capture", source)
        return from_dict(d, source)
    if isinstance(d, dict) and "schema" in d:
        return from_results(d, case, source)
    if isinstance(d, list):
        return from_transcript(d, source=source)
    raise CaptureError(f"neither a ptpcert capture ({JSON_FORMAT!r}) nor a results object", source)


def load(path: str | Path, fmt: str | None = None, case: str | None = None) -> Capture:
    """Read a capture from a file in any of the formats (see :func:`format_of`)."""
    fmt = format_of(path, fmt)
    src = str(path)
    if case is not None and fmt not in ("json", "results"):
        raise CaptureError("a case id selects a case of a results object; a "
                           f"{ {'hexlog': 'hex log'}.get(fmt, fmt)} file has no cases", src)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise CaptureError(f"cannot be read: {exc.strerror}", src) from None
    if fmt == "pcap":
        return read_pcap(raw, src)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise CaptureError(f"not UTF-8 text (byte {exc.start}); is it a pcap file?", src) from None
    if fmt == "hexlog":
        return read_hexlog(text, src)
    return loads_json(text, src, case)


def dumps(cap: Capture, fmt: str, case_id: str = "capture") -> bytes:
    """The capture in format ``fmt``, as the bytes of a file."""
    if fmt == "pcap":
        return pcap_bytes(cap)
    if fmt == "hexlog":
        return hexlog_text(cap).encode()
    if fmt == "json":
        return (json.dumps(to_dict(cap), indent=1, ensure_ascii=False) + "\n").encode()
    if fmt == "results":
        return (json.dumps(to_results(cap, case_id).to_dict(), indent=1) + "\n").encode()
    raise CaptureError(f"unknown format {fmt!r} (one of {', '.join(FORMATS)})")


def save(cap: Capture, path: str | Path, fmt: str | None = None, case_id: str = "capture") -> None:
    """Write a capture to a file (format by ``fmt`` or the extension); written whole to a
    temporary file first, so a failed write leaves no half file."""
    fmt = format_of(path, fmt)
    data = dumps(cap, fmt, case_id)
    p = Path(path)
    tmp = p.with_name(p.name + ".tmp")
    try:
        tmp.write_bytes(data)
        tmp.replace(p)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise CaptureError(f"cannot be written: {exc.strerror}", str(path)) from None
