"""What a procedure that runs on the 3964/3964R link takes of it (RK 512 does): the [iut] keys
of the link in a profile (their schema, Tables 2-3 to 2-5: the ranges every setting allows;
what depends on another key, the timers' minimum at a low baud rate, the model's parameters
check) and their checks, and the ``prime`` step, in which the tester hands the
IUT a block as a conforming sender. The 3964 description uses the same pieces."""

from __future__ import annotations

from typing import Any

from ptpcert.model.line import BAUD_RATES
from ptpcert.procedure import MacroStep, ProcedureError
from ptpcert.scenario import Expr, Step
from ptpcert.schema import Key

from .model import codec
from .model.params import ATTEMPTS_RANGE, TIMER_MAX_MS, TIMER_STEP_MS, min_timer_ms

_TIMER = dict(kind="int", lo=20, hi=TIMER_MAX_MS, step=TIMER_STEP_MS, unit="ms", ref="Table 2-4",
              floor=("baud_rate", {b: min_timer_ms(b) for b in BAUD_RATES}))

#: the link's keys in [iut] (the parameter each sets: description.LINK_KEYS)
LINK_SCHEMA: tuple[Key, ...] = (
    Key("priority", "iut", "choice", "the station's priority in an initialization conflict (the two "
        "partners must have different ones)", ref="Table 2-5", choices=("low", "high")),
    Key("character_delay_ms", "iut", doc="CDT: the longest gap between two characters a receiver "
        "accepts (its minimum rises at 1200 bit/s and below)", **_TIMER),
    Key("acknowledgement_delay_ms", "iut", doc="ADT: how long a sender waits for the partner's DLE "
        "(its minimum rises at 1200 bit/s and below)", **_TIMER),
    Key("setup_attempts", "iut", "int", "how often a sender tries to set up a connection (STX) before "
        "it gives up", ref="Table 2-4", lo=ATTEMPTS_RANGE[0], hi=ATTEMPTS_RANGE[1]),
    Key("transmission_attempts", "iut", "int", "how often a sender tries to send a block, the first "
        "attempt included", ref="Table 2-4", lo=ATTEMPTS_RANGE[0], hi=ATTEMPTS_RANGE[1]),
    Key("baud_rate", "iut", "choice", "the transmission rate in bit/s", ref="Table 2-5",
        default=9600, choices=BAUD_RATES),
    Key("data_bits", "iut", "choice", "data bits of the character frame", ref="Table 2-5",
        default=8, choices=(7, 8)),
    Key("parity", "iut", "choice", "parity bit of the character frame", ref="Table 2-5",
        default="even", choices=("none", "odd", "even")),
    Key("stop_bits", "iut", "choice", "stop bits of the character frame", ref="Table 2-5",
        default=1, choices=(1, 2)),
)

#: [iut] keys of a 3964/3964R profile and the parameter each sets (defaults where optional)
LINK_KEYS = {
    "priority": "priority", "character_delay_ms": "cdt_ms", "acknowledgement_delay_ms": "adt_ms",
    "setup_attempts": "setup_attempts", "transmission_attempts": "transmission_attempts",
    "baud_rate": "baud_rate", "data_bits": "data_bits", "parity": "parity", "stop_bits": "stop_bits",
}
_REQUIRED = ("priority", "character_delay_ms", "acknowledgement_delay_ms", "setup_attempts",
             "transmission_attempts")
LINE_DEFAULTS = {"baud_rate": 9600, "data_bits": 8, "parity": "even", "stop_bits": 1}
_CHOICES = {"priority": ("low", "high"), "parity": ("none", "odd", "even")}


def link_values(iut: dict[str, Any]) -> dict[str, Any]:
    """The profile's [iut] keys of the 3964(R) link, checked (each missing or refused key
    named with what is allowed) and completed with the line's defaults."""
    for key in _REQUIRED:
        if key not in iut:
            hint = f"one of {', '.join(_CHOICES[key])}" if key in _CHOICES else "required"
            raise ProcedureError(f"iut.{key}", f"missing ({hint})")
    values = {**LINE_DEFAULTS, **iut}
    for key, choices in _CHOICES.items():
        if values[key] not in choices:
            raise ProcedureError(f"iut.{key}", f"{values[key]!r} is not allowed; allowed values: "
                                 + ", ".join(f'"{c}"' for c in choices))
    if values["baud_rate"] not in BAUD_RATES:
        raise ProcedureError("iut.baud_rate", f"{values['baud_rate']!r} is not allowed; allowed values: "
                             + ", ".join(map(str, BAUD_RATES)))
    return values
#: the parameter -> its [iut] key
KEY_OF = {v: k for k, v in LINK_KEYS.items()}

#: the macro step the 3964 and RK 512 vectors use to hand the IUT a block as a conforming
#: sender: the tester's STX ``at`` after the reference point, the IUT's DLE, the block, its DLE
PRIME = MacroStep(keys=frozenset({"at", "note"}), max_data=codec.MAX_BLOCK)


def block_end(procedure: str) -> str:
    """How a block ends on the line, in words: "DLE ETX" and, in 3964R, ", BCC"."""
    return "DLE ETX" + (", BCC" if procedure == "3964R" else "")


def prime_steps(step: Step, procedure: str, note: str, block_note: str) -> list[Step]:
    """The ``prime`` step as the exchange it stands for: the tester's STX ``at`` after the
    reference point, the IUT's DLE within ADT, the block (``block_note`` describes it), the
    IUT's DLE within ADT. ``note`` names the step where the vector gives it no note of its
    own."""
    note = step.note or note
    return [
        Step("send", bytes([codec.STX]), at=step.at, note=f"STX ({note})"),
        Step("expect", bytes([codec.DLE]), within=Expr("ADT"), note="DLE: setup acknowledged"),
        Step("send", codec.body(step.data, procedure), note=block_note),
        Step("expect", bytes([codec.DLE]), within=Expr("ADT"), note="DLE: block acknowledged"),
    ]
