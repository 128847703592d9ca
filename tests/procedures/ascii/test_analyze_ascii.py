"""Line analysis (ptpcert analyze / monitor) of the ASCII driver: both stations of a recorded
link judged against the ASCII model.

Captures of conforming exchanges come from two model ASCII drivers wired together
(model.link) and from runs of the suite against the model (sim:); broken ones from the broken
variants (ptpcert.procedures.ascii.mutants). What a finding must cite is the manual's reference of the
rule each variant breaks (§2.2.4's paragraphs, the figures and tables), written here from the
manual's structure, not copied from output."""

from __future__ import annotations

import random
from dataclasses import replace
from pathlib import Path

import pytest

from ptpcert import analysis as A
from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.cli import main as cli_main
from ptpcert.model.events import Status
from ptpcert.model.link import Link
from ptpcert.registry import by_name
from ptpcert.procedures.ascii.description import reference_profile
from ptpcert.procedures.ascii.model import AsciiHost, AsciiParams, AsciiStation, send_bytes
from ptpcert.procedures.ascii.mutants import MUTANTS
from ptpcert.profile import load_profile
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[3]
PROFILE = ROOT / "conformance" / "profiles" / "ascii-reference.toml"
PROC = by_name("ASCII")
ETX = 0x03


# ------------------------------------------------------------------ helpers


def link_capture(link: Link) -> C.Capture:
    """What the two stations of a link put on the line, each byte at its completion; both
    were switched on at 0 (make_link), which a mark says."""
    chunks = []
    for w in link.wire:
        st = link.a if w.src == link.a.name else link.b
        chunks.append(C.Chunk(round(w.start + st.params.char_time, 6), "a" if st is link.a else "b", bytes([w.byte])))
    return C.Capture(chunks, {"a": link.a.name, "b": link.b.name}, C.LineSettings(9600, 8, "even", 1),
                     marks=[C.Mark(0.0, "power-on")])


def kit_for(pa: AsciiParams, pb: AsciiParams, apps=None):
    return PROC.analyzer(pa, pb, apps=apps or {"a": "none", "b": "echo"})


def fails(an: A.Analysis, seat: str | None = None) -> list[A.Finding]:
    return [f for f in an.findings if f.grade == R.FAIL and (seat is None or f.seat == seat)]


def make_link(a: AsciiStation, b: AsciiStation, *, echo=("b",), read_delay=None) -> Link:
    delays = dict(read_delay or {})
    link = Link(a, b, echo=set(echo),
                host_factory=lambda st, app: AsciiHost(st, app, read_delay=delays.get(st.name, 0.0)))
    link.power_on(0.0)
    link.run_until(0.05)
    return link


def run_suite(url: str, profile) -> R.RunResult:
    res = R.RunResult(tool_version="test", started="", iut=url)
    Runner(make_factory(url, profile), profile, RunOptions()).run(load_suite(profile, load_vector_sets()), res)
    return res


def case_of(cap: C.Capture, t: float) -> str:
    marks = [m for m in cap.marks if m.text.startswith("case ") and m.t <= t + 1e-6]
    return marks[-1].text.split()[1] if marks else ""


def _swap(cap: C.Capture) -> C.Capture:
    other = {"a": "b", "b": "a"}
    return C.Capture([replace(c, seat=other[c.seat]) for c in cap.chunks], {"a": cap.seats["b"], "b": cap.seats["a"]},
                     cap.line, cap.start, cap.end, cap.notes, cap.marks)


CRITERIA = {
    "cdt": dict(end_criterion="cdt"),
    "end_chars": dict(end_criterion="end_chars", end_chars=(ETX,)),
    "end_chars_pair": dict(end_criterion="end_chars", end_chars=(0x0D, 0x0A), send_variant="len_append_end"),
    "fixed_length": dict(end_criterion="fixed_length", fixed_length=6),
}


def _payload(rnd: random.Random, crit: str, p: AsciiParams) -> bytes:
    """A job's data for the criterion: every byte a frame may carry (end characters only at
    the end, no XON/XOFF with XON/XOFF flow control)."""
    pool = [0x00, 0x41, 0x42, 0x7F, 0xFF, 0x0D, ETX]
    if p.flow_control == "xon_xoff":
        pool = [x for x in pool if x not in (p.xon, p.xoff)]
    if p.end_criterion == "end_chars":
        pool = [x for x in pool if x not in p.end_chars]
        body = bytes(rnd.choice(pool) for _ in range(rnd.randrange(1, 12)))
        return body if p.send_variant == "len_append_end" else body + p.end_sequence
    n = p.fixed_length if p.end_criterion == "fixed_length" else rnd.randrange(1, 12)
    return bytes(rnd.choice(pool) for _ in range(n))


