"""What a station reports to its user: STATUS events, delivered blocks, job results."""

from __future__ import annotations

from dataclasses import dataclass

from .codes import Code

# The STATUS codes a 3964(R) station raises (Table 8-1); the one list is codes.Code.
FIRST_REPETITION = Code.FIRST_REPETITION
SETUP_REFUSED = Code.SETUP_REFUSED
SETUP_TIMEOUT = Code.SETUP_TIMEOUT
SEND_INTERRUPTED = Code.SEND_INTERRUPTED
RELEASE_REFUSED = Code.RELEASE_REFUSED
RELEASE_TIMEOUT = Code.RELEASE_TIMEOUT
SETUP_ATTEMPTS_EXCEEDED = Code.SETUP_ATTEMPTS_EXCEEDED
TX_ATTEMPTS_EXCEEDED = Code.TX_ATTEMPTS_EXCEEDED
EXPECT_REPETITION = Code.EXPECT_REPETITION
RX_SETUP_ERROR = Code.RX_SETUP_ERROR
RX_LOGICAL_ERROR = Code.RX_LOGICAL_ERROR
CDT_EXCEEDED = Code.CDT_EXCEEDED
BCC_ERROR = Code.BCC_ERROR
NO_RECEIVE_BUFFER = Code.NO_RECEIVE_BUFFER
CHARACTER_ERROR = Code.CHARACTER_ERROR
LINE_BREAK = Code.LINE_BREAK
ATTEMPTS_MISMATCH = Code.ATTEMPTS_MISMATCH
FRAME_TOO_LONG = Code.FRAME_TOO_LONG
LEN_ILLEGAL = Code.LEN_ILLEGAL


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
