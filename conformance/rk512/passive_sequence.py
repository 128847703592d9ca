"""The IUT passive, the order of frames (§2.2.3 "Quasi-full-duplex", Figs. 2-17, 2-19;
§8.3 Table 8-1 16#060E, 16#0A01): P-09 (sequence errors), P-15 (an unsolicited response),
P-16 (its own request while it serves one)."""

import math

from ptpcert.procedures.p3964.model import codec as link

from ._build import DLE, STX, case, cont, expect, header, label, ok, prime, receive, resp, send, seq_data, silence


def cases(c):
    p = c.p
    w = c.db_w
    out = []
    first = header("A", "D", w, 0, 100) + seq_data(128)
    out.append(case(
        c, "P-09A.CONTINUATION-WITHOUT-REQUEST", "A continuation SEND with no request open: REATEL 36h",
        "§2.2.3 Fig. 2-19; §8.3 Table 8-1 16#060E ('1st frame expected, continuation came'); Table 8-3 (36h)",
        "A continuation frame that belongs to no open request is a synchronisation error: the responder reports 16#060E and answers with REATEL 36h in a continuation response; only that answer lets the requester report 16#0908 instead of waiting out its T_RES.",
        "passive-sequence", "receiver",
        [prime(cont("A", "D", seq_data(72))),
         receive(resp(0x36, first=False),
                 note="Table 8-3 pairs 36h with the responder's 16#060E and the requester's 16#0908")],
        iut=(["16#060E"], []), readings=["AMB-26"], needs={"db": [w]}, provenance="[S]"))
    out.append(case(
        c, "P-09B.FIRST-WHILE-CONTINUATION-EXPECTED", "A new first SEND while a continuation is expected: the open request ends",
        "§2.2.3 Fig. 2-19 ('1st command frame received: abort with error'); §8.3 Table 8-1 16#060E; Table 8-3",
        "A first command that comes while the responder waits for a continuation aborts the open request (16#060E); the new command is refused with 36h (or, by another reading, served), and the old continuation then finds no request (36h).",
        "passive-sequence", "receiver",
        [prime(first), receive(resp(0)),
         prime(header("A", "D", w, 0, 2) + seq_data(4, 0x60), note="a new first SEND instead of the continuation"),
         receive(resp(0x36), alternatives=[resp(0)], alt_grade="informational"),
         prime(cont("A", "D", seq_data(72, 0x80)), note="the first request's continuation, too late"),
         receive(resp(0x36, first=False), optional=True, absent_grade="informational")],
        iut=(["16#060E"], []), readings=["AMB-18"], needs={"db": [w], "db_bytes": 200}, provenance="[F][I]"))
    if p.priority == "low":
        # the tester (high) sends its next command right after the IUT took the first: the
        # IUT's response STX, if it has already started, yields to the tester's (§2.2.2)
        second = header("A", "D", w, 8, 2) + seq_data(4, 0x70)
        out.append(case(
            c, "P-09C.COMMAND-BEFORE-RESPONSE", "A second SEND before the IUT's response to the first: REATEL 36h for it",
            "§2.2.3 'Quasi-full-duplex' (nesting depth 1); §8.3 Table 8-1 16#060E ('new command before the response was sent'); Table 8-3",
            "A command that arrives before the responder has sent the response it owes is a synchronisation error: the responder answers the first with 00h and the second with 36h.",
            "passive-sequence", "receiver",
            [prime(header("A", "D", w, 0, 2) + seq_data(4)),
             send([STX], note="the tester's next command at once (it has the high priority)"),
             expect([DLE], alternatives=[[STX, DLE]],
                    note="the IUT (low) answers the tester's STX (after its own STX, if that crossed)"),
             send(link.body(second, p.procedure), note="the second SEND"), expect([DLE]),
             receive(resp(0), alternatives=[resp(0x36)], note="one response to each, in either order"),
             receive(resp(0x36), alternatives=[resp(0)])],
            iut=(["16#060E"], ["16#0702", "16#0701"]), readings=["AMB-31", "N7"],
            needs={"db": [w], "db_bytes": 20, "setup_attempts": 2},
            timing_sensitive=True, provenance="[S]"))
    out.append(case(
        c, "P-15.UNSOLICITED-RESPONSE", "A response 00 00 00 00 that answers nothing: taken by the link, not answered",
        "§2.2.3 'Response message frame' (only commands are answered); §8.3 Table 8-1 16#0A01",
        "A response frame is never answered with an RK 512 frame: the IUT acknowledges the block (DLE) and sends nothing more.",
        "passive-sequence", "receiver",
        [prime(resp(0)), silence("0.5*TRES", note="no RK 512 frame in answer"),
         prime(resp(0, first=False)), silence("0.5*TRES")],
        iut=((), ["16#0A01"]), provenance="[S][I]"))
    # P-16: the IUT's own request starts while it serves the tester's two-frame SEND
    if "active" in p.roles:
        # the IUT's request must start after the first frame's exchange, and the tester's
        # continuation must still reach the IUT within its T_RES
        first = header("A", "D", w, 0, 65) + seq_data(128)
        chars = len(link.frame(first, p.procedure)) + len(link.frame(resp(0), p.procedure)) + 4
        first_ex = chars * p.char_time + 2 * p.adt
        start_ms = math.ceil(1000 * (1.5 * first_ex + 0.1) / 10) * 10
        rest = 60 * p.char_time + 4 * p.adt
        if start_ms / 1000 - first_ex + rest <= 0.8 * p.t_res:
            own = "send DB10:DW0:LEN=4:DATA=0A0B0C0D"
            iut_cmd = header("A", "D", 10, 0, 2) + bytes([0x0A, 0x0B, 0x0C, 0x0D])
            out.append(case(
                c, "P-16.OWN-REQUEST-WHILE-SERVING", "The IUT's own SEND between the frames of the tester's SEND",
                "§2.2.3 'Quasi-full-duplex', Fig. 2-17; §6.3.2 'Parallel processing of requests'",
                "While it serves a multi-frame request, a station may send a command of its own; each direction keeps depth 1 and every command is answered once.",
                "quasi-full-duplex", "both",
                [prime(first), receive(resp(0)),
                 receive(iut_cmd, within="TRES", note=f"the IUT's request ({start_ms} ms after its start)"),
                 prime(cont("A", "D", seq_data(2, 0x80)), note="the tester's continuation before its answer"),
                 receive(resp(0, first=False)),
                 prime(resp(0), note="the tester answers the IUT's SEND")],
                requests=[f"wait {start_ms}", own], results=[ok(label(own))],
                needs={"db": [w], "db_bytes": 130}, readings=["AMB-31"], provenance="[F]"))
    return out
