"""The IUT active, issuing the SEND and FETCH of a request script (§2.2.3 "Sending data",
"Receiving data", Figs. 2-13 to 2-18; §6.3.2 P_SND_RK, Tables 6-4 to 6-8; §8.3 Table 8-1
classes 05, 09, 0A; §8.4 Table 8-3): A-01 to A-12, in three groups - the commands it
sends, how it takes the responses, and its response monitoring time."""

from ptpcert.procedures.p3964.model import codec as link

from ._build import (
    DLE,
    NAK,
    STX,
    case,
    chunks,
    cont,
    expect,
    failed,
    fetched,
    header,
    label,
    ok,
    prime,
    receive,
    resp,
    send,
    send_frames,
    silence,
    under_tres,
)

#: Table 8-3: REATEL -> the event the requester raises
TABLE_8_3 = {0x0A: "16#0905", 0x0C: "16#0902", 0x10: "16#090B", 0x12: "16#0904", 0x14: "16#0903",
             0x16: "16#090A", 0x2A: "16#090D", 0x32: "16#0909", 0x34: "16#090C", 0x36: "16#0908"}
UNKNOWN = "16#090E"
#: A-11: the invalid requests of the local checks (their names as the profile's
#: ``inexpressible_requests`` gives them), the script line and the events that may report it
LOCAL_CHECKS = (
    ("len-1025", "send DB10:DW0:LEN=1025", ("16#0517", "16#1E41"), "a length over 1024 bytes"),
    ("len-0", "fetch DB10:DW0:LEN=0", ("16#1E41", "16#0517"), "a length of 0"),
    ("db-0", "send DB0:DW0:LEN=2", ("16#0514", "16#0301"), "DB 0"),
    ("flag-bit-8", "send DB10:DW0:LEN=2:CF=3.8", ("16#0515",), "a coordination-flag bit over 7"),
    ("cpu-5", "send DB10:DW0:LEN=2:CPU=5", ("16#0516",), "a CPU number over 4"),
    ("send-to-flags", "send M:0:LEN=2", ("16#0301",), "a SEND to the flags (not a DB or DX)"))


def _data(n: int, seed: int = 0x10) -> bytes:
    """The data of a script SEND without DATA: byte i = (SEED + 7 i) & FFh (the interface)."""
    return bytes((seed + 7 * i) & 0xFF for i in range(n))


def _active(c, cid, title, ref, rule, group, lines, steps, results, *, iut=((), ()), readings=(),
            provenance="[S]", timing_sensitive=False, role="sender", needs=None):
    return case(c, cid, title, ref, rule, group, role, steps, iut=iut, requests=lines, results=results,
                readings=readings, provenance=provenance, timing_sensitive=timing_sensitive, needs=needs)


def _send_exchange(frames: list[bytes]) -> list:
    """The IUT's SEND frames, each answered by the tester with (continuation) response 00h."""
    out = []
    for k, f in enumerate(frames):
        out.append(receive(f, within="STARTUP" if k == 0 else "TRES",
                           note="the IUT's SEND" if k == 0 else "the IUT's continuation"))
        out.append(prime(resp(0, first=k == 0)))
    return out


def _fetch_exchange(hdr: bytes, data: bytes) -> list:
    """The IUT's FETCH command and continuation FETCHes, answered with the data in chunks."""
    out = []
    for k, part in enumerate(chunks(data)):
        out.append(receive(hdr if k == 0 else cont(hdr[2], hdr[3]), within="STARTUP" if k == 0 else "TRES",
                           note="the IUT's FETCH" if k == 0 else "the IUT's continuation FETCH (4 bytes)"))
        out.append(prime(resp(0, first=k == 0, data=part)))
    return out


