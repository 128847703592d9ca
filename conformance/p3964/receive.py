"""The IUT as receiver (§2.2.2 Receive; Figs. 2-6, 2-7, 2-11, 2-12; Tables 2-3, 8-1)."""


from ptpcert.procedures.p3964.model.params import Params3964

from ._build import (
    DLE,
    NAK,
    PLAIN,
    STX,
    bcc_of,
    body,
    case,
    expect,
    h,
    maybe,
    nak_after_cdt,
    partner,
    plain_1024,
    receive_block,
    send,
    send_error,
    settle,
    seven_bit,
    wait,
)

REPEAT_OPTIONAL = ["16#0801", "16#0815"]
NO_BUFFER = ("no_buffer", {})


def _accept(p, id, title, ref, rule, payload, rules, provenance="[S]", **kw):
    payload = h(payload)
    return case(p, id, title, ref, rule, "receive", "receiver", receive_block(payload, p, **kw),
                delivered=[payload], echo_after=[payload] if payload else [], provenance=provenance, rules=rules)


def _refuse(p, id, title, ref, rule, data, code, rules, *, window=None, provenance="[S]", readings=(),
            group="receive", extra=(), tester=((), ()), optional=()):
    steps = [send(STX), expect(DLE, note="DLE"), send(data, note="the block")]
    steps.append(window or expect(NAK, note="NAK: the block is refused"))
    steps += list(extra)
    return case(p, id, title, ref, rule, group, "receiver", steps, iut=([code], REPEAT_OPTIONAL + list(optional)),
                tester=tester, readings=readings, provenance=provenance, rules=rules)


def bad_block(p: Params3964):
    """A block the IUT must refuse at its end, the simplest way for the variant: 3964R a
    wrong BCC (16#0808), 3964 a character with a parity error (16#080C)."""
    if p.has_bcc:
        return [send("31 32 10 03 00", note="a block with a wrong BCC (00; 10 is right)"),
                expect(NAK, note="NAK: refused")], "16#0808"
    return [send("31"), send_error("32", note="parity error"), send("10 03"),
            expect(NAK, note="NAK at the end of the block: refused")], "16#080C"


