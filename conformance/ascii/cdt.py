"""Receiving with the end criterion "expiry of the character delay time" (§2.2.4; Fig. 2-21):
delimiting, merging, discarding and error reporting."""

from __future__ import annotations

from ._build import (GAP, IDLE, OVER, RX_ERRORS, UNDER, data, echoes, expect, no_flow, quiet_flow, receive_case,
                     send, send_error, transparent)

REF = "§2.2.4 'expiry of the character delay time'; Fig. 2-21"


def cases(p):
    if p.end_criterion != "cdt":
        return []
    a, b, c = data(p, 5), data(p, 2, 5), data(p, 2, 7)
    out = [
        receive_case(p, "CDT.ONE-FRAME", "A burst followed by idle line is one frame", REF + "; Table 2-7",
                     "A frame ends when no further character arrives within the CDT after the last one.",
                     [send(a)], [a]),
        receive_case(p, "CDT.TWO-FRAMES", "Two bursts separated by idle line are two frames", REF,
                     "An idle line longer than the CDT ends a frame; the next burst is a new frame.",
                     [send(b), send(c, at=IDLE)], [b, c]),
        receive_case(p, "CDT.GAP-MERGES", "Bursts less than the CDT apart are one frame", REF,
                     "Frames separated by less than the CDT merge into one: the CDT must expire between two frames.",
                     [send(b), send(c, at=GAP)], [b + c], timing_sensitive=True),
        receive_case(p, "CDT.EDGE-UNDER", "Gaps of 0.6 CDT between all characters keep one frame", REF + "; Table 2-7",
                     "A gap shorter than the CDT does not end the frame, however often it occurs.",
                     [send(a, gap=UNDER)], [a], timing_sensitive=True),
        receive_case(p, "CDT.EDGE-OVER", "A gap of 1.4 CDT ends the frame", REF + "; Table 2-7",
                     "A gap longer than the CDT ends the frame; what follows is a new frame.",
                     [send(b), send(c, at=OVER)], [b, c], timing_sensitive=True),
        receive_case(p, "CDT.CHARACTER-ERROR", "A character error spoils its frame; the next frame is received",
                     REF + "; Table 8-1 (08)0CH",
                     "On a parity, framing or overrun error the driver waits for the CDT to expire, discards the frame and "
                     "enters an error in STATUS (16#080C by the derived mapping).",
                     [send(b), send_error(data(p, 1, 9)), send(data(p, 1, 10)), send(c, at=IDLE)], [c],
                     status=[RX_ERRORS], soft=["16#080C"], readings=["Q12"]),
        receive_case(p, "CDT.CHARACTER-ERROR-GAPS", "After a character error, characters within the CDT belong to the spoiled frame",
                     REF + "; Table 8-1 (08)0CH",
                     "After an error the driver discards what arrives until the CDT expires, even across gaps shorter than the CDT.",
                     [send_error(data(p, 1, 3)), send(b, at=GAP), send(data(p, 1, 11), at=GAP), send(c, at=IDLE)], [c],
                     status=[RX_ERRORS], soft=["16#080C"], readings=["Q12"], timing_sensitive=True),
    ]
    if no_flow(p):
        t = transparent(p)
        out.append(receive_case(
            p, "CDT.TRANSPARENT", "Every code is data with the CDT criterion and no XON/XOFF",
            "§2.2.4 'code transparency'; " + REF,
            "The CDT criterion without XON/XOFF is code-transparent: every code the character frame carries is data.",
            [send(t)], [t], timing_sensitive=True))
        big = data(p, 1024)
        out.append(receive_case(p, "CDT.MAX-1024", "A frame of 1024 bytes is received whole",
                                "§2.2.4; Table A-7; Table 6-3 LEN 1..1024",
                                "The longest frame, 1024 bytes, is delivered whole; sent back, it has no gap inside.",
                                [send(big)], [big], timing_sensitive=True))
        over = data(p, 1025, 3)
        out.append(receive_case(
            p, "CDT.TOO-LONG", "A burst of 1025 bytes is not delivered whole; the next frame is received",
            "§2.2.4; Table A-7; Table 8-1 (08)16H",
            "A frame longer than 1024 bytes is not delivered whole - split or discarded, with or without an error "
            "(reading Q13) - and the frames after it are received.",
            [send(over), expect(over[:1024], within="2*CDT + 1100*CHAR", optional=True,
                                note="an IUT that splits the burst sends the first 1024 bytes back"),
             expect(over[1024:], within="CDT + 10*CHAR", optional=True, note="... and the last byte"),
             send(c, at=IDLE), send(b, at=IDLE)], [c, b], optional=[RX_ERRORS], soft=["16#0816"], readings=["Q13"],
            timing_sensitive=True))
    if quiet_flow(p):
        # the frame is complete only once the CDT has passed after its last character
        out.append(receive_case(
            p, "CDT.ENDS-AFTER-CDT", "A frame is complete only when the CDT has passed after its last character",
            REF, "The end of a frame is the CDT expiring after its last character, so it cannot be handed on earlier.",
            [send(a), expect(echoes(p, [a])[0], after="CDT", within="2*CDT + 10*CHAR",
                             note="the echo: not before the CDT has expired")], [a], echo=False))
    return out
