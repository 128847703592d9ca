"""The Wireshark dissector (harness/capture/wireshark/ptpcert.lua, docs/wireshark.md) run by
Debian's tshark on the captures of three short runs in virtual time (3964R, RK 512, ASCII).

Each run's decoded fields are compared with a golden file (tests/core/data/wireshark/), and
the golden file is tied to the rules: every decoded block, put back on the line by the rules
of §2.2.2 (DLE doubled, DLE ETX, BCC = XOR), is the bytes its seat sent after its STX; the
blocks of the tester are what the cases sent; every RK 512 field is the header byte Table 2-1
puts there; REATEL meanings name Table 8-3's event; ASCII frames are the data between the end
characters the case's parameters give, without XON/XOFF. A corrupted BCC is flagged.

Regenerate the golden files (after a deliberate change of the dissector) with
PTPCERT_UPDATE_GOLDEN=1; the rule checks still have to pass on them.
"""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
import subprocess
from functools import reduce
from pathlib import Path

import pytest

from ptpcert import capture as C
from ptpcert.capture.wireshark_plugin import plugin_path
from ptpcert.cli.main import main as cli_main

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).parent / "data" / "wireshark"
PROFILES = ROOT / "conformance" / "profiles"
TSHARK = shutil.which("tshark")
needs_tshark = pytest.mark.skipif(TSHARK is None, reason="tshark is not installed (apt-get install tshark)")

#: the runs: a bundled profile, changes to it (old text -> new text), and a few cases
RUNS = {
    "3964r": ("reference-20ms.toml", {}, [
        "SUITE.FRAME.PROFILE-FRAME",            # a block and its echo
        "SUITE.RECEIVE.UNDOUBLE-RUN",           # DLE doubled in the data
        "SUITE.RECEIVE.BCC-OFF-BY-ONE-BIT",     # the tester's wrong BCC, refused with NAK
        "SUITE.RECEIVE.BCC-EQUALS-DLE",         # a BCC of 10h, not doubled
        "SUITE.SEND.NAK-DURING-DATA",           # a block the receiver breaks off
        "SUITE.SEND.OTHER-DURING-DATA",         # a block another character interrupts
    ]),
    "3964": ("reference-20ms.toml", {'procedure = "3964R"': 'procedure = "3964"'}, [
        "3964.FIG2-5.SEND", "3964.FIG2-6.RECEIVE",   # blocks without BCC
    ]),
    "rk512": ("rk512-reference.toml", {}, [
        "RK512.EX1.SEND-10.PASSIVE",            # the manual's Example 1 (Fig. 2-13 header)
        "RK512.EX4.FETCH-300.PASSIVE",          # continuation commands and responses
        "RK512.EX5.REATEL-10",                  # REATEL 10h, doubled on the line
        "RK512.EX5.REATEL-14-CONTINUATION",
        "SUITE.RK512.L-03.BCC-WRONG-NOT-ACTED-ON",
    ]),
    "ascii": ("ascii-reference.toml", {}, [
        "SUITE.ASCII.EC.BACK-TO-BACK",          # one end character, frames back to back
        "SUITE.ASCII.EC.LONE-END",
        "SUITE.ASCII.FC.CODES-NOT-DATA",        # XON/XOFF
        "SUITE.ASCII.FC.XOFF-AFTER-FIRST",
    ]),
    "ascii-pair": ("ascii-reference.toml", {"end_chars = [0x03]": "end_chars = [0x0D, 0x0A]"}, [
        "ASCII.RX-EC2-01.PAIR", "ASCII.RX-EC2-02.LONE-FIRST-IS-DATA",   # two end characters
    ]),
    "ascii-cdt": ("ascii-reference.toml", {'end_criterion = "end_chars"': 'end_criterion = "cdt"'}, [
        "ASCII.RX-CDT-01.ONE-FRAME", "ASCII.RX-CDT-02.TWO-FRAMES", "ASCII.RX-CDT-03.GAP-MERGES",
    ]),
    "ascii-fixed": ("ascii-reference.toml", {'end_criterion = "end_chars"': 'end_criterion = "fixed_length"',
                                             "fixed_length = 240": "fixed_length = 5"}, [
        "ASCII.RX-FL-01.EXACT", "ASCII.RX-FL-02.BACK-TO-BACK",
    ]),
}