def cases(p):
    R = p.has_bcc
    refused, refused_code = bad_block(p)
    N = p.transmission_attempts
    P1 = h("31 10 32 15 03")
    out = [
        case(p, "RECEIVE.DLE-REPLY-TO-STX", "STX in idle is answered with DLE",
             "§2.2.2 Receive/setup; Fig. 2-6; Fig. 2-11 'STX received', 'send DLE'",
             "A station in idle with a free receive buffer answers STX with DLE and starts receiving.",
             "receive", "receiver", [send(STX), expect(DLE), send(body(b"\x30", p)), expect(DLE)],
             delivered=[b"\x30"], echo_after=[b"\x30"], provenance="[S]",
             rules=["3964.RX.SETUP-DLE", "3964.RX.ACK"]),
        _accept(p, "RECEIVE.UNDOUBLE-SINGLE", "One data DLE (sent doubled) is stored once",
                "§2.2.2 Receive/receiving data; Fig. 2-12 'dual DLE'",
                "DLE DLE in the data is stored as one 10.", P1, ["3964.RX.DLE-UNDOUBLING"], provenance="[S][F]"),
        _accept(p, "RECEIVE.UNDOUBLE-TRAILING", "A data DLE right before the end sequence",
                "§2.2.2 Control characters, Note; Fig. 2-12 'dual DLE', 'ETX'",
                "A doubled DLE directly before DLE ETX is one data byte; the end sequence follows it.",
                "41 42 10", ["3964.RX.DLE-UNDOUBLING"], provenance="[S][I]"),
        _accept(p, "RECEIVE.UNDOUBLE-RUN", "A run of data DLEs is undoubled pair by pair",
                "§2.2.2 Receive/receiving data; Fig. 2-12 'dual DLE'",
                "Each DLE DLE pair in the data is one 10, so six DLEs on the line are three data bytes.",
                "10 10 10", ["3964.RX.DLE-UNDOUBLING"], provenance="[S][I]"),
        _accept(p, "RECEIVE.ONLY-DLE", "A block whose only data byte is DLE",
                "§2.2.2 Control characters; Fig. 2-12 'dual DLE'",
                "A block made of one data DLE (DLE DLE DLE ETX) is the byte 10.", "10",
                ["3964.RX.DLE-UNDOUBLING"], provenance="[S][I]"),
        _accept(p, "RECEIVE.CONTROL-VALUES-AS-DATA", "STX, ETX, NAK, 00 and the highest value inside the data are data",
                "§2.2.2 Control characters; Fig. 2-12 'correct characters except DLE'",
                "In the data only DLE-prefixed pairs have a meaning; 02, 03, 15, 00 and FF (7F with 7 data bits) are stored as they are.",
                seven_bit(p, "02 03 15 00 FF 02 15"), ["3964.RX.DLE-PAIRS-ONLY"], provenance="[I]"),
    ]
    for value, name in ((0x03, "ETX"), (0x02, "STX"), (0x15, "NAK")):
        payload = bytes([0x10, value])
        out.append(_accept(
            p, f"RECEIVE.DATA-DLE-THEN-{name}", f"The data 10 {value:02X}: a doubled DLE followed by {name} is data",
            "§2.2.2 Control characters; Fig. 2-12 'dual DLE', 'DLE + ETX'",
            f"After a doubled data DLE the next character starts afresh: 10 10 {value:02X} on the line is the data 10 {value:02X}, "
            "not an end sequence or a control character; a parser that scans the line for 10 03 is wrong.",
            payload, ["3964.RX.DLE-PAIRS-ONLY"], provenance="[S][I]"))
    out += [
        _accept(p, "RECEIVE.ONE-BYTE", "A block of one byte", "Table 6-3 LEN 1..1024",
                "The smallest block, one user byte, is received.", "00", ["3964.RX.LENGTH"], provenance="[S]"),
        _accept(p, "RECEIVE.MAX-1024", "A block of 1024 user bytes is accepted",
                "Table A-5 (maximum frame 1024 bytes); Table 6-3 LEN 1..1024",
                "The largest block, 1024 user bytes (without a data DLE, so that the count is the same before and after doubling), is accepted.",
                plain_1024(p), ["3964.RX.LENGTH"], provenance="[S]"),
        case(p, "RECEIVE.MAX-STUFFING", "A block of 1024 data DLEs (2048 bytes of data on the line)",
             "Table A-5 (maximum frame 1024 bytes); Table 6-3 LEN 1..1024; §2.2.2 Control characters, Note",
             "The 1024-byte limit counts user bytes before doubling (A17): 1024 data DLEs, 2051 bytes on the line with the end sequence and BCC, are accepted; an IUT that counts after doubling refuses them (non-strict).",
             "receive", "receiver",
             [send(STX), expect(DLE), send(body(b"\x10" * 1024, p), note="1024 data DLEs, each doubled"),
              expect(DLE, alternatives=[NAK], alt_grade="non-strict",
                     note="DLE (counted before doubling) or NAK (counted after doubling, non-strict: A17)"),
              partner("2100*CHAR + 2*ADT + BLOCK",
                           "an echo IUT sends the 1024 DLEs back: a conforming partner receives them")],
             iut=((), ["16#0816", "16#0801", "16#0815"]), delivered=[b"\x10" * 1024], readings=["A17"],
             provenance="[S][I]", rules=["3964.RX.LENGTH"]),
        case(p, "RECEIVE.TOO-LONG-1025", "A block of 1025 user bytes is refused, or accepted (non-strict)",
             "Table 8-1 16#0816; Table A-5 (maximum frame 1024 bytes)",
             "More than 1024 user bytes is longer than agreed (16#0816); the manual states no reaction on the line (A17): a NAK at any point of the block is our reading, a DLE is graded non-strict.",
             "receive", "receiver",
             [send(STX), expect(DLE), send(body(b"\x5a" * 1025, p), note="1025 user bytes"),
              expect(NAK, after="-1040*CHAR", alternatives=[DLE], alt_grade="non-strict",
                     note="NAK: at the end of the block (A17), or earlier once the block was too long; DLE: non-strict"),
              partner("1100*CHAR + 2*ADT + BLOCK",
                           "what follows is not graded: a NAK for the rest of a block refused early, an echo")],
             iut=((), ["16#0816", "16#0801", "16#0815", "16#0802"]), readings=["A17"], provenance="[S][O]",
             rules=["3964.RX.TOO-LONG"]),
        case(p, "RECEIVE.ZERO-LENGTH", "A block without user data is answered with DLE or NAK",
             "Table 6-3 LEN 1..1024; §2.2.2 Receive/release",
             "A block without data (DLE ETX [BCC] right after the setup) is not described (A17): the receiver must answer it with DLE or NAK; an echo IUT may send the empty block back or not.",
             "receive", "receiver",
             [send(STX), expect(DLE), send(body(b"", p), note="DLE ETX" + (", BCC 13" if R else "") + ": no data"),
              expect(DLE, alternatives=[NAK], note="DLE (our reading) or NAK (A17)"),
              partner("ADT + BLOCK + 20*CHAR", "an echo IUT may send the empty block back (STX, then DLE ETX"
                           + (" BCC" if R else "") + "), or nothing")],
             iut=((), ["16#0801", "16#0802", "16#0805", "16#0806", "16#0808", "16#0815", "16#0816", "16#1E41"]),
             delivered=[b""], readings=["A17"], provenance="[O]", rules=["3964.RX.ZERO-LENGTH"]),
        _refuse(p, "RECEIVE.DLE-FOLLOWED-BY-OTHER", "DLE followed by a character other than DLE or ETX",
                "§2.2.2 Control characters; Fig. 2-12 'characters except ETX, DLE', 'note NAK'; Table 8-1 16#0805",
                "In the data a DLE must be followed by DLE or ETX; otherwise the block is refused with NAK (16#0805), at once or at its end (A11).",
                h("31 10 41 32 10 03") + (bytes([bcc_of("31 10 41 32")]) if R else b""),
                "16#0805", ["3964.RX.DLE-OTHER"], readings=["A11"],
                window=expect(NAK, after="-6*CHAR", note="NAK (A11: at the odd byte or at the end)"),
                extra=[expect(NAK, after="CDT", within="CDT + ADT", since="sent", optional=True,
                              note="a second NAK for the rest of the block, from an IUT that refused at once")],
                optional=["16#0802"]),
        case(p, "RECEIVE.CDT-AFTER-DLE", "No data after the IUT's DLE: NAK after CDT",
             "Table 8-1 16#0806 (first character after the DLE not within CDT)",
             "The first data character must arrive within CDT of the receiver's DLE; otherwise NAK (16#0806).",
             "receive", "receiver", [send(STX), expect(DLE), nak_after_cdt()],
             iut=(["16#0806"], REPEAT_OPTIONAL), readings=["A2"], provenance="[S]",
             rules=["3964.RX.FIRST-CHARACTER-TIMEOUT"]),
        case(p, "RECEIVE.CDT-INSIDE-DATA", "A pause longer than CDT inside the data: NAK after CDT",
             "§2.2.2 Receive/receiving data; Fig. 2-12 'T > T_CDT'; Table 8-1 16#0806",
             "When the next character does not come within CDT the receiver sends NAK (16#0806).",
             "receive", "receiver", [send(STX), expect(DLE), send("31 32"), nak_after_cdt()],
             iut=(["16#0806"], REPEAT_OPTIONAL), readings=["A2"], provenance="[S]", rules=["3964.RX.CDT-TIMEOUT"]),
        case(p, "RECEIVE.CDT-AFTER-DATA-DLE", "A pause longer than CDT after a DLE in the data: NAK",
             "Fig. 2-12 'wait for ETX', 'T > T_CDT'; Table 8-1 16#0806",
             "After a DLE the receiver waits CDT for the next character (DLE or ETX); otherwise NAK (16#0806).",
             "receive", "receiver", [send(STX), expect(DLE), send("31 10"), nak_after_cdt()],
             iut=(["16#0806"], REPEAT_OPTIONAL), provenance="[F]", rules=["3964.RX.CDT-AFTER-DLE"]),
        case(p, "RECEIVE.PARITY-ERROR-NAK-AT-END", "A parity error in the data is answered by NAK only at the end",
             "§2.2.2 Receive/receiving data; Fig. 2-12 'invalid character', 'note NAK'; Table 8-1 16#080C",
             "A character with a transmission error does not stop reception: NAK (16#080C) comes only after the end of the block, never in its middle.",
             "character-error", "receiver",
             [send(STX), expect(DLE), send("31 32 33"), send_error("34", note="parity error"),
              send(h("35 36 37 38 39 3A 10 03") + (bytes([bcc_of("31 32 33 34 35 36 37 38 39 3A")]) if R else b""),
                   note="the rest of the block; no NAK may come before its end"),
              expect(NAK, note="NAK only now")],
             iut=(["16#080C"], REPEAT_OPTIONAL), provenance="[S][F]", rules=["3964.RX.CHARACTER-ERROR"]),
        case(p, "RECEIVE.CHARACTER-ERROR-AFTER-DATA-DLE", "A parity error right after a data DLE: NAK only at the end",
             "Fig. 2-12 'wait for ETX', 'invalid character', 'note NAK'; Table 8-1 16#080C, 16#0805",
             "A transmission error in the character after a data DLE is noted like any other: the reception goes on and the NAK comes after the end of the block.",
             "character-error", "receiver",
             [send(STX), expect(DLE), send("31 10"), send_error("10", note="the second DLE of the pair, with a parity error"),
              send(h("32 33 34 35 36 37 38 10 03") + (bytes([bcc_of("31 10 10 32 33 34 35 36 37 38")]) if R else b""),
                   note="the rest of the block; no NAK may come before its end"),
              expect(NAK, note="NAK only now")],
             iut=(["16#080C|16#0805"], REPEAT_OPTIONAL + ["16#080C", "16#0805"]), provenance="[F][I]",
             rules=["3964.RX.CHARACTER-ERROR-IN-END"]),
        case(p, "RECEIVE.CHARACTER-ERROR-ON-ETX", "A parity error on the ETX: the block is refused, never acknowledged",
             "Fig. 2-12 'wait for ETX', 'invalid character', 'note NAK'; Table 8-1 16#080C",
             "An ETX received with a transmission error does not end the block as an intact one: the receiver answers NAK, after the end sequence or when CDT runs out.",
             "character-error", "receiver",
             [send(STX), expect(DLE), send("31 32 33 10"), send_error("03", note="ETX with a parity error")]
             + ([send(bytes([bcc_of("31 32 33")]), note="the BCC a correct ETX would need")] if R else [])
             + [expect(NAK, after="-2*CHAR", within="CDT + 2*CHAR",
                       note="NAK: at the end sequence, or when CDT has run out")],
             iut=(["16#080C|16#0806|16#0805"], REPEAT_OPTIONAL + ["16#080C", "16#0806", "16#0805"]),
             provenance="[F][I]", rules=["3964.RX.CHARACTER-ERROR-IN-END"]),
        case(p, "RECEIVE.REPETITION-ACCEPTED", "After refusing a block the IUT accepts its repetition",
             "§2.2.2 Receive/receiving data; Fig. 2-7; Fig. 2-11 'repetition expected', 'W+1'",
             "After a NAK the receiver expects the repetition: the sender's new STX is answered with DLE and the block received.",
             "repetition", "receiver",
             [send(STX), expect(DLE)] + refused + receive_block(b"\x31\x32", p),
             iut=([refused_code], ["16#0801"]), delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"],
             provenance="[S][F]", rules=["3964.RX.REPETITION", "3964.RX.NAK-AWAITS-REPETITION"]),
        case(p, "RECEIVE.REPETITION-LIMIT", f"After {N} refused receptions of one block the next STX starts afresh",
             "§2.2.2 Receive/receiving data; Fig. 2-12 'W > 5 / W <= 5'; Table 8-1 16#0815",
             "A receiver gives up a block after the receptions its transmission attempts allow (A18) and is idle: a further STX is answered with DLE and a new block received; it does not lock up.",
             "repetition", "receiver",
             sum(([send(STX, note=f"reception {i + 1}"), expect(DLE)] + refused for i in range(N)), [])
             + receive_block(PLAIN, p),
             iut=([refused_code], ["16#0801", "16#0815"]), delivered=[PLAIN], echo_after=[PLAIN],
             readings=["A18"], provenance="[S][F][I]", rules=["3964.RX.REPETITION-LIMIT"]),
        case(p, "RECEIVE.AFTER-T-BLOCK", "No repetition within T_BLOCK: the receiver gives up, a later STX starts afresh",
             "§2.2.2 Receive/receiving data; Fig. 2-7; Fig. 2-12 'start T_BLOCK', 'T > T_BLOCK'; Table 8-1 16#0815",
             "The receiver waits T_BLOCK (4 s) for the repetition, then gives up (16#0815 where reported, A19) and is idle: a STX after that is answered with DLE.",
             "repetition", "receiver",
             [send(STX), expect(DLE)] + refused + [wait("BLOCK + CDT", note="no repetition within T_BLOCK")]
             + receive_block(PLAIN, p),
             iut=([refused_code], ["16#0801", "16#0815"]), delivered=[PLAIN], echo_after=[PLAIN],
             readings=["A19"], provenance="[S][F]", rules=["3964.RX.T-BLOCK"]),
        case(p, "RECEIVE.PARTNER-GAVE-UP", "While the IUT waits for a repetition the partner gives up with NAK",
             "§2.2.2 Receive/receiving data; Fig. 2-12 'wait for STX'; Table 8-1 16#0815",
             "What a receiver waiting for a repetition does with the partner's NAK is open (A19): it may report 16#0815 or the block's error, and answer nothing (our reading) or a NAK (informational); it must go on working.",
             "repetition", "receiver",
             [send(STX), expect(DLE)] + refused
             + [send(NAK, note="the partner gives up instead of repeating"),
                maybe(NAK, "informational", after="0", within="CDT + 2*CHAR",
                      note="no reply (our reading), or a NAK as for a stray character (informational)"),
                settle("CDT + 2*CHAR")]
             + receive_block(PLAIN, p),
             iut=([f"{refused_code}|16#0815"], ["16#0801", "16#0802", "16#0815"]), delivered=[PLAIN],
             echo_after=[PLAIN], readings=["A19"], provenance="[S][O]", rules=["3964.RX.WAIT-REPETITION-OTHER"]),
        case(p, "RECEIVE.NO-FREE-BUFFER", "No free receive buffer: NAK after 400 ms, not before, and no DLE",
             "§2.2.2 Receive/setup; Fig. 2-11 'start T_NAKTIM', 'T > T_NAKTIM', 'send NAK'; Table 8-1 16#080A",
             "A receiver without a free buffer waits T_NAKTIM (400 ms) for one; when none frees it answers the STX with NAK (16#080A).",
             "receive", "receiver",
             [send(STX, note="STX while the IUT's receive buffer is full (setup no_buffer)"),
              expect(NAK, after="NAKTIM", within="NAKTIM + 2*CHAR", note="NAK after 400 ms")],
             iut=(["16#080A"], ()), readings=["A14"], provenance="[S][F]", setup=NO_BUFFER,
             rules=["3964.RX.NO-BUFFER"]),
        case(p, "RECEIVE.GARBAGE-DURING-BUFFER-WAIT", "Characters after STX during the buffer wait: no DLE, a NAK",
             "Table 8-1 16#0802 (characters after STX before the DLE); Fig. 2-11 'wait'",
             "Characters that come after STX before the receiver has sent DLE raise 16#0802; the reaction on the line is open (A16): a NAK once the line is quiet (our reading) or at the end of T_NAKTIM, never a DLE.",
             "receive", "receiver",
             [send(STX, mark=True, note="STX while the IUT's receive buffer is full (setup no_buffer)"),
              send("41", at="0.25*NAKTIM", note="a character before the receiver's DLE"),
              expect(NAK, since="mark", after="0.25*NAKTIM", within="NAKTIM + CDT + 2*CHAR",
                     note="NAK: CDT after the 41 (A16), or when T_NAKTIM runs out")],
             iut=(["16#0802|16#080A"], ["16#0802", "16#080A"]), readings=["A16"], provenance="[S][O]",
             setup=NO_BUFFER, rules=["3964.RX.SETUP-GARBAGE"]),
    ]
    if R:
        good = bcc_of("31 32 33")
        wrong = [(h("31 10 10 32 15 03 10 03 16"), "DLE-ONCE", "the doubled DLE counted once", ["16#0706"]),
                 (h("31 32 33 10 03") + bytes([good ^ 0x02]), "STX-INCLUDED", "the STX included", ["16#0706"]),
                 (h("31 32 33 10 03") + bytes([good ^ 0x13]), "END-OMITTED", "the end sequence left out", ["16#0706"]),
                 (h("31 32 33 10 03") + bytes([good ^ 0x01]), "OFF-BY-ONE-BIT", "one bit wrong", ["16#0706"])]
        for data, name, why, tester in wrong:
            out.append(_refuse(
                p, f"RECEIVE.BCC-{name}", f"A BCC computed with {why} is refused",
                "§2.2.2 Block check character, Note; Fig. 2-4; Table 8-1 16#0808",
                "The BCC is the XOR of all bytes after STX through DLE ETX, doubled DLEs counted twice; any other value is refused with NAK (16#0808).",
                data, "16#0808", ["3964.RX.BCC-CHECK"], provenance="[S][I]", tester=(tester, ["16#0701"])))
        out += [
            _accept(p, "RECEIVE.BCC-EQUALS-DLE", "A BCC equal to DLE is the BCC, not a DLE",
                    "Fig. 2-12 'wait for BCC', 'BCC'; Fig. 2-8",
                    "The byte after DLE ETX is the BCC, even when it is 10; it is not doubled.", "41 42 10",
                    ["3964.RX.BCC-ANY-VALUE"], provenance="[I]"),
            _accept(p, "RECEIVE.BCC-OF-ZERO-LOSS", "A block that lost a 00 still matches its BCC and is accepted",
                    "§2.2.1 Limits of 3964R",
                    "The XOR cannot see a lost 00 character; such a block is accepted (a known limit, not a defect).",
                    "31 33", ["3964.RX.BCC-BLIND-SPOTS"], provenance="[S][I]"),
            case(p, "RECEIVE.CDT-BEFORE-BCC", "No BCC after DLE ETX: NAK after CDT",
                 "Fig. 2-12 'wait for BCC', 'T > T_CDT or BCC incorrect'; Table 8-1 16#0806",
                 "A 3964R receiver waits CDT for the BCC after DLE ETX; otherwise NAK (16#0806).",
                 "receive", "receiver", [send(STX), expect(DLE), send("31 10 03"), nak_after_cdt()],
                 iut=(["16#0806"], REPEAT_OPTIONAL), provenance="[F][I]", rules=["3964.RX.BCC-TIMEOUT"]),
            case(p, "RECEIVE.3964R-WAITS-FOR-BCC", "A 3964R receiver does not answer at DLE ETX but after the BCC",
                 "Table 2-3; Fig. 2-12 '3964R', 'wait for BCC'",
                 "With 3964R the receiver answers only after the BCC has come, not at DLE ETX.",
                 "receive", "receiver",
                 [send(STX), expect(DLE), send(body(b"\x31\x32", p)[:-1], note="data, DLE ETX"),
                  wait("0.5*CDT", note="the BCC is not there yet"),
                  send(body(b"\x31\x32", p)[-1:], note="BCC"),
                  expect(DLE, note="DLE, only after the BCC (a DLE before it fails here)")],
                 delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"], provenance="[S][F]",
                 rules=["3964.RX.WAIT-FOR-BCC"]),
            case(p, "RECEIVE.BCC-CHARACTER-ERROR", "A BCC with a parity error is refused, although its value matches",
                 "Fig. 2-12 'invalid character', 'note NAK'; Table 8-1 16#080C",
                 "A BCC received with a transmission error is refused with NAK, even when its value is right.",
                 "character-error", "receiver",
                 [send(STX), expect(DLE), send("31 32 33 10 03", note="data, DLE ETX"),
                  send_error(bytes([good]), note=f"the right BCC ({good:02X}), with a parity error"),
                  expect(NAK, note="NAK: refused")],
                 iut=(["16#080C|16#0808"], REPEAT_OPTIONAL + ["16#0808"]), provenance="[F][I]",
                 rules=["3964.RX.BCC-CHARACTER-ERROR"]),
        ]
    else:
        bcc_r = bcc_of("31 32")
        out += [
            case(p, "RECEIVE.3964-ANSWERS-AT-ETX", "A 3964 receiver answers at DLE ETX (no BCC)",
                 "Table 2-3; §2.2.2 Receive/release",
                 "With 3964 the receiver stops at DLE ETX and answers; it does not wait for a BCC, so its DLE comes before CDT could have run out.",
                 "receive", "receiver",
                 [send(STX), expect(DLE), send("31 32 10 03"),
                  expect(DLE, within="CDT", note="before CDT: it did not wait for a BCC")],
                 delivered=[b"\x31\x32"], echo_after=[b"\x31\x32"], provenance="[S]",
                 rules=["3964.RX.ANSWER-AT-ETX"]),
            case(p, "RECEIVE.FROM-3964R-PARTNER", "A 3964 receiver and a partner configured for 3964R: the stray BCC",
                 "Table 2-3; §2.2.2 Receive/setup; Table 8-1 16#0802",
                 "A 3964 receiver answers a 3964R partner's block at DLE ETX; the partner's BCC then reaches a station that is done with the block (a stray character) and the link comes to rest without a lock-up.",
                 "receive", "receiver",
                 [send(STX), expect(DLE), send("31 32 10 03", note="the partner's data and DLE ETX"),
                  expect(DLE, within="CDT", note="DLE at DLE ETX, before CDT"),
                  send(bytes([bcc_r]), note=f"the partner's BCC ({bcc_r:02X}): a stray character now"),
                  partner("JOB + 40*CDT + 2s",
                          "the tester, a 3964R station, answers whatever follows (the IUT's echo, with every "
                          "attempt the IUT has: JOB)")],
                 iut=((), ["16#0802", "16#0702", "16#0703", "16#0704", "16#0706", "16#0707", "16#0701", "16#0709", "16#070A"]),
                 delivered=[b"\x31\x32"], tester_params=p.with_(procedure="3964R",
                                                                priority="high" if p.priority == "low" else "low"),
                 provenance="[I]", rules=["3964.RX.STRAY-AFTER-ANSWER"]),
        ]
    return out

