"""Receiving with the end criterion "end character(s)" (§2.2.4; Fig. 2-22): delimiting,
merging, discarding and error reporting, with one or two end characters."""

from __future__ import annotations

import math

from ptpcert.procedures.ascii.model import send_bytes

from ._build import (
    GAP,
    IDLE,
    OVER,
    RX_ERRORS,
    UNDER,
    data,
    echoes,
    expect,
    quiet_flow,
    receive_case,
    send,
    send_error,
    unbuilt_case,
    with_echo,
)

REF = "§2.2.4 'end character(s)'; Fig. 2-22"
MAL = REF + " (malformed frames)"


def cases(p):
    if p.end_criterion != "end_chars":
        return []
    E = p.end_sequence
    d1, d2, d3, t = data(p, 3), data(p, 2, 3), data(p, 2, 5), data(p, 2, 7)
    f1, f2, f3 = d1 + E, d2 + E, d3 + E
    out = [
        receive_case(p, "EC.END-INCLUDED", "The end character ends the frame and is part of it", REF,
                     "The frame ends when the end character(s) arrive; they are delivered with the data.",
                     [send(f1)], [f1]),
        *_back_to_back(p, [f1, f2, f3]),
        receive_case(p, "EC.LONE-END", "A frame of only the end character(s)", REF,
                     "The end character(s) alone are a complete frame.", [send(E)], [E]),
        receive_case(p, "EC.TRAILING-DISCARDED", "Characters after the end character are discarded when the CDT expires", MAL,
                     "Characters after the end character go into no frame when the CDT expires after them; whether an "
                     "error is reported is not stated (the model reports 16#0806, reading Q10).",
                     [send(f1 + t), send(f2, at=IDLE, note="the next frame shows the trailing characters were not kept")],
                     [f1, f2], optional=[RX_ERRORS], soft=["16#0806"], readings=["Q10"]),
        receive_case(p, "EC.TRAILING-MERGED", "Characters after the end character merge with a frame that follows within the CDT", MAL,
                     "Characters after the end character are merged with the next frame when it starts before the CDT "
                     "expires: they become its first bytes.",
                     [send(f1 + t), send(f2, at=GAP)], [f1, t + f2], timing_sensitive=True),
        receive_case(p, "EC.TRAILING-EDGE-OVER", "A frame 1.4 CDT after trailing characters does not take them", MAL,
                     "Trailing characters are discarded when the CDT expires before the next frame starts.",
                     [send(f1 + t), send(f2, at=OVER)], [f1, f2], optional=[RX_ERRORS], soft=["16#0806"],
                     readings=["Q10"], timing_sensitive=True),
        receive_case(p, "EC.NO-END-DISCARDED", "A frame without end character is discarded with an error when the CDT expires",
                     REF + "; Table 8-1 (08)06H",
                     "When the CDT expires before the end character, reception is terminated, an error is reported "
                     "(16#0806 by the derived mapping) and the fragment is discarded.",
                     [send(d1), send(f2, at=IDLE, note="the next frame shows the fragment was not kept")], [f2],
                     status=[RX_ERRORS], soft=["16#0806"]),
        receive_case(p, "EC.NO-END-MERGED", "A frame without end character merges with characters that follow within the CDT", MAL,
                     "Characters without an end character are merged with the next frame when it starts before the CDT "
                     "expires; the frame ends at its end character.",
                     [send(d1), send(f2, at=GAP)], [d1 + f2], timing_sensitive=True),
        receive_case(p, "EC.EDGE-UNDER", "Gaps of 0.6 CDT inside a frame are allowed", REF,
                     "The CDT watchdog does not cut a frame whose characters come less than the CDT apart.",
                     [send(f1, gap=UNDER)], [f1], timing_sensitive=True),
        receive_case(p, "EC.EDGE-OVER", "A gap of 1.4 CDT inside a frame discards its first part", REF + "; Table 8-1 (08)06H",
                     "A gap longer than the CDT before the end character discards what came before it with an error; "
                     "the rest is a new frame.",
                     [send(d1), send(f2, at=OVER)], [f2], status=[RX_ERRORS], soft=["16#0806"], timing_sensitive=True),
        receive_case(p, "EC.CHARACTER-ERROR", "A character error spoils the frame up to its end character",
                     REF + "; Table 8-1 (08)0CH",
                     "On a character error the driver waits for a valid end character, discards the frame and enters "
                     "the error in STATUS (16#080C by the derived mapping).",
                     [send(d1[:1]), send_error(d1[1:2]), send(d1[2:] + E), send(f2, at=IDLE)], [f2],
                     status=[RX_ERRORS], soft=["16#080C"], readings=["Q12"]),
        receive_case(p, "EC.CHARACTER-ERROR-ENDS-AT-END-CHAR", "After a character error the next frame starts after the end character",
                     REF + "; Table 8-1 (08)0CH",
                     "The spoiled frame ends at its end character, not at the CDT: a frame that follows at once is received.",
                     [send(d1[:1]), send_error(d1[1:2]), send(d1[2:] + E + f2)], [f2],
                     status=[RX_ERRORS], soft=["16#080C"], readings=["Q12"]),
    ]
    if quiet_flow(p):
        # the end character completes the frame at once: its echo starts while a long frame
        # that follows is still coming in (a driver that waited for the CDT would merge them)
        n = math.ceil((2 * p.cdt + 0.3) / p.char_time) + 20
        if n <= 900:
            long = data(p, n, 11) + E
            out.append(with_echo(receive_case(
                p, "EC.COMPLETES-AT-ONCE", "The end character completes the frame at once", REF,
                "The frame ends when its end character arrives: it is handed on (and sent back) while the next "
                "frame is still coming in.",
                [send(f1, mark=True), send(long, note="a long frame right behind it"),
                 expect(send_bytes(f1, p), within="CDT + 10*CHAR", since="mark",
                        note="the first frame's echo, long before the second frame is complete")],
                [f1, long], echo=False), echoes(p, [long])))
    if len(E) == 2:
        e1, e2 = E[:1], E[1:]
        out += [
            receive_case(p, "EC2.LONE-FIRST-IS-DATA", "Two end characters: a lone first end character is data", REF,
                         "Only end character 1 immediately followed by end character 2 ends a frame; a lone end "
                         "character 1 is data.", [send(d1 + e1 + d2 + E)], [d1 + e1 + d2 + E]),
            receive_case(p, "EC2.HALF-PAIR", "Two end characters: end character 1 alone, then idle: discarded",
                         REF + "; Table 8-1 (08)06H",
                         "A frame ending with end character 1 but without end character 2 has no end: the CDT discards "
                         "it with an error.", [send(d1 + e1), send(f2, at=IDLE)], [f2],
                         status=[RX_ERRORS], soft=["16#0806"]),
            receive_case(p, "EC2.SPLIT-ACROSS-CDT", "Two end characters split by a pause longer than the CDT",
                         REF + "; Table 8-1 (08)06H",
                         "End character 2 that comes more than the CDT after end character 1 ends nothing: both parts "
                         "are fragments, discarded with errors.",
                         [send(d1 + e1), send(e2, at=OVER), send(f2, at=IDLE)], [f2],
                         status=[RX_ERRORS], soft=["16#0806"], timing_sensitive=True),
        ]
        if e1 != e2:
            out += [
                receive_case(p, "EC2.LONE-SECOND-IS-DATA", "Two end characters: a lone second end character is data", REF,
                             "End character 2 without end character 1 before it is data.",
                             [send(d1 + e2 + d2 + E)], [d1 + e2 + d2 + E]),
                receive_case(p, "EC2.REVERSED", "Two end characters in the wrong order end nothing", REF + "; Table 8-1 (08)06H",
                             "End character 2 followed by end character 1 is no end sequence: the CDT discards the frame.",
                             [send(d1 + e2 + e1), send(f2, at=IDLE)], [f2], status=[RX_ERRORS], soft=["16#0806"]),
                receive_case(p, "EC2.OVERLAP", "Two end characters: a repeated end character 1 before end character 2",
                             REF, "End character 1 immediately followed by end character 2 ends the frame, also after "
                             "another end character 1.", [send(d1 + e1 + E)], [d1 + e1 + E]),
            ]
    return out


def _back_to_back(p, frames):
    """Frames back to back, no more than the receive buffer holds: an application that has
    not yet read the first frame when the last arrives must not make a correct driver discard
    it (a full buffer refuses it with 16#080A, or overwrites the oldest). With a buffer of one
    frame there is nothing back to back to show beyond EC.END-INCLUDED: unsupported."""
    frames = frames[:min(len(frames), p.buffer_frames)]
    if len(frames) < 2:
        return [unbuilt_case(p, "EC.BACK-TO-BACK", "Frames back to back: each end character completes its frame",
                             REF + "; Table 2-10", "Each end character completes its frame at once.", "end-criterion",
                             "a receive buffer of one frame (buffer_frames = 1) holds no two frames back to back; "
                             "EC.END-INCLUDED checks the end character")]
    return [receive_case(p, "EC.BACK-TO-BACK", "Frames back to back: each end character completes its frame",
                         REF + "; Table 2-10",
                         "Each end character completes its frame at once; the next character begins a new frame "
                         "(no more frames than the receive buffer holds).",
                         [send(b"".join(frames))], frames)]
