"""Line conditions (Table 8-1 (08)0DH, (08)0CH; §2.2.4): BREAK on an idle line, inside a
frame coming in and while the IUT sends. Character errors inside frames are in the modules
of the end criteria."""

from __future__ import annotations

from ptpcert.procedures.ascii.model import send_bytes

from ._build import IDLE, RX_ERRORS, brk, data, echoes, expect, frame_of, quiet_flow, receive_case, send, silence

REF = "Table 8-1 (08)0DH; §2.2.4"


def cases(p):
    f = frame_of(p, 4, 3)
    part = data(p, 2) if p.end_criterion != "fixed_length" or p.fixed_length > 2 else b""
    out = [
        receive_case(p, "LINE.BREAK-IDLE", "BREAK on an idle line: 16#080D; the next frame is received", REF,
                     "A BREAK on the receive line is reported with 16#080D; afterwards the driver receives normally.",
                     [brk(), send(f, at=IDLE)], [f], group="line-conditions", status=["16#080D"]),
    ]
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
