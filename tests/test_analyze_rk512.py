"""Line analysis of RK 512 links (ptpcert analyze / monitor): the 3964(R) link below and what
the RK 512 frames say, both seats judged.

Conforming captures come from two model RK 512 stations wired together and from runs of the
RK 512 suite against the model (sim:); broken ones from the broken variants
(``ptpcert.procedures.rk512_mutants``), from a bare 3964(R) station in a seat that sends
frames a test writes by hand (tests/rk512_rules.py, written from the manual's tables), and
from stations with the other reading of an open point."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from ptpcert import analyze as A
from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.cli import main as cli_main
from ptpcert.model import Params3964, Station3964
from ptpcert.model.codes import Code
from ptpcert.model.link import Link
from ptpcert.model.rk512 import RK512_READINGS, Rk512Station
from ptpcert.procedures import by_name
from ptpcert.profile import load_profile
from ptpcert.runner import RunOptions, Runner
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

from rk512_helpers import pair, params, settle
from rk512_rules import header, response

ROOT = Path(__file__).resolve().parent.parent
PROFILE = ROOT / "conformance" / "profiles" / "rk512-reference.toml"
PROC = by_name("RK512")


# ------------------------------------------------------------------ helpers


def link_capture(link: Link) -> C.Capture:
    """What the two stations of a link put on the line, each byte at its completion."""
    chunks = []
    for w in link.wire:
        st = link.a if w.src == link.a.name else link.b
        t = w.start + st.params.char_time
        chunks.append(C.Chunk(round(t, 6), "a" if st is link.a else "b", bytes([w.byte])))
    return C.Capture(chunks, {"a": link.a.name, "b": link.b.name}, C.LineSettings(9600, 8, "even", 1))


def swap(cap: C.Capture) -> C.Capture:
    other = {"a": "b", "b": "a"}
    return C.Capture([replace(c, seat=other[c.seat]) for c in cap.chunks], {"a": cap.seats["b"], "b": cap.seats["a"]},
                     cap.line, cap.start, cap.end, cap.notes, cap.marks)


def analyze(cap: C.Capture, pa, pb, **kw) -> A.Analysis:
    return A.analyze(cap, PROC.analyzer(pa, pb), **kw)


def fails(an: A.Analysis, seat: str | None = None) -> list[A.Finding]:
    return [f for f in an.findings if f.grade == R.FAIL and (seat is None or f.seat == seat)]


def settle_run(link: Link, limit: float = 60.0) -> None:
    link.run_until_quiet(link.now + limit)


def case_of(cap: C.Capture, t: float) -> str:
    marks = [m for m in cap.marks if m.text.startswith("case ") and m.t <= t + 1e-6]
    return marks[-1].text.split()[1] if marks else ""


# ------------------------------------------------------------------ conforming links are clean


def test_send_and_fetch_in_both_directions_with_continuations_and_error_reatels_are_judged_clean():
    link, a, b = pair()
    requests = [
        (a, "send DB10:DW0:LEN=10"), (b, "fetch DB10:DW0:LEN=300"), (a, "send DB10:DW0:LEN=200"),
        (b, "send DB12:DW4:LEN=6"), (a, "fetch M:4:LEN=3"), (b, "fetch Z:2:LEN=6"),
        (a, "fetch DB250:DW0:LEN=6"),        # no DB 250 (db_range 1..199): REATEL 14h (Table 8-3)
        (b, "fetch DB10:DW250:LEN=200"),     # beyond the 512-byte DB: REATEL 34h (AMB-25 "length")
        (a, "send DB10:DW0:LEN=1024"),
    ]
    for st, req in requests:
        st.request(link.now + 0.05, req)
        settle_run(link)
    cap = link_capture(link)
    an = analyze(cap, a.params, b.params)
    assert not an.findings, [f.message for f in an.findings]
    labels = [an.line.label(e) for e in an.exchanges]
    # one exchange per request: the command, its continuations and every response
    assert len(an.exchanges) == len(requests), labels
    assert labels[1] == ("b FETCH DB10 DW0 300 bytes, a REATEL 00 + 128 bytes, b continuation FETCH, "
                         "a continuation REATEL 00 + 128 bytes, b continuation FETCH, a continuation REATEL 00 + 44 bytes")
    assert labels[6] == "a FETCH DB250 DW0 6 bytes, b REATEL 14h"
    assert labels[7] == "b FETCH DB10 DW250 200 bytes, a REATEL 34h"
    # the STATUS events of both seats (Table 8-1): the responder's class 06, the requester's class 09
    ev = an.exchanges[6].events
    assert Code.DB_NUMBER_NOT_ALLOWED in ev["b"] and Code.PARTNER_DB_ACCESS in ev["a"]
    ev = an.exchanges[7].events
    assert Code.LENGTH_NOT_ALLOWED in ev["a"] and Code.PARTNER_FRAME_LENGTH in ev["b"]
    # the same with the seats swapped
    assert not analyze(swap(cap), b.params, a.params).findings


def test_quasi_full_duplex_requests_that_cross_are_judged_clean():
    """Both stations send a 300-byte SEND at the same instant, then FETCHes that cross: the
    frames of the two requests interleave (Fig. 2-17), every seat judged."""
    link, a, b = pair()
    for ra, rb in (("send DB10:DW0:LEN=300", "send DB11:DW0:LEN=300"),
                   ("fetch DB10:DW0:LEN=400", "fetch DB11:DW8:LEN=260"),
                   ("send DB12:DW0:LEN=130", "fetch DB12:DW0:LEN=200")):
        t = link.now + 0.05
        a.request(t, ra)
        b.request(t + 0.0003, rb)
        settle_run(link)
    cap = link_capture(link)
    an = analyze(cap, a.params, b.params)
    assert not an.findings, [f.message for f in an.findings]
    # the requests interleave: an exchange holds both stations' commands and responses
    first = an.line.label(an.exchanges[0])
    assert first.startswith("a SEND DB10 DW0 300 bytes (128 in this frame), b SEND DB11 DW0 300 bytes "
                            "(128 in this frame), a REATEL 00, b REATEL 00"), first
    assert not analyze(swap(cap), b.params, a.params).findings


# ------------------------------------------------------------------ what is found


def _tester_link() -> tuple[Link, Rk512Station, Station3964]:
    """Seat a: an RK 512 station; seat b: a bare 3964R station whose frames the test writes."""
    a = Rk512Station(params("high"), name="a")
    t = Station3964(Params3964(procedure="3964R", priority="low", baud_rate=9600), name="b")
    return settle(Link(a, t)), a, t


def _judge_b(link: Link) -> A.Analysis:
    """Seat b judged, on a recording that goes on for longer than T_RES after the line fell quiet."""
    link.run_until(link.now + 1.5 * link.a.params.t_res)
    cap = link_capture(link)
    cap.end = link.now
    return analyze(cap, link.a.params, params("low" if link.a.params.priority == "high" else "high"), judge="b")


def test_a_missing_response_is_found_when_the_requesters_t_res_runs_out():
    link, a, t = _tester_link()
    a.request(link.now + 0.05, "fetch DB10:DW0:LEN=6")
    settle_run(link)          # b takes the FETCH and never answers
    an = _judge_b(link)
    got = [(f.grade, f.kind) for f in an.findings]
    assert got == [(R.FAIL, "missing")], [f.message for f in an.findings]
    f = an.findings[0]
    assert "T_RES" in f.rule and "Fig. 2-18" in f.reference
    # a CP 341 in seat a gives up with 16#0A05 (Table 8-1)
    assert Code.RESPONSE_TIMEOUT in [c for e in an.exchanges for c in e.events["a"]]


def _answer(link: Link, t: Station3964, frame: bytes) -> None:
    t.request_send(link.now + 0.01, frame)
    settle_run(link)


def test_a_response_with_an_unknown_reatel_is_found():
    link, a, t = _tester_link()
    a.request(link.now + 0.05, "send DB10:DW0:LEN=4")
    settle_run(link)
    _answer(link, t, response(0x42))          # 42h: not in Table 8-3 (16#090E)
    an = _judge_b(link)
    bad = fails(an)
    assert [f.kind for f in bad] == ["wrong"], [f.message for f in an.findings]
    assert "Table 8-3" in bad[0].reference and "16#090E" in bad[0].message


def test_a_response_nobody_asked_for_is_found():
    link, a, t = _tester_link()
    _answer(link, t, response(0))
    an = _judge_b(link)
    assert [(f.grade, f.kind) for f in an.findings] == [(R.FAIL, "unexpected")], [f.message for f in an.findings]
    assert "Response message frame" in an.findings[0].reference


def test_a_header_error_must_get_the_reatel_of_table_8_3():
    """b answers a FETCH from a DB that does not exist with 0Ch: the model's header checks
    give 14h (16#0606; Table 8-3)."""
    link, a, t = _tester_link()
    a.request(link.now + 0.05, "fetch DB250:DW0:LEN=6")
    settle_run(link)
    _answer(link, t, response(0x0C))
    bad = fails(_judge_b(link))
    assert len(bad) == 1 and bad[0].kind == "wrong" and "14h" in bad[0].message and "Table 8-3" in bad[0].reference
    assert bad[0].codes == (Code.DB_NUMBER_NOT_ALLOWED,)


def test_a_reatel_the_cpus_stop_explains_is_conforming():
    """REATEL 2Ah (the CPU in STOP, §7.3): the CPU's state is not on the line."""
    link, a, t = _tester_link()
    a.request(link.now + 0.05, "send DB10:DW0:LEN=4")
    settle_run(link)
    _answer(link, t, response(0x2A))
    an = _judge_b(link)
    assert not an.findings, [f.message for f in an.findings]
    assert any("STOP" in n for e in an.exchanges for n in e.notes)


def test_a_second_command_before_the_first_is_answered_is_found():
    """Nesting depth 1 (§2.2.3 'Quasi-full-duplex'): b sends its second SEND before the response
    to its first (b has the high priority: its STX wins over a's, Fig. 2-8)."""
    a = Rk512Station(params("low"), name="a")
    t = Station3964(Params3964(procedure="3964R", priority="high", baud_rate=9600), name="b")
    link = settle(Link(a, t))
    cmd = header("A", "D", 10, 0, 2) + bytes(4)
    t.request_send(link.now + 0.05, cmd)
    t.request_send(link.now + 0.05, header("A", "D", 10, 8, 2) + bytes(4))
    settle_run(link)
    bad = fails(_judge_b(link))
    assert bad and bad[0].kind == "unexpected" and "Quasi-full-duplex" in bad[0].reference, [f.message for f in bad]


def test_the_other_reading_of_an_open_point_is_informational():
    """AMB-25: a request that starts inside its area and runs beyond its end is refused with
    the length error (34h, the model's reading) or as an area error (14h for a DB)."""
    other = replace(RK512_READINGS, amb25_extent_beyond_area="area")
    link, a, b = pair(rb=other)
    a.request(link.now + 0.05, "fetch DB10:DW250:LEN=200")
    settle_run(link)
    an = analyze(link_capture(link), a.params, b.params)
    got = [(f.seat, f.grade, f.kind, f.readings) for f in an.findings]
    assert got == [("b", R.INFORMATIONAL, "reading", ("AMB-25",))], [f.message for f in an.findings]


# ------------------------------------------------------------------ runs of the suite


@pytest.fixture(scope="module")
def rk_run(tmp_path_factory):
    """The whole RK 512 suite against the model (sim:), its results and its pcap."""
    d = tmp_path_factory.mktemp("rkrun")
    rc = cli_main(["run", "--iut", "sim:", "--profile", str(PROFILE), "--json", str(d / "run.json"),
                   "--pcap", str(d / "run.pcap"), "-q"])
    assert rc == 0
    return d


def test_a_run_exported_with_pcap_is_judged_clean_for_the_bundled_reference(rk_run, tmp_path, capsys):
    rc = cli_main(["analyze", str(rk_run / "run.pcap"), "--profile", str(PROFILE), "--judge", "b",
                   "--json", str(tmp_path / "b.json"), "-q"])
    assert rc == 0, capsys.readouterr().out
    res = R.RunResult.read_json(tmp_path / "b.json")
    assert len(res.cases) > 300 and {c.verdict for c in res.cases} == {R.PASS}
    # requests are exchanges: a SEND with its continuation and its responses is one
    assert any(c.title.startswith("a SEND DB") and "continuation SEND" in c.title and "REATEL 00" in c.title
               for c in res.cases)
    # and with the case marks of the run's results
    prof = load_profile(PROFILE)
    an = A.analyze(C.load(rk_run / "run.json"), PROC.analyzer(PROC.tester_params(prof.params), prof.params),
                   judge="b", restart_at_cases={"b"})
    assert not an.findings, [f.message for f in an.findings]


#: The tester's deliberate deviations from what a CP 341 partner does, by case (a review of
#: what --judge a found, each checked against the case's purpose). Every other case of the
#: suite has the tester conform.
DELIBERATE = {
    # the tester's commands no CP 341 sends (Table 2-1): header errors the IUT must refuse
    "RK512.DLE.REATEL": "header", "RK512.ERR06.0601": "header", "RK512.ERR06.0602": "header",
    "RK512.ERR06.0604": "header", "RK512.ERR06.0606": "header", "RK512.ERR06.0607": "header",
    "RK512.ERR06.0608": "header", "RK512.ERR06.0609": "header", "RK512.ERR06.060A": "header",
    "RK512.ERR06.060B": "header", "RK512.ERR06.060C": "header", "RK512.ERR06.0610": "header",
    "SUITE.RK512.L-02.DLE-AS-REATEL": "header", "SUITE.RK512.P-07A.BYTE1-01": "header",
    "SUITE.RK512.P-07A.BYTE1-7F": "header", "SUITE.RK512.P-07B.BYTE3-43": "header",
    "SUITE.RK512.P-07B.BYTE3-61": "header", "SUITE.RK512.P-07C.A-M": "header", "SUITE.RK512.P-07C.A-X": "header",
    "SUITE.RK512.P-07C.E-43": "header", "SUITE.RK512.P-07C.E-51": "header", "SUITE.RK512.P-07C.E-64": "header",
    "SUITE.RK512.P-07C.O-X": "header", "SUITE.RK512.P-07D.FETCH-DB0": "header",
    "SUITE.RK512.P-07D.SEND-DB0": "header", "SUITE.RK512.P-07F.FETCH-513-WORDS": "header",
    "SUITE.RK512.P-07F.FETCH-LENGTH-0": "header", "SUITE.RK512.P-07F.SEND-LENGTH-0": "header",
    "SUITE.RK512.P-07G.FLAG-BIT-14": "header", "SUITE.RK512.P-07G.FLAG-BIT-8": "header",
    "SUITE.RK512.P-07H.CPU-5": "header", "SUITE.RK512.P-07H.CPU-E": "header",
    "SUITE.RK512.P-07I.FIRST-FRAME-SHORT": "header", "SUITE.RK512.P-07I.SEND-12-FOR-10": "header",
    "SUITE.RK512.P-07I.SEND-8-FOR-10": "header", "SUITE.RK512.P-07J.FETCH-WITH-DATA": "header",
    "SUITE.RK512.P-07K.SHORT-6": "header", "SUITE.RK512.P-07L.BYTE2-01": "header",
    "SUITE.RK512.P-17.ERROR-RESPONSE-LAYOUT": "header",
    "SUITE.RK512.P-07B.BYTE3-00": "header",      # byte 3 00h: the command reads as a response
    # continuation frames that break §2.2.3 (bytes 3/4, data count) or come when none is due
    "RK512.ERR06.0603": "continuation", "RK512.ERR06.0605": "continuation", "RK512.ERR06.060E": "continuation",
    "RK512.ERR06.0611": "continuation", "SUITE.RK512.P-06.CONTINUATION-FETCH-WITH-DATA": "continuation",
    "SUITE.RK512.P-07I.CONTINUATION-70-FOR-72": "continuation", "SUITE.RK512.P-07K.SHORT-3": "continuation",
    "SUITE.RK512.P-08.FETCH-CONTINUATION-BYTE4": "continuation",
    "SUITE.RK512.P-08.SEND-CONTINUATION-BYTE3": "continuation",
    "SUITE.RK512.P-08.SEND-CONTINUATION-BYTE4": "continuation",
    "SUITE.RK512.P-09A.CONTINUATION-WITHOUT-REQUEST": "continuation",
    # a second command before the first is answered, or instead of the continuation (depth 1)
    "SUITE.RK512.P-09B.FIRST-WHILE-CONTINUATION-EXPECTED": "depth",
    "SUITE.RK512.P-09C.COMMAND-BEFORE-RESPONSE": "depth",
    # the tester's continuation after the IUT's T_RES, or never
    "SUITE.RK512.P-10.CONTINUATION-TOO-LATE": "late continuation",
    "RK512.TRES.PASSIVE-EXPIRY": "late continuation",
    # the tester answers the IUT's requests wrongly: an error REATEL its memory does not
    # explain, an unknown REATEL, a wrong byte 1, data count or length, or not at all
    "RK512.ERR0A.0A01": "response", "RK512.ERR0A.0A02": "response", "RK512.ERR0A.0A03": "response",
    "RK512.ERR0A.0A04": "response", "RK512.ERR0A.0A05": "no response", "RK512.TRES.ACTIVE-EXPIRY": "no response",
    "SUITE.RK512.A-05.NO-RESPONSE": "no response",
    "SUITE.RK512.A-07.BYTE1-01": "response", "SUITE.RK512.A-07.CONTINUATION-RESPONSE-TO-FIRST": "response",
    "SUITE.RK512.A-07.ERROR-RESPONSE-WITH-DATA": "response", "SUITE.RK512.A-07.FETCH-ONE-LONG": "response",
    "SUITE.RK512.A-07.FETCH-ONE-SHORT": "response", "SUITE.RK512.A-07.FIRST-RESPONSE-TO-CONTINUATION": "response",
    "SUITE.RK512.A-07.SEND-RESPONSE-WITH-DATA": "response", "SUITE.RK512.A-07.SHORT-RESPONSE": "response",
    "SUITE.RK512.A-12.FETCH-ERROR-NO-DATA": "response",
    "SUITE.RK512.P-15.UNSOLICITED-RESPONSE": "unsolicited response",
    # the link: the tester corrupts or interrupts its block, or refuses the IUT's blocks
    "SUITE.RK512.L-03.BCC-WRONG-NOT-ACTED-ON": "link", "SUITE.RK512.L-04.REPEAT-AFTER-NAK": "link",
    "SUITE.RK512.L-06.GAP-OVER-CDT": "link", "SUITE.RK512.A-10.COMMAND-REFUSED": "link",
    "RK512.ERR06.0612": "link",
}
#: Example 5 and A-06: every REATEL of Table 8-3 (and unknown ones) in a response to a first
#: frame and to a continuation - responses the tester's memory does not explain
for _r in ("01", "0A", "0C", "10", "12", "14", "16", "32", "34", "36", "42", "FF"):
    for _c in ("RK512.EX5.REATEL-" + _r, "SUITE.RK512.A-06.REATEL-" + _r):
        DELIBERATE[_c] = DELIBERATE[_c + "-CONTINUATION"] = "response"


def test_judging_the_tester_finds_exactly_the_suites_deliberate_deviations(rk_run):
    """A consistency check of the RK 512 suite: in a run against the model, every deviation of
    the tester's seat is one a case commits on purpose, and every such case shows one."""
    prof = load_profile(PROFILE)
    cap = C.load(rk_run / "run.json")
    kit = PROC.analyzer(PROC.tester_params(prof.params), prof.params)
    an = A.analyze(cap, kit, judge="a", restart_at_cases={"b"})
    flagged = {case_of(cap, f.t) for f in fails(an, "a")}
    assert flagged == set(DELIBERATE), (sorted(flagged - set(DELIBERATE)), sorted(set(DELIBERATE) - flagged))
    assert all(f.seat == "a" for f in an.findings)