# ------------------------------------------------------------------ conforming links are clean


@pytest.mark.parametrize("flow", ["none", "xon_xoff"])
@pytest.mark.parametrize("crit", sorted(CRITERIA))
def test_conforming_exchanges_of_two_model_stations_are_judged_clean(crit, flow):
    """Both directions, b's own frames besides its echoes of a's, jobs handed over while the
    last is still going out (the pause between frames of the CDT and fixed-length criteria
    holds them back): both seats clean, each frame an exchange."""
    p = AsciiParams(cdt_ms=20, flow_control=flow, **CRITERIA[crit])
    link = make_link(AsciiStation(p, name="a"), AsciiStation(p, name="b"))
    rnd = random.Random(11)
    t = link.now + 0.05
    for i in range(30):
        sender = link.a if i % 3 else link.b
        link.request(sender, _payload(rnd, crit, p), at=t)
        if i % 5 == 4:      # a second job at once: it waits for the first (and the pause)
            link.request(sender, _payload(rnd, crit, p), at=t)
        link.run_until_quiet(t + 30)
        t = link.now + rnd.choice([0.0005, 0.03, 0.5])
    cap = link_capture(link)
    an = A.analyze(cap, kit_for(p, p))
    assert not an.findings, [f.message for f in an.findings]
    assert len(an.exchanges) >= 30 and all(e.verdict == R.PASS for e in an.exchanges)
    if flow == "xon_xoff":
        assert an.line.label(an.exchanges[0]) == "a XON, b XON"      # the start-up XONs (§2.2.4)


@pytest.mark.parametrize("crit", ["end_chars", "cdt"])
def test_flow_control_at_work_between_two_model_stations_is_judged_clean(crit):
    """Two slow readers with XON/XOFF and room for two frames: each sends XOFF when its buffer
    is full and XON once its application has read a frame; a holds b's echoes back until
    then. The reads are not on the line: the analysis takes them from the XON (and, for b,
    from its echoes) and, for a, which reads without echoing, from its XOFF."""
    p = AsciiParams(cdt_ms=20, flow_control="xon_xoff", buffer_frames=2, xon_wait_ms=2000, **CRITERIA[crit])
    link = make_link(AsciiStation(p, name="a"), AsciiStation(p, name="b"), read_delay={"a": 0.3, "b": 0.2})
    rnd = random.Random(5)
    t = link.now + 0.05
    for i in range(6):
        for _ in range(4):
            link.request(link.a, _payload(rnd, crit, p), at=t)
        link.run_until_quiet(t + 60)
        t = link.now + 0.5
    cap = link_capture(link)
    xon, xoff = bytes([p.xon]), bytes([p.xoff])
    assert cap.wire_bytes("a").count(xoff) >= 3 and cap.wire_bytes("b").count(xoff) >= 3
    assert cap.wire_bytes("a").count(xon) >= 4 and cap.wire_bytes("b").count(xon) >= 4
    an = A.analyze(cap, kit_for(p, p))
    assert not fails(an), [f.message for f in fails(an)]
    # a station that stops on XOFF and the character it would have sent next may meet within a
    # microsecond, the capture's resolution: either order is judged conforming
    assert all(f.kind == "resolution" and "microseconds" in f.message for f in an.findings), \
        [(f.kind, f.message) for f in an.findings]
    # what a CP 341 in each seat raises is with the exchanges: what the link's stations raised
    # (a frame the XOFF came too late to stop finds the buffer full: 16#080A)
    for seat, st in (("a", link.a), ("b", link.b)):
        assert [c for e in an.exchanges for c in e.events[seat]] == [e.code for e in link.events_of(st, Status)]


@pytest.fixture(scope="module")
def sim_run(tmp_path_factory):
    """The whole suite against the model (sim:), its results and its pcap from run --pcap."""
    d = tmp_path_factory.mktemp("asciirun")
    rc = cli_main(["run", "--iut", "sim:", "--profile", str(PROFILE), "--json", str(d / "run.json"),
                   "--pcap", str(d / "run.pcap"), "-q"])
    assert rc == 0
    return d


def _run_kit():
    prof = load_profile(PROFILE)
    return kit_for(PROC.tester_params(prof.params), prof.params)


def test_a_run_of_the_suite_on_the_model_is_clean_for_the_iut(sim_run):
    cap = C.load(sim_run / "run.json")
    an = A.analyze(cap, _run_kit(), judge="b", restart_at_cases={"b"})
    assert not an.findings, [(case_of(cap, f.t), f.message) for f in an.findings]
    assert len(an.exchanges) > 300
    # the receiver's errors a CP 341 in the IUT's seat raises are with the exchanges
    raised = {c for e in an.exchanges for c in e.events["b"]}
    assert {0x0806, 0x080C, 0x080D} <= raised


