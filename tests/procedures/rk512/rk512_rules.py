"""Test-side statements of the RK 512 and 3964R rules, written independently of the model:
the tests build their expected bytes with these, never from the model's output."""

from __future__ import annotations

STX, DLE, ETX, NAK = 0x02, 0x10, 0x03, 0x15


def header(cmd: str, typ: str, b5: int, b6: int, length: int, b9: int = 0xFF, b10: int = 0x1F,
           b1: int = 0x00) -> bytes:
    """Table 2-1: frame id, 00h, command letter, data type letter, bytes 5/6, the length
    big-endian in bytes 7/8, flag byte, CPU/flag-bit byte."""
    return bytes([b1, 0x00, ord(cmd), ord(typ), b5, b6, length >> 8, length & 0xFF, b9, b10])


def response(reatel: int = 0, first: bool = True, data: bytes = b"") -> bytes:
    """Table 2-2: 00h (first) or FFh (continuation), 00h, 00h, the error number."""
    return bytes([0x00 if first else 0xFF, 0x00, 0x00, reatel]) + bytes(data)


def continuation(cmd: str, typ: str, data: bytes = b"") -> bytes:
    return bytes([0xFF, 0x00, ord(cmd), ord(typ)]) + bytes(data)


def body(payload: bytes, bcc: bool = True) -> bytes:
    """What follows the receiver's DLE: every data DLE doubled, DLE ETX, and (3964R) the XOR
    of every byte sent after STX up to and including DLE ETX (3964R §2.2.2, Fig. 2-4)."""
    out = bytearray()
    for b in payload:
        out += b"\x10\x10" if b == DLE else bytes([b])
    out += bytes([DLE, ETX])
    if bcc:
        x = 0
        for b in out:
            x ^= b
        out.append(x)
    return bytes(out)


def hexb(text: str) -> bytes:
    return bytes.fromhex(text.replace("|", " "))


def exchange(cmd: bytes, resp: bytes, a: str = "a", b: str = "b", bcc: bool = True) -> list[tuple[str, int]]:
    """One command block from ``a`` answered by one response block from ``b`` (3964R:
    STX / DLE / block / DLE each way), as (sender, byte) pairs."""
    out = [(a, STX), (b, DLE)] + [(a, x) for x in body(cmd, bcc)] + [(b, DLE)]
    out += [(b, STX), (a, DLE)] + [(b, x) for x in body(resp, bcc)] + [(a, DLE)]
    return out


#: Table 8-3: REATEL -> the event the requester raises.
TABLE_8_3 = {
    0x0A: 0x0905, 0x0C: 0x0902, 0x10: 0x090B, 0x12: 0x0904, 0x14: 0x0903,
    0x16: 0x090A, 0x2A: 0x090D, 0x32: 0x0909, 0x34: 0x090C, 0x36: 0x0908,
}
UNKNOWN_REATEL = 0x090E

#: Table 8-3 read from the other side: REATEL -> the responder's events that send it (one of
#: them; 0Ah and 12h list none: a CP 341 never sends them, they come from other partners).
RESPONDER_8_3 = {
    0x0C: (0x0301, 0x0607, 0x0609, 0x060A), 0x10: (0x0301, 0x0601, 0x0604, 0x0605), 0x14: (0x0606,),
    0x16: (0x0602, 0x0603), 0x2A: (0x060D,), 0x32: (0x060F,), 0x34: (0x0608, 0x060B, 0x060C, 0x0611),
    0x36: (0x060E,),
}


def unbody(data: bytes, bcc: bool = True) -> bytes | None:
    """The payload of a block as ``body`` builds it (None: ``data`` is not one)."""
    tail = 3 if bcc else 2
    if len(data) < tail + 1 or data[-tail:-tail + 2] != bytes([DLE, ETX]):
        return None
    out, i, raw = bytearray(), 0, data[:-tail]
    while i < len(raw):
        if raw[i] == DLE:
            if i + 1 >= len(raw) or raw[i + 1] != DLE:
                return None
            i += 1
        out.append(raw[i])
        i += 1
    return bytes(out) if body(bytes(out), bcc) == data else None
