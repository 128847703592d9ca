"""The RK 512 golden vectors (vectors/rk512/), built from the rules as the tests state them
(tests/procedures/rk512/rk512_rules.py: Tables 2-1, 2-2 and the 3964R block of §2.2.2), never from the
model. ``python tests/procedures/rk512/rk512_golden.py --write`` writes the files; the tests check that the
files are exactly what this module builds and that the model reproduces every one.

Layout: the manual's worked examples (§6.3 of our notes: Figs. 2-13 to 2-16 and the derived
Examples 1-6) with every byte on the wire spelled out; SEND and FETCH of every size class
and data type; every REATEL of Table 8-3 at the requester; every class-06 event at the
responder and every class-0A event at the requester; quasi-full-duplex; T_RES on both sides;
DLE doubling in the header, the data, the REATEL and the BCC. Elsewhere the link is written
as macro steps (``prime``: the tester sends a frame; ``receive``: the IUT sends one).
"""

from __future__ import annotations

import sys
from pathlib import Path

from rk512_rules import (DLE, NAK, RESPONDER_8_3, STX, TABLE_8_3, UNKNOWN_REATEL, body, continuation, header, response,
                         unbody)
from rk512_vector_rules import rules_for

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "vectors" / "rk512"
BIG = {"db_bytes": 2048, "byte_area_bytes": 2048, "cell_area_cells": 1024}


def hx(data) -> str:
    return bytes(data).hex(" ").upper()


def code(c: int) -> str:
    return f"16#{c:04X}"


def pattern(area: str, number: int, start: int, n: int) -> bytes:
    """The interface's memory pattern."""
    base = {"D": number, "X": number + 0x80, "E": 0x40, "A": 0xC0, "T": 0x20, "Z": 0x60}.get(area)
    if base is None:
        return bytes(n)
    return bytes((base + start + i) & 0xFF for i in range(n))


def seq(n: int, seed: int = 0x10) -> bytes:
    """Byte i = (seed + 7 i) & FFh: the interface's SEND data without DATA."""
    return bytes((seed + 7 * i) & 0xFF for i in range(n))


# -- steps ------------------------------------------------------------------------------------
def send(data, note="", at=None):
    d = {"send": hx(data)}
    if at:
        d["at"] = at
    if note:
        d["note"] = note
    return d


def expect(data, within="ADT", note="", **kw):
    d = {"expect": hx(data), "within": within, **kw}
    if note:
        d["note"] = note
    return d


def prime(frame, note="", at=None):
    d = {"prime": hx(frame)}
    if at:
        d["at"] = at
    if note:
        d["note"] = note
    return d


def receive(frame, within="TRES", note="", alternatives=(), alt_grade=None, optional=False, absent_grade=None,
            or_end=None):
    d = {"receive": hx(frame), "within": within}
    if alternatives:
        d["or"] = [hx(a) for a in alternatives]
        if alt_grade:
            d["or_grade"] = alt_grade
        if or_end is not None:
            d["or_end"] = or_end
    if optional:
        d["optional"] = True
        if absent_grade:
            d["absent_grade"] = absent_grade
    if note:
        d["note"] = note
    return d


def tester_block(frame, bcc=True, note=""):
    """The tester sends ``frame`` byte by byte: STX, the IUT's DLE, the block, its DLE."""
    return [send([STX], note="STX"), expect([DLE], note="DLE: the IUT is ready"),
            send(body(frame, bcc), note=note or "the block: DLE doubled, DLE ETX" + (", BCC" if bcc else "")),
            expect([DLE], note="DLE: the block is accepted")]


def iut_block(frame, bcc=True, within="TRES", note=""):
    """The IUT sends ``frame`` byte by byte and the tester receives it."""
    return [expect([STX], within=within, note=note or "the IUT's STX"), send([DLE], note="DLE"),
            expect(body(frame, bcc), within="CDT", note="the block: DLE doubled, DLE ETX" + (", BCC" if bcc else "")),
            send([DLE], note="DLE: the tester accepts it")]


def tester_send(hdr, data):
    out = []
    parts = [data[i:i + 128] for i in range(0, len(data), 128)]
    for k, part in enumerate(parts):
        frame = hdr + part if k == 0 else continuation(chr(hdr[2]), chr(hdr[3]), part)
        out += [prime(frame), receive(response(0, first=k == 0))]
    return out


def tester_fetch(hdr, data):
    out = []
    for k in range(0, len(data), 128):
        out += [prime(hdr if k == 0 else continuation(chr(hdr[2]), chr(hdr[3]))),
                receive(response(0, first=k == 0, data=data[k:k + 128]))]
    return out


def _responses(steps, bcc):
    """(sender, REATEL, certain) of every error response in the steps: the IUT's (a receive
    step or the block of an expect) and the tester's (a prime step or the block it sends);
    ``certain`` is False where the step is optional or has alternatives."""
    out = []
    for d in steps:
        if "receive" in d or "prime" in d:
            who, frame = ("iut", d["receive"]) if "receive" in d else ("tester", d["prime"])
            frames = [bytes.fromhex(frame)] + [bytes.fromhex(a) for a in d.get("or", [])]
            certain = not d.get("optional") and len(frames) == 1
        elif "expect" in d or "send" in d:
            who = "iut" if "expect" in d else "tester"
            frames = [unbody(bytes.fromhex(d.get("expect", d.get("send"))), bcc)]
            certain = not d.get("optional")
        else:
            continue
        for f in frames:
            if f is not None and len(f) >= 4 and f[0] in (0x00, 0xFF) and f[1] == f[2] == 0x00 and f[3]:
                out.append((who, f[3], certain))
    return out