def test_analyze_judges_a_run_exported_with_pcap_clean_for_the_bundled_reference(sim_run, tmp_path, capsys):
    rc = cli_main(["analyze", str(sim_run / "run.pcap"), "--profile", str(PROFILE), "--judge", "b",
                   "--json", str(tmp_path / "b.json"), "--junit", str(tmp_path / "b.xml"), "-q"])
    assert rc == 0, capsys.readouterr().out
    res = R.RunResult.read_json(tmp_path / "b.json")
    assert res.cases and {c.verdict for c in res.cases} == {R.PASS}
    assert "overall PASS" in capsys.readouterr().out
    assert (tmp_path / "b.xml").read_text().count("<testcase") == len(res.cases)
    assert res.procedure == PROC.title


#: The tester's deliberate deviations from what a CP 341 ASCII partner does, case by case (a
#: review of what --judge a found with the bundled reference profile, each checked against the
#: case's purpose). A case whose tester conforms must not be here; one whose tester breaks a
#: rule on purpose must be.
DELIBERATE = {
    # characters with a parity/framing error, BREAKs (Table 8-1 (08)0CH, (08)0DH: a driver sends neither)
    "SUITE.ASCII.EC.CHARACTER-ERROR": "char error", "SUITE.ASCII.EC.CHARACTER-ERROR-ENDS-AT-END-CHAR": "char error",
    "ASCII.RX-EC-09.PARITY-ERROR": "char error",
    "SUITE.ASCII.LINE.BREAK-IDLE": "BREAK", "SUITE.ASCII.LINE.BREAK-IN-FRAME": "BREAK",
    "SUITE.ASCII.LINE.BREAK-WHILE-SENDING": "BREAK", "ASCII.LINE.BREAK-IN-FRAME": "BREAK",
    # XON/XOFF codes inside the tester's data (§2.2.4: they must not occur in user data)
    "SUITE.ASCII.FC.CODES-NOT-DATA": "XON/XOFF as data",
    # the tester holds the IUT with XOFF though its buffer is far from full (it plays a slow partner)
    "SUITE.ASCII.FC.XOFF-AFTER-FIRST": "XOFF", "SUITE.ASCII.FC.XOFF-MIDDLE": "XOFF",
    "SUITE.ASCII.FC.XOFF-NEAR-END": "XOFF", "SUITE.ASCII.FC.XOFF-WHILE-IDLE": "XOFF",
    "SUITE.ASCII.FC.XON-WAIT-EXPIRES": "XOFF", "SUITE.ASCII.FC.XON-WITHIN-WAIT": "XOFF",
    # the tester goes on sending after the IUT's XOFF (to overflow its buffer, or to finish the frame)
    "SUITE.ASCII.FC.OVERFLOW": "ignores XOFF", "SUITE.ASCII.FC.XOFF-AT-974-BYTES": "ignores XOFF",
}


def test_judging_the_tester_finds_exactly_the_suites_deliberate_deviations(sim_run):
    """A consistency check of the suite: in a run against the model, every deviation of the
    tester's seat is one a case commits on purpose, and every such case shows one. (Fragments
    and frames with a gap inside, which many receive cases send, are what a CP 341 sends for
    short jobs handed over one after the other: with the end-character criterion no pause is
    due between frames.)"""
    cap = C.load(sim_run / "run.json")
    an = A.analyze(cap, _run_kit(), judge="a", restart_at_cases={"b"})
    flagged = {case_of(cap, f.t) for f in fails(an, "a")}
    assert flagged == set(DELIBERATE), (sorted(flagged - set(DELIBERATE)), sorted(set(DELIBERATE) - flagged))
    # the run's pcap has no case marks: the same deviations, case by case
    an_p = A.analyze(C.load(sim_run / "run.pcap"), _run_kit(), judge="a")
    assert {case_of(cap, f.t) for f in fails(an_p, "a")} == flagged
    assert all(f.seat == "a" for f in an.findings)


def test_analyze_exits_1_when_a_station_broke_a_rule_and_reports_it(sim_run, tmp_path, capsys):
    rc = cli_main(["analyze", str(sim_run / "run.pcap"), "--profile", str(PROFILE), "--judge", "a",
                   "--json", str(tmp_path / "a.json"), "--html", str(tmp_path / "a.html"), "-q"])
    out = capsys.readouterr().out
    assert rc == 1 and "overall FAIL" in out
    res = R.RunResult.read_json(tmp_path / "a.json")
    bad = [c for c in res.cases if c.verdict == R.FAIL]
    assert bad and all(c.group == "seat a" and c.reference and c.divergence is not None for c in bad)
    # the IUT's seat sees the tester's errors: a CP 341 there raises 16#080C and 16#080D
    assert any("16#080C" in c.tester_status for c in bad) and any("16#080D" in c.tester_status for c in bad)
    assert cli_main(["report", str(tmp_path / "a.json"), "--html", str(tmp_path / "again.html")]) == 0


