"""Parameters of a 3964 / 3964R station (Tables 2-3, 2-4, 2-5).

:class:`Params3964` is frozen and validated on construction; an invalid setting raises
:class:`ParameterError` naming the parameter, the value and the allowed range.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

from ptpcert.model.errors import ParameterError
from ptpcert.model.line import BAUD_RATES, PARITIES, LineSettings

PRIORITIES = ("low", "high")

TIMER_MAX_MS = 655_350
TIMER_STEP_MS = 10
ATTEMPTS_RANGE = (1, 255)

#: Fixed receiver timers (§2.2.2 Receive; Figs. 2-11, 2-12): not parameters.
T_NAKTIM = 0.400
T_BLOCK = 4.0

#: Default ADT per procedure (Table 2-4). For 3964 the table says 550 ms while the
#: Fig. 2-10 legend says 500 ms; ambiguity A1, resolved in favour of the parameter table.
DEFAULT_ADT_MS = {"3964R": 2000, "3964": 550}
DEFAULT_CDT_MS = 220


def min_timer_ms(baud_rate: int | None) -> int:
    """Baud-rate-dependent minimum of CDT and ADT (Table 2-4)."""
    if baud_rate is None:
        return 20
    if baud_rate <= 300:
        return 60
    if baud_rate <= 600:
        return 40
    if baud_rate <= 1200:
        return 30
    return 20


@dataclass(frozen=True)
class Params3964:
    """One station's parameter set. Defaults are the manual's (Tables 2-3 to 2-5).

    ``baud_rate=None`` is not a manual setting: it means "no line timing" (characters take
    no time on the wire), for simulations and for an IUT that does not pace its output.
    """

    procedure: str = "3964R"
    priority: str = "low"
    cdt_ms: int = DEFAULT_CDT_MS
    adt_ms: int | None = None  # None: the procedure's default (A1)
    setup_attempts: int = 6
    transmission_attempts: int = 6
    baud_rate: int | None = 9600
    data_bits: int = 8
    parity: str = "even"
    stop_bits: int = 1
    # Derived, filled in by __post_init__.
    char_time: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.procedure not in DEFAULT_ADT_MS:
            raise ParameterError("procedure", self.procedure, "one of 3964, 3964R")
        if self.adt_ms is None:
            object.__setattr__(self, "adt_ms", DEFAULT_ADT_MS[self.procedure])
        if self.priority not in PRIORITIES:
            raise ParameterError("priority", self.priority, "one of low, high")
        if self.baud_rate is not None and self.baud_rate not in BAUD_RATES:
            raise ParameterError(
                "baud_rate", self.baud_rate, "one of " + ", ".join(map(str, BAUD_RATES))
            )
        if self.data_bits not in (7, 8):
            raise ParameterError("data_bits", self.data_bits, "7 or 8")
        if self.parity not in PARITIES:
            raise ParameterError("parity", self.parity, "one of none, odd, even")
        if self.stop_bits not in (1, 2):
            raise ParameterError("stop_bits", self.stop_bits, "1 or 2")
        low = min_timer_ms(self.baud_rate)
        at = "" if self.baud_rate is None else f" (minimum {low} ms at {self.baud_rate} bit/s)"
        for name in ("cdt_ms", "adt_ms"):
            v = getattr(self, name)
            if (
                not isinstance(v, int)
                or isinstance(v, bool)
                or v < low
                or v > TIMER_MAX_MS
                or v % TIMER_STEP_MS
            ):
                raise ParameterError(
                    name, v, f"{low}..{TIMER_MAX_MS} ms in steps of {TIMER_STEP_MS} ms{at}"
                )
        for name in ("setup_attempts", "transmission_attempts"):
            v = getattr(self, name)
            lo, hi = ATTEMPTS_RANGE
            if not isinstance(v, int) or isinstance(v, bool) or not lo <= v <= hi:
                raise ParameterError(name, v, f"an integer {lo}..{hi}")
        object.__setattr__(self, "char_time", self._char_time())

    # -- derived values -------------------------------------------------------------
    @property
    def line(self) -> LineSettings:
        """The serial line's settings: baud rate and character frame (Table 2-5)."""
        return LineSettings(self.baud_rate, self.data_bits, self.parity, self.stop_bits)

    @property
    def bits_per_char(self) -> int:
        return self.line.bits_per_char

    def _char_time(self) -> float:
        return self.line.char_time

    @property
    def cdt(self) -> float:
        return self.cdt_ms / 1000.0

    @property
    def adt(self) -> float:
        return self.adt_ms / 1000.0

    @property
    def has_bcc(self) -> bool:
        return self.procedure == "3964R"

    def with_(self, **changes: Any) -> "Params3964":
        """A copy with some fields changed (re-validated). Changing the procedure without
        an explicit ``adt_ms`` resets ADT to the new procedure's default."""
        if "procedure" in changes and "adt_ms" not in changes:
            if self.adt_ms == DEFAULT_ADT_MS[self.procedure]:
                changes["adt_ms"] = None
        return replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.pop("char_time", None)
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Params3964":
        known = {f.name for f in fields(cls) if f.init}
        unknown = sorted(set(data) - known)
        if unknown:
            raise ParameterError(unknown[0], data[unknown[0]], "not a parameter; known: " + ", ".join(sorted(known)))
        return cls(**data)
