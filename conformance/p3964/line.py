"""BREAK (§2.2.2 Error handling; Figs. 2-10 to 2-12 legend 'immediate return to the initial
state on BREAK'; Table 8-1 16#080D). One case per state a BREAK can meet; character errors
inside blocks are in receive.py, send.py and release.py."""

from ._build import (DLE, NAK, STX, bcc_of, body, brk, case, expect, h, long_payload, prime, receive_block, send,
                     send_error, silence)

ECHO = ["echo"]
BREAK_REF = ("§2.2.2 Error handling; Figs. 2-10 to 2-12 legend 'immediate return to the initial state on BREAK'; "
             "Table 8-1 16#080D")
RULE = "On BREAK the procedure returns to idle at once: no NAK, no repetition; once the line is restored it works again."
NO_BUFFER = ("no_buffer", {})


def cases(p):
    P = h("31 32 33")
    L = long_payload(p)
    after = receive_block(b"\x61\x62", p)
    rx = dict(iut=(["16#080D"], ()), readings=["A15"], provenance="[S][F]", rules=["3964.BREAK.RECEIVE"],
              delivered=[b"\x61\x62"], echo_after=[b"\x61\x62"])
    # the send side may report 16#1E0D instead of 16#080D (A15)
    tx = dict(iut=(["16#080D|16#1E0D"], ["16#080D", "16#1E0D"]), readings=["A15"], provenance="[S][F]",
              rules=["3964.BREAK.SEND"], requires=ECHO, echo_after=[b"\x61\x62"])

    def rx_case(id, title, before, rule=RULE, **kw):
        return case(p, id, title, BREAK_REF, rule, "break", "receiver",
                    before + [brk(), silence("2*CDT", note="no NAK: the reception was abandoned, not timed out")]
                    + after, **{**rx, **kw})

    out = [
        case(p, "BREAK.IDLE", "BREAK in idle: no reaction on the line; the next block is received",
             BREAK_REF, RULE, "break", "idle",
             [brk(), silence("2*CDT + ADT", note="no NAK")] + after,
             **{**rx, "rules": ["3964.BREAK.IDLE"]}),
        case(p, "BREAK.IDLE-QUIET-WAIT", "BREAK while a stray character waits for its NAK: the NAK is dropped",
             BREAK_REF + "; §2.2.2 Receive/setup",
             "A BREAK during the wait before the NAK for a stray character returns the station to idle at once: that NAK is not sent.",
             "break", "idle",
             [send("41", note="a stray character: its NAK would come after CDT"),
              brk(note="BREAK before CDT has passed"), silence("2*CDT + ADT", note="no NAK")] + after,
             **{**rx, "iut": (["16#080D"], ["16#0802"]), "rules": ["3964.BREAK.IDLE"]}),
        rx_case("BREAK.RECEPTION", "BREAK during a reception: no NAK; the next block is received",
                [send(STX), expect(DLE), send("31 32")]),
        rx_case("BREAK.WAITING-FOR-ETX", "BREAK after a DLE in the data: no NAK; the next block is received",
                [send(STX), expect(DLE), send("31 10", note="data, then a DLE: the receiver waits for DLE or ETX")]),
        case(p, "BREAK.WAITING-FOR-BUFFER", "BREAK while the IUT waits for a free buffer: no NAK at 400 ms",
             BREAK_REF + "; Fig. 2-11 'start T_NAKTIM'",
             "A BREAK during the wait for a free receive buffer ends it at once: the NAK that T_NAKTIM would bring is not sent.",
             "break", "receiver",
             [send(STX, note="STX while the IUT's receive buffer is full (setup no_buffer)"),
              brk(at="0.25*NAKTIM", note="BREAK during the buffer wait"),
              silence("NAKTIM + 2*CDT", note="no NAK: the wait was abandoned")],
             iut=(["16#080D"], ()), readings=["A15"], provenance="[S][F]", rules=["3964.BREAK.RECEIVE"],
             setup=NO_BUFFER),
        case(p, "BREAK.WAITING-FOR-REPETITION", "BREAK while the IUT waits for a repetition: idle, no NAK",
             BREAK_REF, RULE, "break", "receiver",
             [send(STX), expect(DLE), send("31"), send_error("32", note="parity error: the block will be refused"),
              send(h("10 03") + (bytes([bcc_of("31 32")]) if p.has_bcc else b"")),
              expect(NAK, note="refused: the IUT now waits for the repetition"), brk(), silence("2*CDT")] + after,
             **{**rx, "iut": (["16#080D"], ["16#080C", "16#0801"])}),
        case(p, "BREAK.SETUP", "BREAK while the IUT waits for its setup DLE: no retry, no NAK",
             BREAK_REF, RULE, "break", "sender",
             [prime(P), expect(STX, within="ADT + BLOCK"), brk(),
              silence("2*ADT + CDT", note="no new STX and no NAK")] + after,
             delivered=[P, b"\x61\x62"], **tx),
        case(p, "BREAK.DATA", "BREAK while the IUT sends its block: it stops; no retry, no NAK",
             BREAK_REF, RULE, "break", "sender",
             [prime(L), expect(STX, within="ADT + BLOCK"), send(DLE), expect(L[:10], within="CDT"), brk(),
              expect(body(L, p)[10:], partial=True, after="-22*CHAR", within="4*CHAR",
                     note="the IUT stops (it learnt of the BREAK when the line went to space)"),
              silence("2*ADT + CDT", note="no new STX and no NAK")] + after,
             delivered=[L, b"\x61\x62"], **tx),
        case(p, "BREAK.SENDER-QUIET-WAIT", "BREAK while the IUT waits to NAK a character it got during its block",
             BREAK_REF + "; §2.2.2 Sending data",
             "A BREAK during the sender's quiet wait (after a character during its block) ends the job at once: the NAK and the new attempt are not sent.",
             "break", "sender",
             [prime(L), expect(STX, within="ADT + BLOCK"), send(DLE), expect(L[:10], within="CDT"),
              send("42", note="a character during the block: the IUT stops and waits for CDT of quiet"),
              brk(at="2*CHAR", note="BREAK before CDT has passed"),
              expect(body(L, p)[10:], partial=True, after="-30*CHAR", within="0", note="the IUT had stopped"),
              silence("2*ADT + CDT", note="no NAK, no new STX")] + after,
             delivered=[L, b"\x61\x62"], **{**tx, "iut": (["16#080D|16#1E0D"], ["16#080D", "16#1E0D", "16#0704"])}),
        case(p, "BREAK.RELEASE", "BREAK while the IUT waits for the acknowledgement of its block: no retry",
             BREAK_REF, RULE, "break", "sender",
             [prime(P), expect(STX, within="ADT + BLOCK"), send(DLE), expect(body(P, p), within="CDT"), brk(),
              silence("2*ADT + CDT", note="no repetition and no NAK")] + after,
             delivered=[P, b"\x61\x62"], **tx),
    ]
    if p.has_bcc:
        out.append(rx_case("BREAK.WAITING-FOR-BCC", "BREAK between DLE ETX and the BCC: no NAK; the next block is received",
                           [send(STX), expect(DLE), send("31 32 10 03", note="data, DLE ETX: the receiver waits for the BCC")]))
    return out