def test_live_analysis_chunk_by_chunk_agrees_with_the_whole_capture(sim_run):
    """What ptpcert monitor does (feed chunks as they come, judge up to a lag behind the
    present) finds what the analysis of the whole capture finds, exchange by exchange."""
    cap = C.load(sim_run / "run.json")
    whole = A.analyze(cap, _run_kit(), restart_at_cases={"b"})
    seen = []

    class Listener:
        def finding(self, f):
            seen.append(f)

        def exchange(self, line, e):
            pass

    line = A.LineAnalysis(_run_kit(), restart_at_cases={"b"}, listener=Listener())
    marks = sorted(cap.marks, key=lambda m: m.t)
    for ch in cap.chunks:
        while marks and marks[0].t <= ch.t:
            line.mark(marks.pop(0))
        line.feed(ch)
        line.advance(ch.t + 0.0005)
    line.close(cap.end)
    key = lambda f: (round(f.t, 4), f.seat, f.kind, f.grade)  # noqa: E731
    assert whole.findings and [key(f) for f in line.findings()] == [key(f) for f in whole.findings]
    assert sorted(map(key, seen)) == sorted(map(key, whole.findings))
    assert [(e.first, e.last) for e in line.exchanges] == [(e.first, e.last) for e in whole.exchanges]


# ------------------------------------------------------------------ broken variants

#: where the manual states the rule each broken variant breaks (what its first finding must cite)
BROKEN_RULE = {
    # the receiver, seen in what the echo application sends back
    "cdt-half": "Fig. 2-21", "end-char-not-stored": "Fig. 2-22", "either-end-char": "Table A-7",
    "fixed-length-plus-one": "Fig. 2-23", "no-watchdog": "Fig. 2-23",
    "fragment-delivered": "(08)06H", "trailing-kept": "(08)06H", "end-char-waits-cdt": "(08)06H",
    "char-error-delivered": "(08)0CH", "error-ends-frame-at-once": "(08)0CH", "break-ignored": "(08)0DH",
    "cdt-double": "Fig. 2-21",
    # the receive buffer (FIFO, overwrite, size)
    "newest-first": "'receive buffer'", "no-overwrite": "Table 2-10", "overwrite-when-prevented": "Table 2-10",
    "buffer-2048": "Table 2-10",
    # the send side
    "no-send-pause": "'sending' (expiry of the character delay time)",
    "send-pause-half": "'sending' (expiry of the character delay time)",
    "fixed-length-no-pause": "'sending' (fixed message frame length)",
    "append-end-missing": "variant 3", "len-over-1024-sent": "(1E)41H",
    # flow control
    "no-start-up-xon": "'data flow control", "xoff-ignored": "interrupts its transmission",
    "xon-wait-endless": "(07)08H", "xon-wait-half": "Table 2-9", "no-xoff-when-full": "XOFF when",
    "no-xon-after-read": "XON once",
    # the variants made for the rules catalogue (mutants_rules.py), seen in what the echo
    # application sends back
    "nul-dropped": "'expiry of the character delay time'", "cdt-quarter": "'end character(s)'",
    "trailing-dropped": "'end character(s)'", "pair-across-cdt": "'end character(s)'",
    "frame-limit-1000": "'receive buffer'", "last-byte-not-sent": "'sending'",
    "len-with-end-appends": "'sending' (end character criterion)", "send-limit-1000": "'sending'",
    "flow-code-ends-frame": "'end character(s)'", "overlong-spoils-next": "'expiry of the character delay time'",
}

