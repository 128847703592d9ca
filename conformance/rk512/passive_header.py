"""The IUT passive, checking the tester's frames (§2.2.3 Tables 2-1, 2-2; §8.3 Table 8-1
class 06; §8.4 Table 8-3): every header error answered with its REATEL, P-06, P-07 a-l,
P-08 (continuation consistency), P-17, P-18."""

from ._build import case, cont, header, pattern, prime, receive, resp, seq_data

REF_06 = "§8.3, Table 8-1 {code}; §8.4, Table 8-3 ({reatel:02X}h)"
SHORT_OPTIONAL = ["16#0610", "16#0608", "16#060B", "16#0601"]


def _refuse(c, cid, title, ref, rule, frame, reatel, code, *, pre=(), first=True, alternatives=(),
            alt_grade="informational", readings=(), needs=None, provenance="[S]", strict=True, extra_optional=()):
    """The tester sends ``frame`` (after the steps ``pre``); the IUT answers it with REATEL
    ``reatel`` (16#``code``), no data; ``alternatives``: other answers a reading allows."""
    steps = list(pre) + [prime(frame), receive(resp(reatel, first), alternatives=alternatives, alt_grade=alt_grade)]
    iut = ([code], list(extra_optional)) if strict else ((), [code, *extra_optional])
    return case(c, cid, title, ref, rule, "passive-header", "receiver", steps, iut=iut, readings=readings,
                needs=needs, provenance=provenance)


