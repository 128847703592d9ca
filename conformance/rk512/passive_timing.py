"""The IUT passive, its response monitoring time (§2.2.3 Figs. 2-18, 2-19 "T_RES"): P-10 at
both edges."""

from ._build import case, cont, header, prime, receive, resp, seq_data, under_tres, wait

#: what a responder may report when its T_RES runs out: the manual names no event (AMB-18)
TIMEOUT_OPTIONAL = ["16#0A05", "16#060E", "16#0612", "16#0608", "16#060B", "16#0611"]


def cases(c):
    w = c.db_w
    first = header("A", "D", w, 0, 65) + seq_data(128)
    tail = cont("A", "D", seq_data(2, 0x90))
    return [
        case(c, "P-10.CONTINUATION-IN-TIME", "A continuation well within T_RES after the first response: accepted",
             "§2.2.3 Fig. 2-19 ('start T_RES'; 'continuation frame received')",
             "After a non-final response the responder waits T_RES for the continuation; one that comes in time is served.",
             "passive-timing", "receiver",
             [prime(first), receive(resp(0)), wait(under_tres(c.p, 0.8, tail), note="less than T_RES, the continuation's time on the line included"),
              prime(tail), receive(resp(0, first=False))],
             needs={"db": [w], "db_bytes": 130}, readings=["AMB-02", "AMB-17"], timing_sensitive=True, provenance="[F]"),
        case(c, "P-10.CONTINUATION-TOO-LATE", "A continuation after T_RES: the request was aborted, 36h",
             "§2.2.3 Fig. 2-19 ('T > T_RES: abort with error'); §8.3 Table 8-1 16#060E; Table 8-3",
             "When T_RES runs out before the continuation the responder aborts the request; a continuation after that belongs to no request (36h).",
             "passive-timing", "receiver",
             [prime(first), receive(resp(0)), wait("TRES + 2*ADT", note="longer than T_RES"),
              prime(tail), receive(resp(0x36, first=False), optional=True, absent_grade="informational")],
             iut=((), TIMEOUT_OPTIONAL), needs={"db": [w], "db_bytes": 130}, readings=["AMB-18"], provenance="[F][I]"),
    ]
