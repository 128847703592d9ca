"""The codec of line conditions on a byte stream, as POSIX termios PARMRK marks them: a
literal FF as ``FF FF``, a BREAK as ``FF 00 00``, a character received with a parity or
framing error as ``FF 00 xx``. The exec: and pty: transports mark what they send to an IUT
this way; the reference IUT and ``ptpcert monitor`` decode what they read. Pure: bytes in,
line events out.
"""

from __future__ import annotations

#: the mark of a BREAK
BREAK_MARK = b"\xff\x00\x00"


def encode(data: bytes) -> bytes:
    """Data bytes as a PARMRK stream carries them (every FF doubled)."""
    return data.replace(b"\xff", b"\xff\xff")


def error_mark(byte: int) -> bytes:
    """The mark of ``byte`` received with a parity or framing error. A corrupted 00 is shown
    with bit 7 set (80): ``FF 00 00`` would read as BREAK."""
    return bytes((0xFF, 0x00, byte or 0x80))


class ParmrkDecoder:
    """Turns a byte stream marked as POSIX termios PARMRK marks it into line events:
    ``FF FF`` -> data FF, ``FF 00 00`` -> BREAK, ``FF 00 xx`` -> xx with a parity/framing
    error. Without marking (``enabled=False``) every byte is data."""

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self._pending = b""

    def feed(self, t: float, data: bytes) -> list[tuple[float, str, int]]:
        if not self.enabled:
            return [(t, "byte", b) for b in data]
        buf = self._pending + data
        out: list[tuple[float, str, int]] = []
        i, n = 0, len(buf)
        while i < n:
            b = buf[i]
            if b != 0xFF:
                out.append((t, "byte", b))
                i += 1
                continue
            if i + 1 >= n:
                break
            if buf[i + 1] == 0xFF:
                out.append((t, "byte", 0xFF))
                i += 2
                continue
            if buf[i + 1] != 0x00:
                out.append((t, "byte", 0xFF))  # not a mark: take FF as data
                i += 1
                continue
            if i + 2 >= n:
                break
            x = buf[i + 2]
            out.append((t, "break", 0) if x == 0 else (t, "invalid", x))
            i += 3
        self._pending = buf[i:]
        return out
