"""The IUT passive, serving the tester's SEND (§2.2.3 "Sending data", Figs. 2-13, 2-14,
2-19; §6.3.2 "Receiving data"): P-01, P-02, P-03, P-14 (SEND to a DX), P-18."""

from ._build import case, header, seq_data, tester_fetch, tester_send


def cases(c):
    w = c.db_w
    out = []
    d10 = bytes([0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99, 0xAA])
    out.append(case(
        c, "P-01.SEND-10", "SEND 10 bytes (Example 1): response 00 00 00 00, data stored at DB/DW as addressed",
        "§2.2.3 'Sending data', Fig. 2-13, Table 2-2; §6.3.2 'Receiving data'",
        "A SEND of up to 128 bytes is answered by one response 00 00 00 00 without data, after its data are stored at the DB and data word it names.",
        "passive-send", "receiver",
        tester_send(header("A", "D", w, 0, 5), d10) + tester_fetch(header("E", "D", w, 0, 5), d10),
        needs={"db": [w], "db_bytes": 10}, provenance="[S][F]"))
    out.append(case(
        c, "P-01.SEND-1-WORD", "SEND of one byte (LEN 1 = one word, padded with 00h): answered and stored",
        "§2.2.3, Table 2-1 (length in words); §6.3.2 'Important notes' (odd LEN)",
        "A SEND of one data word is the smallest request; it is answered 00 00 00 00 and stored.",
        "passive-send", "receiver",
        tester_send(header("A", "D", w, 0, 1), b"\xab\x00") + tester_fetch(header("E", "D", w, 0, 1), b"\xab\x00"),
        needs={"db": [w]}, provenance="[S]"))
    wide = bytes(range(8))
    mid = bytes([0xA1, 0xA2, 0xA3, 0xA4])
    out.append(case(
        c, "P-01.DATA-WORD-ADDRESSING", "A SEND to DW 5 lands on bytes 10..13 of the DB (DW n = bytes 2n, 2n+1)",
        "§2.2.3, Table 2-1 footnote 1 (DW number); §6.4.1, Fig. 6-7 (DW n = DBB 2n, 2n+1)",
        "Byte 6 of a DB/DX header is a data word number: DW n is the byte pair 2n, 2n+1, high byte first.",
        "passive-send", "receiver",
        tester_send(header("A", "D", w, 4, 4), wide) + tester_send(header("A", "D", w, 5, 2), mid)
        + tester_fetch(header("E", "D", w, 4, 4), wide[:2] + mid + wide[6:]),
        needs={"db": [w], "db_bytes": 16}, provenance="[S][I]"))
    d128 = seq_data(128)
    out.append(case(
        c, "P-01.SEND-128", "SEND of 128 bytes: one frame of 10 + 128 bytes, one response",
        "§2.2.3 'Continuation message frame' (more than 128 bytes), Fig. 2-13",
        "A SEND of 128 bytes needs no continuation: one frame, one response 00 00 00 00.",
        "passive-send", "receiver",
        tester_send(header("A", "D", w, 0, 64), d128) + tester_fetch(header("E", "D", w, 0, 64), d128),
        needs={"db": [w], "db_bytes": 128}, provenance="[S]"))
    for n, title in ((130, "SEND of 130 bytes: 128 in the first frame, 2 in a continuation"),
                     (200, "SEND of 200 bytes (Example 2): one continuation frame FF 00 41 44"),
                     (1024, "SEND of 1024 bytes: eight frames, each answered")):
        data = seq_data(n, 0x21)
        out.append(case(
            c, f"P-02.SEND-{n}", title,
            "§2.2.3 'Sending a continuation message frame', Figs. 2-13, 2-14, Table 2-2",
            "Above 128 bytes the SEND goes on in continuation frames FF 00 41 44 of 128 bytes each; the first frame is answered 00 00 00 00, each continuation FF 00 00 00.",
            "passive-send", "receiver",
            tester_send(header("A", "D", w, 0, n // 2), data) + tester_fetch(header("E", "D", w, 0, n // 2), data),
            needs={"db": [w], "db_bytes": n}, provenance="[S][F][I]"))
    out.append(case(
        c, "P-03.RESPONSE-TIME", "The response to a SEND comes within the response monitoring time",
        "§2.2.3 'Response message frame', Figs. 2-18, 2-19 (T_RES)",
        "The responder answers before the requester's T_RES runs out (the profile's response_time_ms; left out, 10 s as the CP 341's prose gives it).",
        "passive-send", "receiver",
        tester_send(header("A", "D", w, 0, 5), d10),
        needs={"db": [w], "db_bytes": 10}, readings=["AMB-02"], provenance="[F]"))
    d128b = bytes([0x5A]) * 128
    out.append(case(
        c, "P-18.SEND-RESPONSE-WITHOUT-DATA", "The response to a 128-byte SEND is exactly 4 bytes",
        "§2.2.3 'SEND message frame', Table 2-2; Table 8-1 16#0A04",
        "A SEND response carries no data: 00 00 00 00 and nothing more.",
        "passive-send", "receiver", tester_send(header("A", "D", w, 0, 64), d128b),
        needs={"db": [w], "db_bytes": 128}, provenance="[S]"))
    if c.dx_w is not None:
        x = c.dx_w
        dxd = bytes([0xAB, 0xCD, 0x10, 0x02])
        out.append(case(
            c, "P-14.SEND-TO-DX", "SEND to a DX (command 'O', type 'D'): accepted",
            "§2.2.3, Table 2-1 ('O' 4Fh, byte 4 only 'D' when sending); §6.3.2 'Receiving data', Table 6-9",
            "A SEND with command letter O (destination DX) and type D is accepted and answered 00 00 00 00.",
            "passive-send", "receiver", tester_send(header("O", "D", x, 0, 2), dxd),
            needs={"dx": [x], "db_bytes": 4}, readings=["AMB-03", "AMB-21"], provenance="[S]"))
        for n in (130, 1024):
            data = seq_data(n, 0x33)
            out.append(case(
                c, f"P-14.SEND-TO-DX-{n}", f"SEND of {n} bytes to a DX: continuations FF 00 4F 44",
                "§2.2.3, Table 2-1, Fig. 2-14; §6.3.2 'Receiving data'",
                "A multi-frame SEND to a DX repeats bytes 3/4 'O' 'D' in its continuation frames; each frame is answered.",
                "passive-send", "receiver", tester_send(header("O", "D", x, 0, n // 2), data),
                needs={"dx": [x], "db_bytes": n}, readings=["AMB-21"], provenance="[S][I]"))
    return out