def tester_side(steps, bcc=True) -> tuple[list[str], list[str]]:
    """What a CP 341 in the tester's seat raises by Table 8-3 (required, optional): for each
    error response of the IUT the requester's class-09 event (16#090E for a number the table
    does not list); for each error response the tester sends, the responder's event that
    sends that number (one of those the table lists; none for 0Ah, 12h and unlisted ones)."""
    required, optional = [], []
    for who, reatel, certain in _responses(steps, bcc):
        if who == "iut":
            group = code(TABLE_8_3.get(reatel, UNKNOWN_REATEL))
        elif reatel in RESPONDER_8_3:
            group = "|".join(code(c) for c in RESPONDER_8_3[reatel])
        else:
            continue
        if certain and group not in required:
            required.append(group)
        elif not certain:
            for c in group.split("|"):
                if c not in optional:
                    optional.append(c)
    return required, sorted(optional)


def vector(vid, title, reference, rule, group, role, steps, *, link="3964R", iut=(), optional=(), requests=(),
           results=(), needs=None, readings=(), provenance="", params=None, binds=("link",), setup=None, notes=""):
    v = {"id": vid, "procedure": "RK512", "title": title, "reference": reference, "rule": rule, "group": group,
         "iut_role": role, "binds": list(binds)}
    if readings:
        v["readings"] = list(readings)
    if provenance:
        v["provenance"] = provenance
    if notes:
        v["notes"] = notes
    if setup is not None:
        v["setup"] = setup
    v["steps"] = steps
    v["params"] = {"link": link, **(params or {})}
    tester, tester_optional = tester_side(steps, link == "3964R")
    v["expected"] = {"iut_status": list(iut), "tester_status": tester}
    if optional:
        v["expected"]["iut_status_optional"] = list(optional)
    if tester_optional:
        v["expected"]["tester_status_optional"] = tester_optional
    extra = {}
    if requests:
        extra["requests"] = list(requests)
    if requests or results:
        extra["results"] = list(results)
    if needs:
        extra["needs"] = dict(needs)
    if extra:
        v["extra"] = extra
    return v


#: what a CP 341 does not serve a partner, the profile key that declares it, and how it may
#: refuse (the manual names no number, AMB-20): timers/counters over 32 bytes with 16#0608 and
#: 34h (Table 8-3) or 0Ch; a DX with 10h (16#0604), 14h (16#0606) or 0Ch (16#0607)
CP341_REFUSALS = {
    "T": ("cell_fetch_limit_bytes", (0x34, 0x0C), ["16#0608", "16#0607"]),
    "Z": ("cell_fetch_limit_bytes", (0x34, 0x0C), ["16#0608", "16#0607"]),
    "X": ("serves_dx_fetch", (0x10, 0x14, 0x0C), ["16#0604", "16#0606", "16#0607"]),
}


# -- the vectors ------------------------------------------------------------------------------
D10 = bytes.fromhex("112233445566778899AA")
EX1_CMD = header("A", "D", 10, 0, 5) + D10
LINE1 = "send DB10:DW0:LEN=10:DATA=112233445566778899AA"


