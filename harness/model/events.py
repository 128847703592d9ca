"""What a station reports to its user: STATUS events, delivered blocks, job results."""

from __future__ import annotations

from dataclasses import dataclass


def status_text(code: int) -> str:
    """``0x0703`` -> ``'16#0703'``, the manual's notation."""
    return f"16#{code:04X}"


@dataclass(frozen=True, slots=True)
class Status:
    """A STATUS event raised at ``time``. ``side`` is the FB that reports it
    (``'send'`` = P_SND_RK, ``'receive'`` = P_RCV_RK); ``final`` marks the end of a job."""

    time: float
    code: int
    side: str
    final: bool = False

    def __str__(self) -> str:
        return status_text(self.code)


@dataclass(frozen=True, slots=True)
class Delivered:
    """A block was received intact and acknowledged with DLE (NDR, LEN)."""

    time: float
    payload: bytes


@dataclass(frozen=True, slots=True)
class SendDone:
    """A send job ended with the partner's positive acknowledgement (DONE)."""

    time: float
    payload: bytes
    attempts: int


@dataclass(frozen=True, slots=True)
class SendFailed:
    """A send job ended without success (ERROR). ``code`` is the final event
    (16#0709, 16#070A, a BREAK code...), ``first_error`` the first specific error."""

    time: float
    payload: bytes
    code: int
    first_error: int | None


Event = Status | Delivered | SendDone | SendFailed
