"""BREAK and character errors (§2.2.2 Error handling; Figs. 2-10 to 2-12 legend; 3964r.md §10).
Character errors inside blocks are in receive.py, send.py and release.py."""

from ._build import DLE, NAK, STX, body, brk, case, expect, h, long_payload, prime, receive_block, send, send_error, silence

ECHO = ["echo"]
BREAK_REF = "§2.2.2 Error handling; Figs. 2-10 to 2-12 'immediate return to the initial state on BREAK'; Table 8-1 16#080D; 3964r.md §10 item 5"
RULE = "On BREAK the procedure returns to idle at once: no NAK, no repetition; once the line is restored it works again."


def cases(p):
    P = h("31 32 33")
    L = long_payload(p)
    after = receive_block(b"\x61\x62", p)
    common = dict(iut=(["16#080D"], ["16#1E0D"]), readings=["A15"], provenance="[S][F]")
    return [
        case(p, "BREAK.IDLE", "BREAK in idle: no reaction on the line; the next block is received",
             BREAK_REF, RULE, "break", "idle",
             [brk(), silence("2*CDT + ADT", note="no NAK")] + after,
             delivered=[b"\x61\x62"], echo_after=[b"\x61\x62"], **common),
        case(p, "BREAK.RECEPTION", "BREAK during a reception: no NAK; the next block is received",
             BREAK_REF + "; 3964r.md §13.5 D21", RULE, "break", "receiver",
             [send(STX), expect(DLE), send("31 32"), brk(),
              silence("2*CDT", note="no NAK: the reception was abandoned, not timed out")] + after,
             delivered=[b"\x61\x62"], echo_after=[b"\x61\x62"], **common),
        case(p, "BREAK.SETUP", "BREAK while the IUT waits for its setup DLE: no retry, no NAK",
             BREAK_REF + "; 3964r.md §7.6", RULE, "break", "sender",
             [prime(P), expect(STX), brk(), silence("2*ADT + CDT", note="no new STX and no NAK")] + after,
             delivered=[P, b"\x61\x62"], echo_after=[b"\x61\x62"], requires=ECHO, **common),
        case(p, "BREAK.DATA", "BREAK while the IUT sends its block: it stops; no retry, no NAK",
             BREAK_REF + "; 3964r.md §7.6", RULE, "break", "sender",
             [prime(L), expect(STX), send(DLE), expect(L[:10], within="CDT"), brk(),
              expect(body(L, p)[10:], partial=True, after="-22*CHAR", within="4*CHAR",
                     note="the IUT stops (it learnt of the BREAK when the line went to space)"),
              silence("2*ADT + CDT", note="no new STX and no NAK")] + after,
             delivered=[L, b"\x61\x62"], echo_after=[b"\x61\x62"], requires=ECHO, **common),
        case(p, "BREAK.RELEASE", "BREAK while the IUT waits for the acknowledgement of its block: no retry",
             BREAK_REF + "; 3964r.md §7.6", RULE, "break", "sender",
             [prime(P), expect(STX), send(DLE), expect(body(P, p), within="CDT"), brk(),
              silence("2*ADT + CDT", note="no repetition and no NAK")] + after,
             delivered=[P, b"\x61\x62"], echo_after=[b"\x61\x62"], requires=ECHO, **common),
        case(p, "BREAK.WAITING-FOR-REPETITION", "BREAK while the IUT waits for a repetition: idle, no NAK",
             BREAK_REF, RULE, "break", "receiver",
             [send(STX), expect(DLE), send("31"), send_error("32", note="parity error: the block will be refused"),
              send(h("10 03") + (bytes([0x31 ^ 0x32 ^ 0x13]) if p.has_bcc else b"")),
              expect(NAK, note="refused: the IUT now waits for the repetition"), brk(), silence("2*CDT")] + after,
             delivered=[b"\x61\x62"], echo_after=[b"\x61\x62"],
             iut=(["16#080D"], ["16#1E0D", "16#080C", "16#0801"]), readings=["A15"], provenance="[S][F]"),
    ]