def examples():
    out = []
    ref1 = "§2.2.3 'Sending data', Fig. 2-13, Table 2-1, Table 2-2; §2.2.2 Fig. 2-4 (BCC)"
    rule1 = ("A SEND of 10 bytes to DB 10 from DW 0 is the header 00 00 41 44 0A 00 00 05 FF 1F and the data, "
             "answered by the response 00 00 00 00.")
    out.append(vector(
        "RK512.EX1.SEND-10.PASSIVE", "Example 1, the IUT passive: SEND 10 bytes to DB 10, response 00 00 00 00",
        ref1, rule1, "passive-send", "receiver",
        tester_block(EX1_CMD, note="header and 10 data bytes, DLE ETX, BCC 42") + iut_block(response(0)),
        needs={"db": [10], "db_bytes": 10}, provenance="[S][F]"))
    out.append(vector(
        "RK512.EX1.SEND-10.ACTIVE", "Example 1, the IUT active: its SEND 10 bytes to DB 10, byte for byte",
        ref1, rule1, "active-command", "sender",
        iut_block(EX1_CMD, within="STARTUP", note="the IUT's STX for its request") + tester_block(response(0)),
        requests=[LINE1], results=[f"RESULT {LINE1.replace(' ', ':', 1)} OK"], provenance="[S][F]"))
    line = "send DB10:DW0:LEN=10:CPU=none:DATA=112233445566778899AA"
    out.append(vector(
        "RK512.EX1.SEND-10-NO-CPU.ACTIVE", "Example 1 with neither CPU nor flag: bytes 9/10 FF FF, BCC A2",
        "§2.2.3 Table 2-1 (byte 10 Fh/Fh when neither is given)",
        "With neither CPU number nor coordination flag bytes 9 and 10 are FF FF.",
        "active-command", "sender",
        iut_block(header("A", "D", 10, 0, 5, b10=0xFF) + D10, within="STARTUP") + tester_block(response(0)),
        requests=[line], results=[f"RESULT {line.replace(' ', ':', 1)} OK"], readings=["AMB-22"], provenance="[S]"))
    out.append(vector(
        "RK512.EX1.SEND-10.PASSIVE-3964", "Example 1 over 3964 without BCC",
        "§2.2.3 Figs. 2-13 ('only with BCC'); §2.3.1 Table 2-3", rule1 + " Over 3964 the blocks have no BCC.",
        "passive-send", "receiver",
        tester_block(EX1_CMD, bcc=False) + iut_block(response(0), bcc=False),
        link="3964", needs={"db": [10], "db_bytes": 10}, readings=["AMB-27"], provenance="[S][I]"))

    d200 = bytes(range(200))
    first = header("A", "D", 10, 0, 100) + d200[:128]
    cont = continuation("A", "D", d200[128:])
    ref2 = "§2.2.3 'Sending a continuation message frame', Figs. 2-13, 2-14"
    rule2 = ("A SEND of 200 bytes goes out as a first frame with bytes 1..128 and a continuation FF 00 41 44 "
             "with bytes 129..200; the first is answered 00 00 00 00, the continuation FF 00 00 00.")
    out.append(vector(
        "RK512.EX2.SEND-200.PASSIVE", "Example 2, the IUT passive: SEND 200 bytes, one continuation",
        ref2, rule2, "passive-send", "receiver",
        tester_block(first) + iut_block(response(0)) + tester_block(cont) + iut_block(response(0, first=False)),
        needs={"db": [10], "db_bytes": 200}, provenance="[S][F]"))
    line2 = "send DB10:DW0:LEN=200:DATA=" + d200.hex().upper()
    out.append(vector(
        "RK512.EX2.SEND-200.ACTIVE", "Example 2, the IUT active: its SEND of 200 bytes, one continuation",
        ref2, rule2, "active-command", "sender",
        iut_block(first, within="STARTUP") + tester_block(response(0)) + iut_block(cont)
        + tester_block(response(0, first=False)),
        requests=[line2], results=[f"RESULT {line2.replace(' ', ':', 1)} OK"], provenance="[S][F]"))

    d6 = bytes.fromhex("123456789ABC")
    cmd3 = header("E", "D", 10, 0, 3)
    ref3 = "§2.2.3 'Receiving data', Fig. 2-15, Tables 2-1, 2-2"
    rule3 = "A FETCH of 6 bytes is the 10-byte header alone (3 words), answered by 00 00 00 00 and the 6 bytes."
    out.append(vector(
        "RK512.EX3.FETCH-6.ACTIVE", "Example 3, the IUT active: its FETCH of 6 bytes from DB 10",
        ref3, rule3, "active-command", "sender",
        iut_block(cmd3, within="STARTUP") + tester_block(response(0, data=d6)),
        requests=["fetch DB10:DW0:LEN=6"],
        results=["FETCHED fetch:DB10:DW0:LEN=6 123456789ABC", "RESULT fetch:DB10:DW0:LEN=6 OK"], provenance="[S][F]"))
    out.append(vector(
        "RK512.EX3.FETCH-6.PASSIVE", "Example 3, the IUT passive: the 6 bytes written first, then fetched",
        ref3, rule3, "passive-fetch", "receiver",
        tester_send(header("A", "D", 10, 0, 3), d6) + tester_block(cmd3) + iut_block(response(0, data=d6)),
        needs={"db": [10], "db_bytes": 6}, provenance="[S][F]"))

    d300 = bytes((0x80 + i) & 0xFF for i in range(300))
    cmd4 = header("E", "D", 10, 0, 150)
    c4 = continuation("E", "D")
    ref4 = "§2.2.3 'Receiving data', Figs. 2-15, 2-16"
    rule4 = ("A FETCH of 300 bytes is answered in chunks of 128, 128 and 44 bytes, each further chunk asked for by "
             "a continuation FETCH FF 00 45 44 of exactly 4 bytes.")
    ex4 = (tester_block(cmd4) + iut_block(response(0, data=d300[:128])) + tester_block(c4)
           + iut_block(response(0, first=False, data=d300[128:256])) + tester_block(c4)
           + iut_block(response(0, first=False, data=d300[256:])))
    out.append(vector(
        "RK512.EX4.FETCH-300.PASSIVE", "Example 4, the IUT passive: 300 bytes written, then fetched in three chunks",
        ref4, rule4, "passive-fetch", "receiver", tester_send(header("A", "D", 10, 0, 150), d300) + ex4,
        needs={"db": [10], "db_bytes": 300}, provenance="[S][F]"))
    out.append(vector(
        "RK512.EX4.FETCH-300.ACTIVE", "Example 4, the IUT active: its FETCH of 300 bytes, two continuations",
        ref4, rule4, "active-command", "sender",
        iut_block(cmd4, within="STARTUP") + tester_block(response(0, data=d300[:128])) + iut_block(c4)
        + tester_block(response(0, first=False, data=d300[128:256])) + iut_block(c4)
        + tester_block(response(0, first=False, data=d300[256:])),
        requests=["fetch DB10:DW0:LEN=300"],
        results=["FETCHED fetch:DB10:DW0:LEN=300 " + d300.hex().upper(), "RESULT fetch:DB10:DW0:LEN=300 OK"],
        provenance="[S][F]"))

    # Example 5: every REATEL of Table 8-3 at the requester, in first and continuation responses
    two = "send DB10:DW0:LEN=200"
    f2 = header("A", "D", 10, 0, 100) + seq(200)[:128]
    c2 = continuation("A", "D", seq(200)[128:])
    for reatel in sorted(TABLE_8_3) + [0x01, 0x42, 0xFF]:
        ev = TABLE_8_3.get(reatel, UNKNOWN_REATEL)
        listed = reatel in TABLE_8_3
        rule = (f"A response with error number {reatel:02X}h ends the request with {code(ev)} (Table 8-3)." if listed
                else f"An error number Table 8-3 does not list ({reatel:02X}h) ends the request with 16#090E.")
        out.append(vector(
            f"RK512.EX5.REATEL-{reatel:02X}", f"Example 5: response REATEL {reatel:02X}h to a SEND -> {code(ev)}",
            "§8.4 Table 8-3; §8.3 Table 8-1 class 09; §2.2.3 Table 2-2", rule, "active-response", "sender",
            iut_block(EX1_CMD, within="STARTUP") + tester_block(response(reatel), note="the error response block"),
            iut=[code(ev)], requests=[LINE1], results=[f"RESULT {LINE1.replace(' ', ':', 1)} STATUS {code(ev)}"],
            provenance="[S]"))
        out.append(vector(
            f"RK512.EX5.REATEL-{reatel:02X}-CONTINUATION",
            f"Example 5: continuation response REATEL {reatel:02X}h -> {code(ev)}, no further frame",
            "§8.4 Table 8-3; §2.2.3 Fig. 2-19", rule + " No further frame of the request follows.",
            "active-response", "sender",
            [receive(f2, within="STARTUP"), prime(response(0)), receive(c2)]
            + tester_block(response(reatel, first=False), note="the error continuation response block"),
            iut=[code(ev)], requests=[two], results=[f"RESULT send:DB10:DW0:LEN=200 STATUS {code(ev)}"],
            provenance="[S][I]"))

    # Example 6: further headers
    out.append(vector(
        "RK512.EX6.DLE-IN-HEADER-AND-DATA.PASSIVE", "Example 6: SEND 10 20 30 10 to DB 16 from DW 16, DLEs doubled",
        "§2.2.2 note (DLE doubling); §2.2.3 Table 2-1",
        "Header bytes 5 and 6 (16 = 10h) and the data DLEs are doubled on the wire; the block's BCC is E4h.",
        "link", "receiver",
        tester_block(header("A", "D", 16, 16, 2) + bytes.fromhex("10203010")) + iut_block(response(0))
        + tester_fetch(header("E", "D", 16, 16, 2), bytes.fromhex("10203010")),
        needs={"db": [16], "db_bytes": 36}, provenance="[S]"))
    for vid, title, line, frame, resp_, results, reads in (
            ("RK512.EX6.SEND-DX.ACTIVE", "Example 6: SEND AB CD to DX 5 ('O' 'D'), BCC 9A", "send DX5:DW0:LEN=2:DATA=ABCD",
             header("O", "D", 5, 0, 1) + b"\xab\xcd", response(0), None, ["AMB-03"]),
            ("RK512.EX6.FLAG-CPU-2.ACTIVE", "Example 6: SEND DE AD with flag 3.5 for CPU 2, BCC 48",
             "send DB10:DW0:LEN=2:CF=3.5:CPU=2:DATA=DEAD", header("A", "D", 10, 0, 1, b9=3, b10=0x25) + b"\xde\xad",
             response(0), None, []),
            ("RK512.EX6.SEND-ODD-LEN.ACTIVE", "Example 6: SEND LEN 11 at offset 7: DW 3, 6 words, pad 00, BCC F9",
             "send DB10:OFF=7:LEN=11:DATA=0102030405060708090A0B", header("A", "D", 10, 3, 6) + bytes(range(1, 12)) + b"\x00",
             response(0), None, []),
            ("RK512.EX6.FETCH-ODD-LEN.ACTIVE", "Example 6: FETCH LEN 5 at offset 6: 3 words asked for, 5 stored, BCC F8",
             "fetch DB10:OFF=6:LEN=5", header("E", "D", 10, 3, 3), response(0, data=bytes.fromhex("A1A2A3A4A5A6")),
             ["FETCHED fetch:DB10:OFF=6:LEN=5 A1A2A3A4A5"], []),
            ("RK512.EX6.FETCH-DX.ACTIVE", "Example 6: FETCH 4 bytes from DX 7, DW 4, BCC EF", "fetch DX7:DW4:LEN=4",
             header("E", "X", 7, 4, 2), response(0, data=bytes.fromhex("01020304")),
             ["FETCHED fetch:DX7:DW4:LEN=4 01020304"], []),
            ("RK512.EX6.FETCH-FLAGS.ACTIVE", "Example 6: FETCH flag bytes MB 20..25, BCC E9", "fetch M:20:LEN=6",
             header("E", "M", 0, 0x14, 6), response(0, data=bytes(6)), ["FETCHED fetch:M:20:LEN=6 000000000000"],
             ["AMB-14"]),
            ("RK512.EX6.FETCH-COUNTERS.ACTIVE", "Example 6: FETCH 10 counters from C 5 ('Z'), BCC E3", "fetch Z:5:LEN=20",
             header("E", "Z", 0, 5, 10), response(0, data=bytes(range(20))),
             ["FETCHED fetch:Z:5:LEN=20 " + bytes(range(20)).hex().upper()], ["AMB-01", "AMB-14"])):
        lab = line.replace(" ", ":", 1)
        out.append(vector(
            vid, title, "§2.2.3 Table 2-1; §6.3.2 Tables 6-4 to 6-8",
            "The requester's header carries the command and type letters, DB/DW or the 16-bit address, the length in "
            "its unit, and bytes 9/10 per the CPU/flag rule.",
            "active-command", "sender", iut_block(frame, within="STARTUP") + tester_block(resp_),
            requests=[line], results=(results or []) + [f"RESULT {lab} OK"], readings=reads, provenance="[S][I]"))
    return out