def commands(c):
    """A-01, A-02, A-03, A-09, A-11: what the IUT puts on the wire for its requests."""
    out = []
    d10 = bytes.fromhex("112233445566778899AA")
    for cid, title, line, hdr, data, alt, amb in (
            ("A-01.SEND-DB", "SEND 10 bytes to DB 10 (Example 1): 00 00 41 44 0A 00 00 05 FF 1F",
             "send DB10:DW0:LEN=10:DATA=112233445566778899AA", header("A", "D", 10, 0, 5), d10, None, None),
            ("A-01.SEND-NEITHER-CPU-NOR-FLAG", "SEND without CPU number or flag: bytes 9/10 FF FF",
             "send DB10:DW0:LEN=10:CPU=none:DATA=112233445566778899AA", header("A", "D", 10, 0, 5, b10=0xFF), d10,
             None, None),
            ("A-01.SEND-FLAG-CPU-2", "SEND with coordination flag 3.5 for CPU 2: bytes 9/10 03 25",
             "send DB10:DW0:LEN=2:CF=3.5:CPU=2:DATA=DEAD", header("A", "D", 10, 0, 1, b9=3, b10=0x25),
             b"\xde\xad", None, None),
            ("A-01.SEND-FLAG-NO-CPU", "SEND with flag 12.3 and no CPU number: bytes 9/10 0C 03",
             "send DB10:DW0:LEN=2:CF=12.3:CPU=none:DATA=0102", header("A", "D", 10, 0, 1, b9=12, b10=0x03),
             b"\x01\x02", None, None),
            ("A-01.SEND-CPU-0", "SEND for CPU 0 without a flag: byte 10 0Fh (or FFh, 'not given')",
             "send DB10:DW0:LEN=2:CPU=0:DATA=0102", header("A", "D", 10, 0, 1, b10=0x0F), b"\x01\x02",
             header("A", "D", 10, 0, 1, b10=0xFF), "AMB-22"),
            ("A-01.SEND-DX", "SEND to DX 5: command 'O', type 'D' (4F 44)",
             "send DX5:DW0:LEN=2:DATA=ABCD", header("O", "D", 5, 0, 1), b"\xab\xcd", header("A", "D", 5, 0, 1),
             "AMB-03"),
            ("A-01.SEND-DLE-IN-HEADER", "SEND to DB 16 from DW 16 of 4 bytes 10 20 30 10 (Example 6): DLEs doubled",
             "send DB16:DW16:LEN=4:DATA=10203010", header("A", "D", 16, 16, 2), bytes.fromhex("10203010"), None, None),
            ("A-09.SEND-ODD-LENGTH", "SEND of LEN 11 at offset 7: 6 words from DW 3, padded with 00h (Example 6)",
             "send DB10:OFF=7:LEN=11:DATA=0102030405060708090A0B", header("A", "D", 10, 3, 6),
             bytes(range(1, 12)) + b"\x00", None, None),
            ("A-03.SEND-200", "SEND of 200 bytes: 128 in the first frame, 72 in a continuation FF 00 41 44",
             "send DB10:DW0:LEN=200", header("A", "D", 10, 0, 100), _data(200), None, None),
            ("A-03.SEND-1024", "SEND of 1024 bytes: eight frames of 128 bytes",
             "send DB10:DW0:LEN=1024", header("A", "D", 10, 0, 512), _data(1024), None, None),
            ("A-03.SEND-DX-130", "SEND of 130 bytes to a DX: the last 2 bytes in a continuation FF 00 4F 44",
             "send DX7:DW0:LEN=130", header("O", "D", 7, 0, 65), _data(130), None, None)):
        frames = send_frames(hdr, data)
        steps = _send_exchange(frames)
        if alt is not None:
            steps[0] = receive(frames[0], within="STARTUP", alternatives=[alt + data], alt_grade="informational")
        out.append(_active(
            c, cid, title,
            "§2.2.3 Tables 2-1, 2-2, Figs. 2-13, 2-14; §6.3.2 P_SND_RK, Tables 6-4, 6-5",
            "A requester's first command frame is 00 00, the command letter and type, DB/DW (word addressing), the length in words, and bytes 9/10 per the CPU/flag rule; above 128 bytes continuation frames FF 00 b3 b4 follow, each after the previous response.",
            "active-command", [line], steps, [ok(label(line))], readings=[amb] if amb else [],
            provenance="[S][F]"))
    for cid, title, line, hdr, data, stored in (
            ("A-01.FETCH-DB", "FETCH 6 bytes from DB 10 (Example 3): 00 00 45 44 0A 00 00 03 FF 1F",
             "fetch DB10:DW0:LEN=6", header("E", "D", 10, 0, 3), bytes.fromhex("123456789ABC"), None),
            ("A-01.FETCH-DX", "FETCH 4 bytes from DX 7, DW 4 (Example 6): type 'X'",
             "fetch DX7:DW4:LEN=4", header("E", "X", 7, 4, 2), bytes.fromhex("CAFEBABE"), None),
            ("A-01.FETCH-FLAGS", "FETCH 6 flag bytes MB 20..25 (Example 6): type 'M', byte address, length in bytes",
             "fetch M:20:LEN=6", header("E", "M", 0, 20, 6), bytes(range(6)), None),
            ("A-02.FETCH-INPUTS", "FETCH 10 input bytes: type 'E' (45h)",
             "fetch E:0:LEN=10", header("E", "E", 0, 0, 10), bytes(range(0x40, 0x4A)), None),
            ("A-02.FETCH-OUTPUTS", "FETCH 6 output bytes from byte 3: type 'A' (41h)",
             "fetch A:3:LEN=6", header("E", "A", 0, 3, 6), bytes(range(0xC3, 0xC9)), None),
            ("A-02.FETCH-TIMERS", "FETCH 4 timers from T 3: type 'T', length in words",
             "fetch T:3:LEN=8", header("E", "T", 0, 3, 4), bytes(range(0x26, 0x2E)), None),
            ("A-02.FETCH-COUNTERS", "FETCH 10 counters from C 5 (Example 6): type 'Z' (5Ah), not 'C'",
             "fetch Z:5:LEN=20", header("E", "Z", 0, 5, 10), bytes(range(0x6A, 0x7E)), None),
            ("A-09.FETCH-ODD-LENGTH", "FETCH of LEN 5 at offset 6: 3 words asked for, 5 bytes stored (Example 6)",
             "fetch DB10:OFF=6:LEN=5", header("E", "D", 10, 3, 3), bytes.fromhex("112233445566"),
             bytes.fromhex("1122334455")),
            ("A-03.FETCH-130", "FETCH of 130 bytes: a 4-byte continuation FETCH for the last 2",
             "fetch DB10:DW0:LEN=130", header("E", "D", 10, 0, 65), bytes((0x80 + i) & 0xFF for i in range(130)), None),
            ("A-03.FETCH-300", "FETCH of 300 bytes (Example 4): two continuation FETCHes FF 00 45 44",
             "fetch DB10:DW0:LEN=300", header("E", "D", 10, 0, 150), bytes((0x80 + i) & 0xFF for i in range(300)),
             None)):
        out.append(_active(
            c, cid, title,
            "§2.2.3 Tables 2-1, 2-2, Figs. 2-15, 2-16; §6.3.2 Tables 6-6 to 6-8",
            "A FETCH command is the 10-byte header alone, with the type letter of the area (D, X, E, A, M, T, Z) and the length in its unit; each further 128 bytes are asked for by a 4-byte continuation FETCH FF 00 45 xx.",
            "active-command", [line], _fetch_exchange(hdr, data),
            [fetched(label(line), stored if stored is not None else data), ok(label(line))],
            readings=["AMB-01", "AMB-14"] if hdr[3] in b"EAMTZ" else [], provenance="[S][F][I]"))
    # requests the FB or the CP refuses never reach the wire, one case per invalid
    # parameter (an IUT whose interface cannot express one says so in its profile)
    good = "send DB10:DW0:LEN=2:DATA=0102"
    for name, line, codes, what in LOCAL_CHECKS:
        out.append(_active(
            c, f"A-11.LOCAL-CHECK-{name.upper()}", f"A request with {what} fails locally, nothing on the wire",
            "§6.3.2 Tables 6-4, 6-6; §8.3 Table 8-1 " + ", ".join(x for x in codes if x.startswith("16#05"))
            + ("; Table 8-2 16#1E41" if "16#1E41" in codes else "") + ("; 16#0301" if "16#0301" in codes else ""),
            f"The requester checks its parameters before it sends: a request with {what} fails with "
            f"{' or '.join(codes)} and puts nothing on the wire; the next valid request goes out as usual.",
            "active-command", [line, good], _send_exchange([header("A", "D", 10, 0, 1) + b"\x01\x02"]),
            [failed(label(line), *codes), ok(label(good))], iut=(["|".join(codes)], []), readings=["N5", "N6"],
            needs={"expressible": name}, provenance="[S][I]"))
    return out


