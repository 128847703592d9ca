"""The IUT as sender, made to send by the echo convention (§2.2.2 Send; Figs. 2-5, 2-10;
3964r.md §7.1-7.2)."""

from ._build import (DLE, NAK, STX, body, case, echo_send, expect, h, long_payload, nak_after_cdt, prime,
                     send, send_error)

ECHO = ["echo"]


def _echo_case(p, id, title, payload, rule, ref="§2.2.2 Send; Fig. 2-5; 3964r.md §3, §4, §7", max_gap="CDT",
               provenance="[S][F]"):
    payload = h(payload)
    return case(p, id, title, ref, rule, "send", "sender", [prime(payload)] + echo_send(payload, p, max_gap=max_gap),
                delivered=[payload], sent=[payload], requires=ECHO, provenance=provenance)


def cases(p):
    N, M = p.setup_attempts, p.transmission_attempts
    P = h("31 10 32 15 03")
    out = [
        _echo_case(p, "SEND.ECHO-P1", "The IUT sends a block with a data DLE: doubled, with DLE ETX and BCC", P,
                   "A sender doubles every data DLE, ends with DLE ETX and, for 3964R, the XOR of all bytes after STX through DLE ETX."),
        _echo_case(p, "SEND.ECHO-ONE-BYTE", "The IUT sends a one-byte block", "00",
                   "The smallest block, one user byte, is framed like any other."),
        _echo_case(p, "SEND.ECHO-ONLY-DLES", "The IUT sends a block made of data DLEs", "10 10 10 10 10",
                   "Every data DLE is sent twice; the BCC counts both."),
        _echo_case(p, "SEND.ECHO-CONTROL-VALUES", "The IUT sends STX, ETX, NAK, 00 and FF as plain data",
                   "02 03 15 00 FF 10 02 15 03",
                   "Only DLE is doubled; 02, 03, 15, 00 and FF go out unchanged.", provenance="[S][I]"),
        _echo_case(p, "SEND.ECHO-MAX-1024", "The IUT sends a block of 1024 bytes without gaps longer than CDT",
                   bytes(range(256)) * 4,
                   "A sender may not pause longer than CDT between two characters of a block (the receiver would NAK).",
                   ref="§2.2.2 Sending data; Table A-5; 3964r.md §7.2 item 2"),
    ]
    if p.has_bcc:
        out.append(_echo_case(p, "SEND.ECHO-BCC-EQUALS-DLE", "The IUT sends a block whose BCC is 10, not doubled",
                              "41 42 10", "The BCC after DLE ETX is never doubled, even when it equals DLE.",
                              ref="3964r.md §3 item 5, §4.3, §13.4", provenance="[I]"))
    # connection setup (§7.1)
    out += [
        case(p, "SEND.SETUP-REFUSED-BY-NAK", "STX answered by NAK: a new STX, then the block",
             "§2.2.2 Send/setup; Table 8-1 16#0702; 3964r.md §7.1 item 3",
             "A NAK in answer to STX is a failed setup attempt: the sender sends STX again.",
             "send", "sender",
             [prime(P), expect(STX), send(NAK, note="refused"), expect(STX, note="a new setup attempt")]
             + echo_send(P, p)[1:], iut=((), ["16#0702"]), delivered=[P], sent=[P], requires=ECHO,
             readings=["A8"], provenance="[S]"),
        case(p, "SEND.SETUP-REFUSED-BY-OTHER", "STX answered by another character: a new STX",
             "§2.2.2 Send/setup; Table 8-1 16#0702; 3964r.md §7.1 item 3",
             "Any character other than DLE or STX in answer to STX is a failed setup attempt.",
             "send", "sender",
             [prime(P), expect(STX), send("41", note="not DLE"), expect(STX, note="a new setup attempt")]
             + echo_send(P, p)[1:], iut=((), ["16#0702"]), delivered=[P], sent=[P], requires=ECHO,
             provenance="[S]"),
        case(p, "SEND.SETUP-TIMEOUT-RETRY", "No answer to STX: a new STX after ADT, not before",
             "§2.2.2 Send/setup; Table 8-1 16#0703; 3964r.md §7.1 item 3",
             "When no DLE comes within ADT the sender repeats STX; it does not give up early.",
             "send", "sender",
             [prime(P), expect(STX, note="the tester stays silent"),
              expect(STX, after="ADT", within="ADT + 2*CHAR", note="the next STX, ADT later")]
             + echo_send(P, p)[1:], iut=((), ["16#0703"]), delivered=[P], sent=[P], requires=ECHO,
             provenance="[S]"),
        case(p, "SEND.SETUP-ATTEMPTS-REFUSED", f"Setup refused {N} times: exactly {N} STX, then one NAK",
             "§2.2.2 Send/setup; Fig. 2-10 'X+1', 'send NAK'; Table 2-4; Table 8-1 16#0709; 3964r.md §7.1 items 5-6",
             "The sender makes exactly 'setup attempts' connection setups and then sends NAK and gives up (16#0709).",
             "send", "sender",
             [prime(P)] + sum(([expect(STX, note=f"STX {i + 1}"), send(NAK)] for i in range(N)), [])
             + [expect(NAK, note="the sender's NAK")],
             iut=(["16#0702|16#0709"], ()), delivered=[P], requires=ECHO, provenance="[S][F]"),
        case(p, "SEND.SETUP-ATTEMPTS-TIMEOUT", f"No answer to {N} STX: then one NAK, each ADT apart",
             "§2.2.2 Send/setup; Fig. 2-10; Table 8-1 16#0703, 16#0709; 3964r.md §7.1, §13.5 D10",
             "Setup attempts that time out are counted like refused ones; after the last the sender sends NAK (16#0703, 16#0709).",
             "send", "sender",
             [prime(P), expect(STX, note="STX 1")]
             + [expect(STX, after="ADT", within="ADT + 2*CHAR", note=f"STX {i + 2}") for i in range(N - 1)]
             + [expect(NAK, after="ADT", within="ADT + 2*CHAR", note="NAK")],
             iut=(["16#0703|16#0709"], ()), delivered=[P], requires=ECHO, provenance="[S][F]"),
        case(p, "SEND.SETUP-CHARACTER-ERROR", "STX answered by a character with a parity error: a new STX",
             "Fig. 2-10 'invalid character'; Table 8-1 16#080C; 3964r.md §7.1 item 3",
             "A corrupted character in answer to STX is a failed setup attempt.",
             "character-error", "sender",
             [prime(P), expect(STX), send_error("10", note="DLE with a parity error"), expect(STX)]
             + echo_send(P, p)[1:], iut=((), ["16#080C", "16#0702"]), delivered=[P], sent=[P], requires=ECHO,
             provenance="[F]"),
    ]
    # data phase (§7.2)
    L = long_payload(p)
    rest = body(L, p)[10:]
    out += [
        case(p, "SEND.NAK-DURING-DATA", "NAK during the data: the IUT stops, sends no NAK, starts again with STX",
             "§2.2.2 Sending data; Table 8-1 16#0704, 16#0701; 3964r.md §7.2 item 3, §13.5 D14",
             "A NAK received while sending the block cancels it; the sender starts a new attempt with STX and sends no NAK of its own.",
             "send", "sender",
             [prime(L), expect(STX), send(DLE), expect(L[:10], within="CDT", note="the first 10 data bytes"),
              send(NAK, note="NAK in the middle of the block"),
              expect(rest, partial=True, within="4*CHAR", note="the IUT stops"),
              expect(STX, note="new STX, no NAK before it")] + echo_send(L, p)[1:],
             iut=((), ["16#0704", "16#0701"]), delivered=[L], sent=[L], requires=ECHO, provenance="[S]"),
        case(p, "SEND.OTHER-DURING-DATA", "Another character during the data: stop, quiet for CDT, NAK, new STX",
             "§2.2.2 Sending data; Table 8-1 16#0704; 3964r.md §7.2 item 4, §13.5 D15",
             "A character received while sending stops the block; the sender waits until CDT has passed, sends NAK, then STX.",
             "send", "sender",
             [prime(L), expect(STX), send(DLE), expect(L[:10], within="CDT"), send("42", note="an unexpected character"),
              expect(rest, partial=True, within="4*CHAR", note="the IUT stops"),
              nak_after_cdt(since="sent"), expect(STX, note="new STX")] + echo_send(L, p)[1:],
             iut=((), ["16#0704", "16#0701"]), delivered=[L], sent=[L], requires=ECHO, readings=["A7"],
             provenance="[S]"),
        case(p, "SEND.EVERY-ATTEMPT-INTERRUPTED", f"NAK during the data of every attempt: {M} attempts, then NAK",
             "§2.2.2 Sending data; Table 2-4; Table 8-1 16#0704, 16#070A; 3964r.md §7.2, §7.4, §7.5",
             "A NAK during the data is a failed transmission attempt; after the last the sender sends NAK (16#070A).",
             "send", "sender",
             [prime(L)] + sum(([expect(STX, note=f"attempt {i + 1}"), send(DLE), expect(L[:10], within="CDT"), send(NAK),
                                expect(rest, partial=True, within="4*CHAR")] for i in range(M)), [])
             + [expect(NAK, note="the sender's NAK")],
             iut=(["16#0704|16#070A"], ["16#0701"]), delivered=[L], requires=ECHO, provenance="[S][I]"),
    ]
    return out
