"""The hex notation of vectors: bytes as the manual's figures write them, with runs.

A vector writes the bytes of a step as hex pairs (``"02 10"``), where a token ``XX*N``
stands for the byte XX repeated N times (``"41*1024"``). :func:`parse_vector_hex` reads
that notation (bounded: :data:`MAX_REPEAT` per token, :data:`MAX_STEP_BYTES` per step),
:func:`vector_hex` writes it back, and :func:`brief_hex` shortens long byte strings for
messages. The plain hex of single bytes is :mod:`ptpcert.model.hexbytes`'s; this module
adds only the runs and the bounds, for loading, writing and reporting vectors.
"""

from __future__ import annotations

import re
from typing import Mapping

from ..model.hexbytes import parse_hex

_REPEAT = re.compile(r"^([0-9A-Fa-f]{2})\*(\d+)$")
#: the longest run one ``XX*N`` token may stand for (2 x 1024 bytes and a frame's few more:
#: the longest frame a procedure of the CP 341 puts on the line, its data doubled), and the
#: most one step may hold
MAX_REPEAT = 2 * 1024 + 8
MAX_STEP_BYTES = 64 * 1024


def parse_vector_hex(text: str, names: Mapping[str, int] | None = None) -> bytes:
    """Hex bytes as in the figures (``"02 10"``), where a token ``XX*N`` stands for the
    byte XX repeated N times (``"41*1024"``). A name is refused; where ``names`` (a
    procedure's names of its characters) knows it, the message gives its byte."""
    out = bytearray()
    for token in text.split():
        m = _REPEAT.match(token)
        if m:
            n = int(m.group(2))
            if n > MAX_REPEAT:
                raise ValueError(f"{token!r}: at most {MAX_REPEAT} repetitions (the longest block on the line)")
            out += bytes([int(m.group(1), 16)]) * n
        elif re.fullmatch(r"[A-Za-z_]\w*", token) and not re.fullmatch(r"[0-9A-Fa-f]+", token):
            known = (names or {}).get(token.upper())
            raise ValueError(f"{token!r}: names are not allowed here; write the bytes in hex "
                             + (f"(e.g. {known:02X} for {token.upper()})" if known is not None else "(e.g. 02 10)"))
        else:
            out += parse_hex(token)
        if len(out) > MAX_STEP_BYTES:
            raise ValueError(f"more than {MAX_STEP_BYTES} bytes in one step")
    return bytes(out)


def vector_hex(data: bytes) -> str:
    """Inverse of :func:`parse_vector_hex`, compressing runs of 8 or more equal bytes."""
    parts, i = [], 0
    while i < len(data):
        j = i
        while j < len(data) and data[j] == data[i]:
            j += 1
        n = j - i
        parts.append(f"{data[i]:02X}*{n}" if n >= 8 else " ".join([f"{data[i]:02X}"] * n))
        i = j
    return " ".join(parts)


def brief_hex(data: bytes, limit: int = 24) -> str:
    """Bytes for messages: as :func:`vector_hex`, long ones cut to their head and tail."""
    text = vector_hex(data)
    toks = text.split()
    if len(toks) <= limit:
        return text
    return " ".join(toks[: limit - 6]) + " … " + " ".join(toks[-4:]) + f" ({len(data)} bytes)"
