"""The serial line's settings: baud rate and character frame (start bit, 7 or 8 data bits,
parity, 1 or 2 stop bits). Every procedure's parameters carry one; transports and the
driver need nothing else from them."""

from __future__ import annotations

from dataclasses import dataclass

#: the CP 341's transmission rates in bit/s (Table 2-5), for every procedure
BAUD_RATES = (300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 76800)
PARITIES = ("none", "odd", "even")


@dataclass(frozen=True)
class LineSettings:
    """``baud_rate=None`` means "no line timing": characters take no time on the wire
    (simulations, and an IUT that does not pace its output)."""

    baud_rate: int | None = 9600
    data_bits: int = 8
    parity: str = "even"
    stop_bits: int = 1

    @property
    def bits_per_char(self) -> int:
        """Start bit + data bits + parity bit (if any) + stop bits."""
        return 1 + self.data_bits + (0 if self.parity == "none" else 1) + self.stop_bits

    @property
    def char_time(self) -> float:
        """Seconds one character takes on the line."""
        return 0.0 if self.baud_rate is None else self.bits_per_char / self.baud_rate

    @property
    def max_value(self) -> int:
        """The largest character value the frame can carry (7F with 7 data bits)."""
        return (1 << self.data_bits) - 1

    def describe(self) -> str:
        baud = "unpaced" if self.baud_rate is None else f"{self.baud_rate} bit/s"
        return f"{baud} {self.data_bits}{self.parity[0].upper()}{self.stop_bits}"
