"""What the ASCII driver's station keeps about its own doings: the send job it works on, and,
with ``explain=True``, the reasons behind every character it sent and every modem output it
switched.

A :class:`Why` names the table row that acted (:mod:`.table`: receiver, sender or flow
control), the decisions taken after it and the manual's reference; :class:`TxRecord` and
:class:`SignalRecord` pair it with what went on the line. Tools that explain a transcript
(the analysis of a capture, the fuzzer's reports) read them from the station's ``tx_log``
and ``signal_log``. Plain data, no behaviour: the station (:mod:`.station`) makes and keeps
them; standard library only.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Why:
    """Why the station did something: the table (``rx``, ``tx``, ``fc``), the state, the
    input, the row's action, the decisions taken after it, and the manual's reference."""

    machine: str
    state: str
    input: str
    action: str
    ref: str
    decisions: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        path = " -> ".join([self.action, *self.decisions])
        return f"{self.machine} {self.state} + {self.input}: {path} ({self.ref})"


@dataclass(frozen=True, slots=True)
class TxRecord:
    """Characters that went on the line back to back, and why (``kind``: ``data`` for a
    send job's frame, ``control`` for XON/XOFF)."""

    start: float
    end: float
    data: bytes
    kind: str
    why: Why


@dataclass(frozen=True, slots=True)
class SignalRecord:
    """A modem output (``rts``, ``dtr``) the station switched to ``value`` at ``time``, and
    why."""

    time: float
    name: str
    value: int
    why: Why


@dataclass
class AsciiJob:
    """A send job: the data handed over (LEN bytes) and what goes on the line for it."""

    payload: bytes
    wire: bytes
    pos: int = 0   # characters of ``wire`` handed to the transmitter (and not taken back)