def cases(c):
    p = c.p
    d = c.db
    w = c.db_w
    lo, hi = p.db_range
    known = c.pattern_known
    out = []
    db = {"db": [d]}
    # a: byte 1 neither 00h nor FFh
    for b1 in (0x01, 0x7F):
        out.append(_refuse(
            c, f"P-07A.BYTE1-{b1:02X}", f"Command byte 1 = {b1:02X}h: REATEL 10h",
            "§2.2.3 Table 2-1 (byte 1 00h/FFh); " + REF_06.format(code="16#0601", reatel=0x10),
            "A command whose byte 1 is neither 00h nor FFh is refused with REATEL 10h (16#0601); the response's byte 1 is 00h (there is no frame id to mirror).",
            header("E", "D", d, 0, c.fw, b1=b1), 0x10, "16#0601", alternatives=[resp(0x10, first=False)],
            readings=["N1"], needs=db))
    # b: byte 3 not a command letter
    for b3, what in ((0x43, "'C'"), (0x61, "'a'")):
        out.append(_refuse(
            c, f"P-07B.BYTE3-{b3:02X}", f"Command byte 3 = {what}: REATEL 16h",
            "§2.2.3 Table 2-1 (A, O, E); " + REF_06.format(code="16#0602", reatel=0x16),
            "A command letter other than A, O or E is refused with REATEL 16h (16#0602).",
            header(b3, "D", d, 0, c.fw), 0x16, "16#0602", needs=db, readings=["AMB-04"]))
    out.append(case(
        c, "P-07B.BYTE3-00", "Command byte 3 = 00h: the frame reads as a response; what the IUT does is recorded",
        "§2.2.3 Tables 2-1, 2-2 (byte 3 00h in responses); Table 8-1 16#0602, 16#0A01",
        "A first frame whose byte 3 is 00h is a response by its header; the IUT may take it as an unsolicited response (no answer) or refuse it with REATEL 16h.",
        "passive-header", "receiver",
        [prime(header(0x00, "D", d, 0, c.fw)),
         receive(resp(0x16), optional=True, absent_grade="pass", alternatives=[resp(0x10)],
                 alt_grade="informational", note="an answer is not required")],
        iut=((), ["16#0A01", "16#0602", "16#0601", "16#0610", "16#0A03"]), readings=["AMB-13"], provenance="[I]"))
    # c: byte 4 not a type, or a pair the receiver does not allow
    dx_w = c.dx_w or 1
    for cmd, typ, what, frame, alt, amb in (
            ("E", 0x51, "FETCH with type 'Q' (51h)", header("E", 0x51, d, 0, c.fw), None, None),
            ("E", 0x64, "FETCH with type 'd' (64h, lower case)", header("E", 0x64, d, 0, c.fw), None, None),
            ("A", "M", "SEND to flags ('A' 'M')", header("A", "M", 0, 0, 4) + seq_data(4), None, None),
            ("E", 0x43, "FETCH of 3 counters with 'C' (43h) instead of 'Z' (5Ah)", header("E", 0x43, 0, 0, 3),
             resp(0, data=pattern("Z", 0, 0, 6)) if known else None, "AMB-01"),
            ("A", "X", "SEND with type 'X' ('A' 'X')", header("A", "X", w, 0, 2) + seq_data(4), resp(0), "AMB-03"),
            ("O", "X", "SEND to a DX with type 'X' ('O' 'X')", header("O", "X", dx_w, 0, 2) + seq_data(4), resp(0),
             "AMB-03")):
        tname = typ if isinstance(typ, str) else f"{typ:02X}"
        out.append(_refuse(
            c, f"P-07C.{cmd}-{tname}", f"{what}: REATEL 10h",
            "§2.2.3 Table 2-1 (byte 4; 'only D when sending'); " + REF_06.format(code="16#0604", reatel=0x10),
            "A data type letter that is not one, or a command/type pair the receiver does not allow, is refused with REATEL 10h (16#0604).",
            frame, 0x10, "16#0604", alternatives=[alt] if alt else (), strict=alt is None,
            readings=[amb] if amb else [], needs={"db": [d, w]}, provenance="[S]" if amb is None else "[S][O]"))
    # d: DB/DX that does not exist
    missing = [(0, "DB 0")] + ([(hi + 1, f"DB {hi + 1} (above the profile's db_range)")] if hi < 255 else [])
    for n, what in missing:
        out.append(_refuse(
            c, f"P-07D.FETCH-DB{n}", f"FETCH from {what}: REATEL 14h",
            "§2.2.3 Table 2-1 (byte 5); " + REF_06.format(code="16#0606", reatel=0x14),
            "A DB number that is not permitted or does not exist is refused with REATEL 14h (16#0606), without data.",
            header("E", "D", n, 0, 3), 0x14, "16#0606"))
    out.append(_refuse(
        c, "P-07D.SEND-DB0", "SEND to DB 0: REATEL 14h, nothing stored",
        "§2.2.3 Table 2-1 (byte 5); " + REF_06.format(code="16#0606", reatel=0x14),
        "A SEND to DB 0 is refused with REATEL 14h (16#0606).",
        header("A", "D", 0, 0, 2) + seq_data(4), 0x14, "16#0606"))
    # e: start address beyond the area
    size = p.byte_area_bytes
    if size <= 0xFFFF:
        b5, b6 = size >> 8, size & 0xFF
        alt = None
        if b5 and known and (size & 0xFF) < size:     # AMB-14: byte 6 alone would be the address
            alt = resp(0, data=pattern("E", 0, size & 0xFF, 2))
        if b5 == 0 or known:
            out.append(_refuse(
                c, "P-07E.INPUTS-BEYOND-AREA", f"FETCH of inputs from byte {size} (the area has {size} bytes): REATEL 0Ch",
                "§2.2.3 Table 2-1 (bytes 5/6); §6.3.2 Table 6-8; " + REF_06.format(code="16#0607", reatel=0x0C),
                "A start address beyond the area is refused with REATEL 0Ch (16#0607).",
                header("E", "E", b5, b6, 2), 0x0C, "16#0607", alternatives=[alt] if alt else (), strict=alt is None,
                readings=["AMB-14"], provenance="[S][I]"))
    cells = p.cell_area_cells
    if cells < 256:
        out.append(_refuse(
            c, "P-07E.TIMERS-BEYOND-AREA", f"FETCH from timer {cells} (there are {cells}): REATEL 0Ch",
            "§6.3.2 Table 6-8; " + REF_06.format(code="16#0607", reatel=0x0C),
            "A timer number beyond the timers that exist is refused with REATEL 0Ch (16#0607).",
            header("E", "T", 0, cells, 1), 0x0C, "16#0607", readings=["AMB-14"]))
    if p.db_bytes <= 510:
        out.append(_refuse(
            c, "P-07E.DB-WORD-BEYOND-END", f"FETCH from DW {p.db_bytes // 2} of a {p.db_bytes}-byte DB: REATEL 0Ch",
            "§2.2.3 Table 2-1 (byte 6); " + REF_06.format(code="16#0607", reatel=0x0C),
            "A data word beyond the end of the DB is refused with REATEL 0Ch (16#0607).",
            header("E", "D", d, p.db_bytes // 2, 1), 0x0C, "16#0607", needs=db))
    # f: length 0, over 512 words, beyond the area
    out.append(_refuse(
        c, "P-07F.FETCH-LENGTH-0", "FETCH of length 0: REATEL 34h",
        "§2.2.3 Table 2-1 (bytes 7/8); §6.3.2 Table 6-6 (LEN 1..1024); " + REF_06.format(code="16#0608", reatel=0x34),
        "A length of 0 is not permitted: REATEL 34h (16#0608).",
        header("E", "D", d, 0, 0), 0x34, "16#0608", needs=db, provenance="[I]"))
    out.append(_refuse(
        c, "P-07F.SEND-LENGTH-0", "SEND of length 0 (a header alone): REATEL 34h",
        "§2.2.3 Table 2-1 (bytes 7/8); " + REF_06.format(code="16#0608", reatel=0x34),
        "A SEND announcing no data is not permitted: REATEL 34h (16#0608).",
        header("A", "D", w, 0, 0), 0x34, "16#0608", needs={"db": [w]}, extra_optional=["16#060B"],
        provenance="[I]"))
    out.append(_refuse(
        c, "P-07F.FETCH-513-WORDS", "FETCH of 513 words (1026 bytes, over 1 KB): REATEL 34h",
        "§6.3.2 Table 6-6 (LEN 1..1024); App. A.1 Table A-6; " + REF_06.format(code="16#0608", reatel=0x34),
        "A request over 1024 bytes is refused with REATEL 34h (16#0608).",
        header("E", "D", d, 0, 513), 0x34, "16#0608", needs=db, extra_optional=["16#0606", "16#0607"],
        alternatives=[resp(0x14), resp(0x0C)], strict=False, readings=["AMB-25"]))
    words = p.db_bytes // 2 + 1
    if 2 * words <= 1024:
        out.append(_refuse(
            c, "P-07F.FETCH-BEYOND-DB", f"FETCH of {words} words from DW 0 of a {p.db_bytes}-byte DB: a length error",
            "§2.2.3 Table 2-1 (bytes 7/8); Table 8-1 16#0608, 16#0606; Table 8-3",
            "A request running past the end of its DB is refused: REATEL 34h (length not allowed) or, as a too-short DB, 14h.",
            header("E", "D", d, 0, words), 0x34, "16#0608", needs=db, alternatives=[resp(0x14)], strict=False,
            extra_optional=["16#0606"], readings=["AMB-25"]))
    # g, h: byte 10
    for b10, what in ((0x18, "flag bit 8"), (0x1E, "flag bit 14")):
        out.append(_refuse(
            c, f"P-07G.FLAG-BIT-{b10 & 0xF}", f"FETCH naming flag byte 0, {what}: REATEL 0Ch",
            "§2.2.3 Table 2-1 (byte 10, bits 0-3: 0..7); " + REF_06.format(code="16#0609", reatel=0x0C),
            "A coordination-flag bit number above 7 is refused with REATEL 0Ch (16#0609).",
            header("E", "D", d, 0, c.fw, b9=0x00, b10=b10), 0x0C, "16#0609", needs=db))
    served = resp(0, data=pattern("D", d, 0, 2 * c.fw)) if known else None
    for b10 in (0x5F, 0xEF):
        out.append(_refuse(
            c, f"P-07H.CPU-{b10 >> 4:X}", f"FETCH for CPU {b10 >> 4:X}h (byte 10 = {b10:02X}h): REATEL 0Ch",
            "§2.2.3 Table 2-1 (byte 10, bits 4-7: CPU 1..4); §6.3.2 Table 6-4; " + REF_06.format(code="16#060A", reatel=0x0C),
            "A CPU number that is not permitted (5..E) is refused with REATEL 0Ch (16#060A).",
            header("E", "D", d, 0, c.fw, b10=b10), 0x0C, "16#060A", needs=db, alternatives=[served] if served else (),
            strict=served is None, readings=["AMB-22"], provenance="[S][I]"))
    # i: SEND data count against the header
    for n in (8, 12):
        out.append(_refuse(
            c, f"P-07I.SEND-{n}-FOR-10", f"SEND announcing 10 bytes (5 words) with {n}: REATEL 34h",
            "§2.2.3 'Sending data'; " + REF_06.format(code="16#060B", reatel=0x34),
            "A SEND frame with more or fewer data bytes than its header announces is refused with REATEL 34h (16#060B), nothing stored.",
            header("A", "D", w, 0, 5) + seq_data(n), 0x34, "16#060B", needs={"db": [w], "db_bytes": 10},
            extra_optional=["16#0611"]))
    first = header("A", "D", w, 0, 100) + seq_data(128)
    pre = [prime(first), receive(resp(0))]
    send200 = {"db": [w], "db_bytes": 200}     # the SEND of 200 bytes must fit the DB
    out.append(_refuse(
        c, "P-07I.CONTINUATION-70-FOR-72", "SEND of 200 bytes whose continuation carries 70 instead of 72: REATEL 34h",
        "§2.2.3 Fig. 2-14; " + REF_06.format(code="16#0611", reatel=0x34),
        "A continuation with a data count that does not complete the announced length is refused with REATEL 34h (16#0611 or 16#060B) in a continuation response.",
        cont("A", "D", seq_data(70, 0x80)), 0x34, "16#0611|16#060B", pre=pre, first=False, needs=send200,
        readings=["N3"]))
    out.append(_refuse(
        c, "P-07I.FIRST-FRAME-SHORT", "SEND of 200 bytes whose first frame carries 100: refused (128 expected)",
        "§2.2.3 Figs. 2-13, 2-14 (the first continuation starts with byte 129); " + REF_06.format(code="16#060B", reatel=0x34),
        "Every frame but the last carries 128 data bytes; a first frame with fewer is refused with REATEL 34h (16#060B).",
        header("A", "D", w, 0, 100) + seq_data(100), 0x34, "16#060B", alternatives=[resp(0)], strict=False,
        needs=send200, readings=["AMB-16"], provenance="[I]"))
    # j: FETCH with data
    out.append(_refuse(
        c, "P-07J.FETCH-WITH-DATA", "FETCH command with 2 trailing data bytes: REATEL 34h",
        "§2.2.3 'Receiving data' (no user data in a FETCH); " + REF_06.format(code="16#060C", reatel=0x34),
        "A FETCH command carries no data; one that does is refused with REATEL 34h (16#060C).",
        header("E", "D", d, 0, c.fw) + b"\x01\x02", 0x34, "16#060C", needs=db, readings=["AMB-06"]))
    fetch200 = header("E", "D", d, 0, 100)
    pre_f = [prime(fetch200), receive(resp(0, data=pattern("D", d, 0, 128)))] if known else None
    if pre_f:
        out.append(_refuse(
            c, "P-06.CONTINUATION-FETCH-WITH-DATA", "A continuation FETCH of 5 bytes: REATEL 34h in a continuation response",
            "§2.2.3 Fig. 2-16 (continuation FETCH FF 00 45 xx); " + REF_06.format(code="16#060C", reatel=0x34),
            "A continuation FETCH is exactly 4 bytes; a longer one is refused with REATEL 34h, the response's byte 1 FFh as the command's (16#060C).",
            cont("E", "D", b"\x00"), 0x34, "16#060C", pre=pre_f, first=False, needs={**db, "db_bytes": 200, "pattern": True}))
        out.append(_refuse(
            c, "P-08.FETCH-CONTINUATION-BYTE4", "Continuation FETCH with type 'X' after a first frame of type 'D': REATEL 10h",
            "§2.2.3 Table 2-1 (continuation bytes 3/4 as in the first frame); " + REF_06.format(code="16#0605", reatel=0x10),
            "Bytes 3 and 4 of a continuation must repeat the first frame's; a different byte 4 is refused with REATEL 10h (16#0605).",
            cont("E", "X"), 0x10, "16#0605", pre=pre_f, first=False, needs={**db, "db_bytes": 200, "pattern": True}))
    out.append(_refuse(
        c, "P-08.SEND-CONTINUATION-BYTE3", "Continuation with command 'O' after a first frame 'A': REATEL 16h",
        "§2.2.3 Table 2-1; " + REF_06.format(code="16#0603", reatel=0x16),
        "A continuation whose byte 3 differs from the first frame's is refused with REATEL 16h (16#0603).",
        cont("O", "D", seq_data(72, 0x80)), 0x16, "16#0603", pre=pre, first=False, needs=send200))
    out.append(_refuse(
        c, "P-08.SEND-CONTINUATION-BYTE4", "Continuation with type 'X' after a first frame 'D': REATEL 10h",
        "§2.2.3 Table 2-1; " + REF_06.format(code="16#0605", reatel=0x10),
        "A continuation whose byte 4 differs from the first frame's is refused with REATEL 10h (16#0605).",
        cont("A", "X", seq_data(72, 0x80)), 0x10, "16#0605", pre=pre, first=False, needs=send200))
    # k: frames too short for their kind (no REATEL is defined: recorded)
    for frame, first_, what in ((header("E", "D", d, 0, c.fw)[:6], True, "a 6-byte command"),
                                (cont("A", "D")[:3], False, "a 3-byte continuation")):
        out.append(case(
            c, f"P-07K.SHORT-{len(frame)}", f"{what.capitalize()}: 16#0610; an answer (34h) or none",
            "§8.3 Table 8-1 16#0610 (frame too short); §8.4 Table 8-3 (no REATEL listed)",
            "A frame too short for its kind is an error (16#0610); the manual names no REATEL for it, so the IUT may answer it with 34h or not at all.",
            "passive-header", "receiver",
            [prime(frame), receive(resp(0x34, first_), optional=True, absent_grade="informational",
                                   alternatives=[resp(0x10, first_), resp(0x36, first_)], alt_grade="informational")],
            iut=((), SHORT_OPTIONAL + ["16#060E"]), readings=["AMB-10"], provenance="[S][O]"))
    # l: byte 2 not 00h (unspecified)
    if known:
        out.append(case(
            c, "P-07L.BYTE2-01", "Command byte 2 = 01h: served, or refused with 10h (the manual names no event)",
            "§2.2.3 Table 2-1 (byte 2 00h); Table 8-1 (no event for byte 2)",
            "No event exists for a byte 2 other than 00h; the IUT may ignore it (and serve the FETCH) or refuse the frame.",
            "passive-header", "receiver",
            [prime(header("E", "D", d, 0, c.fw, b2=0x01)),
             receive(resp(0, data=pattern("D", d, 0, 2 * c.fw)), alternatives=[resp(0x10)], alt_grade="informational")],
            iut=((), ["16#0601"]), readings=["AMB-13"], needs={**db, "pattern": True}, provenance="[O]"))
    # P-17 / P-18: the layout of error responses
    out.append(_refuse(
        c, "P-17.ERROR-RESPONSE-LAYOUT", "An error response is 00 00 00 REATEL: bytes 2 and 3 are 00h, no data",
        "§2.2.3 Table 2-2; §8.4 Table 8-3",
        "Response bytes 2 and 3 are always 00h and the REATEL is one of Table 8-3; an error response carries no data.",
        header("E", "D", 0, 0, 64), 0x14, "16#0606"))
    return out

