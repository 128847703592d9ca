"""The link below RK 512 (§2.2.2 as §2.2.3 uses it: every RK 512 frame is the user data of
one 3964(R) block): L-01 to L-07 over RK 512 frames."""

from ptpcert.procedures.p3964.model import codec as link

from ._build import (
    DLE,
    NAK,
    STX,
    case,
    cont,
    expect,
    header,
    iut_request,
    prime,
    receive,
    resp,
    send,
    silence,
    tester_fetch,
    tester_send,
)

OPT_REPEAT = ["16#0801", "16#0815"]


def _bcc_10_data(db: int) -> bytes:
    """Two data bytes that make the tester's SEND frame to ``db`` end in BCC 10h."""
    base = header("A", "D", db, 0, 1) + b"\x00\x00"
    x = link.body(base, "3964R")[-1] ^ 0x10
    if x == DLE:       # a data DLE would be doubled and cancel out: take the second byte too
        return bytes([0x11, 0x01])
    return bytes([x, 0x00])


def cases(c):
    p = c.p
    R = p.procedure == "3964R"
    w = c.db_w
    out = []
    hi = bytes([0x80, 0xFF, 0x7F, 0xC3, 0xA5, 0x5A, 0x01, 0xFE])
    out.append(case(
        c, "L-01.EIGHT-DATA-BITS", "Header and data bytes with bit 7 set arrive and are stored unchanged",
        "§2.3.2 note (8 data bits, fixed for RK 512); §2.3.1, Table 2-5; App. A.1, Table A-6",
        "RK 512 characters carry 8 data bits: bytes with bit 7 set are sent, stored and fetched back unchanged.",
        "link", "receiver",
        tester_send(header("A", "D", w, 0, 4), hi) + tester_fetch(header("E", "D", w, 0, 4), hi),
        needs={"db": [w], "db_bytes": 8}, provenance="[S]"))

    # L-02: DLE doubling in the header, the data, a REATEL and a BCC (Example 5/6)
    d16 = bytes([0x10, 0x20, 0x30, 0x10]) * 8
    out.append(case(
        c, "L-02.DLE-IN-HEADER-AND-DATA", "DB 16, DW 16, 16 words, data full of 10h: every DLE doubled both ways",
        "§2.2.2 note (DLE doubling); §2.2.3, Table 2-1",
        "Every 10h of an RK 512 frame, header or data, is sent twice and stored once; the IUT's FETCH response doubles the data DLEs.",
        "link", "receiver",
        tester_send(header("A", "D", 16, 16, 16), d16) + tester_fetch(header("E", "D", 16, 16, 16), d16),
        needs={"db": [16], "db_bytes": 64}, provenance="[S]"))
    out.append(case(
        c, "L-02.DLE-AS-REATEL", "REATEL 10h (a header error in byte 4) is sent as DLE DLE",
        "§2.2.2 note (DLE doubling); §8.4, Table 8-3 (10h); Table 8-1 16#0604",
        "A response whose error number is 10h carries it doubled: 00 00 00 10 10 DLE ETX.",
        "link", "receiver",
        [prime(header("E", "Q", c.db, 0, 1)), receive(resp(0x10))],
        iut=(["16#0604"], ()), needs={"db": [c.db]}, provenance="[S]"))
    if R:
        out.append(case(
            c, "L-02.BCC-10-FROM-TESTER", "A frame whose BCC is 10h: the BCC is not doubled and the frame is taken",
            "§2.2.2, Fig. 2-4 and note (BCC); §2.2.3",
            "The BCC after DLE ETX is sent once even when it is 10h; the receiver takes the block and answers it.",
            "link", "receiver",
            [prime(header("A", "D", w, 0, 1) + _bcc_10_data(w)), receive(resp(0))],
            needs={"db": [w]}, provenance="[S][I]"))
        if p.byte_area_bytes > 0xC3:
            out.append(case(
                c, "L-02.BCC-10-FROM-IUT", "A FETCH response whose BCC is 10h (input byte 195 = 03h)",
                "§2.2.2, Fig. 2-4 and note (BCC); §6.3.2 Table 6-8",
                "The IUT sends a BCC of 10h once, not doubled.",
                "link", "receiver",
                [prime(header("E", "E", 0, 0xC3, 1)), receive(resp(0, data=b"\x03"))],
                needs={"pattern": True}, provenance="[S][I]"))

    first = bytes([0x11, 0x22, 0x33, 0x44])
    other = bytes([0xAA, 0xBB, 0xCC, 0xDD])
    write = tester_send(header("A", "D", w, 0, 2), first)
    back = tester_fetch(header("E", "D", w, 0, 2), first)
    bad_frame = header("A", "D", w, 0, 2) + other
    if R:
        good = link.body(bad_frame, "3964R")
        bad = good[:-1] + bytes([good[-1] ^ 0xFF])
        out.append(case(
            c, "L-03.BCC-WRONG-NOT-ACTED-ON", "A SEND with a wrong BCC: NAK, no response, nothing written",
            "§2.2.2 'Receive release', Fig. 2-12; §2.2.3 notes (no RK 512 response to a procedure error); Table 8-1 16#0808",
            "A block with a wrong BCC is refused with NAK; the RK 512 layer neither answers nor stores it.",
            "link", "receiver",
            write + [send([STX]), expect([DLE]), send(bad, note="the SEND with its BCC inverted"),
                     expect([NAK], note="NAK: BCC error"), silence("2*ADT", note="no response follows")] + back,
            iut=(["16#0808"], OPT_REPEAT), needs={"db": [w], "db_bytes": 4}, provenance="[S]"))
    gap_body = link.body(bad_frame, p.procedure)
    out.append(case(
        c, "L-06.GAP-OVER-CDT", "A pause longer than CDT inside a SEND block: NAK, no response, nothing written",
        "§2.2.2 'Receiving data' (character delay time); Table 8-1 16#0806; §2.2.3 notes",
        "A gap over CDT between characters of a block makes the receiver send NAK; no RK 512 response follows.",
        "link", "receiver",
        write + [send([STX]), expect([DLE]), send(gap_body[:6], note="part of the block, then nothing"),
                 expect([NAK], after="CDT", within="CDT + 2*CHAR", since="previous",
                        note="NAK once CDT has passed"),
                 silence("2*ADT", note="no response follows")] + back,
        iut=(["16#0806"], OPT_REPEAT), needs={"db": [w], "db_bytes": 4}, provenance="[S]"))

    # L-04: the block refused once (3964R: a wrong BCC; 3964: a gap over CDT), then repeated
    if R:
        refused = [send(bad), expect([NAK])]
        how, code = "a wrong BCC", "16#0808"
    else:
        refused = [send(gap_body[:6], note="part of the block, then nothing"),
                   expect([NAK], after="CDT", within="CDT + 2*CHAR", since="previous", note="NAK once CDT has passed")]
        how, code = "a gap over CDT", "16#0806"
    out.append(case(
        c, "L-04.REPEAT-AFTER-NAK", "The block repeated after the NAK: accepted and answered exactly once",
        "§2.2.2 'Receive release', Fig. 2-12 (repetition within the block wait time); §2.2.3 'Response message frame'",
        f"After a NAK (here for {how}) the sender repeats the block; the receiver takes the repetition and the RK 512 layer answers it once.",
        "link", "receiver",
        [send([STX]), expect([DLE])] + refused + [
            send([STX], note="the repetition"), expect([DLE]), send(link.body(bad_frame, p.procedure)), expect([DLE]),
            receive(resp(0)), silence("2*ADT", note="no second response")]
        + tester_fetch(header("E", "D", w, 0, 2), other),
        iut=([code], OPT_REPEAT), needs={"db": [w], "db_bytes": 4}, provenance="[S]"))

    # L-08: the IUT's response block refused at every attempt: 16#0612, no other response
    M = p.line.transmission_attempts
    refuse = []
    for i in range(M):
        refuse += [expect([STX], within="TRES" if i == 0 else "ADT", note=f"the IUT's response, attempt {i + 1}"),
                   send([DLE]), expect(link.body(resp(0), p.procedure), within="CDT"),
                   send([NAK], note="the tester refuses the response block")]
    out.append(case(
        c, "L-08.RESPONSE-REFUSED", f"The IUT's response block refused {M} times: 16#0612, no other response",
        "§2.2.2 'Connection release', Fig. 2-10 (transmission attempts); §8.3 Table 8-1 16#0612, 16#070A",
        "The link repeats a refused response block up to the transmission attempts; then the responder reports 16#0612 (after the link's event) and sends no other response for that command.",
        "link", "receiver",
        [prime(header("A", "D", w, 0, 2) + first)] + refuse
        + [expect([NAK], note="the IUT gives up (NAK after the last attempt)"),
           silence("2*ADT", note="no other response, no new attempt")],
        iut=(["16#0612", "16#0706|16#070A"], ["16#0701"]), needs={"db": [w], "db_bytes": 4}, provenance="[S][I]"))

    big = bytes([0x10, 0x41]) * 64
    out.append(case(
        c, "L-07.LARGEST-BLOCKS", "The largest frames: a 138-byte SEND frame and a 132-byte response, DLE-rich",
        "§2.2.3, Fig. 2-14 (128 data bytes per frame); App. A.1, Table A-6",
        "A first SEND frame of 10 + 128 bytes (with every other byte a doubled DLE) and a FETCH response of 4 + 128 bytes pass the link.",
        "link", "receiver",
        tester_send(header("A", "D", w, 0, 64), big) + tester_fetch(header("E", "D", w, 0, 64), big),
        needs={"db": [w], "db_bytes": 128}, provenance="[S]"))

    # L-05: the initialization conflict over RK 512 frames, with the IUT's request
    own = bytes([0x01, 0x02, 0x03, 0x04])
    label = f"send:DB{w}:DW0:LEN=4:DATA=01020304"
    iut_cmd = header("A", "D", w, 0, 2) + own
    theirs = header("A", "D", w, 8, 2) + bytes([0x55, 0x66, 0x77, 0x88])
    tb = link.body(theirs, p.procedure)
    if p.priority == "low":
        steps = [expect([STX], within="STARTUP", note="the IUT's STX for its SEND"),
                 send([STX], note="the tester's STX crosses it"),
                 expect([DLE], note="the IUT (low) yields and answers the tester's STX"),
                 send(tb, note="the tester's SEND"), expect([DLE]),
                 receive(iut_cmd, alternatives=[resp(0)], note="the IUT's SEND again, or its response first"),
                 receive(resp(0), alternatives=[iut_cmd], note="the other of the two"),
                 prime(resp(0), note="the tester answers the IUT's SEND")]
        rule = ("In an initialization conflict the low-priority station answers the partner's STX with DLE, "
                "takes its block and sends its own afterwards.")
        needs = {"db": [w], "db_bytes": 20, "setup_attempts": 2}
    else:
        steps = [expect([STX], within="STARTUP", note="the IUT's STX for its SEND"),
                 send([STX], note="the tester's STX crosses it"),
                 silence("0.25*ADT", note="the IUT (high) does not answer it"),
                 send([DLE], note="the tester (low) yields"),
                 expect(link.body(iut_cmd, p.procedure), within="CDT", note="the IUT's SEND"), send([DLE]),
                 prime(theirs, note="the tester's own SEND"), receive(resp(0)),
                 prime(resp(0), note="the tester answers the IUT's SEND")]
        rule = ("In an initialization conflict the high-priority station ignores the partner's STX and waits for "
                "its DLE; the partner sends its block afterwards.")
        needs = {"db": [w], "db_bytes": 20}
    out.append(case(
        c, f"L-05.CONFLICT-IUT-{p.priority.upper()}", f"Crossing STX with the IUT {p.priority} priority, over RK 512 frames",
        "§2.2.2 'Initialization conflict', Fig. 2-8; §2.3.1 Table 2-5; §2.2.3 'Quasi-full-duplex', Fig. 2-17",
        rule, "link", "both", steps, requests=[f"send DB{w}:DW0:LEN=4:DATA=01020304"], results=[f"RESULT {label} OK"],
        iut=((), ["16#0702", "16#0701"]), needs=needs, readings=["AMB-31"], timing_sensitive=True,
        provenance="[S][F]"))
    return out
