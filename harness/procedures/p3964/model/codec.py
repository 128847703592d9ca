"""Pure byte-level codec for 3964 / 3964R blocks (§2.2.2 Control characters, Block check character; Figs. 2-4 to 2-6).

Everything here is a function of its arguments: no state, no time, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import reduce
from operator import xor

STX = 0x02
ETX = 0x03
DLE = 0x10
NAK = 0x15

#: Largest number of user-data bytes in one block, counted before DLE doubling
#: (Table A-5; LEN 1..1024 in Tables 6-2/6-3; reading of ambiguity A17).
MAX_BLOCK = 1024

PROCEDURES = ("3964", "3964R")

CONTROL_NAMES = {STX: "STX", ETX: "ETX", DLE: "DLE", NAK: "NAK"}

_END = bytes((DLE, ETX))
_DOUBLE = bytes((DLE, DLE))
_SINGLE = bytes((DLE,))


def stuff(payload: bytes) -> bytes:
    """Double every data DLE (§2.2.2 Control characters, Note). Other control values pass unchanged."""
    return bytes(payload).replace(_SINGLE, _DOUBLE)


def unstuff(data: bytes) -> bytes:
    """Undo :func:`stuff`: every ``DLE DLE`` pair becomes one DLE (Fig. 2-12 'dual DLE').

    Raises :class:`FrameError` when a DLE is not followed by a second DLE, since that is
    not the image of any payload.
    """
    out = bytearray()
    i, n = 0, len(data)
    while i < n:
        b = data[i]
        if b == DLE:
            if i + 1 >= n or data[i + 1] != DLE:
                raise FrameError("lone-dle", i, f"DLE at offset {i} is not doubled")
            i += 2
        else:
            i += 1
        out.append(b)
    return bytes(out)


def bcc(stuffed_data: bytes) -> int:
    """Block check character over the bytes *as transmitted* (§2.2.2 Block check character, Note).

    ``stuffed_data`` is everything after STX up to, but not including, DLE ETX; the end
    sequence DLE ETX is included in the XOR here. STX is never part of it, a doubled DLE
    counts twice, and the result is never doubled on the line even when it equals DLE.
    """
    return reduce(xor, stuffed_data, DLE ^ ETX)


def payload_bcc(payload: bytes) -> int:
    """BCC of the block that carries ``payload``: equal to ``bcc(stuff(payload))``."""
    return bcc(stuff(payload))


def body(payload: bytes, procedure: str) -> bytes:
    """What a sender transmits after the partner's DLE: stuffed data, DLE ETX and, for
    3964R, the BCC (Figs. 2-5/2-6)."""
    _check_procedure(procedure)
    stuffed = stuff(payload)
    out = stuffed + _END
    if procedure == "3964R":
        out += bytes((bcc(stuffed),))
    return out


def frame(payload: bytes, procedure: str) -> bytes:
    """The sender's complete byte stream for one block, STX first, acknowledgements not
    included (they come from the partner): ``STX`` + :func:`body`."""
    return bytes((STX,)) + body(payload, procedure)


@dataclass(frozen=True)
class FrameError(Exception):
    """A framed block could not be parsed. ``kind`` is a stable name for tests and reports."""

    kind: str
    offset: int
    message: str

    def __str__(self) -> str:
        return f"{self.kind} at offset {self.offset}: {self.message}"


#: Kinds raised by :func:`parse` / :func:`parse_body`, each tied to the STATUS event a
#: receiver raises for it (Table 8-1).
FRAME_ERROR_STATUS = {
    "missing-stx": None,
    "lone-dle": 0x0805,
    "dle-other": 0x0805,
    "no-end": 0x0806,
    "missing-bcc": 0x0806,
    "bcc-mismatch": 0x0808,
    "trailing-bytes": None,
    "too-long": 0x0816,
}


def parse_body(data: bytes, procedure: str) -> bytes:
    """Parse what follows the receiver's DLE (data, DLE ETX, [BCC]) and return the payload.

    Raises :class:`FrameError` with a precise kind and offset for anything a conforming
    receiver would reject: a DLE followed by something other than DLE/ETX (16#0805), no
    end sequence (16#0806), a missing BCC (16#0806), a wrong BCC (16#0808), bytes after
    the end of the block, or more than :data:`MAX_BLOCK` user bytes (16#0816).
    """
    _check_procedure(procedure)
    out = bytearray()
    i, n = 0, len(data)
    while True:
        if i >= n:
            raise FrameError("no-end", i, "block ends without DLE ETX")
        b = data[i]
        if b != DLE:
            out.append(b)
            i += 1
            continue
        if i + 1 >= n:
            raise FrameError("no-end", i, "block ends after a DLE")
        nxt = data[i + 1]
        if nxt == DLE:
            out.append(DLE)
            i += 2
        elif nxt == ETX:
            i += 2
            break
        else:
            raise FrameError("dle-other", i + 1, f"DLE followed by {nxt:02X}, not DLE or ETX")
    end = i
    if procedure == "3964R":
        if i >= n:
            raise FrameError("missing-bcc", i, "3964R block ends without a BCC")
        expected = bcc(data[: end - 2])
        if data[i] != expected:
            raise FrameError(
                "bcc-mismatch", i, f"BCC {data[i]:02X} received, {expected:02X} computed"
            )
        i += 1
    if i != n:
        raise FrameError("trailing-bytes", i, f"{n - i} byte(s) after the end of the block")
    if len(out) > MAX_BLOCK:
        raise FrameError("too-long", 0, f"{len(out)} user bytes, at most {MAX_BLOCK} allowed")
    return bytes(out)


def parse(data: bytes, procedure: str) -> bytes:
    """Parse a complete framed block starting with STX (as :func:`frame` produces it)."""
    if not data or data[0] != STX:
        raise FrameError("missing-stx", 0, "a framed block starts with STX (02)")
    try:
        return parse_body(data[1:], procedure)
    except FrameError as exc:
        raise FrameError(exc.kind, exc.offset + 1, exc.message) from None


def _check_procedure(procedure: str) -> None:
    if procedure not in PROCEDURES:
        raise ValueError(f"procedure {procedure!r}: allowed values are 3964, 3964R")


