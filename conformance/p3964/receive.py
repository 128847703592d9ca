"""The IUT as receiver (§2.2.2 Receive; Figs. 2-6, 2-11, 2-12; 3964r.md §8)."""


from ._build import (DLE, NAK, STX, body, case, expect, h, nak_after_cdt, receive_block, send,
                     send_error, silence)

REPEAT_OPTIONAL = ["16#0801", "16#0815"]


def _accept(p, id, title, ref, rule, payload, provenance="[S]", **kw):
    payload = h(payload)
    return case(p, id, title, ref, rule, "receive", "receiver", receive_block(payload, p, **kw),
                delivered=[payload], echo_after=[payload] if payload else [], provenance=provenance)


def _refuse(p, id, title, ref, rule, data, code, *, window=None, provenance="[S]", readings=(), group="receive",
            extra=(), tester=((), ())):
    steps = [send(STX), expect(DLE, note="DLE"), send(data, note="the block")]
    steps.append(window or expect(NAK, note="NAK: the block is refused"))
    steps += list(extra)
    return case(p, id, title, ref, rule, group, "receiver", steps, iut=([code], REPEAT_OPTIONAL),
                tester=tester, readings=readings, provenance=provenance)


def cases(p):
    R = p.has_bcc
    if R:   # a block with a wrong BCC, refused at once
        refused, refused_code = [send(h("31 32 10 03 00"), note="a bad block"), expect(NAK)], "16#0808"
    else:   # a 3964 block cut short: the NAK comes after CDT of waiting for more
        refused, refused_code = [send("31 32"), nak_after_cdt()], "16#0806"
    P1 = h("31 10 32 15 03")
    out = [
        case(p, "RECEIVE.DLE-REPLY-TO-STX", "STX in idle is answered with DLE",
             "§2.2.2 Receive/setup; Fig. 2-6; 3964r.md §8.2 item 1",
             "A station in idle with a free receive buffer answers STX with DLE and starts receiving.",
             "receive", "receiver", [send(STX), expect(DLE), send(body(b"\x30", p)), expect(DLE)],
             delivered=[b"\x30"], echo_after=[b"\x30"], provenance="[S]"),
        _accept(p, "RECEIVE.UNDOUBLE-SINGLE", "One data DLE (sent doubled) is stored once",
                "§2.2.2 Receive/receiving data; Fig. 2-12 'dual DLE'; 3964r.md §3 item 2",
                "DLE DLE in the data is stored as one 10.", P1, provenance="[S][F]"),
        _accept(p, "RECEIVE.UNDOUBLE-TRAILING", "A data DLE right before the end sequence",
                "§2.2.2 Control characters; 3964r.md §3, §13.5 D22",
                "A doubled DLE directly before DLE ETX is one data byte; the end sequence follows it.",
                "41 42 10", provenance="[S][I]"),
        _accept(p, "RECEIVE.UNDOUBLE-RUN", "A run of data DLEs is undoubled pair by pair",
                "§2.2.2 Receive/receiving data; 3964r.md §3 item 2",
                "Each DLE DLE pair in the data is one 10, so six DLEs on the line are three data bytes.",
                "10 10 10", provenance="[S][I]"),
        _accept(p, "RECEIVE.ONLY-DLE", "A block whose only data byte is DLE",
                "§2.2.2 Control characters; 3964r.md §3, §13.5 D23",
                "A block made of one data DLE (DLE DLE DLE ETX) is the byte 10.", "10", provenance="[S][I]"),
        _accept(p, "RECEIVE.CONTROL-VALUES-AS-DATA", "STX, ETX, NAK, 00 and FF inside the data are data",
                "§2.2.2 Control characters; Fig. 2-12; 3964r.md §3 item 3",
                "In the data phase only DLE-prefixed pairs have a meaning; 02, 03, 15, 00 and FF are stored as they are.",
                "02 03 15 00 FF 02 15", provenance="[I]"),
        _accept(p, "RECEIVE.ONE-BYTE", "A block of one byte", "Tables 6-2/6-3 LEN 1..1024; 3964r.md §2.2",
                "The smallest block, one user byte, is received.", "00", provenance="[S]"),
        _accept(p, "RECEIVE.MAX-1024", "A block of 1024 user bytes is accepted",
                "Table A-5; Tables 6-2/6-3 LEN 1..1024; 3964r.md §2.2, §17 A17",
                "The largest block, 1024 user bytes counted before DLE doubling, is accepted.",
                bytes(range(256)) * 4, provenance="[S][I]"),
        _refuse(p, "RECEIVE.TOO-LONG-1025", "A block of 1025 user bytes is refused",
                "Table 8-1 16#0816; Table A-5; 3964r.md §8.3 item 6, §17 A17",
                "More than 1024 user bytes is longer than agreed (16#0816): the block is refused with NAK.",
                body(b"\x5a" * 1025, p), "16#0816", provenance="[S][I]", readings=["A17"]),
        _refuse(p, "RECEIVE.DLE-FOLLOWED-BY-OTHER", "DLE followed by a character other than DLE or ETX",
                "§2.2.2 Control characters; Table 8-1 16#0805; 3964r.md §8.3 item 3, §17 A11",
                "In the data a DLE must be followed by DLE or ETX; otherwise the block is refused with NAK (16#0805), at once or at its end (A11).",
                h("31 10 41 32 10 03") + (bytes([0x31 ^ 0x10 ^ 0x41 ^ 0x32 ^ 0x10 ^ 0x03]) if R else b""),
                "16#0805", readings=["A11"],
                window=expect(NAK, after="-6*CHAR", note="NAK (A11: at the odd byte or at the end)"),
                extra=[expect(NAK, after="CDT", within="CDT + ADT", since="sent", optional=True,
                              note="a second NAK for the rest of the block, from an IUT that refused at once")]),
        case(p, "RECEIVE.CDT-AFTER-DLE", "No data after the IUT's DLE: NAK after CDT",
             "Table 8-1 16#0806; 3964r.md §8.2 item 3",
             "The first data character must arrive within CDT of the receiver's DLE; otherwise NAK (16#0806).",
             "receive", "receiver", [send(STX), expect(DLE), nak_after_cdt()],
             iut=(["16#0806"], REPEAT_OPTIONAL), readings=["A2"], provenance="[S]"),
        case(p, "RECEIVE.CDT-INSIDE-DATA", "A pause longer than CDT inside the data: NAK after CDT",
             "§2.2.2 Receive/receiving data; Table 8-1 16#0806; 3964r.md §8.3 item 5",
             "When the next character does not come within CDT the receiver sends NAK (16#0806).",
             "receive", "receiver", [send(STX), expect(DLE), send("31 32"), nak_after_cdt()],
             iut=(["16#0806"], REPEAT_OPTIONAL), readings=["A2"], provenance="[S]"),
        case(p, "RECEIVE.CDT-AFTER-DATA-DLE", "A pause longer than CDT after a DLE in the data: NAK",
             "Fig. 2-12 'wait for ETX', 'T > T_CDT'; 3964r.md §8.3 item 2",
             "After a DLE the receiver waits CDT for the next character (DLE or ETX); otherwise NAK (16#0806).",
             "receive", "receiver", [send(STX), expect(DLE), send("31 10"), nak_after_cdt()],
             iut=(["16#0806"], REPEAT_OPTIONAL), provenance="[F]"),
        case(p, "RECEIVE.PARITY-ERROR-NAK-AT-END", "A parity error in the data is answered by NAK only at the end",
             "§2.2.2 Receive/receiving data; Fig. 2-12 'invalid character, note NAK'; Table 8-1 16#080C; 3964r.md §8.3 item 4",
             "A character with a transmission error does not stop reception: NAK (16#080C) comes only after the end of the block, never in its middle.",
             "character-error", "receiver",
             [send(STX), expect(DLE), send("31 32 33"), send_error("34", note="parity error"),
              send(h("35 36 37 38 39 3A 10 03") + (bytes([0x31 ^ 0x32 ^ 0x33 ^ 0x34 ^ 0x35 ^ 0x36 ^ 0x37 ^ 0x38 ^ 0x39 ^ 0x3A ^ 0x13]) if R else b""),
                   note="the rest of the block; no NAK may come before its end"),
              expect(NAK, note="NAK only now")],
             iut=(["16#080C"], REPEAT_OPTIONAL), provenance="[S][F]"),
        case(p, "RECEIVE.REPETITION-ACCEPTED", "After refusing a block the IUT accepts its repetition",
             "§2.2.2 Receive/receiving data; Fig. 2-7; 3964r.md §8.5 item 2",
             "After a NAK the receiver waits for the repetition; a STX within T_BLOCK is answered with DLE and the block received.",
             "repetition", "receiver",
             [send(STX), expect(DLE)] + refused + receive_block(b"\x31\x32", p),
             iut=([refused_code], ["16#0801"]), delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"],
             provenance="[S][F]"),
    ]
    if R:
        wrong = [(0x16, "DLE-ONCE", "the doubled DLE counted once"), (0x04, "STX-INCLUDED", "the STX included"),
                 (0x15, "END-OMITTED", "the end sequence left out"), (0x07, "OFF-BY-ONE-BIT", "one bit wrong")]
        for bcc, name, why in wrong:
            out.append(_refuse(
                p, f"RECEIVE.BCC-{name}", f"A BCC computed with {why} is refused",
                "§2.2.2 Block check character; Table 8-1 16#0808; 3964r.md §4.1, §4.3",
                "The BCC is the XOR of all bytes after STX through DLE ETX, doubled DLEs counted twice; any other value is refused with NAK (16#0808).",
                h("31 10 10 32 15 03 10 03") + bytes([bcc]), "16#0808", provenance="[S][I]",
                tester=(["16#0706"], ["16#0701"])))
        out += [
            _accept(p, "RECEIVE.BCC-EQUALS-DLE", "A BCC equal to DLE is the BCC, not a DLE",
                    "3964r.md §3 item 5, §4.3, §13.4",
                    "The byte after DLE ETX is the BCC, even when it is 10; it is not doubled.", "41 42 10",
                    provenance="[I]"),
            _accept(p, "RECEIVE.BCC-OF-ZERO-LOSS", "A block that lost a 00 still matches its BCC and is accepted",
                    "§2.2.1 Limits of 3964R; 3964r.md §4.4, §13.5 D20",
                    "The XOR cannot see a lost 00 character; such a block is accepted (a known limit, not a defect).",
                    "31 33", provenance="[S][I]"),
            case(p, "RECEIVE.CDT-BEFORE-BCC", "No BCC after DLE ETX: NAK after CDT",
                 "Fig. 2-12 'wait for BCC'; 3964r.md §8.4 item 2, §13.5 D9",
                 "A 3964R receiver waits CDT for the BCC after DLE ETX; otherwise NAK (16#0806).",
                 "receive", "receiver", [send(STX), expect(DLE), send("31 10 03"), nak_after_cdt()],
                 iut=(["16#0806"], REPEAT_OPTIONAL), provenance="[F][I]"),
            case(p, "RECEIVE.3964R-WAITS-FOR-BCC", "A 3964R receiver does not answer at DLE ETX but after the BCC",
                 "Table 2-3; Fig. 2-12 '3964 / 3964R', 'wait for BCC'; 3964r.md §8.4",
                 "With 3964R the receiver answers only after the BCC has come, not at DLE ETX.",
                 "receive", "receiver",
                 [send(STX), expect(DLE), send(body(b"\x31\x32", p)[:-1], note="data, DLE ETX"),
                  silence("0.5*CDT", note="no answer yet: the BCC is missing"),
                  send(body(b"\x31\x32", p)[-1:], note="BCC"), expect(DLE)],
                 delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"], provenance="[S][F]"),
        ]
    else:
        out.append(case(p, "RECEIVE.3964-ANSWERS-AT-ETX", "A 3964 receiver answers at DLE ETX (no BCC)",
                        "Table 2-3; §2.2.2 Receive/release; 3964r.md §8.4 item 1",
                        "With 3964 the receiver stops at DLE ETX and answers at once; it does not wait for a BCC.",
                        "receive", "receiver",
                        [send(STX), expect(DLE), send("31 32 10 03"), expect(DLE, within="0.5*CDT")],
                        delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"], provenance="[S]"))
    return out