def sizes():
    out = []
    for typ, cmd, number in (("D", "A", 11), ("X", "O", 8)):
        for n in (1, 10, 128, 129, 200, 1024):
            words = (n + 1) // 2
            data = seq(n) + bytes(2 * words - n)
            out.append(vector(
                f"RK512.SEND.{'DB' if typ == 'D' else 'DX'}-{n}",
                f"SEND of {n} byte{'s' if n > 1 else ''} to {'DB' if typ == 'D' else 'DX'} {number}"
                + (" (padded to whole words)" if n % 2 else ""),
                "§2.2.3 Figs. 2-13, 2-14, Tables 2-1, 2-2; §6.3.2 'Important notes' (odd LEN)",
                "A SEND is answered frame by frame: the first frame 00 00 00 00, every continuation FF 00 00 00, no data.",
                "passive-send", "receiver", tester_send(header(cmd, "D", number, 0, words), data),
                params=BIG, needs={"db" if typ == "D" else "dx": [number], "db_bytes": 2 * words},
                readings=["AMB-03"] if typ == "X" else [], provenance="[S][F]"))
    for typ in "DXEAMTZ":
        for n in (6, 128, 300, 1024):
            number = 10 if typ == "D" else 7 if typ == "X" else 0
            length = n // 2 if typ in "DXTZ" else n
            needs = {"pattern": True}
            if typ in "DX":
                needs.update({"db" if typ == "D" else "dx": [number], "db_bytes": n})
            elif typ in "TZ":
                needs["cell_area_cells"] = n // 2
                if n <= 32:
                    needs["cell_fetch_bytes"] = n   # served by every partner whose limit allows it
            else:
                needs["byte_area_bytes"] = n
            steps = tester_fetch(header("E", typ, number, 0, length), pattern(typ, number, 0, n))
            ref = "§2.2.3 Figs. 2-15, 2-16, Tables 2-1, 2-2; §6.3.2 Table 6-8"
            rule = ("A FETCH is answered with exactly the data asked for, 128 bytes per response and the rest in the "
                    "last, each further chunk after a continuation FETCH.")
            readings, events = ["AMB-14", "AMB-15"] if typ in "EAMTZ" else [], []
            refused = CP341_REFUSALS.get(typ) if typ == "X" or n > 32 else None
            if refused:
                # a CP 341 serves no DX and at most 32 bytes of timers/counters to a partner
                # (§6.3.2 "Providing data", Table 6-10): with the profile silent, its refusal at
                # once (no data; the manual names no number, AMB-20) ends the vector too
                key, reatels, events = refused
                steps[1] = receive(bytes.fromhex(steps[1]["receive"]), alternatives=[response(r) for r in reatels],
                                   alt_grade="informational", or_end=0)
                needs["silent"] = [key]
                readings = readings + ["AMB-20"]
                ref += "; §6.3.2 'Providing data', Table 6-10"
                rule += (" A responder that does not serve it (a CP 341: no DX, at most 32 bytes of timers or "
                         "counters) refuses it at once with an error number and no data.")
            out.append(vector(
                f"RK512.FETCH.{typ}-{n}", f"FETCH of {n} bytes of type '{typ}' from the start of its area",
                ref, rule, "passive-fetch", "receiver", steps, params=BIG, needs=needs, readings=readings,
                optional=events, provenance="[S][F]" if typ == "D" else "[S][I]"))
    return out