FIELDS = [
    "frame.number", "frame.time_relative", "rtacser.eventtype", "data.data", "ptpcert.seat", "ptpcert.mark", "ptpcert.char",
    "ptpcert.condition", "ptpcert.block", "ptpcert.block.seat", "ptpcert.block.end", "ptpcert.block.bcc", "ptpcert.block.bcc_computed",
    "ptpcert.block.bcc_ok", "ptpcert.rk512.kind", "ptpcert.rk512.byte1", "ptpcert.rk512.byte2",
    "ptpcert.rk512.command", "ptpcert.rk512.type", "ptpcert.rk512.address_high", "ptpcert.rk512.address_low",
    "ptpcert.rk512.length", "ptpcert.rk512.length_unit", "ptpcert.rk512.cf_byte", "ptpcert.rk512.cpu",
    "ptpcert.rk512.cf_bit", "ptpcert.rk512.reatel", "ptpcert.rk512.reatel_meaning", "ptpcert.rk512.data",
    "ptpcert.ascii.frame", "ptpcert.ascii.seat", "ptpcert.ascii.end", "ptpcert.ascii.flow",
]
STX, DLE, ETX = 0x02, 0x10, 0x03


def tshark_fields(pcap: Path, *, two_pass: bool = False) -> list[dict[str, str]]:
    cmd = [TSHARK, "-n", "-X", f"lua_script:{plugin_path()}", "-r", str(pcap), "-T", "fields", "-E", "header=n",
           "-E", "aggregator=|"]
    if two_pass:
        cmd.insert(1, "-2")
    for f in FIELDS:
        cmd += ["-e", f]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "Lua: Error" not in p.stderr, p.stderr
    rows = [dict(zip(FIELDS, line.split("\t"))) for line in p.stdout.splitlines()]
    for r in rows:   # tshark 4.0 writes booleans 1/0, later versions True/False
        r["ptpcert.block.bcc_ok"] = {"True": "1", "False": "0"}.get(r["ptpcert.block.bcc_ok"],
                                                                   r["ptpcert.block.bcc_ok"])
    return rows