def responses(c):
    """A-06, A-07, A-08, A-12: how the IUT takes the tester's responses."""
    out = []
    one = "send DB10:DW0:LEN=10:DATA=112233445566778899AA"
    one_f = header("A", "D", 10, 0, 5) + bytes.fromhex("112233445566778899AA")
    two = "send DB10:DW0:LEN=200"
    two_f = send_frames(header("A", "D", 10, 0, 100), _data(200))
    fetch6 = "fetch DB10:DW0:LEN=6"
    fetch6_f = header("E", "D", 10, 0, 3)
    for reatel in sorted(TABLE_8_3) + [0x01, 0x42, 0xFF]:
        code = TABLE_8_3.get(reatel, UNKNOWN)
        known = reatel in TABLE_8_3
        out.append(_active(
            c, f"A-06.REATEL-{reatel:02X}", f"Response with REATEL {reatel:02X}h: the request fails with {code}",
            "§2.2.3 Table 2-2 footnote; §8.4 Table 8-3; §8.3 Table 8-1 class 09",
            ("The requester maps the error number of a response to its class-09 event (Table 8-3) and ends the request."
             if known else "An error number that Table 8-3 does not list is reported as 16#090E (unknown error number)."),
            "active-response", [one], [receive(one_f, within="STARTUP"), prime(resp(reatel))],
            [failed(label(one), code)], iut=([code], []), provenance="[S]"))
        out.append(_active(
            c, f"A-06.REATEL-{reatel:02X}-CONTINUATION",
            f"Continuation response with REATEL {reatel:02X}h: {code}, no further frames",
            "§2.2.3 Fig. 2-19 ('send response with error message: partner request finished'); §8.4 Table 8-3",
            "A continuation response with an error number ends the request: the requester reports its event and sends no further continuation.",
            "active-response", [two],
            [receive(two_f[0], within="STARTUP"), prime(resp(0)), receive(two_f[1]), prime(resp(reatel, first=False)),
             silence("2*ADT", note="no further frame of this request")],
            [failed(label(two), code)], iut=([code], []), provenance="[S][I]"))
    # an error number on a response that is not the last of the request: the request ends
    # there, with no further continuation (every position of a three-frame request)
    fetch3 = "fetch DB10:DW0:LEN=300"
    fetch3_h = header("E", "D", 10, 0, 150)
    for cid, reatel, line, frames, at in (
            ("A-06.REATEL-14-FIRST-OF-THREE", 0x14, "send DB10:DW0:LEN=300", send_frames(header("A", "D", 10, 0, 150), _data(300)), 0),
            ("A-06.REATEL-36-FIRST-OF-THREE", 0x36, "send DB10:DW0:LEN=300", send_frames(header("A", "D", 10, 0, 150), _data(300)), 0),
            ("A-06.REATEL-14-MIDDLE-OF-THREE", 0x14, "send DB10:DW0:LEN=300", send_frames(header("A", "D", 10, 0, 150), _data(300)), 1),
            ("A-06.REATEL-14-FETCH-FIRST-OF-THREE", 0x14, fetch3, [fetch3_h, cont("E", "D"), cont("E", "D")], 0)):
        code = TABLE_8_3[reatel]
        fetch = line.startswith("fetch")
        steps = []
        for k in range(at):
            steps += [receive(frames[k], within="STARTUP" if k == 0 else "TRES"),
                      prime(resp(0, first=k == 0, data=bytes(128) if fetch else b""))]
        steps += [receive(frames[at], within="STARTUP" if at == 0 else "TRES"),
                  prime(resp(reatel, first=at == 0)),
                  silence("2*ADT", note=f"no continuation: frame {at + 2} of 3 must not follow")]
        where = "first" if at == 0 else "continuation"
        out.append(_active(
            c, cid, f"{'FETCH' if fetch else 'SEND'} of 300 bytes, REATEL {reatel:02X}h on its {where} response "
                    f"(frame {at + 1} of 3): {code}, no further continuation",
            "§2.2.3 Fig. 2-19 ('send response with error message': 'partner request finished'), Fig. 2-18; §8.4 Table 8-3",
            "A response with an error number ends the request wherever it comes: the requester reports its event and sends none of the frames still left.",
            "active-response", [line], steps, [failed(label(line), code)], iut=([code], []), provenance="[F][I]"))
    for cid, title, rule, line, steps, code, extra in (
            ("A-07.BYTE1-01", "Response with byte 1 = 01h: 16#0A02",
             "A response whose byte 1 is neither 00h nor FFh is a structure error (16#0A02).",
             one, [receive(one_f, within="STARTUP"), prime(bytes([0x01, 0, 0, 0]))], "16#0A02", ()),
            ("A-07.SEND-RESPONSE-WITH-DATA", "SEND response carrying a data byte: 16#0A04",
             "A response to a SEND carries no data; one with data is 16#0A04.",
             one, [receive(one_f, within="STARTUP"), prime(resp(0, data=b"\xaa"))], "16#0A04", ()),
            ("A-07.FETCH-ONE-SHORT", "FETCH response one byte short: 16#0A03",
             "A FETCH response must carry exactly its chunk; one byte less is 16#0A03.",
             fetch6, [receive(fetch6_f, within="STARTUP"), prime(resp(0, data=bytes(5)))], "16#0A03", ()),
            ("A-07.FETCH-ONE-LONG", "FETCH response one byte long: 16#0A03",
             "A FETCH response must carry exactly its chunk; one byte more is 16#0A03.",
             fetch6, [receive(fetch6_f, within="STARTUP"), prime(resp(0, data=bytes(7)))], "16#0A03", ()),
            ("A-07.CONTINUATION-RESPONSE-TO-FIRST", "Continuation response FF to a first command: 16#0A01",
             "A first command must be answered by a first response (byte 1 00h); FFh is a synchronisation error (16#0A01).",
             one, [receive(one_f, within="STARTUP"), prime(resp(0, first=False))], "16#0A01", ()),
            ("A-07.FIRST-RESPONSE-TO-CONTINUATION", "First response 00 to a continuation: 16#0A01",
             "A continuation must be answered by a continuation response (byte 1 FFh); 00h is a synchronisation error (16#0A01).",
             two, [receive(two_f[0], within="STARTUP"), prime(resp(0)), receive(two_f[1]), prime(resp(0))],
             "16#0A01", ())):
        out.append(_active(
            c, cid, title, "§2.2.3 Table 2-2; §8.3 Table 8-1 class 0A", rule, "active-response", [line],
            steps + [silence("2*ADT", note="the request is over: nothing more")], [failed(label(line), code)],
            iut=([code], list(extra)), provenance="[S]"))
    out.append(_active(
        c, "A-07.ERROR-RESPONSE-WITH-DATA", "Error response (14h) carrying data: a length error or the REATEL's event",
        "§2.2.3 'Receiving data' (an error response has no data); §8.3 Table 8-1 16#0A03; Table 8-3",
        "A response with an error number carries no data; one that does is taken as a wrong length (16#0A03) or by its REATEL (16#0903).",
        "active-response", [fetch6], [receive(fetch6_f, within="STARTUP"), prime(resp(0x14, data=bytes(6)))],
        [failed(label(fetch6), "16#0A03", "16#0903")], iut=(["16#0A03|16#0903"], []), readings=["AMB-33"],
        provenance="[S][O]"))
    out.append(_active(
        c, "A-07.SHORT-RESPONSE", "A 3-byte response: 16#0610, the request ends then or at T_RES",
        "§8.3 Table 8-1 16#0610 (frame too short), 16#0A05",
        "A response shorter than 4 bytes is too short (16#0610); the manual does not say whether the request ends at once or waits for T_RES.",
        "active-response", [one],
        [receive(one_f, within="STARTUP"), prime(bytes(3)),
         silence("TRES + 2*ADT", note="the request ends at once or at T_RES; nothing further is sent for it")],
        [failed(label(one), "16#0610", "16#0A05")], iut=((), ["16#0610", "16#0A05"]), readings=["AMB-10", "AMB-19"],
        provenance="[S][O]"))
    out.append(_active(
        c, "A-12.FETCH-ERROR-NO-DATA", "FETCH answered with REATEL 14h: no data are stored (no FETCHED line)",
        "§2.2.3 'Receiving data'; §8.4 Table 8-3 (14h: 16#0903)",
        "A FETCH answered with an error number stores nothing: the request fails with the REATEL's event.",
        "active-response", [fetch6], [receive(fetch6_f, within="STARTUP"), prime(resp(0x14))],
        [failed(label(fetch6), "16#0903")], iut=(["16#0903"], []), provenance="[S][I]"))
    # quasi-full-duplex - the tester's own SEND while the IUT waits for its response
    theirs = header("A", "D", c.db_w, 0, 2) + bytes([0x21, 0x22, 0x23, 0x24])
    theirs_needs = {"db": [c.db_w], "db_bytes": 4}
    out.append(_active(
        c, "A-08.TESTER-SEND-BEFORE-RESPONSE", "While the IUT waits for its response the tester SENDs: answered, then the response is taken",
        "§2.2.3 'Quasi-full-duplex', Fig. 2-17; §6.3.2 'Parallel processing of requests'",
        "A station waiting for the response to its command still serves the partner's command, and then takes the response it waits for.",
        "quasi-full-duplex", [one],
        [receive(one_f, within="STARTUP"), prime(theirs, note="the tester's own SEND first"), receive(resp(0)),
         prime(resp(0), note="then the answer to the IUT's SEND")],
        [ok(label(one))], role="both", needs=theirs_needs, provenance="[S][F]"))
    three = "send DB10:DW0:LEN=300"
    f3 = send_frames(header("A", "D", 10, 0, 150), _data(300))
    out.append(_active(
        c, "A-08.FIGURE-2-17", "Fig. 2-17: the tester's SEND goes before the continuation response it owes",
        "§2.2.3 'Quasi-full-duplex', Fig. 2-17",
        "A station may send its own command before the response it owes; the partner answers that command and then takes the held-back response and goes on with its request.",
        "quasi-full-duplex", [three],
        [receive(f3[0], within="STARTUP"), prime(resp(0)), receive(f3[1]),
         prime(theirs, note="the tester's SEND before its continuation response (Fig. 2-17, frame 4)"),
         receive(resp(0), note="the IUT answers it"),
         prime(resp(0, first=False), note="the held-back continuation response (frame 5)"),
         receive(f3[2], note="the IUT's 2nd continuation"), prime(resp(0, first=False))],
        [ok(label(three))], role="both", needs=theirs_needs, provenance="[F]"))
    return out


