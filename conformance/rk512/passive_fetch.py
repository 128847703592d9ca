"""The IUT passive, serving the tester's FETCH (§2.2.3 "Receiving data", Figs. 2-15, 2-16,
2-19; §6.3.2 "Providing data", Tables 6-8, 6-10): P-04, P-05 for every data type, P-13,
P-14 (FETCH from a DX)."""

from ._build import case, cont, header, pattern, prime, receive, resp, seq_data, tester_fetch, tester_send, unprompted

SIZES = (6, 128, 300, 1024)
NAMES = {"D": "DB", "X": "DX", "E": "inputs", "A": "outputs", "M": "flags", "T": "timers", "Z": "counters"}


def _fetch(c, typ: str, n: int):
    """(steps, needs) of a FETCH of ``n`` bytes of type ``typ`` from the start of its area,
    answered from the memory pattern (or, for DB/DX of unknown contents, written first)."""
    pause = unprompted(c.p, cont("E", typ))
    if typ in "DX":
        number = c.db if typ == "D" else c.dx
        needs = {"db" if typ == "D" else "dx": [number], "db_bytes": n}
        if c.pattern_known:
            return tester_fetch(header("E", typ, number, 0, n // 2), pattern(typ, number, 0, n), pause=pause), \
                {**needs, "pattern": True}
        number = c.db_w if typ == "D" else c.dx_w
        needs = {"db" if typ == "D" else "dx": [number], "db_bytes": n}
        data = seq_data(n, 0x45)
        cmd = "A" if typ == "D" else "O"
        return tester_send(header(cmd, "D", number, 0, n // 2), data) + \
            tester_fetch(header("E", typ, number, 0, n // 2), data, pause=pause), needs
    if typ in "TZ":
        return tester_fetch(header("E", typ, 0, 0, n // 2), pattern(typ, 0, 0, n), pause=pause), \
            {"cell_area_cells": n // 2, "pattern": True}
    return tester_fetch(header("E", typ, 0, 0, n), pattern(typ, 0, 0, n), pause=pause), \
        {"byte_area_bytes": n, "pattern": True}


def cases(c):
    out = []
    for typ in "DXEAMTZ":
        if typ == "X" and c.dx is None:
            continue
        for n in SIZES:
            steps, needs = _fetch(c, typ, n)
            unit = "words" if typ in "DXTZ" else "bytes"
            if n <= 128:
                cid, title = f"P-04.FETCH-{typ}-{n}", f"FETCH {n} bytes of {NAMES[typ]}: one response with exactly {n} data bytes"
                ref = "§2.2.3 'Receiving data', Fig. 2-15, Table 2-2; §6.3.2 Table 6-8"
                rule = (f"A FETCH of {n} bytes ({n // 2 if unit == 'words' else n} {unit} in bytes 7/8) is answered by one "
                        f"response 00 00 00 00 followed by exactly {n} data bytes.")
            else:
                cid, title = f"P-05.FETCH-{typ}-{n}", f"FETCH {n} bytes of {NAMES[typ]}: 128-byte chunks, each on request"
                ref = "§2.2.3 'Receiving data', Figs. 2-15, 2-16; §6.3.2 Table 6-8"
                rule = ("Above 128 bytes the responder sends 128 data bytes per response and the rest in the last; "
                        "it sends each further chunk only in answer to a continuation FETCH FF 00 45 xx.")
            out.append(case(c, cid, title, ref, rule, "passive-fetch", "receiver", steps, needs=needs,
                            readings=["AMB-14", "AMB-15"] if typ in "EAMTZ" else [],
                            provenance="[S][F]" if typ == "D" else "[S][I]"))
    # P-13: a CP 341 serves at most 32 bytes of timers or counters
    out.append(case(
        c, "P-13.FETCH-COUNTERS-40", "FETCH of 20 counters (40 bytes): served, or refused as a CP 341 does",
        "§6.3.2 'Providing data' note (32 bytes of timers/counters); Table 8-1 16#0608; Table 8-3",
        "A partner FETCH of more than 32 bytes of counters is served by a station that can, or refused (REATEL 34h or 0Ch; the manual names none) by a CP 341.",
        "passive-fetch", "receiver",
        [prime(header("E", "Z", 0, 0, 20)),
         receive(resp(0, data=pattern("Z", 0, 0, 40)), alternatives=[resp(0x34), resp(0x0C)],
                 alt_grade="informational")],
        iut=((), ["16#0608", "16#0607"]), needs={"cell_area_cells": 20, "pattern": True}, readings=["AMB-20"],
        provenance="[S][O]"))
    if c.dx is not None:
        out.append(case(
            c, "P-14.FETCH-FROM-DX", "FETCH 6 bytes from a DX (type 'X'): served, or refused as a CP 341 may",
            "§6.3.2 Tables 6-7, 6-10 (DX not listed as a source); §2.2.3 Table 2-1",
            "A FETCH from a DX the IUT declares is served; a CP 341, which lists no DX source, may refuse it (recorded).",
            "passive-fetch", "receiver",
            [prime(header("E", "X", c.dx, 0, 3)),
             receive(resp(0, data=pattern("X", c.dx, 0, 6)), alternatives=[resp(0x14), resp(0x0C), resp(0x10)],
                     alt_grade="informational")],
            iut=((), ["16#0606", "16#0604", "16#0607"]), needs={"dx": [c.dx], "pattern": True},
            readings=["AMB-20"], provenance="[S][O]"))
    return out
