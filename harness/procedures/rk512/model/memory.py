"""The partner CPU's memory, as the passive side of RK 512 reads and writes it (§6.3.2
"Receiving data", "Providing data"; Tables 6-9, 6-10).

Areas: the data blocks DB n and extended data blocks DX n of the parameters' ranges
(``db_bytes`` each), the input (E), output (A) and flag (M) bytes, the timer (T) and
counter (Z) cells (two bytes each). Coordination flags (§6.3.2 "Using interprocessor
communication flags") are bits of the flag area: flag B.b is bit b of flag byte B.

The "pattern" start contents (the reference IUT's, so that a tester knows what a FETCH
returns): DB n byte i = (n + i) & FFh; DX n byte i = (n + i + 80h) & FFh; E byte i =
(40h + i) & FFh; A byte i = (C0h + i) & FFh; T byte i = (20h + i) & FFh; Z byte i =
(60h + i) & FFh; M all 00h.
"""

from __future__ import annotations

from .codec import Area
from .params import Rk512Params

_RAMP = bytes(range(256)) * 2


def _pattern(base: int, n: int) -> bytearray:
    """n bytes (base + i) & FFh: the pattern repeats every 256 bytes."""
    period = _RAMP[base & 0xFF:(base & 0xFF) + 256]
    return bytearray((period * (n // 256 + 1))[:n])


class Memory:
    """The memory of the CPU behind an RK 512 station, with its RUN/STOP state."""

    def __init__(self, params: Rk512Params, *, fill: str = "pattern"):
        if fill not in ("pattern", "zero"):
            raise ValueError(f"fill {fill!r}: pattern or zero")
        p = params
        self.params = p
        pat = fill == "pattern"
        lo, hi = p.db_range
        self.db: dict[int, bytearray] = {
            n: _pattern(n, p.db_bytes) if pat else bytearray(p.db_bytes) for n in range(lo, hi + 1)}
        self.dx: dict[int, bytearray] = {}
        if p.dx_range:
            lo, hi = p.dx_range
            self.dx = {n: _pattern(n + 0x80, p.db_bytes) if pat else bytearray(p.db_bytes)
                       for n in range(lo, hi + 1)}
        nb, nc = p.byte_area_bytes, 2 * p.cell_area_cells
        self.areas: dict[Area, bytearray] = {
            Area.E: _pattern(0x40, nb) if pat else bytearray(nb),
            Area.A: _pattern(0xC0, nb) if pat else bytearray(nb),
            Area.M: bytearray(nb),
            Area.T: _pattern(0x20, nc) if pat else bytearray(nc),
            Area.Z: _pattern(0x60, nc) if pat else bytearray(nc),
        }
        #: False while the CPU is in STOP: every partner command is refused (16#060D, 2Ah).
        self.running = True

    # -- areas ------------------------------------------------------------------------------
    def buffer(self, area: Area, number: int = 0) -> bytearray | None:
        """The bytes of an area (a DB/DX by number); None when it does not exist."""
        if area is Area.DB:
            return self.db.get(number)
        if area is Area.DX:
            return self.dx.get(number)
        return self.areas[area]

    def read(self, area: Area, number: int, start: int, n: int) -> bytes:
        buf = self.buffer(area, number)
        if buf is None or start < 0 or start + n > len(buf):
            raise IndexError(f"{area.name}{number if area.block else ''} bytes {start}..{start + n - 1} do not exist")
        return bytes(buf[start:start + n])

    def write(self, area: Area, number: int, start: int, data: bytes) -> None:
        buf = self.buffer(area, number)
        if buf is None or start < 0 or start + len(data) > len(buf):
            raise IndexError(f"{area.name}{number if area.block else ''} bytes {start}..{start + len(data) - 1} do not exist")
        buf[start:start + len(data)] = data

    # -- coordination flags (bits of the flag area) ------------------------------------------
    def flag_exists(self, byte: int, bit: int) -> bool:
        return 0 <= bit <= 7 and 0 <= byte < len(self.areas[Area.M])

    def flag(self, byte: int, bit: int) -> int:
        return (self.areas[Area.M][byte] >> bit) & 1

    def set_flag(self, byte: int, bit: int, value: int = 1) -> None:
        m = self.areas[Area.M]
        if value:
            m[byte] |= 1 << bit
        else:
            m[byte] &= ~(1 << bit) & 0xFF

    def snapshot(self) -> dict:
        """A deep copy of every area, for comparisons."""
        return {"db": {n: bytes(b) for n, b in self.db.items()},
                "dx": {n: bytes(b) for n, b in self.dx.items()},
                **{a.name: bytes(b) for a, b in self.areas.items()},
                "running": self.running}