def timing(c):
    """A-04, A-05, A-10: the requester's pace, its T_RES and the link's repetitions."""
    p = c.p
    out = []
    three = "send DB10:DW0:LEN=300"
    f3 = send_frames(header("A", "D", 10, 0, 150), _data(300))
    steps = []
    for k, f in enumerate(f3):
        steps += [receive(f, within="STARTUP" if k == 0 else "TRES"),
                  silence(under_tres(p, 0.6, resp(0)), note="the response is late: the IUT sends nothing meanwhile"),
                  prime(resp(0, first=k == 0))]
    out.append(_active(
        c, "A-04.NO-PIPELINING", "Responses held back 0.6 T_RES: the IUT sends nothing further meanwhile",
        "§2.2.3 'Sending data', 'Quasi-full-duplex' (nesting depth 1)",
        "A requester sends its next frame of a request only after the response to the previous one.",
        "active-timing", [three], steps, [ok(label(three))], readings=["AMB-02"], provenance="[S]"))
    one = "send DB10:DW0:LEN=10:DATA=112233445566778899AA"
    one_f = header("A", "D", 10, 0, 5) + bytes.fromhex("112233445566778899AA")
    out.append(_active(
        c, "A-05.RESPONSE-AT-0.8-TRES", "The response late but within T_RES (0.8 of what it leaves): the request succeeds",
        "§2.2.3 Fig. 2-18 (T_RES); §8.3 Table 8-1 16#0A05",
        "A requester waits T_RES for the response; one that comes in time ends the request with success.",
        "active-timing", [one], [receive(one_f, within="STARTUP"), prime(resp(0), at=under_tres(p, 0.8, resp(0)))],
        [ok(label(one))], readings=["AMB-02", "AMB-17"], timing_sensitive=True, provenance="[F]"))
    two = "send DB10:DW0:LEN=200"
    f2 = send_frames(header("A", "D", 10, 0, 100), _data(200))
    out.append(_active(
        c, "A-05.NO-RESPONSE", "No response: 16#0A05 after T_RES, no continuation, a late response is not success",
        "§2.2.3 Fig. 2-18 ('T > T_RES'); §8.3 Table 8-1 16#0A05, 16#0A01",
        "Without a response within T_RES the request fails (16#0A05); its continuation is never sent, and a response after that answers nothing.",
        "active-timing", [two],
        [receive(f2[0], within="STARTUP"), silence("TRES + 2*ADT", note="no response; no continuation either"),
         prime(resp(0), note="the late response"), silence("2*ADT", note="still no continuation")],
        [failed(label(two), "16#0A05")], iut=(["16#0A05"], ["16#0A01"]), readings=["AMB-02", "AMB-17"],
        provenance="[S][F]"))
    M = p.line.transmission_attempts
    body = link.body(one_f, p.procedure)
    steps = []
    for i in range(M):
        steps += [expect([STX], within="STARTUP" if i == 0 else "ADT", note=f"attempt {i + 1}"), send([DLE]),
                  expect(body, within="CDT"), send([NAK], note="the tester refuses the block")]
    steps += [expect([NAK], note="the IUT gives up (3964R: NAK after the last attempt)"),
              silence("2*ADT", note="no new RK 512 attempt of its own")]
    out.append(_active(
        c, "A-10.COMMAND-REFUSED", f"The command block refused {M} times: the request fails with 16#051A, no retry",
        "§2.2.2 'Connection release', Fig. 2-10 (transmission attempts); §8.3 Table 8-1 16#051A, 16#070A",
        "The link repeats a refused command block up to the transmission attempts; then the request fails (16#051A after the link's event) and the RK 512 layer starts no retry of its own.",
        "active-timing", [one], steps, [failed(label(one), "16#051A")],
        iut=(["16#051A", "16#0706|16#070A"], ["16#0701"]), provenance="[S]"))
    return out


def cases(c):
    return commands(c) + responses(c) + timing(c)
