"""Timing, both edges of every limit (Table 2-4; Figs. 2-10 to 2-12). The tester's own replies
and gaps at 80 % of the IUT's ADT and CDT must be accepted; gaps well over CDT must be refused;
the IUT's own replies must come within the partner's ADT."""

from ._build import DLE, NAK, PLAIN, STX, body, case, echo_send, expect, h, prime, receive_block, send

ECHO = ["echo"]


def cases(p):
    P = h("31 32 33 34 35 36 37 38")
    B = body(P, p)
    out = [
        case(p, "TIMING.DLE-REPLY-WITHIN-ADT", "The IUT answers STX and the block within the partner's ADT",
             "Table 2-4 ADT; §2.2.2 Send/setup; §2.2.2 Send/release",
             "A receiver must answer STX, and the end of the block, before the partner's ADT runs out; the manual sets no other limit (A8).",
             "timing", "receiver",
             [send(STX), expect(DLE, within="ADT"), send(B), expect(DLE, within="ADT")],
             delivered=[P], echo_after=[P], readings=["A8"], provenance="[S][I]",
             rules=["3964.RX.ANSWER-WITHIN-ADT"]),
        case(p, "TIMING.GAPS-AT-80-CDT-ACCEPTED", "Gaps of 80 % of CDT between the tester's characters are accepted",
             "Table 2-4 CDT; §2.2.2 Receive/receiving data; Fig. 2-12 'start T_CDT'",
             "A receiver that times out before CDT has passed between two characters is wrong.",
             "timing", "receiver", receive_block(P, p, gap="0.8*CDT - CHAR"),
             delivered=[P], echo_after=[P], provenance="[S]", rules=["3964.RX.CDT-WAIT"]),
        case(p, "TIMING.GAP-AT-80-CDT-IN-DLE-PAIR", "A gap of 80 % of CDT inside a doubled data DLE is accepted",
             "Table 2-4 CDT; Fig. 2-12 'DLE', 'wait for ETX', 'start T_CDT'",
             "T_CDT starts again after a DLE in the data: the second DLE of a pair may come up to CDT later.",
             "timing", "receiver",
             [send(STX), expect(DLE), send(body(b"\x31\x10\x32", p)[:2], note="data, then the first DLE of a pair"),
              send(body(b"\x31\x10\x32", p)[2:], at="0.8*CDT - CHAR", note="the second DLE, 80 % of CDT later, and the rest"),
              expect(DLE, note="accepted")],
             delivered=[b"\x31\x10\x32"], echo_after=[b"\x31\x10\x32"], provenance="[F]", rules=["3964.RX.CDT-WAIT"]),
        case(p, "TIMING.FIRST-CHARACTER-AT-80-CDT", "The first data character 80 % of CDT after the DLE is accepted",
             "Table 2-4 CDT; Table 8-1 16#0806",
             "The first character after the receiver's DLE may come up to CDT later.",
             "timing", "receiver", receive_block(P, p, first_at="0.8*CDT - CHAR"),
             delivered=[P], echo_after=[P], provenance="[S]", rules=["3964.RX.FIRST-CHARACTER-WAIT"]),
        case(p, "TIMING.GAP-OVER-CDT-REFUSED", "A gap of 1.5 x CDT inside the block makes the IUT refuse it",
             "§2.2.2 Receive/receiving data; Fig. 2-12 'T > T_CDT'; Table 8-1 16#0806",
             "A receiver must time out once CDT has passed between two characters: after a gap of 1.5 x CDT it has sent NAK and does not accept the rest of the block.",
             "timing", "receiver",
             [send(STX), expect(DLE), send(B[:3], mark=True),
              send(B[3:], at="1.5*CDT", note="the rest of the block, after a gap of 1.5 x CDT"),
              expect(NAK, after="CDT", within="CDT + 2*CHAR", since="mark", note="NAK once CDT had passed"),
              expect(NAK, after="CDT", within="CDT + ADT + 2*CHAR", since="sent", optional=True,
                     note="a NAK for the rest, which came as stray characters: CDT after the last of them, "
                          "with the one-character allowance and the NAK's own time (the ADT beyond is slack)")],
             iut=(["16#0806"], ["16#0801", "16#0802", "16#0815"]), provenance="[S]", rules=["3964.RX.CDT-TIMEOUT"]),
        case(p, "TIMING.SETUP-DLE-AT-80-ADT", "The tester's DLE 80 % of ADT after the IUT's STX is accepted",
             "Table 2-4 ADT; §2.2.2 Send/setup",
             "A sender must wait the whole ADT for the setup DLE; one that gives up early is wrong.",
             "timing", "sender", [prime(PLAIN)] + echo_send(PLAIN, p, setup_reply_at="0.8*ADT - CHAR"),
             delivered=[PLAIN], sent=[PLAIN], requires=ECHO, provenance="[S]", rules=["3964.TX.SETUP-WAIT"]),
        case(p, "TIMING.RELEASE-DLE-AT-80-ADT", "The tester's DLE 80 % of ADT after the IUT's block is accepted",
             "Table 2-4 ADT; §2.2.2 Send/release; Fig. 2-10 'send BCC', 'start T_ADT'",
             "A sender must wait the whole ADT for the DLE after its block.",
             "timing", "sender",
             [prime(PLAIN)] + echo_send(PLAIN, p, release_reply_at="0.8*ADT - CHAR"),
             delivered=[PLAIN], sent=[PLAIN], requires=ECHO, readings=["A12"], provenance="[S]",
             rules=["3964.TX.RELEASE-WAIT", "3964.TX.RELEASE-DLE"]),
    ]
    if p.has_bcc:
        out.append(case(p, "TIMING.BCC-AT-80-CDT", "The BCC 80 % of CDT after DLE ETX is accepted",
                        "Fig. 2-12 'wait for BCC'; Table 2-4 CDT",
                        "A 3964R receiver waits up to CDT for the BCC.", "timing", "receiver",
                        receive_block(P, p, bcc_at="0.8*CDT - CHAR"), delivered=[P], echo_after=[P],
                        provenance="[F]", rules=["3964.RX.BCC-WAIT"]))
    return out
