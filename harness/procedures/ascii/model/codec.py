"""Pure byte-level helpers of the ASCII driver: what a send job puts on the line (§2.2.4,
the three send variants of the end-character criterion), names of control characters, and
a decoder that splits a byte stream into frames for transcripts and diagrams.

Everything here is a function of its arguments: no state, no time, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

from .params import AsciiParams
from .readings import READINGS, AsciiReadings

#: The ASCII names of the control characters 00..1F and 7F.
CONTROL_NAMES = dict(enumerate((
    "NUL", "SOH", "STX", "ETX", "EOT", "ENQ", "ACK", "BEL", "BS", "HT", "LF", "VT", "FF", "CR",
    "SO", "SI", "DLE", "DC1", "DC2", "DC3", "DC4", "NAK", "SYN", "ETB", "CAN", "EM", "SUB",
    "ESC", "FS", "GS", "RS", "US")))
CONTROL_NAMES[0x7F] = "DEL"


def char_name(b: int) -> str:
    """``0x03`` -> ``'ETX'``; a printable or 8-bit character -> its hex value ``'41'``."""
    return CONTROL_NAMES.get(b, f"{b:02X}")


def find_end(data: bytes, end: bytes, start: int = 0) -> int:
    """Index just past the first end sequence in ``data`` at or after ``start``; -1 if
    there is none. With two end characters only the pair in order counts (a lone end
    character is data)."""
    i = bytes(data).find(end, start)
    return -1 if i < 0 else i + len(end)


def send_bytes(payload: bytes, params: AsciiParams,
               readings: AsciiReadings = READINGS) -> bytes | None:
    """The characters a send job of ``payload`` (LEN = len(payload)) puts on the line, or
    None when the driver refuses it (only with reading Q6 "refuse").

    * CDT and fixed-length criteria: the LEN bytes as given (§2.2.4).
    * End-character criterion (§2.2.4):
      ``up_to_end``: the data up to and including the first end character (sequence); what
      follows is not sent even if LEN is larger;
      ``len_with_end``: exactly LEN bytes (the last should be the end character(s));
      ``len_append_end``: the LEN bytes followed by the end character(s).
    """
    payload = bytes(payload)
    if params.end_criterion != "end_chars":
        return payload
    end = params.end_sequence
    variant = params.send_variant
    if variant == "len_with_end":
        return payload
    if variant == "len_append_end":
        return payload + end
    # up_to_end
    if readings.q6_up_to_end_finds_sequence:
        n = find_end(payload, end)
    else:
        n = find_end(payload, end[:1])
    if n < 0:
        return payload if readings.q6_up_to_end_without_end_sends_all else None
    return payload[:n]


# ----------------------------------------------------------------------- decoding a stream
@dataclass(frozen=True, slots=True)
class Piece:
    """One piece of a decoded byte stream: a ``frame`` (complete by the end criterion), a
    ``fragment`` (incomplete: what a receiver would discard), or an ``xon`` / ``xoff``
    flow-control character. ``start``/``end``: the first start bit and the last stop bit
    when the stream was timed, else None. ``end_len``: how many of the last bytes are the
    end character(s)."""

    kind: str
    data: bytes
    start: float | None = None
    end: float | None = None
    end_len: int = 0

    def __str__(self) -> str:
        if self.kind in ("xon", "xoff"):
            return f"{self.kind.upper()}({self.data[0]:02X})"
        body = self.data[:len(self.data) - self.end_len]
        text = " ".join(f"{b:02X}" for b in body)
        if self.end_len:
            ends = " ".join("<" + char_name(b) + ">" for b in self.data[len(body):])
            text = f"{text} {ends}" if text else ends
        return f"[{text}]" if self.kind == "frame" else f"[{text}]?"


def split_frames(stream: bytes | Sequence[tuple[float, int]], params: AsciiParams,
                 readings: AsciiReadings = READINGS) -> list[Piece]:
    """Split what one side sent into frames as a receiver with ``params`` would delimit
    them: by pauses longer than the CDT (only when ``stream`` is timed: (start, byte)
    pairs), by the end character(s), or by the fixed length; with XON/XOFF flow control the
    XON and XOFF codes are pieces of their own. A pause longer than the CDT always ends a
    frame; under the end-character and fixed-length criteria what it cuts off is a
    fragment. Meant for transcripts and diagrams, not as an oracle."""
    if isinstance(stream, (bytes, bytearray)):
        timed = [(None, b) for b in stream]
    else:
        timed = list(stream)
    char = params.char_time
    cdt = params.cdt + (char if readings.q4_cdt_grace_one_character else 0.0)
    flow = (params.xon, params.xoff) if params.flow_control == "xon_xoff" else ()
    crit = params.end_criterion
    end = params.end_sequence
    out: list[Piece] = []
    cur = bytearray()
    first: float | None = None
    last: float | None = None

    def close(kind: str, end_len: int = 0) -> None:
        nonlocal cur, first
        if cur:
            stop = None if last is None else last + char
            out.append(Piece(kind, bytes(cur), first, stop, end_len))
        cur = bytearray()
        first = None

    for t, b in timed:
        if t is not None and last is not None and cur and (t + char) - (last + char) > cdt + 1e-12:
            close("frame" if crit == "cdt" else "fragment")
        if b in flow:
            out.append(Piece("xon" if b == params.xon else "xoff", bytes((b,)), t,
                             None if t is None else t + char))
            continue
        if not cur:
            first = t
        cur.append(b)
        last = t
        if crit == "end_chars" and len(cur) >= len(end) and cur[-len(end):] == end:
            close("frame", len(end))
        elif crit == "fixed_length" and len(cur) == params.fixed_length:
            close("frame")
    close("frame" if crit == "cdt" else "fragment")
    return out


def describe(stream: bytes | Sequence[tuple[float, int]], params: AsciiParams,
             readings: AsciiReadings = READINGS) -> str:
    """One line for a transcript: ``[41 42 <ETX>] XOFF(13) [43]?`` (``?``: a fragment)."""
    return " ".join(str(p) for p in split_frames(stream, params, readings))

