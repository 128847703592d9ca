"""Timing, both edges of every limit (Table 2-4; 3964r.md §5, §13.6). The tester's own
replies and gaps at 80 % of the IUT's ADT and CDT must be accepted; gaps well over CDT must
be refused; the IUT's own replies must come well inside the partner's ADT."""

from ._build import DLE, NAK, STX, body, case, echo_send, expect, h, prime, receive_block, send

ECHO = ["echo"]


def cases(p):
    P = h("31 32 33 34 35 36 37 38")
    B = body(P, p)
    out = [
        case(p, "TIMING.DLE-REPLY-WELL-INSIDE-ADT", "The IUT answers STX well inside the partner's ADT",
             "Table 2-4 ADT; 3964r.md §13.6, §17 A8",
             "A receiver must answer STX before the partner's ADT expires; the suite asks for half of it.",
             "timing", "receiver",
             [send(STX), expect(DLE, within="0.5*ADT"), send(B), expect(DLE, within="0.5*ADT")],
             delivered=[P], echo_after=[P], readings=["A8"], provenance="[S][I]"),
        case(p, "TIMING.GAPS-AT-80-CDT-ACCEPTED", "Gaps of 80 % of CDT between the tester's characters are accepted",
             "Table 2-4 CDT; §2.2.2 Receive/receiving data; 3964r.md §8.3 item 2",
             "A receiver that times out before CDT has passed between two characters is wrong.",
             "timing", "receiver", receive_block(P, p, gap="0.8*CDT - CHAR"),
             delivered=[P], echo_after=[P], provenance="[S]"),
        case(p, "TIMING.FIRST-CHARACTER-AT-80-CDT", "The first data character 80 % of CDT after the DLE is accepted",
             "Table 8-1 16#0806; 3964r.md §8.2 item 3",
             "The first character after the receiver's DLE may come up to CDT later.",
             "timing", "receiver", receive_block(P, p, first_at="0.8*CDT - CHAR"),
             delivered=[P], echo_after=[P], provenance="[S]"),
        case(p, "TIMING.GAP-OVER-CDT-REFUSED", "A gap of 1.5 x CDT inside the block makes the IUT refuse it",
             "§2.2.2 Receive/receiving data; Table 8-1 16#0806; 3964r.md §8.3 item 5",
             "A receiver must time out once CDT has passed between two characters: after a gap of 1.5 x CDT it has sent NAK and does not accept the rest of the block.",
             "timing", "receiver",
             [send(STX), expect(DLE), send(B[:3], mark=True),
              send(B[3:], at="1.5*CDT", note="the rest of the block, after a gap of 1.5 x CDT"),
              expect(NAK, after="CDT", within="CDT + 2*CHAR", since="mark", note="NAK once CDT had passed"),
              expect(NAK, after="CDT", within="CDT + ADT", since="sent", optional=True,
                     note="a NAK for the rest, which came as stray characters")],
             iut=(["16#0806"], ["16#0801", "16#0802", "16#0815"]), provenance="[S]"),
        case(p, "TIMING.SETUP-DLE-AT-80-ADT", "The tester's DLE 80 % of ADT after the IUT's STX is accepted",
             "Table 2-4 ADT; §2.2.2 Send/setup; 3964r.md §7.1 item 2",
             "A sender must wait the whole ADT for the setup DLE; one that gives up early is wrong.",
             "timing", "sender", [prime(P)] + echo_send(P, p, setup_reply_at="0.8*ADT - CHAR"),
             delivered=[P], sent=[P], requires=ECHO, provenance="[S]"),
        case(p, "TIMING.RELEASE-DLE-AT-80-ADT", "The tester's DLE 80 % of ADT after the IUT's block is accepted",
             "Table 2-4 ADT; §2.2.2 Send/release; 3964r.md §7.3 item 3",
             "A sender must wait the whole ADT for the DLE after its block.",
             "timing", "sender",
             [prime(P)] + echo_send(P, p, release_reply_at="0.8*ADT - CHAR"),
             delivered=[P], sent=[P], requires=ECHO, provenance="[S]"),
    ]
    if p.has_bcc:
        out.append(case(p, "TIMING.BCC-AT-80-CDT", "The BCC 80 % of CDT after DLE ETX is accepted",
                        "Fig. 2-12 'wait for BCC'; 3964r.md §8.4 item 2",
                        "A 3964R receiver waits up to CDT for the BCC.", "timing", "receiver",
                        receive_block(P, p, bcc_at="0.8*CDT - CHAR"), delivered=[P], echo_after=[P],
                        provenance="[F]"))
    return out
