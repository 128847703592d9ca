"""What an ASCII driver reports besides the shared events of :mod:`ptpcert.model.events`.

From the shared module: :class:`Status` (a STATUS event), :class:`Delivered` (the
application read a frame with P_RCV_RK: NDR, LEN), :class:`SendDone` (DONE) and
:class:`SendFailed` (ERROR). Here: what happens inside the CP's receive buffer, which the
CPU does not see directly but a transcript should show.
"""

from __future__ import annotations

from dataclasses import dataclass

from ptpcert.model.events import Delivered, Event, SendDone, SendFailed, Status

# Why a received frame did not reach the receive buffer (or left it unread).
CDT_EXPIRED = "cdt_expired"          # a fragment: the CDT expired before the frame was complete
CHARACTER_ERROR = "character_error"  # a parity, framing or overrun error spoiled it
NO_ROOM = "no_room"                  # the receive buffer overflowed while it came in
TOO_LONG = "too_long"                # longer than 1024 bytes
BUFFER_FULL = "buffer_full"          # complete, but buffer_frames frames were stored already
OVERWRITTEN = "overwritten"          # stored, unread, replaced by a newer frame (no overwrite protection)
LINE_BREAK = "break"                 # the receive line was interrupted
DSR_OFF = "dsr_off"                  # automatic V.24: DSR went OFF while it came in

REASONS = (CDT_EXPIRED, CHARACTER_ERROR, NO_ROOM, TOO_LONG, BUFFER_FULL, OVERWRITTEN,
           LINE_BREAK, DSR_OFF)


@dataclass(frozen=True, slots=True)
class FrameStored:
    """A complete frame entered the CP's receive buffer (it waits there for P_RCV_RK)."""

    time: float
    payload: bytes


@dataclass(frozen=True, slots=True)
class FrameDiscarded:
    """Received characters that will never reach the CPU. ``data`` holds the characters
    received intact (a character with an error is left out), ``reason`` one of
    :data:`REASONS`, ``code`` the STATUS raised for it (None: discarded silently)."""

    time: float
    data: bytes
    reason: str
    code: int | None


AsciiEvent = Event | FrameStored | FrameDiscarded

__all__ = ["Status", "Delivered", "SendDone", "SendFailed", "FrameStored", "FrameDiscarded",
           "AsciiEvent", "REASONS", "CDT_EXPIRED", "CHARACTER_ERROR", "NO_ROOM", "TOO_LONG",
           "BUFFER_FULL", "OVERWRITTEN", "LINE_BREAK", "DSR_OFF"]