#: variants whose defect the captures of the suite's failed cases do not show (each case ends
#: before the variant's echo or frame is complete): a link of the tester and the variant
#: running to a quiet line instead - settings besides the variant's profile, and the tester's
#: jobs (time, data)
OWN_EXCHANGE = {
    # two frames 1.5 CDT apart: the variant takes them for one and sends both back together
    "cdt-double": ({}, [(0.0, b"AB"), (0.002 + 1.5 * 0.020 + 2 * 0.00115, b"CD")]),
    # characters after the end character (a second job), then a quiet line: the variant keeps
    # them with the frame. Its echo shows them only with a send variant that sends the job's
    # data as it is ("up to and including the end character" cuts them off again)
    "end-char-waits-cdt": ({"send_variant": "len_with_end"}, [(0.0, b"AB\x03"), (0.0, b"CD")]),
    # the variant's own job of 1025 bytes (a CP 341 refuses it: Table 8-2 (1E)41H)
    "len-over-1024-sent": ({}, []),
    # characters after the end character and a frame within the CDT (merged by a conforming
    # driver), then a frame that shows the merged one was not sent back
    "trailing-dropped": ({}, [(0.0, b"AB\x03XY"), (0.0155, b"CD\x03"), (0.2, b"EF\x03")]),
    # a frame of 1024 bytes, then a short one that shows the long one was not sent back
    "frame-limit-1000": ({}, [(0.0, bytes(0x41 + i % 26 for i in range(1024))), (2.0, b"XY")]),
    "send-limit-1000": ({}, [(0.0, bytes(0x41 + i % 26 for i in range(1024))), (2.0, b"XY")]),
}

#: broken variants added after the analysis was built, not yet checked against it: each must
#: move to BROKEN_RULE (or NOT_VISIBLE_ON_THE_WIRE) once reviewed
NOT_YET_REVIEWED: frozenset[str] = frozenset()

#: variants whose defect a recording of the line cannot show, and why (proved below)
NOT_VISIBLE_ON_THE_WIRE = {
    # §2.2.4 'sending', variant 1: a job "AB ETX DE" goes on the line as "AB ETX DE" instead of
    # "AB ETX" - which is exactly what a conforming driver sends for two jobs, "AB ETX" and then
    # "DE" (with the end-character criterion no pause is due between frames, and a job without
    # an end character goes out as it is: reading Q6). The job's data is not on the line.
    "up-to-end-not-cut": "the rest of the job after its end character looks like a second job",
    # Table 8-1 (08)06H: a fragment the CDT cut off is discarded alike with or without the
    # STATUS event, which is not on the line
    "fragment-silent": "the missing 16#0806 is a STATUS event, not a character",
}


def test_every_broken_variant_has_the_rule_it_breaks_named():
    """Every variant is either checked (the rule it breaks named), shown not to be visible on
    the wire, or listed as not yet reviewed: a new variant cannot go unnoticed."""
    sets = (set(BROKEN_RULE), set(NOT_VISIBLE_ON_THE_WIRE), set(NOT_YET_REVIEWED))
    assert sum(map(len, sets)) == len(set().union(*sets))
    assert set().union(*sets) == set(MUTANTS)
    assert len(MUTANTS) == 39 and not NOT_YET_REVIEWED
    assert set(OWN_EXCHANGE) <= set(BROKEN_RULE)


def test_a_variant_not_visible_on_the_wire_sends_what_a_conforming_station_sends():
    """up-to-end-not-cut with one job "AB ETX DE" puts on the line what the reference puts
    there for the two jobs "AB ETX" and "DE": the analysis fails nothing."""
    prof = reference_profile(**MUTANTS["up-to-end-not-cut"].profile)
    p = prof.params

    def wire(b_station, jobs):
        link = make_link(AsciiStation(PROC.tester_params(p), name="a"), b_station, echo=())
        for data in jobs:
            link.request(link.b, data, at=0.1)
        link.run_until_quiet(5.0)
        return link

    variant = wire(MUTANTS["up-to-end-not-cut"].make(p, name="b"), [b"AB\x03DE"])
    reference = wire(AsciiStation(p, name="b"), [b"AB\x03", b"DE"])
    on_line = [(round(w.start, 6), w.src, w.byte) for w in variant.wire]
    assert on_line == [(round(w.start, 6), w.src, w.byte) for w in reference.wire]
    assert send_bytes(b"AB\x03DE", p) == b"AB\x03"       # the defect: the reference cuts the job
    an = A.analyze(link_capture(variant), kit_for(PROC.tester_params(p), p, {"a": "none", "b": "none"}), judge="b")
    assert not fails(an), [f.message for f in fails(an)]


def _variant_capture(name: str):
    """The capture in which the variant's defect shows: the suite's failed cases against it
    (sim:), or its own exchange with the tester (OWN_EXCHANGE)."""
    m = MUTANTS[name]
    settings, jobs = OWN_EXCHANGE.get(name, ({}, None))
    prof = reference_profile(**{**m.profile, **settings})
    pb, pa = prof.params, PROC.tester_params(prof.params)
    if jobs is not None:
        link = make_link(AsciiStation(pa, name="a"), m.make(pb, name="b"))
        t0 = link.now + 0.05
        for at, data in jobs:
            link.request(link.a, data, at=t0 + at)
        if not jobs:
            link.request(link.b, bytes(range(256)) * 4 + b"X", at=t0)
        link.run_until_quiet(t0 + 10)
        return link_capture(link), pa, pb, None
    res = run_suite(f"sim:?mutant={name}", prof)
    failed = [c for c in res.cases if c.verdict == R.FAIL]
    assert failed
    res.cases = failed
    cap = C.from_results(res)
    if len(failed) == 1:
        # a capture of one case has no case marks: it begins with the case, as for analyze --case
        cap.marks.insert(0, C.Mark(0.0, f"case {failed[0].id}"))
    return cap, pa, pb, {c.id for c in failed}


