"""The IUT passive, serving the tester's FETCH (§2.2.3 "Receiving data", Figs. 2-15, 2-16,
2-19; §6.3.2 "Providing data", Tables 6-8, 6-10): P-04, P-05 for every data type, P-13,
P-14 (FETCH from a DX)."""

from ._build import case, cont, header, pattern, prime, receive, resp, seq_data, tester_fetch, tester_send, unprompted

SIZES = (6, 128, 300, 1024)
NAMES = {"D": "DB", "X": "DX", "E": "inputs", "A": "outputs", "M": "flags", "T": "timers", "Z": "counters"}
#: a CP 341 serves a partner at most 32 bytes of timers or counters (§6.3.2 "Providing data")
CP341_CELL_LIMIT = 32
#: how a responder refuses what it does not serve (open point AMB-20: the manual names no
#: number): timers/counters over its limit with 16#0608 and 34h (Table 8-3) or 0Ch (area too
#: short); a FETCH from a DX with 10h (16#0604, a type the CP does not allow), 14h (16#0606,
#: no such DX) or 0Ch (16#0607)
REFUSALS = {"T": (0x34, 0x0C), "Z": (0x34, 0x0C), "X": (0x10, 0x14, 0x0C)}
REFUSAL_EVENTS = {"T": ["16#0608", "16#0607"], "Z": ["16#0608", "16#0607"], "X": ["16#0604", "16#0606", "16#0607"]}


def service(p, typ: str, n: int) -> str:
    """Whether the IUT serves a partner's FETCH of ``n`` bytes of ``typ``: "serve", "refuse"
    (the profile declares it), or "either" (the profile is silent and a CP 341 would refuse:
    open point AMB-20)."""
    if typ in "TZ":
        limit = p.cell_fetch_limit_bytes
        if limit is None:
            return "either" if n > CP341_CELL_LIMIT else "serve"
        return "refuse" if n > limit else "serve"
    if typ == "X":
        return "either" if p.serves_dx_fetch is None else "serve" if p.serves_dx_fetch else "refuse"
    return "serve"


def served_or_refused(p, typ: str, n: int, cmd: bytes, served: list) -> tuple[list, list[str]]:
    """The steps of a partner FETCH (``served``: the tester's FETCH answered in full, its
    command ``cmd`` first) as the profile has the IUT serve it, and the events it may raise:
    served; refused at once (no data, REATEL per REFUSALS); or, where the profile is silent,
    either - the refusal ends the case (``or_end``), graded informational."""
    how = service(p, typ, n)
    if how == "serve":
        return served, []
    refusals = [resp(r) for r in REFUSALS[typ]]
    if how == "refuse":
        return [prime(cmd), receive(refusals[0], alternatives=refusals[1:])], REFUSAL_EVENTS[typ]
    first = served[1]
    either = receive(first.data, alternatives=refusals, alt_grade="informational", or_end=0,
                     note="served, or refused as a CP 341 does (AMB-20)")
    return [served[0], either] + served[2:], REFUSAL_EVENTS[typ]


def _fetch(c, typ: str, n: int):
    """(steps, needs, events) of a FETCH of ``n`` bytes of type ``typ`` from the start of its
    area, answered from the memory pattern (or, for DB/DX of unknown contents, written
    first), as the profile has the IUT serve it."""
    steps, needs = _fetch_served(c, typ, n)
    k = next(i for i, s in enumerate(steps) if s.kind == "prime" and s.data[2] == ord("E"))
    fetch, events = served_or_refused(c.p, typ, n, steps[k].data, steps[k:])
    return steps[:k] + fetch, needs, events


def _fetch_served(c, typ: str, n: int):
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
            steps, needs, events = _fetch(c, typ, n)
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
            if events:
                ref += "; §6.3.2 'Providing data', Table 6-10; Table 8-3"
                rule += (" A responder that does not serve it (the profile's cell_fetch_limit_bytes / serves_dx_fetch; "
                         "a CP 341) refuses it at once with an error number and no data.")
            out.append(case(c, cid, title, ref, rule, "passive-fetch", "receiver", steps, needs=needs,
                            iut=((), events),
                            readings=(["AMB-14", "AMB-15"] if typ in "EAMTZ" else []) + (["AMB-20"] if events else []),
                            provenance="[S][F]" if typ == "D" else "[S][I]"))
    # P-13: a CP 341 serves at most 32 bytes of timers or counters
    out.append(case(
        c, "P-13.FETCH-COUNTERS-40", "FETCH of 20 counters (40 bytes): served, or refused as a CP 341 does",
        "§6.3.2 'Providing data' note (32 bytes of timers/counters); Table 8-1 16#0608; Table 8-3",
        "A partner FETCH of more than 32 bytes of counters is served by a station that can, or refused (REATEL 34h or 0Ch; the manual names none) by a CP 341.",
        "passive-fetch", "receiver",
        served_or_refused(c.p, "Z", 40, header("E", "Z", 0, 0, 20),
                          [prime(header("E", "Z", 0, 0, 20)), receive(resp(0, data=pattern("Z", 0, 0, 40)))])[0],
        iut=((), ["16#0608", "16#0607"]), needs={"cell_area_cells": 20, "pattern": True}, readings=["AMB-20"],
        provenance="[S][O]"))
    if c.dx is not None:
        out.append(case(
            c, "P-14.FETCH-FROM-DX", "FETCH 6 bytes from a DX (type 'X'): served, or refused as a CP 341 may",
            "§6.3.2 Tables 6-7, 6-10 (DX not listed as a source); §2.2.3 Table 2-1",
            "A FETCH from a DX the IUT declares is served; a CP 341, which lists no DX source, may refuse it (recorded).",
            "passive-fetch", "receiver",
            served_or_refused(c.p, "X", 6, header("E", "X", c.dx, 0, 3),
                              [prime(header("E", "X", c.dx, 0, 3)), receive(resp(0, data=pattern("X", c.dx, 0, 6)))])[0],
            iut=((), ["16#0606", "16#0604", "16#0607"]), needs={"dx": [c.dx], "db_bytes": 6, "pattern": True},
            readings=["AMB-20"], provenance="[S][O]"))
    return out
