"""Line analysis of RK 512 links (ptpcert analyze / monitor): the 3964(R) link below and what
the RK 512 frames say, both seats judged.

Conforming captures come from two model RK 512 stations wired together and from runs of the
RK 512 suite against the model (sim:); broken ones from the broken variants
(``ptpcert.procedures.rk512_mutants``), from a bare 3964(R) station in a seat that sends
frames a test writes by hand (tests/procedures/rk512/rk512_rules.py, written from the manual's tables), and
from stations with the other reading of an open point."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from rk512_helpers import pair, params, settle
from rk512_rules import header, response

from ptpcert import analysis as A
from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.cli import main as cli_main
from ptpcert.model.codes import Code
from ptpcert.model.link import Link
from ptpcert.registry import by_name
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.procedures.rk512.model import RK512_READINGS, Rk512Station
from ptpcert.profile import load_profile
from ptpcert.rules import for_procedure, for_rule
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[3]
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
    assert "T_RES" in f.rule and "Figs. 2-18, 2-19" in f.reference
    assert "RK512.RESP.ONE-PER-COMMAND" in f.rules and "RK512.TRES.RESPONSE-IN-TIME" in f.rules
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
    assert bad[0].rules == ("RK512.RESP.REATEL-VALUES",)


def test_a_response_nobody_asked_for_is_found():
    link, a, t = _tester_link()
    _answer(link, t, response(0))
    an = _judge_b(link)
    assert [(f.grade, f.kind) for f in an.findings] == [(R.FAIL, "unexpected")], [f.message for f in an.findings]
    assert "Response message frame" in an.findings[0].reference
    assert "RK512.RESP.NOT-ANSWERED" in an.findings[0].rules


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
    assert "RK512.RESP.REATEL-VALUES" in bad[0].rules


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
    assert bad[0].rules == ("RK512.QFD.NESTING-DEPTH-1",)


def test_every_rule_a_finding_cites_is_in_the_catalogue_and_every_response_problem_has_ids():
    from ptpcert.procedures.rk512.analysis import judging
    cat = for_procedure("rk512")
    cited = [i for ids in (*judging.RULE_IDS.values(), *judging._PROBLEM_IDS.values()) for i in ids]
    assert cited and not cat.unknown(cited)
    # every kind of difference response_problem finds has its own ids (not the fallback)
    want = response(0, data=bytes(6))
    for got in (b"\x00\x00\x00", response(0, first=False, data=bytes(6)), b"\x00\x01\x00\x00" + bytes(6),
                response(0x42), response(0x0C), response(0x14, data=bytes(2)), response(0, data=bytes(5))):
        problem = judging.response_problem(got, want)
        assert problem is not None and problem[1] in judging._PROBLEM_IDS, (got, problem)
    problem = judging.response_problem(response(0, data=b"\x01"), response(0))
    assert judging.rule_ids((judging._RESPONSE_RULE, problem[1])) == ("RK512.RESP.SEND-NO-DATA",)


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


def test_a_requester_that_takes_the_other_reading_of_an_open_point_is_informational():
    """AMB-16: a FETCH response chunk shorter than 128 bytes ends the request (16#0A03, the
    model's reading), or is taken and the next asked for (a SEND/FETCH may be split
    otherwise). b takes the other reading; a answers in chunks of 126 bytes (a broken
    variant in seat a, not judged)."""
    other = replace(RK512_READINGS, amb16_exact_chunks=False)
    a = MUTANTS["fetch-chunks-126"].make(params("high"), name="a")
    b = Rk512Station(params("low"), other, name="b")
    link = settle(Link(a, b))
    link.run_until(link.now + 5.0)
    b.request(link.now + 0.05, "fetch DB10:DW0:LEN=300")
    settle_run(link)
    cap = link_capture(link)
    cap.end = link.now
    an = analyze(cap, params("high"), params("low"), judge="b")
    got = [(f.grade, f.kind, f.readings) for f in an.findings]
    assert got == [(R.INFORMATIONAL, "reading", ("AMB-16",))], [f.message for f in an.findings]
    # the reference requester ends the request there: nothing to note
    b = Rk512Station(params("low"), name="b")
    link = settle(Link(MUTANTS["fetch-chunks-126"].make(params("high"), name="a"), b))
    link.run_until(link.now + 5.0)
    b.request(link.now + 0.05, "fetch DB10:DW0:LEN=300")
    settle_run(link)
    cap = link_capture(link)
    cap.end = link.now
    assert not analyze(cap, params("high"), params("low"), judge="b").findings


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
    "RK512.ERR06.0612": "link", "SUITE.RK512.L-08.RESPONSE-REFUSED": "link",
    # an error number where the tester's memory has the data (the request's first or middle frame)
    "SUITE.RK512.A-06.REATEL-14-FIRST-OF-THREE": "response", "SUITE.RK512.A-06.REATEL-36-FIRST-OF-THREE": "response",
    "SUITE.RK512.A-06.REATEL-14-MIDDLE-OF-THREE": "response",
    "SUITE.RK512.A-06.REATEL-14-FETCH-FIRST-OF-THREE": "response",
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


# ------------------------------------------------------------------ broken variants

MUTANTS = PROC.mutants()

#: the frames a partner crafts (Table 2-1, written from the manual in rk512_rules)
SEND_200 = header("A", "D", 10, 0, 100) + bytes(128)           # the first frame of a 200-byte SEND
CONT_72 = bytes([0xFF, 0x00, ord("A"), ord("D")]) + bytes(72)  # its continuation

#: How the line shows each variant's defect: the partner in seat a ("ref": the reference
#: station, which also sends the raw frames a step names; "bare": a 3964R station that sends
#: only raw frames; or a broken variant), and the steps: ("a"/"b", request) a request of
#: that seat's station, ("raw", frame) a frame seat a sends as it is, ("wait", s) the line
#: runs on until s seconds after the step before began.
SCENARIOS = {
    "send-response-with-data": ("ref", [("a", "send DB10:DW0:LEN=10")]),
    "continuation-response-id-00": ("ref", [("a", "send DB10:DW0:LEN=200")]),
    "error-response-byte3-01": ("ref", [("a", "fetch DB250:DW0:LEN=6")]),
    "error-response-with-data": ("ref", [("a", "fetch DB250:DW0:LEN=6")]),
    "db-missing-reatel-0c": ("ref", [("a", "fetch DB250:DW0:LEN=6")]),
    "response-to-response": ("ref", [("raw", response(0))]),
    # (more data than announced: fewer would be the other reading of AMB-16, a SEND split otherwise)
    "send-count-not-checked": ("ref", [("raw", header("A", "D", 10, 0, 5) + bytes(12))]),
    "fetch-with-data-served": ("ref", [("raw", header("E", "D", 10, 0, 3) + bytes(2))]),
    "continuation-bytes-not-checked": ("ref", [("raw", SEND_200), ("raw", CONT_72[:3] + b"X" + CONT_72[4:])]),
    "dw-as-byte-offset": ("ref", [("a", "fetch DB10:DW250:LEN=20")]),
    "fetch-chunks-126": ("ref", [("a", "fetch DB10:DW0:LEN=300")]),
    "fetch-chunks-unprompted": ("ref", [("a", "fetch DB10:DW0:LEN=300")]),
    "sequence-error-answered-ok": ("ref", [("raw", CONT_72)]),
    "continuation-without-request-ignored": ("ref", [("raw", CONT_72), ("wait", 3.0)]),
    "pipelined-command-served": ("ref", [("raw2", header("A", "D", 10, 0, 2) + bytes(4),
                                          header("A", "D", 10, 8, 2) + bytes(4))]),
    "passive-tres-ignored": ("ref", [("raw", SEND_200), ("wait", 13.0), ("raw", CONT_72)]),
    "counter-letter-c": ("ref", [("b", "fetch Z:0:LEN=6")]),
    "continuation-full-header": ("ref", [("b", "send DB10:DW0:LEN=200")]),
    "error-reatel-taken-as-success": ("ref", [("b", "send DB250:DW0:LEN=200")]),
    "error-response-goes-on": ("ref", [("b", "send DB250:DW0:LEN=300")]),
    # (more data than asked for: fewer would be the other reading of AMB-16)
    "fetch-length-not-checked": ("bare", [("b", "fetch DB10:DW0:LEN=300"), ("raw", response(0, data=bytes(130)))]),
    # (the response later than T_RES, 10 s by default, and the tolerance of a timer, 25 % and 50 ms)
    "no-tres-active": ("bare", [("b", "send DB10:DW0:LEN=200"), ("wait", 16.0), ("raw", response(0))]),
    "tres-half": ("bare", [("b", "send DB10:DW0:LEN=200"), ("wait", 7.0), ("raw", response(0))]),
    "link-no-dle-doubling": ("ref", [("b", "send DB16:DW0:LEN=4:DATA=10101010")]),
    "link-bcc-not-checked": ("bcc-includes-stx", [("raw", header("A", "D", 10, 0, 2) + bytes(4))]),
    "link-high-priority-yields": ("ref", [("both", "send DB10:DW0:LEN=10", "send DB11:DW0:LEN=10")]),
    # the variants of the rules catalogue's kill matrix that the line shows
    "check-byte3-reatel-10": ("ref", [("raw", header("C", "D", 10, 0, 3))]),
    "check-byte4-reatel-16": ("ref", [("raw", header("E", "Q", 10, 0, 3))]),
    "check-address-reatel-14": ("ref", [("raw", header("E", "E", 1, 0, 2))]),
    "check-length-reatel-0c": ("ref", [("raw", header("E", "D", 10, 0, 0))]),
    "check-flag-reatel-34": ("ref", [("raw", header("E", "D", 10, 0, 3, b9=0, b10=0x18))]),
    "check-cpu-reatel-14": ("ref", [("raw", header("E", "D", 10, 0, 3, b10=0x5F))]),
    "check-short-reatel-16": ("ref", [("raw", header("E", "D", 10, 0, 3)[:6])]),
    "byte1-reatel-16": ("ref", [("raw", header("E", "D", 10, 0, 3, b1=0x01))]),
    "reatel-36-as-37": ("ref", [("raw", CONT_72)]),
    "send-to-dx-refused": ("ref", [("a", "send DX7:DW0:LEN=4")]),
    "byte-areas-not-served": ("ref", [("a", "fetch E:0:LEN=6")]),
    "fetch-response-in-two-blocks": ("ref", [("a", "fetch DB10:DW0:LEN=6")]),
    "response-sent-twice": ("ref", [("a", "send DB10:DW0:LEN=10")]),
    "send-dx-type-x": ("ref", [("b", "send DX7:DW0:LEN=4")]),
    "fetch-command-letter-f": ("ref", [("b", "fetch DB10:DW0:LEN=6")]),
    "length-of-first-frame": ("ref", [("b", "send DB10:DW0:LEN=200")]),
}

#: where the manual states the rule each variant breaks (what its first finding must cite)
BROKEN_RULE = {
    "send-response-with-data": "'SEND message frame'", "continuation-response-id-00": "Table 2-2",
    "error-response-byte3-01": "Table 2-2", "error-response-with-data": "'Receiving data'",
    "db-missing-reatel-0c": "Table 8-3", "response-to-response": "'Response message frame'",
    "send-count-not-checked": "Table 8-3", "fetch-with-data-served": "Table 8-3",
    "continuation-bytes-not-checked": "Table 8-3", "dw-as-byte-offset": "Table 8-3",
    "fetch-chunks-126": "Figs. 2-15, 2-16", "fetch-chunks-unprompted": "'Response message frame'",
    "sequence-error-answered-ok": "Table 8-3", "pipelined-command-served": "Table 8-3",
    "continuation-without-request-ignored": "'Response message frame'",
    "passive-tres-ignored": "Table 8-3", "counter-letter-c": "Table 2-1",
    "continuation-full-header": "'Continuation frames'", "error-reatel-taken-as-success": "Fig. 2-18",
    "error-response-goes-on": "Fig. 2-18",
    "fetch-length-not-checked": "Fig. 2-18", "no-tres-active": "Fig. 2-18", "tres-half": "Fig. 2-18",
    "link-no-dle-doubling": "Sending data", "link-bcc-not-checked": "Receive",
    "link-high-priority-yields": "Initialization conflict",
    "check-byte3-reatel-10": "Table 8-3", "check-byte4-reatel-16": "Table 8-3", "check-address-reatel-14": "Table 8-3",
    "check-length-reatel-0c": "Table 8-3", "check-flag-reatel-34": "Table 8-3", "check-cpu-reatel-14": "Table 8-3",
    "check-short-reatel-16": "Table 8-3", "byte1-reatel-16": "Table 8-3", "reatel-36-as-37": "Table 8-3",
    "send-to-dx-refused": "Table 8-3", "byte-areas-not-served": "Table 8-3",
    "fetch-response-in-two-blocks": "Figs. 2-15, 2-16", "response-sent-twice": "'Response message frame'",
    "send-dx-type-x": "Table 2-1", "fetch-command-letter-f": "Table 2-1", "length-of-first-frame": "Fig. 2-18",
}

#: broken variants not yet checked against the analysis: each must move to BROKEN_RULE (or
#: NOT_VISIBLE_ON_THE_WIRE) once reviewed
NOT_YET_REVIEWED: frozenset[str] = frozenset()

#: variants whose defect a recording of the line cannot show, and why (proved below: the
#: variant's line is the line of the reference station in a state, or with a request, that
#: the line does not show)
NOT_VISIBLE_ON_THE_WIRE = {
    "fetch-word-bytes-swapped": "the data values of a FETCH: the memory behind the station is not on the line",
    "flag-lock-ignored": "a coordination flag is the application's: it may have cleared the flag at any time",
    "cpu-stop-ignored": "the CPU's RUN/STOP state is not on the line",
    "cpu-nibble-0": "its frames for CPU 1 are the reference's for CPU 0 (byte 10 0Fh): the request is not on the line",
    "odd-send-not-padded": "its SEND of 9 bytes is the reference's SEND of 8: the request is not on the line",
    "unknown-reatel-0905": "only the STATUS it reports differs (16#0905 for 16#090E): a STATUS is not on the line",
    "retry-after-link-failure": "its retried request is the reference's request issued again by its application",
}


#: the variants made for the rules catalogue's kill matrix (mutants_rules.py): the kill matrix
#: proves each fails a case citing its rule; their review against the line analysis (a scenario
#: here, or a proof that the line cannot show them) is still to be done
KILL_MATRIX_VARIANTS = frozenset(n for n, m in MUTANTS.items() if m.make.__module__.endswith(".mutants_rules")
                                 and n not in BROKEN_RULE)


def test_every_rk512_broken_variant_has_the_rule_it_breaks_named():
    assert not KILL_MATRIX_VARIANTS & set(NOT_VISIBLE_ON_THE_WIRE)
    sets = (set(BROKEN_RULE), set(NOT_VISIBLE_ON_THE_WIRE), set(NOT_YET_REVIEWED), set(KILL_MATRIX_VARIANTS))
    assert sum(map(len, sets)) == len(set().union(*sets))
    assert set().union(*sets) == set(MUTANTS)
    assert set(SCENARIOS) == set(BROKEN_RULE)
    assert not NOT_YET_REVIEWED


def _seat_a(kind: str):
    pa = params("high")
    if kind == "ref":
        return Rk512Station(pa, name="a")
    if kind == "bare":
        return Station3964(pa.line, name="a")
    if kind in MUTANTS:
        return MUTANTS[kind].make(pa, name="a")
    from ptpcert.procedures.p3964.mutants import MUTANTS as LINK_MUTANTS
    return LINK_MUTANTS[kind].make(pa.line, name="a")


def scenario_capture(name: str, b_kind: str = "variant") -> tuple[C.Capture, object, object]:
    """The scenario of ``name`` with the variant (``b_kind`` "variant") or the reference
    ("reference") in seat b: the capture of the whole line, and both seats' parameters."""
    partner, steps = SCENARIOS[name]
    a = _seat_a(partner)
    prof = MUTANTS[name].profile
    pb = params(prof.get("priority", "low"))
    if pb.priority == "high":
        a = Rk512Station(params("low"), name="a") if partner == "ref" else a
    b = MUTANTS[name].make(pb, name="b") if b_kind == "variant" else Rk512Station(pb, name="b")
    link = settle(Link(a, b))
    link.run_until(link.now + 5.0)     # a quiet line first: every station is known to be at rest
    for step in steps:
        t = link.now + 0.05
        if step[0] == "a":
            a.request(t, step[1])
        elif step[0] == "b":
            b.request(t, step[1])
        elif step[0] == "both":
            a.request(t, step[1])
            b.request(t, step[2])
        elif step[0] == "raw":
            a.request_send(t, step[1])
        elif step[0] == "raw2":
            a.request_send(t, step[1])
            a.request_send(t, step[2])
        elif step[0] == "wait":      # until this long after the step before began
            link.run_until(max(link.now, last + step[1]))
            continue
        last = t
        link.run_until_quiet(t + 2.0)
    link.run_until(link.now + 1.5 * pb.t_res)
    cap = link_capture(link)
    cap.end = link.now
    pa = a.params if isinstance(a, Rk512Station) else params(a.params.priority)
    return cap, pa, pb