@pytest.mark.parametrize("name", sorted(BROKEN_RULE))
def test_a_capture_of_each_broken_variant_is_flagged_with_the_rule_it_breaks(name):
    """The variant's exchanges judged from the wire alone: the variant's seat is flagged (in
    cases the runner failed too), citing the rule the variant breaks. With the seats swapped,
    the same defect is found in seat a."""
    cap, pa, pb, failed = _variant_capture(name)
    restart = {"b"} if failed is not None else set()
    an = A.analyze(cap, kit_for(pa, pb), judge="b", restart_at_cases=restart)
    bad = fails(an, "b")
    assert bad, f"{name} is not flagged: {[f.message for f in an.findings]}"
    if failed is not None:
        assert {case_of(cap, f.t) for f in bad} <= failed
    first = bad[0]
    assert BROKEN_RULE[name] in first.reference + " " + first.rule, first.message
    # both seats are judged alike: the variant in seat a
    swapped = A.analyze(_swap(cap), kit_for(pb, pa, {"a": "echo", "b": "none"}), judge="a",
                        restart_at_cases={"a"} if restart else set())
    assert [(f.t, f.kind, f.rule) for f in fails(swapped, "a")][:1] == [(first.t, first.kind, first.rule)]


# ------------------------------------------------------------------ open points, resolution


def _two_frames(gap: float, *, cdt_ms: int = 20) -> tuple[AsciiParams, C.Capture]:
    """Seat b sends "AB" and "CD" (CDT criterion) with ``gap`` seconds of idle line between
    them; seat a is quiet."""
    p = AsciiParams(cdt_ms=cdt_ms, end_criterion="cdt")
    c = p.char_time
    t = 1.0
    chunks = [C.Chunk(round(t + c, 6), "b", b"A"), C.Chunk(round(t + 2 * c, 6), "b", b"B")]
    t2 = t + 2 * c + gap
    chunks += [C.Chunk(round(t2 + c, 6), "b", b"C"), C.Chunk(round(t2 + 2 * c, 6), "b", b"D")]
    return p, C.Capture(chunks, line=C.LineSettings(9600, 8, "even", 1), end=t2 + 1.0)


def test_the_pause_between_frames_is_judged_and_a_difference_within_the_resolution_is_informational():
    """§2.2.4 'sending' (CDT criterion): the next frame only after a pause of more than the
    CDT. The model's pause (reading Q5) is CDT plus one character; one character less is the
    other reading, 5 % of the pause a timer's granularity."""
    kit = lambda p: kit_for(p, p, {"a": "none", "b": "none"})  # noqa: E731
    p, ok = _two_frames(0.020 + 0.0012)
    assert not A.analyze(ok, kit(p), judge="b").findings
    p, exact = _two_frames(0.020 + 0.0001)       # "more than the CDT": hardly, but conforming
    assert not fails(A.analyze(exact, kit(p), judge="b"))
    p, short = _two_frames(0.015)                # 5 ms short: breaks the rule
    bad = fails(A.analyze(short, kit(p), judge="b"))
    assert [f.kind for f in bad] == ["early"] and "'sending'" in bad[0].reference and "pause" in bad[0].rule
    # ... but a capture stamped to within 8 ms may have shifted it: informational
    an = A.analyze(short, kit(p), judge="b", resolution=0.008)
    assert not fails(an) and any(f.grade == R.INFORMATIONAL and f.kind in ("resolution", "timing")
                                 for f in an.findings), [(f.kind, f.message) for f in an.findings]


def test_a_station_with_the_other_reading_of_an_open_point_is_informational():
    """Q15: a station that sends XON after every read, not only to lift an XOFF, follows the
    other reading: informational, never failed."""
    p = AsciiParams(cdt_ms=20, end_criterion="end_chars", end_chars=(ETX,), flow_control="xon_xoff")
    readings = replace(PROC.station(p).readings, q15_xon_only_after_xoff=False)
    a, b = AsciiStation(p, name="a"), AsciiStation(p, readings, name="b")
    link = make_link(a, b, echo=())
    for i in range(3):
        link.request(a, b"HELLO\x03", at=0.1 + i * 0.2)
    link.run_until_quiet(3.0)
    cap = link_capture(link)
    assert cap.wire_bytes("b").count(bytes([p.xon])) == 4          # start-up, and one per frame read
    an = A.analyze(cap, kit_for(p, p, {"a": "none", "b": "none"}), judge="b")
    assert not fails(an), [f.message for f in fails(an)]
    assert {(f.kind, f.readings) for f in an.findings} == {("reading", ("Q15",))}


