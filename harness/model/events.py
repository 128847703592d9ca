"""What a station reports to its user: STATUS events, delivered blocks, job results."""

from __future__ import annotations

from dataclasses import dataclass

# STATUS event codes a 3964(R) station raises (Table 8-1; 3964r.md §14.1).
FIRST_REPETITION = 0x0701          # send: transmission of the first repetition
SETUP_REFUSED = 0x0702             # send: NAK or other character after STX
SETUP_TIMEOUT = 0x0703             # send: ADT exceeded after STX
SEND_INTERRUPTED = 0x0704          # send: character received while sending the block
RELEASE_REFUSED = 0x0706           # send: NAK/other after DLE ETX [BCC], or DLE too early
RELEASE_TIMEOUT = 0x0707           # send: ADT exceeded after DLE ETX [BCC]
SETUP_ATTEMPTS_EXCEEDED = 0x0709   # send: setup attempts used up
TX_ATTEMPTS_EXCEEDED = 0x070A      # send: transmission attempts used up
EXPECT_REPETITION = 0x0801         # receive: first NAK for a block, repetition expected
RX_SETUP_ERROR = 0x0802            # receive: stray characters in idle / during setup
RX_LOGICAL_ERROR = 0x0805          # receive: DLE followed by a character other than DLE/ETX
CDT_EXCEEDED = 0x0806              # receive: character delay time exceeded
BCC_ERROR = 0x0808                 # receive: BCC mismatch (3964R)
NO_RECEIVE_BUFFER = 0x080A         # receive: no free receive buffer within T_NAKTIM
CHARACTER_ERROR = 0x080C           # parity / framing / overrun error in a received character
LINE_BREAK = 0x080D                # BREAK: receive line interrupted
ATTEMPTS_MISMATCH = 0x0815         # receive: transfer-attempt settings differ (A19)
FRAME_TOO_LONG = 0x0816            # receive: more than 1024 user bytes
LEN_ILLEGAL = 0x1E41               # send request with LEN outside 1..1024 (Table 8-2)


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