def row_text(row: dict[str, str]) -> str:
    """A row of a golden file: the raw data of status records (the start record, marks) left
    out (ptpcert.note and ptpcert.mark say it)."""
    return "\t".join("" if f == "data.data" and row["rtacser.eventtype"] == "0x00" else row[f] for f in FIELDS)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Each run's pcap, results and tshark's rows (single pass)."""
    out = {}
    for name, (profile, changes, cases) in RUNS.items():
        d = tmp_path_factory.mktemp(name)
        pcap, js = d / "run.pcap", d / "run.json"
        text = (PROFILES / profile).read_text()
        for old, new in changes.items():
            assert old in text
            text = text.replace(old, new)
        (d / profile).write_text(text)
        argv = ["run", "--iut", "sim:", "--profile", str(d / profile), "--pcap", str(pcap),
                "--json", str(js), "-q"]
        for c in cases:
            argv += ["--select", c]
        assert cli_main(argv) == 0
        results = json.loads(js.read_text())
        assert sorted(c["id"] for c in results["cases"]) == sorted(cases)
        assert {c["verdict"] for c in results["cases"]} == {"pass"}, name
        out[name] = {"pcap": pcap, "results": results, "rows": tshark_fields(pcap) if TSHARK else None}
    return out


# ----------------------------------------------------------------------------- the rules, in the test

def bcc_of(body: bytes) -> int:
    return reduce(lambda a, b: a ^ b, body, 0)


def on_the_line(data: bytes, with_bcc: bool) -> bytes:
    """§2.2.2: every DLE of the data doubled, then DLE ETX, then (3964R) the BCC: the XOR of
    every byte after STX up to and including DLE ETX."""
    body = data.replace(b"\x10", b"\x10\x10") + bytes([DLE, ETX])
    return body + (bytes([bcc_of(body)]) if with_bcc else b"")


def seat_streams(rows):
    """What each seat put on the line, byte by byte with its frame number (from the RTAC
    dissector's raw data, not ours)."""
    streams = {"a": [], "b": []}
    for r in rows:
        if r["rtacser.eventtype"] in ("0x01", "0x02", "0x07", "0x08") and r["data.data"]:
            seat = "a" if r["rtacser.eventtype"] == "0x01" else ("b" if r["rtacser.eventtype"] == "0x02"
                                                                 else r["ptpcert.seat"])
            streams[seat] += [(int(r["frame.number"]), b) for b in bytes.fromhex(r["data.data"])]
    return streams


def case_of_rows(rows, results):
    """Each row's case and that case's result: the last case mark before it (a mark's own
    record shows what the case before it left unfinished)."""
    by_id = {c["id"]: c for c in results["cases"]}
    current = None
    for r in rows:
        yield r, current
        if r["ptpcert.mark"].startswith("case "):
            current = by_id[r["ptpcert.mark"].split()[1]]


def has_bcc(case) -> bool:
    p = case["params"]
    return (p.get("link") or p.get("procedure")) == "3964R"


def sent_by_tester(case) -> bytes:
    return bytes.fromhex(" ".join(s["data"] for s in case["steps"] if s["kind"] in ("send", "send_error")))


def check_blocks(rows, results) -> list[dict]:
    """Every decoded block against §2.2.2; returns the blocks."""
    streams = seat_streams(rows)
    blocks = []
    for r, case in case_of_rows(rows, results):
        if not r["ptpcert.block.end"]:
            continue
        seat, frame = r["ptpcert.block.seat"], int(r["frame.number"])
        data = bytes.fromhex(r["ptpcert.block"])
        assert r["ptpcert.char"] in ("BCC", "ETX (end of block)", "NAK (block aborted by the receiver)",
                                     "after DLE: logic error") or r["ptpcert.char"].endswith(
            ("data", "(interrupts the partner's block)"))
        if r["ptpcert.block.end"] != "DLE ETX":
            blocks.append({"row": r, "case": case, "data": data, "complete": False})
            continue
        sent = bytes(b for k, b in streams[seat] if k <= frame)
        line = on_the_line(data, has_bcc(case))
        n = len(line)
        assert sent[-n:-1] == line[:-1], f"frame {frame}: the block is not what seat {seat} sent"
        assert sent[-n - 1] == STX, f"frame {frame}: the block does not follow its sender's STX"
        if has_bcc(case):
            assert int(r["ptpcert.block.bcc"], 16) == sent[-1]
            assert int(r["ptpcert.block.bcc_computed"], 16) == line[-1]
            assert r["ptpcert.block.bcc_ok"] == ("1" if sent[-1] == line[-1] else "0")
        else:
            assert sent[-1] == ETX and r["ptpcert.block.bcc"] == "" and r["ptpcert.block.bcc_ok"] == ""
        if seat == "a":     # the tester's blocks are what the case sent
            assert sent[-n - 1:-1] + sent[-1:] in sent_by_tester(case)
        blocks.append({"row": r, "case": case, "data": data, "complete": True, "bcc_ok": sent[-1] == line[-1]})
    return blocks


def compare_golden(name: str, rows) -> None:
    text = "".join(row_text(r) + "\n" for r in rows)
    path = GOLDEN / f"{name}.tsv"
    if os.environ.get("PTPCERT_UPDATE_GOLDEN"):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    assert path.read_text(encoding="utf-8") == text, f"tshark's fields differ from {path}"


# ----------------------------------------------------------------------------- 3964R

@needs_tshark
def test_3964r_blocks_are_decoded_by_the_rules(runs):
    run = runs["3964r"]
    rows = run["rows"]
    compare_golden("3964r", rows)
    blocks = check_blocks(rows, run["results"])
    complete = [b for b in blocks if b["complete"]]
    cases_with_blocks = {b["case"]["id"] for b in complete}
    assert cases_with_blocks >= {"SUITE.FRAME.PROFILE-FRAME", "SUITE.RECEIVE.UNDOUBLE-RUN",
                                 "SUITE.RECEIVE.BCC-EQUALS-DLE"}
    # the doubled DLEs are undoubled: the decoded data hold 10h once per pair on the line
    assert any(DLE in b["data"] for b in complete if b["case"]["id"] == "SUITE.RECEIVE.UNDOUBLE-RUN")
    # the case with a wrong BCC: exactly its tester's block is flagged, every other block is good
    bad = [b for b in complete if not b["bcc_ok"]]
    assert bad and {(b["case"]["id"], b["row"]["ptpcert.block.seat"]) for b in bad} == {
        ("SUITE.RECEIVE.BCC-OFF-BY-ONE-BIT", "a")}
    # blocks the receiver broke off (NAK) or interrupted (another character) are shown as such;
    # the IUT's repetition after it is whole, and no block of the reference IUT has a wrong BCC
    ends = {(b["case"]["id"], b["row"]["ptpcert.block.seat"], b["row"]["ptpcert.block.end"])
            for b in blocks if not b["complete"]}
    assert {("SUITE.SEND.NAK-DURING-DATA", "b", "aborted by NAK"),
            ("SUITE.SEND.OTHER-DURING-DATA", "b", "interrupted by the partner")} <= ends
    for case in ("SUITE.SEND.NAK-DURING-DATA", "SUITE.SEND.OTHER-DURING-DATA"):
        assert any(b["complete"] and b["row"]["ptpcert.block.seat"] == "b" for b in blocks if b["case"]["id"] == case)
    # the case marks and the 3964 control characters are named
    marks = [r["ptpcert.mark"] for r in rows if r["ptpcert.mark"].startswith("case ")]
    assert [m.split()[1] for m in marks] == [c["id"] for c in run["results"]["cases"]]
    chars = {c for r in rows for c in r["ptpcert.char"].split("|")}
    assert {"STX (connection setup)", "DLE (ready to receive)", "DLE (block accepted)", "BCC",
            "DLE (doubled: data 10)", "ETX (end of block)"} <= chars
    assert any(c.startswith("NAK") for c in chars)


@needs_tshark
def test_3964_blocks_without_bcc(runs):
    run = runs["3964"]
    compare_golden("3964", run["rows"])
    blocks = check_blocks(run["rows"], run["results"])
    assert {b["row"]["ptpcert.block.seat"] for b in blocks if b["complete"]} == {"a", "b"}
    assert all(b["row"]["ptpcert.char"] == "ETX (end of block)" for b in blocks if b["complete"])


@needs_tshark
def test_a_corrupted_bcc_is_flagged(runs, tmp_path):
    """Every good BCC of the run turned wrong on the line: each of those blocks is flagged
    (bcc_ok 0, the expert info), the data are decoded all the same."""
    run = runs["3964r"]
    cap = C.load(run["pcap"])
    good = [b for b in check_blocks(run["rows"], run["results"]) if b["complete"] and b.get("bcc_ok")
            and has_bcc(b["case"])]
    assert good
    # the records are the capture's chunks in order after the start record and the marks
    frames = {int(b["row"]["frame.number"]) for b in good}
    rows = run["rows"]
    chunk_frames = [int(r["frame.number"]) for r in rows if r["rtacser.eventtype"] in ("0x01", "0x02")]
    data_chunks = [c for c in cap.chunks if c.condition is None]
    assert len(chunk_frames) == len(data_chunks)
    flipped = {id(c): dataclasses.replace(c, data=c.data[:-1] + bytes([c.data[-1] ^ 0x01]))
               for k, c in zip(chunk_frames, data_chunks) if k in frames}
    cap.chunks = [flipped.get(id(c), c) for c in cap.chunks]
    bad_pcap = tmp_path / "bad.pcap"
    C.save(cap, bad_pcap)
    flagged = {int(r["frame.number"]): r for r in tshark_fields(bad_pcap) if r["ptpcert.block.bcc_ok"] == "0"}
    assert set(flagged) >= frames
    for k in frames:
        r = flagged[k]
        assert int(r["ptpcert.block.bcc"], 16) == int(r["ptpcert.block.bcc_computed"], 16) ^ 0x01
    p = subprocess.run([TSHARK, "-n", "-X", f"lua_script:{plugin_path()}", "-r", str(bad_pcap), "-Y",
                        "ptpcert.block.bcc_bad", "-T", "fields", "-e", "frame.number"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert {int(x) for x in p.stdout.split()} >= frames


@needs_tshark
def test_one_pass_and_two_passes_give_the_same_fields(runs):
    for name, run in runs.items():
        assert tshark_fields(run["pcap"], two_pass=True) == run["rows"], name


# ----------------------------------------------------------------------------- RK 512

@needs_tshark
def test_rk512_telegrams_are_decoded_field_by_field(runs):
    from ptpcert.procedures.rk512.model.codec import status_for_reatel

    run = runs["rk512"]
    rows = run["rows"]
    compare_golden("rk512", rows)
    kinds = set()
    for b in check_blocks(rows, run["results"]):
        r, d = b["row"], b["data"]
        if not b["complete"]:
            continue
        kind = r["ptpcert.rk512.kind"]
        kinds.add(kind)
        # Table 2-1 / 2-2: bytes 1 and 2 are the frame ID; byte 3 = 00h is a response
        assert int(r["ptpcert.rk512.byte1"], 16) == d[0] and int(r["ptpcert.rk512.byte2"], 16) == d[1]
        if d[2] == 0:
            assert kind == {0x00: "response", 0xFF: "continuation response"}[d[0]]
            assert int(r["ptpcert.rk512.reatel"], 16) == d[3]
            meaning = r["ptpcert.rk512.reatel_meaning"]
            assert meaning == "no error" if d[3] == 0 else meaning.endswith(f"({status_for_reatel(d[3]):04X}H)")
            assert bytes.fromhex(r["ptpcert.rk512.data"]) == d[4:]
        elif d[0] == 0xFF:
            assert kind == "continuation command"
            assert (int(r["ptpcert.rk512.command"], 16), int(r["ptpcert.rk512.type"], 16)) == (d[2], d[3])
            assert bytes.fromhex(r["ptpcert.rk512.data"]) == d[4:]
        else:
            assert kind == "command"
            assert (int(r["ptpcert.rk512.command"], 16), int(r["ptpcert.rk512.type"], 16)) == (d[2], d[3])
            assert int(r["ptpcert.rk512.address_high"]) == d[4] and int(r["ptpcert.rk512.address_low"]) == d[5]
            assert int(r["ptpcert.rk512.length"]) == d[6] << 8 | d[7]
            assert r["ptpcert.rk512.length_unit"] == ("words" if chr(d[3]) in "DXTZ" else "bytes")
            assert int(r["ptpcert.rk512.cf_byte"], 16) == d[8]
            assert int(r["ptpcert.rk512.cpu"], 16) == d[9] >> 4 and int(r["ptpcert.rk512.cf_bit"], 16) == d[9] & 15
            assert bytes.fromhex(r["ptpcert.rk512.data"]) == d[10:]
    assert kinds == {"command", "response", "continuation command", "continuation response"}
    # the manual's Example 1 (§2.2.3, Fig. 2-13): SEND to DB 10 from DW 0, 5 words, no flag, CPU 1
    ex1 = [b for b in check_blocks(rows, run["results"])
           if b["case"]["id"] == "RK512.EX1.SEND-10.PASSIVE" and b["row"]["ptpcert.rk512.kind"] == "command"]
    assert [b["data"].hex(" ") for b in ex1] == ["00 00 41 44 0a 00 00 05 ff 1f 11 22 33 44 55 66 77 88 99 aa"]
    assert ex1[0]["row"]["ptpcert.block.bcc"] == "0x42"
    # REATEL 10h, doubled on the line, is one byte 10h of a response
    r10 = [b["row"] for b in check_blocks(rows, run["results"])
           if b["case"]["id"] == "RK512.EX5.REATEL-10" and b["row"]["ptpcert.rk512.reatel"]]
    assert [r["ptpcert.rk512.reatel"] for r in r10] == ["0x10"]
    assert r10[0]["ptpcert.rk512.reatel_meaning"].startswith("header error in byte 1 or byte 4")


#: the manual's worked examples (§2.2.3 Figs. 2-13...2-16 and the examples derived from
#: them; §2.2.2 Fig. 2-4), as blocks on the line after STX and what their fields must be
EXAMPLES = [
    # Example 1: SEND to DB 10 from DW 0, 5 words, no coordination flag, CPU 1; BCC 42h
    ("00 00 41 44 0A 00 00 05 FF 1F 11 22 33 44 55 66 77 88 99 AA 10 03 42",
     {"kind": "command", "command": "0x41", "type": "0x44", "address_high": "10", "address_low": "0",
      "length": "5", "length_unit": "words", "cf_byte": "0xff", "cpu": "0x01", "cf_bit": "0x0f",
      "data": "112233445566778899aa"}),
    # Example 6: coordination flag byte 3, bit 5, CPU 2
    ("00 00 41 44 0A 00 00 01 03 25 DE AD 10 03 48",
     {"kind": "command", "cf_byte": "0x03", "cpu": "0x02", "cf_bit": "0x05", "data": "dead"}),
    # Example 6: FETCH 6 flag bytes MB 20...25: a length in bytes
    ("00 00 45 4D 00 14 00 06 FF 1F 10 03 E9",
     {"kind": "command", "command": "0x45", "type": "0x4d", "address_low": "20", "length": "6",
      "length_unit": "bytes", "data": ""}),
    # Example 4: a continuation FETCH and a continuation response
    ("FF 00 45 44 10 03 ED", {"kind": "continuation command", "byte1": "0xff", "command": "0x45", "type": "0x44"}),
    ("FF 00 00 00 10 03 EC", {"kind": "continuation response", "byte1": "0xff", "reatel": "0x00", "data": ""}),
    # Example 5: REATEL 10h, doubled on the line; REATEL 14h
    ("00 00 00 10 10 10 03 13", {"kind": "response", "reatel": "0x10", "data": ""}),
    ("00 00 00 14 10 03 07", {"kind": "response", "reatel": "0x14", "data": ""}),
]


@needs_tshark
@pytest.mark.parametrize("how", ["preference", "parameters note"])
def test_the_manuals_examples(tmp_path, how):
    """The manual's blocks in a capture of another recorder (no ptpcert notes): decoded as RK 512
    by the preference, or by a parameters note; every field as the example says."""
    lines = []
    t = 0.0
    for block, _ in EXAMPLES:
        lines += [f"{t + 0.001:.6f} a 02", f"{t + 0.002:.6f} b 10", f"{t + 0.003:.6f} a {block}",
                  f"{t + 0.004:.6f} b 10"]
        t += 0.1
    head = ['# note: parameters {"link":"3964R","cdt_ms":100}'] if how == "parameters note" else []
    (tmp_path / "ex.hexlog").write_text("\n".join(head + lines) + "\n")
    assert cli_main(["capture", "convert", str(tmp_path / "ex.hexlog"), str(tmp_path / "ex.pcap")]) == 0
    cmd = [TSHARK, "-n", "-X", f"lua_script:{plugin_path()}", "-r", str(tmp_path / "ex.pcap"), "-T", "fields",
           "-E", "aggregator=|", "-Y", "ptpcert.block"]
    pref = ["-o", "ptpcert.procedure:RK 512 on 3964R"] if how == "preference" else []
    keys = ["kind", "byte1", "command", "type", "address_high", "address_low", "length", "length_unit", "cf_byte",
            "cpu", "cf_bit", "reatel", "reatel_meaning", "data"]
    for k in ["ptpcert.block.bcc_ok", *(f"ptpcert.rk512.{k}" for k in keys)]:
        cmd += ["-e", k]
    p = subprocess.run(cmd + pref, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    rows = [line.split("\t") for line in p.stdout.splitlines()]
    assert len(rows) == len(EXAMPLES)
    for row, (block, want) in zip(rows, EXAMPLES):
        assert row[0] in ("1", "True"), block   # every example's BCC is right
        got = dict(zip(keys, row[1:]))
        for k, v in want.items():
            assert got[k] == v, (block, k)
    assert rows[-1][keys.index("reatel_meaning") + 1].startswith("DB/DX does not exist")
    # without the preference nor a note, nothing says which procedure: no decoding
    if how == "preference":
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        assert p.returncode == 0 and p.stdout == ""


@needs_tshark
def test_the_3964r_example_of_the_manual(tmp_path):
    """§2.2.2 Fig. 2-4: the data 30 31 32 go on the line as 02 | 30 31 32 10 03 20."""
    (tmp_path / "x.hexlog").write_text("0.001 a 02\n0.002 b 10\n0.003 a 30 31 32 10 03 20\n0.004 b 10\n")
    assert cli_main(["capture", "convert", str(tmp_path / "x.hexlog"), str(tmp_path / "x.pcap")]) == 0
    p = subprocess.run([TSHARK, "-n", "-X", f"lua_script:{plugin_path()}", "-o", "ptpcert.procedure:3964R",
                        "-r", str(tmp_path / "x.pcap"), "-T", "fields", "-e", "ptpcert.char", "-e", "ptpcert.block",
                        "-e", "ptpcert.block.bcc_computed", "-E", "aggregator=|"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    rows = [line.split("\t") for line in p.stdout.splitlines()]
    assert rows[1:] == [["STX (connection setup)", "", ""], ["DLE (ready to receive)", "", ""],
                        ["data|data|data|DLE|ETX (end of block)|BCC", "303132", "0x20"],
                        ["DLE (block accepted)", "", ""]]


# ----------------------------------------------------------------------------- ASCII

def frames_by_rule(sent: list[tuple[float, int]], params: dict, char_time: float) -> list[bytes]:
    """The frames of one seat's characters (time, byte) as the ASCII driver's receive
    criterion cuts them (§2.2.4), without XON/XOFF: at the end character(s), at the fixed
    length, or where the line was idle for the CDT or longer."""
    flow = {params["xon"], params["xoff"]} if params["flow_control"] == "xon_xoff" else set()
    frames, cur, last = [], b"", None
    for t, b in sent:
        if b in flow:
            continue
        if cur and params["end_criterion"] == "cdt" and t - last - char_time >= params["cdt_ms"] / 1000 - 1e-9:
            frames.append(cur)
            cur = b""
        cur, last = cur + bytes([b]), t
        if params["end_criterion"] == "end_chars" and cur.endswith(bytes(params["end_chars"])):
            frames.append(cur)
            cur = b""
        elif params["end_criterion"] == "fixed_length" and len(cur) == params["fixed_length"]:
            frames.append(cur)
            cur = b""
    return frames + ([cur] if cur and params["end_criterion"] == "cdt" else [])


@needs_tshark
@pytest.mark.parametrize("name", [n for n in RUNS if n.startswith("ascii")])
def test_ascii_frames_end_where_the_parameters_say(runs, name):
    run = runs[name]
    rows = run["rows"]
    compare_golden(name, rows)
    seen, sent = {}, {}
    char_time = C.load(run["pcap"]).timing.char_time
    for r, case in case_of_rows(rows, run["results"]):
        if case is None:
            continue
        for frame, seat, end in zip(*(r[f"ptpcert.ascii.{k}"].split("|") for k in ("frame", "seat", "end"))):
            if frame:
                seen.setdefault((case["id"], seat), []).append((bytes.fromhex(frame), end))
        if r["rtacser.eventtype"] in ("0x01", "0x02"):
            for b in bytes.fromhex(r["data.data"]):
                sent.setdefault((case["id"], r["ptpcert.seat"]), []).append((float(r["frame.time_relative"]), b))
        for label, b in zip(r["ptpcert.ascii.flow"].split("|"), bytes.fromhex(r["data.data"] or "")):
            if label:   # XON/XOFF named where the parameters say
                p = case["params"]
                assert p["flow_control"] == "xon_xoff" and b == {"XON": p["xon"], "XOFF": p["xoff"]}[label]
    frames = 0
    for case in run["results"]["cases"]:
        p = case["params"]
        end = {"end_chars": "end character", "fixed_length": "fixed length", "cdt": "CDT expired"}[p["end_criterion"]]
        for seat in "ab":
            got = seen.get((case["id"], seat), [])
            expected = frames_by_rule(sent.get((case["id"], seat), []), p, char_time)
            assert [f for f, e in got if e.startswith(end)] == expected, (case["id"], seat)
            # the rest: data without its end (the CDT expired, or the case's capture ended)
            assert all(e.startswith(end) or e.endswith(("incomplete", "ends")) for _, e in got), (case["id"], got)
            frames += len(got)
        if seat == "a":   # the tester's frames are what the case sent
            assert b"".join(f for f, _ in seen.get((case["id"], "a"), [])) in sent_by_tester(case)
    assert frames >= 2 * len(run["results"]["cases"])
    if name == "ascii":
        assert any(r["ptpcert.ascii.flow"] == "XOFF" for r in rows)