def test_a_missing_start_up_xon_after_a_power_on_mark_fails_and_a_restart_is_a_note():
    p = AsciiParams(cdt_ms=20, end_criterion="end_chars", end_chars=(ETX,), flow_control="xon_xoff")
    link = make_link(AsciiStation(p, name="a"), AsciiStation(p, name="b"), echo=())
    link.request(link.a, b"1\x03", at=0.1)
    link.run_until_quiet(3.0)
    cap = link_capture(link)
    kit = lambda: kit_for(p, p, {"a": "none", "b": "none"})  # noqa: E731
    # b restarts after a quiet line: its start-up XON is no finding
    restart = C.Chunk(round(link.now + 2.0, 6), "b", bytes([p.xon]))
    an = A.analyze(C.Capture(cap.chunks + [restart], line=cap.line), kit())
    assert not an.findings and any("restarted" in n for e in an.exchanges for n in e.notes)
    # b switched on (a mark says so) and its first character not the XON
    no_xon = C.Capture([c for c in cap.chunks if not (c.seat == "b" and c.data == bytes([p.xon]))],
                       line=cap.line, marks=[C.Mark(0.0, "power-on b")])
    bad = fails(A.analyze(no_xon, kit(), judge="b"))
    assert [f.kind for f in bad] == ["start-up"] and "XON" in bad[0].message and "Table 2-9" in bad[0].reference
    # without flow control a driver sends nothing at start-up: nothing to miss
    q = p.with_(flow_control="none")
    quiet = C.Capture([c for c in no_xon.chunks if c.data not in (bytes([p.xon]),)], line=cap.line,
                      marks=[C.Mark(0.0, "power-on b")])
    assert not A.analyze(quiet, kit_for(q, q, {"a": "none", "b": "none"}), judge="b").findings


# ------------------------------------------------------------------ real time


ASCII_IUT = ["--procedure", "ASCII", "--baud", "9600", "--cdt-ms", "220", "--end-criterion", "end_chars",
             "--end-chars", "03", "--flow-control", "xon_xoff"]