def fits(steps) -> dict | None:
    """What the IUT's memory must offer for the first frames the tester primes to be valid
    but for the field a vector is about (whichever field a responder checks first): the DB
    of each frame that names one (type D, or a type letter that is wrong) with the words it
    addresses (bytes 5/6 and 7/8), the flag byte (byte 9) where byte 10 names a flag bit
    (0..7)."""
    dbs, size, flag = set(), 0, 0
    for s in steps:
        f = bytes.fromhex(s["prime"]) if isinstance(s, dict) and "prime" in s else b""
        if len(f) < 10 or f[0] == 0xFF or f[3] in b"XEAMTZ" or not f[4]:
            continue
        dbs.add(f[4])
        size = max(size, 2 * (f[5] + max(1, (f[6] << 8) | f[7])))
        if f[8] != 0xFF and (f[9] & 0x0F) <= 7:
            flag = max(flag, f[8] + 1)
    need = {"db": sorted(dbs), "db_bytes": size} if dbs else {}
    if flag:
        need["byte_area_bytes"] = flag
    return need or None


def class06():
    out = []
    R06 = "§8.3 Table 8-1 {c}; §8.4 Table 8-3 ({r:02X}h)"

    def refuse(c, what, frame, reatel, rule, pre=(), first=True, alternatives=(), optional=(), readings=(),
               needs=None, strict=True, setup=None, params=None):
        out.append(vector(
            f"RK512.ERR06.{c[3:]}", f"{c}: {what}", R06.format(c=c, r=reatel), rule, "passive-header",
            "receiver", list(pre) + [prime(frame), receive(response(reatel, first), alternatives=alternatives,
                                                         alt_grade="informational" if alternatives else None)],
            iut=[c] if strict else [], optional=([] if strict else [c]) + list(optional),
            needs={**(fits(list(pre) + [prime(frame)]) or {}), **(needs or {})} or None,
            readings=readings, setup=setup, params=params, provenance="[S]"))
    first200 = header("A", "D", 11, 0, 100) + seq(128)
    pre = [prime(first200), receive(response(0))]
    refuse("16#0601", "command byte 1 = 01h: REATEL 10h", header("E", "D", 10, 0, 3, b1=0x01), 0x10,
           "A command whose byte 1 is neither 00h nor FFh is refused with REATEL 10h.",
           alternatives=[response(0x10, first=False)], readings=["N1"])
    refuse("16#0602", "command byte 3 = 'C': REATEL 16h", header("C", "D", 10, 0, 3), 0x16,
           "A command letter other than A, O, E is refused with REATEL 16h.", readings=["AMB-04"])
    refuse("16#0603", "continuation byte 3 'O' after 'A': REATEL 16h", continuation("O", "D", seq(72, 0x90)), 0x16,
           "A continuation whose byte 3 differs from the first frame's is refused with REATEL 16h.", pre=pre, first=False)
    refuse("16#0604", "FETCH with type 'Q' (51h): REATEL 10h, doubled", header("E", "Q", 10, 0, 3), 0x10,
           "A data type letter that is not one is refused with REATEL 10h (a DLE, doubled on the wire).")
    refuse("16#0605", "continuation byte 4 'X' after 'D': REATEL 10h", continuation("A", "X", seq(72, 0x90)), 0x10,
           "A continuation whose byte 4 differs from the first frame's is refused with REATEL 10h.", pre=pre, first=False)
    refuse("16#0606", "FETCH from DB 0: REATEL 14h", header("E", "D", 0, 0, 3), 0x14,
           "A DB number that is not permitted is refused with REATEL 14h, without data.")
    refuse("16#0607", "FETCH of timer FFFFh (beyond every timer area): REATEL 0Ch", header("E", "T", 0xFF, 0xFF, 1), 0x0C,
           "A start address beyond the area is refused with REATEL 0Ch.", readings=["AMB-14"],
           alternatives=[response(0, data=pattern("T", 0, 510, 2))], strict=False, needs={"pattern": True})
    refuse("16#0608", "FETCH of length 0: REATEL 34h", header("E", "D", 10, 0, 0), 0x34,
           "A length of 0 is not permitted: REATEL 34h.")
    refuse("16#0609", "FETCH naming flag bit 8: REATEL 0Ch", header("E", "D", 10, 0, 3, b9=0, b10=0x18), 0x0C,
           "A coordination-flag bit above 7 is refused with REATEL 0Ch.")
    refuse("16#060A", "FETCH for CPU 5: REATEL 0Ch", header("E", "D", 10, 0, 3, b10=0x5F), 0x0C,
           "A CPU number that is not permitted is refused with REATEL 0Ch.", readings=["AMB-22"],
           alternatives=[response(0, data=pattern("D", 10, 0, 6))], strict=False, needs={"pattern": True})
    refuse("16#060B", "SEND announcing 10 bytes with 8: REATEL 34h", header("A", "D", 11, 0, 5) + seq(8), 0x34,
           "A SEND frame with fewer data than its header announces is refused with REATEL 34h.")
    refuse("16#060C", "FETCH with 2 data bytes: REATEL 34h", header("E", "D", 10, 0, 3) + b"\x01\x02", 0x34,
           "A FETCH command carries no data; one that does is refused with REATEL 34h.", readings=["AMB-06"])
    refuse("16#060D", "the CPU in STOP: REATEL 2Ah", header("A", "D", 11, 0, 2) + seq(4), 0x2A,
           "A command that arrives while the CPU is in STOP is refused with REATEL 2Ah.", setup="cpu_stop")
    out.append(vector(
        "RK512.ERR06.060E", "16#060E: a continuation with no request open: REATEL 36h",
        R06.format(c="16#060E", r=0x36) + ", 16#0908",
        "A continuation that belongs to no open request is a synchronisation error (16#060E), answered with REATEL "
        "36h, which the requester reports as 16#0908; a responder that stays silent leaves it waiting out T_RES.",
        "passive-header", "receiver",
        [prime(continuation("A", "D", seq(72))), receive(response(0x36, first=False))],
        iut=["16#060E"], readings=["AMB-26"], provenance="[S]"))
    refuse("16#060F", "flag 12.3 set: REATEL 32h", header("A", "D", 11, 0, 2, b9=12, b10=0x13) + seq(4), 0x32,
           "While the named coordination flag is set the request is refused with REATEL 32h.", readings=["AMB-07"],
           setup={"name": "flag_set", "flag": "12.3", "reset_ms": 1000})
    out.append(vector(
        "RK512.ERR06.0610", "16#0610: a 6-byte command; REATEL 34h or no answer (the manual names none)",
        "§8.3 Table 8-1 16#0610; §8.4 Table 8-3 (no REATEL listed)",
        "A command frame shorter than 10 bytes is too short (16#0610); no REATEL is defined for it.",
        "passive-header", "receiver",
        [prime(header("E", "D", 10, 0, 3)[:6]), receive(response(0x34), optional=True, absent_grade="informational",
                                                        alternatives=[response(0x10)], alt_grade="informational")],
        optional=["16#0610", "16#0608", "16#0601"], readings=["AMB-10"], provenance="[S][O]"))
    refuse("16#0611", "continuation with 70 data bytes for 72: REATEL 34h", continuation("A", "D", seq(70, 0x90)), 0x34,
           "A continuation whose data count does not complete the announced length is refused with REATEL 34h.",
           pre=pre, first=False, optional=["16#060B"], readings=["N3"], strict=False)
    # 16#0612: the response cannot be sent (every setup refused by NAK)
    steps = [prime(header("A", "D", 11, 0, 2) + seq(4))]
    for i in range(6):
        steps += [expect([STX], within="TRES" if i == 0 else "ADT", note=f"the response's setup, attempt {i + 1}"),
                  send([NAK], note="refused")]
    steps += [expect([NAK], note="the IUT gives up (3964R: NAK)")]
    out.append(vector(
        "RK512.ERR06.0612", "16#0612: the response is refused by the link every time: the IUT gives up",
        "§8.3 Table 8-1 16#0612, 16#0709; §2.2.2 'Connection setup for sending', Fig. 2-10",
        "When the link cannot deliver the response (setup attempts exhausted) the responder reports 16#0612 after the link's event.",
        "passive-header", "receiver", steps, iut=["16#0612", "16#0702|16#0709"], optional=["16#0701"],
        params={"setup_attempts": 6}, binds=("link", "setup_attempts"), needs=fits(steps), provenance="[S]"))
    return out


