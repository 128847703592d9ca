"""The serial line's settings: baud rate and character frame (start bit, 5 to 8 data bits,
parity, 1 or 2 stop bits). Every procedure's parameters carry one; transports and the
driver need nothing else from them, and a capture records the one its line ran with. The
usual short notation ``9600 8E1`` is its text form both ways (``str`` and :meth:`parse`)."""

from __future__ import annotations

import re
from dataclasses import dataclass

#: the CP 341's transmission rates in bit/s (Table 2-5), for every procedure
BAUD_RATES = (300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 76800)
PARITIES = ("none", "odd", "even")
#: Every parity a character frame can have (a superset of :data:`PARITIES`), each with its
#: letter in the short notation ``8E1``.
PARITY_LETTERS = {"none": "N", "odd": "O", "even": "E", "mark": "M", "space": "S"}


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

    def problem(self) -> str | None:
        """What makes these settings no frame a UART can have, or None when they are one:
        the baud rate (when given) a positive whole number, 5 to 8 data bits, a parity of
        :data:`PARITY_LETTERS`, 1 or 2 stop bits. Nothing checks this on construction (a
        procedure's parameters check their own, narrower, ranges); readers of settings from
        outside, such as the capture formats, ask."""
        baud = self.baud_rate
        if baud is not None and (not isinstance(baud, int) or isinstance(baud, bool) or baud <= 0):
            return f"baud rate {baud!r} is not a positive whole number"
        if self.data_bits not in (5, 6, 7, 8):
            return f"data bits {self.data_bits!r}: 5, 6, 7 or 8"
        if self.parity not in PARITY_LETTERS:
            return f"parity {self.parity!r}: one of {', '.join(PARITY_LETTERS)}"
        if self.stop_bits not in (1, 2):
            return f"stop bits {self.stop_bits!r}: 1 or 2"
        return None

    def __str__(self) -> str:
        """The short notation: ``9600 8E1``, ``- 7N2`` without a baud rate."""
        baud = "-" if self.baud_rate is None else str(self.baud_rate)
        return f"{baud} {self.data_bits}{PARITY_LETTERS[self.parity]}{self.stop_bits}"

    @classmethod
    def parse(cls, text: str) -> "LineSettings":
        """Settings from the short notation (``"9600 8E1"``, ``-`` for no baud rate, parity
        letters in any case). Raises ValueError on anything else."""
        m = re.fullmatch(r"\s*(\d+|-)\s+([5-8])([NOEMSnoems])([12])\s*", text)
        if not m:
            raise ValueError(f"line settings {text.strip()!r} are not of the form '9600 8E1' "
                             "(baud rate or -, data bits, parity N/O/E/M/S, stop bits)")
        parity = {v: k for k, v in PARITY_LETTERS.items()}[m.group(3).upper()]
        return cls(None if m.group(1) == "-" else int(m.group(1)), int(m.group(2)), parity, int(m.group(4)))