@pytest.mark.realtime
def test_ptpcert_iut_against_ptpcert_iut_is_judged_clean():
    """Two ASCII reference drivers as real processes (both with the echo application, one
    handing over a frame at start-up, so the frame goes back and forth), wired back to back
    through pipes by the relay of test_monitor that records the line: both seats clean."""
    import os
    import subprocess
    import sys
    import time

    from test_monitor import STALL, Relay, attempts, stop_process

    def iut(*args: str) -> list[str]:
        return [sys.executable, "-m", "ptpcert.cli", "iut", *ASCII_IUT, *args]

    def once(_attempt: int):
        b = subprocess.Popen(iut(), stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        a_in, relay_out = os.pipe()
        relay = a = None
        try:
            a_out, a_w = os.pipe()
            relay = Relay({"a": (a_out, b.stdin.fileno()), "b": (b.stdout.fileno(), relay_out)}, record=True)
            relay.start()
            relay.wait_on("b")       # its start-up XON
            a = subprocess.Popen(iut("--send", "48454C4C4F0D0A03"), stdin=a_in, stdout=a_w, stderr=subprocess.DEVNULL)
            os.close(a_w)
            os.close(a_in)
            relay.wait_on("a")
            time.sleep(3.0)
        finally:
            end = round(time.monotonic() - relay.t0, 6) if relay is not None else 0.0
            for proc in (a, b):
                if proc is not None:
                    stop_process(proc)
            if relay is not None:
                relay.stop()
        if relay.stall > STALL:
            return None
        return C.Capture([c for c in relay.chunks if c.t <= end], {"a": "ptpcert iut --send", "b": "ptpcert iut"},
                         C.LineSettings(9600, 8, "even", 1), end=end)

    cap = attempts(once)
    assert cap.wire_bytes("a").count(ETX) >= 3, "the stations did not keep the line busy"
    p = AsciiParams(cdt_ms=220, end_criterion="end_chars", end_chars=(ETX,), flow_control="xon_xoff")
    an = A.analyze(cap, kit_for(p, p, {"a": "echo", "b": "echo"}), resolution=p.char_time + 0.002)
    assert not fails(an), [f.message for f in fails(an)]
    assert sum(1 for e in an.exchanges if e.verdict == R.PASS) >= 3


def test_a_repeated_xoff_is_the_other_reading_of_q15():
    """Q15: the model sends XOFF once; a station that repeats it while its partner keeps
    sending takes the other reading: informational, never failed."""
    p = AsciiParams(cdt_ms=20, end_criterion="end_chars", end_chars=(ETX,), flow_control="xon_xoff", buffer_frames=1)
    c = p.char_time
    chunks = [C.Chunk(round(c, 6), "a", bytes([p.xon])), C.Chunk(round(c, 6), "b", bytes([p.xon]))]
    t = 1.0
    for x in b"AB\x03":                         # a's frame fills b's buffer (one frame): XOFF
        t += c
        chunks.append(C.Chunk(round(t, 6), "a", bytes([x])))
    chunks.append(C.Chunk(round(t + c, 6), "b", bytes([p.xoff])))
    for x in b"CD":                             # a goes on; b says XOFF again
        t += c
        chunks.append(C.Chunk(round(t + c, 6), "a", bytes([x])))
    chunks.append(C.Chunk(round(t + 2 * c, 6), "b", bytes([p.xoff])))
    cap = C.Capture(chunks, line=C.LineSettings(9600, 8, "even", 1), marks=[C.Mark(0.0, "power-on")], end=t + 2.0)
    an = A.analyze(cap, kit_for(p, p, {"a": "none", "b": "none"}), judge="b")
    assert not fails(an), [f.message for f in fails(an)]
    assert [(f.kind, f.readings) for f in an.findings] == [("reading", ("Q15",))], [f.message for f in an.findings]


def _echo_capture(reply: bytes, *more: tuple[float, bytes]) -> C.Capture:
    """Both stations switched on at 0 (without flow control: no start-up XON); a sends
    41 42 ETX at 0.1 s; b, an echo station, answers ``reply`` in one read at 0.2 s, then
    ``more``."""
    chunks = [C.Chunk(0.1, "a", b"\x41\x42\x03"), C.Chunk(0.2, "b", reply)]
    chunks += [C.Chunk(t, "b", d) for t, d in more]
    return C.Capture(chunks, {"a": "a", "b": "b"}, C.LineSettings(9600, 8, "even", 1), marks=[C.Mark(0.0, "power-on")])


def _echo_kit(app="echo-only"):
    p = replace(reference_profile().params, flow_control="none")
    return kit_for(p, p, apps={"a": "none", "b": app})


def _case_of_finding(an: A.Analysis, f: A.Finding) -> A.Exchange:
    (e,) = [e for e in an.line.exchanges if f in e.findings]
    return e


def test_an_echo_station_judged_on_its_own_exchange():
    """Issue 27, item 13: a wrong echo fails, on the echo station's exchange (the frame's
    characters read at once end up to the read's time, so the finding on its second
    character belongs to the chunk's exchange, not the one before); a frame of its own from
    an echo station fails (it sends back what it received, nothing else); the right echo
    passes."""
    kit = _echo_kit()
    assert not fails(A.analyze(_echo_capture(b"\x41\x42\x03"), kit))
    an = A.analyze(_echo_capture(b"\x41\x43\x03"), kit)
    (f,) = fails(an, "b")
    assert f.observed.startswith("43")
    e = _case_of_finding(an, f)
    assert an.line.chunks[e.first].seat == "b", "the wrong echo is shown on a's exchange"
    an = A.analyze(_echo_capture(b"\x41\x42\x03", (0.4, b"\x58\x59\x03")), kit)
    (f,) = fails(an, "b")
    assert f.observed.startswith("58") and "no frame of its own" in f.message
    # a station whose application echoes and may send frames of its own (a link's station), or
    # that does not echo, may send one
    for app in ("echo", "none"):
        assert not fails(A.analyze(_echo_capture(b"\x41\x42\x03", (0.4, b"\x58\x59\x03")), _echo_kit(app)))


def test_analyze_of_a_run_capture_takes_the_suites_echo_interface(tmp_path, capsys):
    """In a capture of a run, seat b is the suite's IUT, which sends back what it receives and
    nothing else: an unsolicited frame there fails (issue 27, item 13)."""
    cap = _echo_capture(b"\x41\x42\x03", (0.4, b"\x58\x59\x03"))
    cap.timing = C.Timing("sim", 0.0, 11 / 9600)
    path = tmp_path / "run.json"
    C.save(cap, path, "json")
    prof = tmp_path / "p.toml"
    prof.write_text(PROFILE.read_text().replace('flow_control = "xon_xoff"', 'flow_control = "none"'))
    assert cli_main(["analyze", str(path), "--profile", str(prof), "-q"]) == 1
    assert cli_main(["analyze", str(path), "--profile", str(prof), "-q", "--judge", "both"]) == 0
