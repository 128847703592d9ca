"""The receive buffer (§2.2.4 'receive buffer'; Table 2-10): first in, first out; the frame
count and the 1024 bytes; overwrite prevented or allowed. The IUT's application reads late
(the slow_reader setup), so frames wait in the buffer."""

from __future__ import annotations

from ptpcert.procedures.ascii.model.params import BUFFER_BYTES

from ._build import FILL_TIME, OVER, RX_ERRORS, SLOW_SETUP, case, echo_steps, frame_of, no_flow, send, sending_time

REF = "§2.2.4 'receive buffer'; Table 2-10"


def _gap(p) -> str:
    return OVER if p.end_criterion == "cdt" else "0"


def _buffered(p, id, title, ref, rule, sent, kept, **kw):
    """The tester sends ``sent`` frames while the application does not read; then it reads
    them late and sends ``kept`` back, the oldest first. None where sending them would take
    longer than the application is sure to wait."""
    gap = _gap(p)
    if sending_time(p, sent, 1.4 if gap != "0" else 0.0) > FILL_TIME:
        return None
    steps = [send(f, at=gap if i else "0") for i, f in enumerate(sent)] + echo_steps(p, kept)
    return case(p, id, title, ref, rule, "buffer", "receiver", steps, delivered=kept, setup=SLOW_SETUP, **kw)


def cases(p):
    out = []
    b = p.buffer_frames
    small = 2 if p.end_criterion != "fixed_length" else p.fixed_length
    if b >= 4 and 3 * small <= 300:
        frames = [frame_of(p, small + i, i) for i in range(3)] if p.end_criterion != "fixed_length" else \
            [frame_of(p, 0, 5 * i) for i in range(3)]
        out.append(_buffered(p, "BUF.FIFO", "Frames waiting in the receive buffer are read oldest first", REF,
                             "With several frames in the receive buffer the oldest is handed to the CPU first.",
                             frames, frames))
    if no_flow(p) and p.prevent_overwrite and (b + 1) * small <= BUFFER_BYTES - 100:
        frames = [frame_of(p, small, i) for i in range(b + 1)]
        out.append(_buffered(p, "BUF.FULL-PREVENT-OVERWRITE", "Buffer full, overwrite prevented: a further frame is discarded",
                             REF + "; Table 8-1 (08)0AH",
                             "With 'prevent overwrite' and the configured number of frames stored, a further frame does not "
                             "enter the buffer; the stored frames stay (discarded with 16#080A by reading Q18).",
                             frames, frames[:b], optional=[RX_ERRORS], soft=["16#080A"], readings=["Q18"]))
    if no_flow(p) and not p.prevent_overwrite:
        frames = [frame_of(p, small, i) for i in range(3)]
        out.append(_buffered(p, "BUF.OVERWRITE", "Overwrite allowed: a new frame replaces the unread one", REF,
                             "With one buffered frame and 'prevent overwrite = no' each new frame overwrites the frame not "
                             "yet read, so the CPU always gets the latest.", frames, frames[-1:]))
    size = 100 if p.end_criterion != "fixed_length" else p.fixed_length
    fit = BUFFER_BYTES // size
    if no_flow(p) and p.prevent_overwrite and b >= fit + 1 and fit >= 2 and (fit + 1) * size <= 1100:
        frames = [frame_of(p, size, i) for i in range(fit + 1)]
        out.append(_buffered(p, "BUF.BYTES-FULL", "The 1024-byte buffer full: the frame that does not fit is discarded",
                             REF + "; Table 8-1 (08)0AH",
                             "The receive buffer holds 1024 bytes: a frame that does not fit is discarded with an error "
                             "(16#080A by reading Q17); the stored frames stay.",
                             frames, frames[:fit], status=[RX_ERRORS], soft=["16#080A"], readings=["Q17"]))
    return [v for v in out if v is not None]