@pytest.mark.parametrize("name", sorted(SCENARIOS))
def test_a_capture_of_each_rk512_broken_variant_is_flagged_with_the_rule_it_breaks(name):
    """The variant in seat b against a partner that makes its defect show; the capture of
    the whole line, judged from the wire alone: seat b is flagged, citing the rule the
    variant breaks, and the reference station in the same scenario is not. With the seats
    swapped, the same defect is found in seat a."""
    cap, pa, pb = scenario_capture(name)
    an = analyze(cap, pa, pb, judge="b")
    bad = fails(an, "b")
    assert bad, f"{name} is not flagged: {[f.message for f in an.findings]}"
    first = bad[0]
    assert BROKEN_RULE[name] in first.reference + " " + first.rule, first.message
    # the rules it breaks by id: RK 512's, or (a broken link below) the 3964 catalogue's
    want = "3964" if name.startswith("link-") else "RK512"
    assert first.rules and all(r.startswith(want + ".") and for_rule(r).get(r) for r in first.rules), first.rules
    ref_cap, ra, rb = scenario_capture(name, "reference")
    assert not fails(analyze(ref_cap, ra, rb, judge="b")), "the reference is flagged in the same scenario"
    swapped = analyze(swap(cap), pb, pa, judge="a")
    assert [(round(f.t, 6), f.kind, f.rule) for f in fails(swapped, "a")][:1] == [(round(first.t, 6), first.kind,
                                                                                      first.rule)]