def class0a():
    out = []
    fetch6 = header("E", "D", 10, 0, 3)
    two = header("A", "D", 10, 0, 100) + seq(200)[:128]
    for c, what, line, steps, readings in (
            ("16#0A01", "a continuation response FF 00 00 00 to a first command", LINE1,
             [receive(EX1_CMD, within="STARTUP"), prime(response(0, first=False))], []),
            ("16#0A02", "a response whose byte 1 is 01h", LINE1,
             [receive(EX1_CMD, within="STARTUP"), prime(bytes([1, 0, 0, 0]))], []),
            ("16#0A03", "a FETCH response with 5 of 6 data bytes", "fetch DB10:DW0:LEN=6",
             [receive(fetch6, within="STARTUP"), prime(response(0, data=bytes(5)))], []),
            ("16#0A04", "a SEND response with a data byte", LINE1,
             [receive(EX1_CMD, within="STARTUP"), prime(response(0, data=b"\x00"))], []),
            ("16#0A05", "no response within T_RES", "send DB10:DW0:LEN=200",
             [receive(two, within="STARTUP"), {"silence": "TRES + 2*ADT", "note": "no response, no continuation"}],
             ["AMB-02", "AMB-17"])):
        label = line.replace(" ", ":", 1)
        out.append(vector(
            f"RK512.ERR0A.{c[3:]}", f"{c}: {what}", "§8.3 Table 8-1 class 0A; §2.2.3 Table 2-2, Fig. 2-18",
            f"The requester reports {c} for {what} and ends the request.", "active-response", "sender",
            steps + [{"silence": "2*ADT", "note": "nothing more of this request"}],
            iut=[c], requests=[line], results=[f"RESULT {label} STATUS {c}"], readings=readings, provenance="[S]"))
    return out


