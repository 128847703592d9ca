"""The data model of a capture: :class:`Capture`, its :class:`Chunk` s and :class:`Mark` s,
the line conditions (:class:`Cond`), and :class:`CaptureError`, which every reader and
writer of the package raises. It sits at the bottom of :mod:`ptpcert.capture`: the file
formats (``json_format``, ``results_format``, ``hexlog``, ``pcap``) build on it, and it
imports none of them. Procedure-neutral: bytes and line conditions, no protocol.

Besides the classes it holds what every format shares: a capture's times (seconds since
its start, rounded to the microsecond, :func:`capture_time`), the start date and bytes as
text (:func:`iso_time`, :func:`parse_start`, :func:`hex_text`), and the check of the line
settings a capture carries (:func:`checked_line`; the settings are the neutral
:class:`ptpcert.model.line.LineSettings`). The specification of the formats is
``docs/capture-formats.md``.
"""

from __future__ import annotations

import datetime as _dt
import enum
import math
from dataclasses import dataclass, field
from typing import Any

from ptpcert.model.line import LineSettings

SEATS = ("a", "b")

#: Modem lines, in the bit order of the RTAC control-line byte (bit 0 = CTS).
MODEM_LINES = ("CTS", "DCD", "DSR", "RTS", "DTR", "RI", "MBOK")
#: Other names a reader accepts for a modem line.
LINE_ALIASES = {"RING": "RI"}


class Cond(enum.StrEnum):
    """A line condition, one per chunk (docs/capture-formats.md, "Line conditions", says
    what each means)."""

    BREAK = "break"
    PARITY = "parity"
    FRAMING = "framing"
    OVERRUN = "overrun"
    LOST = "lost"
    MODEM = "modem"


#: Conditions whose chunk may hold the character(s) concerned.
WITH_DATA = (Cond.PARITY, Cond.FRAMING)
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


def checked_line(line: LineSettings) -> LineSettings:
    """``line``, when it is a frame a UART can have (see
    :meth:`~ptpcert.model.line.LineSettings.problem`); else a :class:`CaptureError` saying
    what is wrong."""
    problem = line.problem()
    if problem is not None:
        raise CaptureError(problem)
    return line


# ------------------------------------------------------------------ the model


def capture_time(t: Any, what: str = "time") -> float:
    """``t`` as a time of the capture: seconds since its start, rounded to the microsecond
    (what every format holds). A :class:`CaptureError` names ``what`` when ``t`` is no
    number or negative."""
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
        object.__setattr__(self, "t", capture_time(self.t))
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
            if self.data and self.condition not in WITH_DATA:
                raise CaptureError(f"a {self.condition} chunk carries no bytes")
        if self.duration is not None:
            if self.condition is not Cond.BREAK:
                raise CaptureError("only a BREAK has a duration")
            object.__setattr__(self, "duration", capture_time(self.duration, "BREAK duration"))
        if self.condition is Cond.MODEM:
            lines = frozenset(LINE_ALIASES.get(x.upper(), x.upper()) for x in (self.lines or ()))
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
        object.__setattr__(self, "t", capture_time(self.t, "mark time"))
        if "\n" in self.text or "\r" in self.text:
            raise CaptureError("a mark's text is one line")


def _merged(chunks: list[Chunk]) -> list[Chunk]:
    """Adjacent chunks of one seat at one instant, both bytes (or both characters with the
    same error), are one chunk: every format then gives back what it was given."""
    out: list[Chunk] = []
    for c in chunks:
        p = out[-1] if out else None
        if (p is not None and p.t == c.t and p.seat == c.seat and p.condition == c.condition
                and (c.condition is None or c.condition in WITH_DATA) and p.data and c.data):
            out[-1] = Chunk(p.t, p.seat, p.data + c.data, p.condition)
        else:
            out.append(c)
    return out


@dataclass
class Capture:
    """A recording of both directions of one serial link: chunks in time order (adjacent
    ones of one seat at one instant merged), who sits in each seat, the line settings, the
    absolute time of t = 0, when the recording ended, notes and marks, and how its times
    were taken."""

    chunks: list[Chunk] = field(default_factory=list)
    seats: dict[str, str] = field(default_factory=lambda: {"a": "a", "b": "b"})
    line: LineSettings | None = None
    start: _dt.datetime | None = None      # the absolute time of t = 0 (UTC)
    end: float | None = None               # when the recording ended; None: at its last chunk
    notes: list[str] = field(default_factory=list)
    marks: list[Mark] = field(default_factory=list)
    #: how the times were taken (:class:`ptpcert.capture.timing.Timing`); None: not said
    #: (a capture written before captures said it, or another recorder's)
    timing: Any = None

    def __post_init__(self) -> None:
        if self.timing is not None:
            if not hasattr(self.timing, "resolution"):   # a Timing (capture.timing builds on this module)
                raise CaptureError(f"timing must be a Timing, not {self.timing!r}")
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
            self.end = capture_time(self.end, "end")
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
            elif c.condition in WITH_DATA:
                for b in c.data or b"\x00":
                    out.append((c.t, c.seat, "invalid", b))
            elif c.condition is Cond.BREAK:
                out.append((c.t, c.seat, "break", c.duration))
        return out

    def wire_bytes(self, seat: str) -> bytes:
        """All data bytes one seat sent, concatenated (conditions left out)."""
        return b"".join(c.data for c in self.chunks if c.seat == seat and c.condition is None)



# ------------------------------------------------------------------ text forms the formats share


def iso_time(d: _dt.datetime | None) -> str | None:
    """A capture's start as the formats write it: ISO 8601 to the microsecond (None stays
    None)."""
    return None if d is None else d.isoformat(timespec="microseconds")


def parse_start(text: Any, where: str = "start") -> _dt.datetime | None:
    """A start date from its ISO 8601 text, in UTC (a date without a zone is taken as UTC;
    None or "" is no date). A :class:`CaptureError` names ``where`` when it is none."""
    if text in (None, ""):
        return None
    try:
        d = _dt.datetime.fromisoformat(str(text).strip().replace("Z", "+00:00"))
    except ValueError:
        raise CaptureError(f"{where} {text!r} is not an ISO 8601 date and time "
                           "(e.g. 2026-01-31T09:00:00.000000+00:00)") from None
    return (d if d.tzinfo else d.replace(tzinfo=_dt.timezone.utc)).astimezone(_dt.timezone.utc)


def hex_text(data: bytes) -> str:
    """Bytes as the text formats write them: upper-case hex pairs, blank-separated."""
    return data.hex(" ").upper()