def _proof_link(b, partner="ref") -> tuple[Link, object, object]:
    a = _seat_a(partner)
    link = settle(Link(a, b))
    link.run_until(link.now + 5.0)
    return link, a, b


def _run_steps(link: Link, steps) -> None:
    for who, what in steps:
        t = link.now + 0.05
        if who == "raw":
            link.a.request_send(t, what)
        else:
            (link.a if who == "a" else link.b).request(t, what)
        link.run_until_quiet(t + 40.0)
    link.run_until(link.now + 1.5 * link.b.params.t_res)


def _swapped_words(st) -> None:
    db = st.memory.db[10]
    db[0::2], db[1::2] = db[1::2], db[0::2]


#: for each variant not visible on the wire: the variant's set-up and steps, and the
#: reference's (the state or request the line does not show)
PROOFS = {
    "fetch-word-bytes-swapped": (None, [("a", "fetch DB10:DW0:LEN=6")], _swapped_words, [("a", "fetch DB10:DW0:LEN=6")]),
    "flag-lock-ignored": (lambda st: st.memory.set_flag(0, 0, 1), [("a", "send DB10:DW0:LEN=4:CF=0.0")],
                          None, [("a", "send DB10:DW0:LEN=4:CF=0.0")]),
    "cpu-stop-ignored": (lambda st: setattr(st.memory, "running", False), [("a", "send DB10:DW0:LEN=4")],
                         None, [("a", "send DB10:DW0:LEN=4")]),
    "cpu-nibble-0": (None, [("b", "send DB10:DW0:LEN=4")], None, [("b", "send DB10:DW0:LEN=4:CPU=0")]),
    "odd-send-not-padded": (None, [("b", "send DB10:DW0:LEN=9:DATA=010203040506070809")],
                            None, [("b", "send DB10:DW0:LEN=8:DATA=0102030405060708")]),
    "unknown-reatel-0905": (None, [("b", "send DB10:DW0:LEN=4"), ("raw", response(0x42))],
                            None, [("b", "send DB10:DW0:LEN=4"), ("raw", response(0x42))]),
    "retry-after-link-failure": (None, [("b", "send DB10:DW0:LEN=4")],
                                 None, [("b", "send DB10:DW0:LEN=4"), ("b", "send DB10:DW0:LEN=4")]),
}
_PARTNER = {"unknown-reatel-0905": "bare", "retry-after-link-failure": "busy"}