def duplex_timing_dle():
    out = []
    own = header("A", "D", 10, 0, 2) + bytes([1, 2, 3, 4])
    theirs = header("A", "D", 11, 8, 2) + bytes([0x55, 0x66, 0x77, 0x88])
    line = "send DB10:DW0:LEN=4:DATA=01020304"
    out.append(vector(
        "RK512.QFD.CROSSING-IUT-LOW", "Quasi-full-duplex crossing: the IUT (low) yields, serves, then sends its SEND",
        "§2.2.3 'Quasi-full-duplex', Fig. 2-17; §2.2.2 'Initialization conflict', Fig. 2-8",
        "When both stations' STX cross, the low-priority IUT answers the tester's, takes its SEND and answers it, and "
        "sends its own SEND as well; both requests end once.",
        "quasi-full-duplex", "both",
        [expect([STX], within="STARTUP", note="the IUT's STX"), send([STX], note="the tester's STX crosses it"),
         expect([DLE], note="the IUT (low) yields"), send(body(theirs), note="the tester's SEND"), expect([DLE]),
         receive(own, alternatives=[response(0)], note="its own SEND or its response first"),
         receive(response(0), alternatives=[own]), prime(response(0))],
        requests=[line], results=[f"RESULT {line.replace(' ', ':', 1)} OK"], optional=["16#0702", "16#0701"],
        params={"priority": "low"}, binds=("link", "priority"), readings=["AMB-31"], provenance="[S][F]",
        needs={"db": [11], "db_bytes": 20, "setup_attempts": 2}))
    out.append(vector(
        "RK512.QFD.TESTER-SEND-WHILE-WAITING", "The tester SENDs while the IUT waits for its response",
        "§2.2.3 'Quasi-full-duplex', Fig. 2-17",
        "A station that waits for its response still serves the partner's command, then takes its own response.",
        "quasi-full-duplex", "both",
        [receive(own, within="STARTUP"), prime(theirs), receive(response(0)), prime(response(0))],
        requests=[line], results=[f"RESULT {line.replace(' ', ':', 1)} OK"], needs={"db": [11], "db_bytes": 20},
        provenance="[S][F]"))
    two = "send DB10:DW0:LEN=200"
    out.append(vector(
        "RK512.TRES.ACTIVE-EXPIRY", "T_RES at the requester: no response, 16#0A05, the continuation never sent",
        "§2.2.3 Fig. 2-18 ('T > T_RES'); §8.3 Table 8-1 16#0A05, 16#0A01",
        "Without a response within T_RES the request fails with 16#0A05; a response after that answers nothing.",
        "active-timing", "sender",
        [receive(header("A", "D", 10, 0, 100) + seq(200)[:128], within="STARTUP"),
         {"silence": "TRES + 2*ADT"}, prime(response(0), note="too late"), {"silence": "2*ADT"}],
        iut=["16#0A05"], optional=["16#0A01"], requests=[two], results=["RESULT send:DB10:DW0:LEN=200 STATUS 16#0A05"],
        readings=["AMB-02", "AMB-17"], provenance="[S][F]"))
    first = header("A", "D", 11, 0, 65) + seq(128)
    out.append(vector(
        "RK512.TRES.PASSIVE-EXPIRY", "T_RES at the responder: the continuation after T_RES finds no request (36h)",
        "§2.2.3 Fig. 2-19 ('T > T_RES: abort with error'); §8.3 Table 8-1 16#060E",
        "After T_RES without the continuation the responder aborts the request; a continuation after that is a sequence error.",
        "passive-timing", "receiver",
        [prime(first), receive(response(0)), {"wait": "TRES + 2*ADT"}, prime(continuation("A", "D", seq(2, 0x90))),
         receive(response(0x36, first=False), optional=True, absent_grade="informational")],
        optional=["16#0A05", "16#060E"], needs={"db": [11], "db_bytes": 130}, readings=["AMB-18"], provenance="[F][I]"))
    d16 = bytes([0x10, 0x20, 0x30, 0x10]) * 8
    out.append(vector(
        "RK512.DLE.HEADER", "DLE doubling in the header: DB 16, DW 16, 16 words (10h in bytes 5, 6 and 8)",
        "§2.2.2 note (DLE doubling); §2.2.3 Table 2-1",
        "Header bytes that are 10h are doubled like data; the receiver stores one.", "link", "receiver",
        tester_block(header("A", "D", 16, 16, 16) + d16) + iut_block(response(0)),
        needs={"db": [16], "db_bytes": 64}, provenance="[S]"))
    out.append(vector(
        "RK512.DLE.DATA", "DLE doubling in FETCH data: the IUT doubles every data DLE it sends",
        "§2.2.2 note (DLE doubling)", "Data bytes 10h in the IUT's response go out doubled.", "link", "receiver",
        tester_send(header("A", "D", 16, 16, 16), d16) + tester_block(header("E", "D", 16, 16, 16))
        + iut_block(response(0, data=d16)), needs={"db": [16], "db_bytes": 64}, provenance="[S]"))
    out.append(vector(
        "RK512.DLE.REATEL", "DLE doubling in the REATEL: 00 00 00 10 10 DLE ETX (Example 5)",
        "§2.2.2 note; §8.4 Table 8-3 (10h)", "An error number 10h is doubled in the response block.", "link", "receiver",
        tester_block(header("E", "Q", 10, 0, 3)) + iut_block(response(0x10)), iut=["16#0604"], provenance="[S]"))
    # a tester frame with BCC 10h, and a response of the IUT with BCC 10h (input byte 195 = 03h)
    base = header("A", "D", 11, 0, 1)
    x = body(base + b"\x00\x00")[-1] ^ 0x10
    frame = base + bytes([x, 0])
    assert body(frame)[-1] == 0x10 and x != DLE
    out.append(vector(
        "RK512.DLE.BCC", "A BCC of 10h in both directions: sent once, never doubled",
        "§2.2.2 Fig. 2-4 and note (BCC)", "A BCC equal to 10h follows DLE ETX once; it is not doubled.", "link",
        "receiver",
        tester_block(frame) + iut_block(response(0)) + tester_block(header("E", "E", 0, 0xC3, 1))
        + iut_block(response(0, data=b"\x03")),
        needs={"db": [11], "byte_area_bytes": 196, "pattern": True}, provenance="[S][I]"))
    return out


def all_vectors() -> list[dict]:
    out = examples() + sizes() + class06() + class0a() + duplex_timing_dle()
    for v in out:
        v["rules"] = rules_for(file_name(v).removesuffix(".toml"))
    return out


def file_name(v: dict) -> str:
    return v["id"].removeprefix("RK512.").lower().replace(".", "-") + ".toml"


def render(v: dict) -> str:
    from ptpcert.scenario import dump_vector, vector_from_dict
    return dump_vector(vector_from_dict(v, v["id"]))


def write() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    names = set()
    for v in all_vectors():
        name = file_name(v)
        names.add(name)
        (OUT / name).write_text(render(v), "utf-8")
    for f in OUT.glob("*.toml"):
        if f.name not in names:
            f.unlink()
    return len(names)


if __name__ == "__main__":
    if "--write" in sys.argv:
        print(f"{write()} vectors written to {OUT}")
    else:
        print(f"{len(all_vectors())} vectors (--write to write them)")
