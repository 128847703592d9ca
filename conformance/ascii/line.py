"""The character frame and line conditions (Table 2-8; §2.2.4 'code transparency'; Table 8-1
(08)0DH): every code the profile leaves as data, BREAK on an idle line, inside a frame coming
in and while the IUT sends. Character errors inside frames are in the modules of the end
criteria."""

from __future__ import annotations

from ptpcert.procedures.ascii.model import send_bytes

from ._build import (IDLE, RX_ERRORS, brk, data, echoes, expect, frame_of, quiet_flow, receive_case, send, silence,
                     transparent)

REF = "Table 8-1 (08)0DH; §2.2.4"


def _all_codes(p):
    """Every code that is data in this profile, in frames of its criterion: one frame (CDT),
    one frame ending with the end character(s), or frames of the fixed length (the last one
    filled up with letters); None where they are more frames than the buffer holds."""
    t = transparent(p)
    if p.end_criterion == "fixed_length":
        n = p.fixed_length
        t += data(p, -len(t) % n)
        frames = [t[i:i + n] for i in range(0, len(t), n)]
    else:
        frames = [t + (p.end_sequence if p.end_criterion == "end_chars" else b"")]
    if len(frames) > p.buffer_frames:
        return None
    return receive_case(p, "LINE.ALL-CODES", "Every code the profile leaves as data is received and sent back",
                        "Table 2-8; §2.2.4 'code transparency'",
                        "The character frame carries every code 00..FF (00..7F with 7 data bits); all of them but the "
                        "end characters and XON/XOFF are data, received and sent back unchanged.",
                        [send(b"".join(frames))], frames, group="line-conditions", timing_sensitive=True)


def cases(p):
    f = frame_of(p, 4, 3)
    part = data(p, 2) if p.end_criterion != "fixed_length" or p.fixed_length > 2 else b""
    out = [
        receive_case(p, "LINE.BREAK-IDLE", "BREAK on an idle line: 16#080D; the next frame is received", REF,
                     "A BREAK on the receive line is reported with 16#080D; afterwards the driver receives normally.",
                     [brk(), send(f, at=IDLE)], [f], group="line-conditions", status=["16#080D"]),
    ]
    codes = _all_codes(p)
    if codes is not None:
        out.append(codes)
    if part:
        out.append(receive_case(
            p, "LINE.BREAK-IN-FRAME", "BREAK inside a frame coming in: 16#080D, the frame is lost", REF,
            "A BREAK while a frame comes in is reported with 16#080D and the frame is not delivered (reading d_break); "
            "the next frame is received.",
            [send(part), brk(), send(f, at=IDLE)], [f], group="line-conditions", status=["16#080D"],
            optional=[RX_ERRORS], readings=["d_break"]))
    if quiet_flow(p):
        long = frame_of(p, 200, 7) if p.end_criterion != "fixed_length" else frame_of(p, 0, 7)
        w = send_bytes(long, p)
        if len(w) >= 40:
            first = "2*CDT + 10*CHAR" if p.end_criterion == "cdt" else "CDT + 10*CHAR"
            out.append(receive_case(
                p, "LINE.BREAK-WHILE-SENDING", "BREAK on the receive line while the IUT sends", REF,
                "A BREAK on the receive line is reported with 16#080D; the frame being sent is not repeated or garbled "
                "(whether it is finished or cut off is open: reading d_break), and the next frame is received.",
                [send(long), expect(w[:10], within=first), brk(),
                 # the rest may come at the IUT's own pace: a frame stays one frame while its
                 # gaps stay under the CDT (max_gap), and a repeated frame meets the silence
                 expect(w[10:], after="-22*CHAR", within=f"{len(w)}*CDT", partial=True,
                        note="the rest of the frame, or part of it"),
                 silence("3*CDT"), send(f), expect(send_bytes(f, p), within="2*CDT + 10*CHAR")],
                [long, f], group="line-conditions", status=["16#080D"], echo=False, readings=["d_break"]))
    return out


__all__ = ["cases", "echoes"]