def _proof(name: str, which: str) -> Link:
    set_v, steps_v, set_r, steps_r = PROOFS[name]
    pb = params("low")
    b = MUTANTS[name].make(pb, name="b") if which == "variant" else Rk512Station(pb, name="b")
    setup, steps = (set_r, steps_r) if which == "reference" else (set_v, steps_v)
    if setup is not None:
        setup(b)
    partner = _PARTNER.get(name, "ref")
    link, a, _ = _proof_link(b, "bare" if partner == "busy" else partner)
    if partner == "busy":
        a.set_buffer_free(link.now, False)     # it refuses every block: b's link gives up (16#051A)
    if name == "retry-after-link-failure" and which == "reference":
        for _, what in steps:      # the application hands over the request twice at once
            b.request(link.now + 0.05, what)
        link.run_until_quiet(link.now + 60.0)
        link.run_until(link.now + 1.5 * pb.t_res)
        return link
    _run_steps(link, steps)
    return link


@pytest.mark.parametrize("name", sorted(NOT_VISIBLE_ON_THE_WIRE))
def test_an_rk512_variant_not_visible_on_the_wire_sends_what_a_conforming_station_sends(name):
    """The variant's line is the reference station's line with the state or the request that
    the line does not show; the analysis of the variant's line fails nothing."""
    def wire(link):
        return [(round(w.start, 6), w.src, w.byte) for w in link.wire]

    variant, reference = _proof(name, "variant"), _proof(name, "reference")
    assert len(variant.wire) > 20 and wire(variant) == wire(reference)
    if name != "unknown-reatel-0905":      # (its defect is the STATUS it reports, never on the line)
        # the defect does change the line: the reference in the variant's own state sends otherwise
        assert wire(variant) != wire(_proof(name, "reference in the variant's state"))
    cap = link_capture(variant)
    cap.end = variant.now
    an = analyze(cap, params("high"), params("low"), judge="b")
    assert not fails(an), [f.message for f in fails(an)]


