"""What the RK 512 fuzz kit knows of a request: a request in progress, the tester's own or
the IUT's (:class:`OpenRequest`: its header, its data, how many of its frames are done), and
the header of a first command frame as the tester builds it (:func:`command_header`).

The generator (:mod:`.generator`) draws the tester's requests; the example's two sides
(:mod:`.passive`, :mod:`.active`) follow them frame by frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: the most data bytes one RK 512 frame carries: a longer request goes on in continuation frames
CHUNK = 128


@dataclass
class OpenRequest:
    """A request in progress, the tester's own or the IUT's: its header and data."""

    hdr: bytes
    fetch: bool
    data: bytes
    k: int = 0                       # frames done
    sent: list = field(default_factory=list)

    @property
    def nbytes(self) -> int:
        return len(self.data)

    @property
    def frames(self) -> int:
        return max(1, -(-self.nbytes // CHUNK))

    def chunk(self, k: int) -> bytes:
        return self.data[k * CHUNK:(k + 1) * CHUNK]


def command_header(cmd: int, typ: int, b5: int, b6: int, length: int, b9: int = 0xFF, b10: int = 0x1F) -> bytes:
    """The 10-byte header of a first command frame (Table 2-1): command ``cmd``, type ``typ``,
    bytes 5/6 (the block and start or the address), the length in units, bytes 9/10 (the
    coordination flag and the CPU, none by default)."""
    return bytes([0, 0, cmd, typ, b5, b6, (length >> 8) & 0xFF, length & 0xFF, b9, b10])
