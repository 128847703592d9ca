"""Receiving with the end criterion "fixed message frame length" (§2.2.4; Fig. 2-23):
delimiting, merging, discarding and error reporting."""

from __future__ import annotations

from ._build import (GAP, IDLE, OVER, RX_ERRORS, UNDER, data, receive_case, send, send_error, transparent)

REF = "§2.2.4 'fixed message frame length'; Fig. 2-23"
MAL = REF + " (malformed frames)"


def cases(p):
    if p.end_criterion != "fixed_length":
        return []
    n = p.fixed_length
    a, b, c = data(p, n), data(p, n, 7), data(p, n, 13)
    out = [
        receive_case(p, "FL.EXACT", "N characters are a frame", REF + "; Table 2-7",
                     "The frame ends once the configured number of characters has arrived.", [send(a)], [a]),
        receive_case(p, "FL.BACK-TO-BACK", "2N characters without a gap are two frames", REF,
                     "The N-th character completes a frame at once; the next character begins a new frame.",
                     [send(a + b)], [a, b]),
        receive_case(p, "FL.EDGE-UNDER", "Gaps of 0.6 CDT inside a frame are allowed", REF,
                     "The CDT watchdog does not cut a frame whose characters come less than the CDT apart.",
                     [send(a[:3], gap=UNDER)] + ([send(a[3:], at=UNDER)] if n > 3 else []), [a],
                     timing_sensitive=True),
        receive_case(p, "FL.CHARACTER-ERROR", "A character error spoils its frame of N characters", REF + "; Table 8-1 (08)0CH",
                     "On a character error the driver waits for the configured number of characters, discards the frame "
                     "and enters the error in STATUS (16#080C by the derived mapping).",
                     [send_error(a[:1])] + ([send(a[1:])] if n > 1 else []) + [send(b, at=IDLE)], [b],
                     status=[RX_ERRORS], soft=["16#080C"], readings=["Q12"]),
        receive_case(p, "FL.CHARACTER-ERROR-ENDS-AT-N", "After a character error the next frame starts after N characters",
                     REF + "; Table 8-1 (08)0CH",
                     "The spoiled frame ends with its N-th character, not at the CDT: a frame that follows at once is received.",
                     [send_error(a[:1])] + ([send(a[1:])] if n > 1 else []) + [send(b)], [b],
                     status=[RX_ERRORS], soft=["16#080C"], readings=["Q12"]),
    ]
    if p.flow_control != "xon_xoff":
        t = transparent(p)
        t = (t * (n // len(t) + 1))[:n]
        out.append(receive_case(p, "FL.TRANSPARENT", "Every code is data with fixed length and no XON/XOFF",
                                "§2.2.4 'code transparency'; " + REF,
                                "With the fixed-length criterion and no XON/XOFF every code the character frame carries is data.",
                                [send(t)], [t]))
    if n >= 2:
        s = min(n - 1, 3)
        short = data(p, s, 20)
        out += [
            receive_case(p, "FL.SHORT-DISCARDED", "A short frame is discarded with an error when the CDT expires",
                         REF + "; Table 8-1 (08)06H",
                         "When the CDT expires before N characters, reception is terminated, an error is reported (16#0806 "
                         "by the derived mapping) and the fragment is discarded.",
                         [send(short), send(a, at=IDLE)], [a], status=[RX_ERRORS], soft=["16#0806"]),
            receive_case(p, "FL.SHORT-MERGED", "A short frame merges with characters that follow within the CDT", MAL,
                         "A short frame is merged with the next characters when they start before the CDT expires: they "
                         "complete its N characters; what is left over is discarded when the CDT expires.",
                         [send(short), send(a, at=GAP)], [short + a[:n - s]], optional=[RX_ERRORS], soft=["16#0806"],
                         readings=["Q10", "Q11"], timing_sensitive=True),
            receive_case(p, "FL.EDGE-OVER", "A gap of 1.4 CDT inside a frame discards its first part", REF + "; Table 8-1 (08)06H",
                         "A gap longer than the CDT before the N-th character discards what came before it with an error; "
                         "the rest starts a new frame.", [send(short), send(a, at=OVER)], [a],
                         status=[RX_ERRORS], soft=["16#0806"], timing_sensitive=True),
        ]
    if n >= 3:
        extra = data(p, 2, 30)
        out += [
            receive_case(p, "FL.SURPLUS-DISCARDED", "Characters beyond N are discarded when the CDT expires", MAL,
                         "Characters beyond N are discarded when the CDT expires after them (with an error by the derived "
                         "mapping, reading Q10).", [send(a + extra), send(b, at=IDLE)], [a, b],
                         optional=[RX_ERRORS], soft=["16#0806"], readings=["Q10"]),
            receive_case(p, "FL.SURPLUS-MERGED", "Characters beyond N merge with a frame that follows within the CDT", MAL,
                         "Characters beyond N count towards the next frame when it starts before the CDT expires; what is "
                         "left over at the end is discarded.",
                         [send(a + extra), send(c, at=GAP)], [a, extra + c[:n - 2]],
                         optional=[RX_ERRORS], soft=["16#0806"], readings=["Q10", "Q11"], timing_sensitive=True),
        ]
    return out