def test_live_rk512_analysis_chunk_by_chunk_agrees_with_the_whole_capture(rk_run):
    """What ptpcert monitor does: chunks fed as they are read, judged up to a lag behind the
    clock; the findings (the tester's deliberate deviations, frames and link) and exchanges
    are those of the whole capture."""
    prof = load_profile(PROFILE)
    cap = C.load(rk_run / "run.json")
    kit = PROC.analyzer(PROC.tester_params(prof.params), prof.params)
    whole = A.analyze(cap, kit, restart_at_cases={"b"})
    assert fails(whole, "a")
    seen = []

    class Listener:
        def finding(self, f):
            seen.append(f)

        def exchange(self, line, e):
            pass

    line = A.LineAnalysis(PROC.analyzer(PROC.tester_params(prof.params), prof.params), restart_at_cases={"b"},
                          listener=Listener())
    marks = sorted(cap.marks, key=lambda m: m.t)
    for ch in cap.chunks:
        while marks and marks[0].t <= ch.t:
            line.mark(marks.pop(0))
        line.feed(ch)
        line.advance(ch.t + 0.0005)
    line.close(cap.end)
    key = lambda f: (round(f.t, 4), f.seat, f.kind, f.grade)  # noqa: E731
    assert [key(f) for f in line.findings()] == [key(f) for f in whole.findings]
    assert sorted(map(key, seen)) == sorted(map(key, whole.findings))
    assert [(e.first, e.last) for e in line.exchanges] == [(e.first, e.last) for e in whole.exchanges]
