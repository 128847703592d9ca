"""The HTML report (ptpcert.report.html): one self-contained file rendered from the results
object. Reports are built from real runs (the suite in-process on ``sim:``, in virtual
time) and from cases made here, for passing, failing, unsupported, errored and xpassed
cases; the output is parsed (html.parser for the page, xml.etree for each SVG diagram) and
checked: arrows in time order and per direction, labels, the divergence mark, the order of
the cases, anchors, self-containedness and size. One check renders a report in headless
Chromium and saves a screenshot under reports/ for a person to look at."""

from __future__ import annotations

import copy
import dataclasses
import re
import subprocess
import tempfile
import xml.etree.ElementTree as ET
from argparse import Namespace
from html.parser import HTMLParser
from pathlib import Path

import pytest

from ptpcert import results as R
from ptpcert.registry import by_id
from ptpcert.procedures.ascii import tokens as ascii_tokens
from ptpcert.procedures.p3964.tokens import tokens
from ptpcert.profile import load_profile
from ptpcert.report import anchor
from ptpcert.report import html as H
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets, vector_set_hash
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
CHROMIUM = Path("/usr/bin/chromium")
MB2 = 2 * 1024 * 1024
#: how the reports show a 3964/3964R run (the command line hands the procedure's view in)
VIEW = by_id("p3964").report_view()


# ------------------------------------------------------------------ building results
def sim_run(profile=None, select=None) -> R.RunResult:
    """The suite against the reference model in-process (virtual time: well under a second)."""
    profile = profile or load_profile(PROFILE)
    cases = load_suite(profile, load_vector_sets(), select=select)
    factory = make_factory("sim:", profile)
    runner = Runner(factory, profile, RunOptions(echo=profile.echo, check_status=profile.status_from_stderr))
    result = R.RunResult(tool_version="test", started="2026-01-01T00:00:00+00:00", iut="sim:",
                         profile=profile.to_dict(), profile_path=str(PROFILE), vector_set="bundled",
                         vector_set_hash=vector_set_hash(cases))
    try:
        runner.run(cases, result)
    finally:
        factory.shutdown()
    result.finished = "2026-01-01T00:00:01+00:00"
    return result


@pytest.fixture(scope="module")
def full_run() -> R.RunResult:
    r = sim_run()
    assert len(r.cases) >= 40
    return r


def case_by_id(run: R.RunResult, cid: str) -> R.CaseResult:
    return next(c for c in run.cases if c.id == cid)


def byte(t, d, b, step):
    return {"t": t, "dir": d, "kind": "byte", "byte": b, "step": step}


def exchange_transcript(t0: float = 0.0) -> list[dict]:
    """A 3964R block from the tester: STX / DLE / 31 10 10 32 DLE ETX BCC / DLE; then the IUT
    answers a second STX with NAK."""
    C = 0.001146
    tr = [byte(0.001146, "iut", 0x15, -1), {"dir": "note", "kind": "start", "t": 0.001146, "step": -1},
          byte(t0 + 2 * C, "tester", 0x02, 0),
          {"dir": "note", "kind": "window", "t0": t0 + 2 * C, "t1": t0 + 2 * C + 0.02,
           "label": "expect 10 in [0, ADT]", "step": 1},
          byte(t0 + 3 * C, "iut", 0x10, 1)]
    block = [0x31, 0x10, 0x10, 0x32, 0x10, 0x03, 0x23]
    for k, b in enumerate(block):
        tr.append(byte(t0 + (4 + k) * C, "tester", b, 2))
    tr.append(byte(t0 + 12 * C, "iut", 0x10, 3))
    tr.append(byte(t0 + 13 * C, "tester", 0x02, 4))
    tr.append(byte(t0 + 14 * C, "iut", 0x15, 5))
    return tr


def per_byte(transcript: list[dict]) -> list[dict]:
    """A transcript of runs (results schema 2) with one entry per byte (schema 1), which the
    views read as well: so a test can change one byte."""
    out = []
    for e in transcript:
        if e.get("kind") in R.RUN_KINDS:
            data = R.run_bytes(e)
            times = e.get("times") or [e["t"]] * len(data)
            out += [{"t": t, "dir": e["dir"], "kind": R.RUN_KINDS[e["kind"]], "byte": b, "step": e["step"]}
                    for t, b in zip(times, data)]
        else:
            out.append(dict(e))
    return out


def made_case(cid="TEST.EXCHANGE", verdict=R.PASS, transcript=None, divergence=None, **kw) -> R.CaseResult:
    c = R.CaseResult(id=cid, title=f"made-up case {cid}", reference="§2.2.2 Fig. 2-6", rule="a rule & <more>",
                     group=kw.pop("group", "receive"), iut_role="receiver", verdict=verdict,
                     transcript=exchange_transcript() if transcript is None else transcript,
                     divergence=divergence, params={"procedure": "3964R", "parity": "even"}, **kw)
    return c


def mixed_run(full_run: R.RunResult) -> R.RunResult:
    """Real cases of every kind: pass and unsupported from the sim run, an xpass (a real run
    with an expected failure listed), a failing and an errored case made from real ones."""
    run = copy.deepcopy(full_run)
    shown = ("3964R.FIG2-6.RECEIVE", "3964R.FIG2-7.PARITY", "3964R.D21.BREAK-DURING-RECEPTION")
    run.cases = [c for c in run.cases if c.verdict == R.PASS][:4] + \
        [c for c in run.cases if c.id in shown and c.verdict == R.PASS] + \
        [c for c in run.cases if c.verdict == R.UNSUPPORTED][:2]
    assert all(any(c.id == i for c in run.cases) for i in shown)
    # a failure: a real transcript, the IUT's DLE after the block replaced by NAK
    fail = copy.deepcopy(case_by_id(full_run, "3964R.FIG2-6.RECEIVE"))
    fail.id = "3964R.FIG2-6.RECEIVE-BROKEN"
    fail.transcript = per_byte(fail.transcript)
    t_div = _nth_iut_byte_time(fail, 0x10, 2)
    for e in fail.transcript:
        if e.get("kind") == "byte" and e["dir"] == "iut" and e["t"] == t_div:
            e["byte"] = 0x15
    fail.verdict = R.FAIL
    fail.message = "step 4: expected 10; received 15"
    fail.divergence = R.Divergence(step=3, time=t_div, expected="10", observed="received 15",
                                   window=(t_div - 0.001, t_div + 0.019))
    # an error: a harness fault, part of a transcript, a traceback in the notes
    err = copy.deepcopy(case_by_id(full_run, "3964R.D02.NAK-IN-IDLE"))
    err.id, err.verdict = "3964R.D02.NAK-IN-IDLE-ERR", R.ERROR
    err.message = "harness timing fault: step 1: the tester's byte 1 went out 80.0 ms late"
    err.notes = ["Traceback (most recent call last):\n  File \"x.py\", line 1\nRuntimeError: <boom>"]
    err.transcript = err.transcript[:2]
    err.stderr_tail = "STATUS 16#0808\nsomething on stderr <b>not html</b>"
    run.cases.insert(3, fail)          # in the middle: the report must put it first
    run.cases.append(err)
    # an xpass, from a real run that lists a passing case as an expected failure
    prof = load_profile(PROFILE)
    prof = dataclasses.replace(prof, expected_failures={"3964R.D03.GARBAGE-IN-IDLE": "known issue 7"})
    xp = sim_run(prof, select=["3964R.D03.GARBAGE-IN-IDLE"]).cases[0]
    assert xp.verdict == R.XPASS
    run.cases.insert(1, xp)
    return run


def _nth_iut_byte_time(c: R.CaseResult, value: int, n: int) -> float:
    ts = [t for t, d, kind, b, _ in R.wire_events(c.transcript) if kind == "byte" and d == "iut" and b == value]
    return ts[n - 1]


# ------------------------------------------------------------------ parsing the output
class Page(HTMLParser):
    """Sections of class "case" (id, verdict) in order, every id, every href."""

    def __init__(self, text: str):
        super().__init__(convert_charrefs=True)
        self.cases: list[tuple[str, str]] = []
        self.ids: list[str] = []
        self.hrefs: list[str] = []
        self.tags: list[str] = []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.append(tag)
        if "id" in a:
            self.ids.append(a["id"])
        if "href" in a:
            self.hrefs.append(a["href"])
        if tag == "section" and "case" in (a.get("class") or "").split():
            self.cases.append((a["id"], a["data-verdict"]))


def case_svgs(text: str) -> dict[str, ET.Element]:
    """Case anchor -> its diagram, parsed as XML."""
    out = {}
    for m in re.finditer(r'<section class="case[^"]*" id="([^"]+)".*?</section>', text, re.S):
        svg = re.search(r"<svg.*?</svg>", m.group(0), re.S)
        if svg:
            out[m.group(1)] = ET.fromstring(svg.group(0))
    return out


def groups(svg: ET.Element, cls: str) -> list[ET.Element]:
    return [g for g in svg.iter("g") if cls in (g.get("class") or "").split()]


def label(g: ET.Element) -> str:
    t = next(t for t in g.iter("text") if t.get("class") == "label")
    return t.text or ""


def path_points(g: ET.Element) -> tuple[float, float, float, float]:
    d = next(g.iter("path")).get("d")
    x0, y0, x1, y1 = map(float, re.match(r"M([\d.]+) ([\d.]+)L([\d.]+) ([\d.]+)", d).groups())
    return x0, y0, x1, y1


def render_one(c: R.CaseResult, view=VIEW) -> ET.Element:
    run = R.RunResult(tool_version="test", started="now", cases=[c])
    return case_svgs(H.render(run, view))[anchor(c.id)]


# ------------------------------------------------------------------ the diagram
def test_arrows_labels_directions_and_order():
    svg = render_one(made_case())
    arrows = groups(svg, "arrow")
    assert [(a.get("data-dir"), label(a)) for a in arrows] == [
        ("iut", "NAK"), ("tester", "STX"), ("iut", "DLE"),
        ("tester", "31 10 10 32 DLE ETX BCC=23"), ("iut", "DLE"), ("tester", "STX"), ("iut", "NAK")]
    ts = [float(a.get("data-t")) for a in arrows]
    assert ts == sorted(ts) and len(set(ts)) == len(ts)
    ys = []
    for a in arrows:
        x0, y0, x1, y1 = path_points(a)
        if a.get("data-dir") == "tester":
            assert x0 == H.TX and x1 == H.IX          # left to right
        else:
            assert x0 == H.IX and x1 == H.TX          # right to left
        assert y1 > y0                                # sloped: ends lower
        ys.append(y0)
    assert ys == sorted(ys)                           # time flows down
    # the block arrow carries its bytes; timestamps in ms on the side
    block = arrows[3]
    assert block.get("data-n") == "7"
    assert any(t.get("class") == "ts" and t.text == f"{float(block.get('data-t')) * 1000:.3f}" for t in block.iter("text"))
    # the timer window is drawn as a bar with its label
    (win,) = groups(svg, "window")
    assert "expect 10 in [0, ADT]" in "".join(win.itertext())
    assert groups(svg, "divergence") == []


def test_labels_3964_long_blocks_and_control_characters():
    assert tokens(bytes([0x02])) == ["STX"]
    assert tokens(bytes([0x15])) == ["NAK"]
    assert tokens(bytes([0x10])) == ["DLE"]
    assert tokens(bytes([0x03])) == ["ETX"]
    # inside a block, 02/03/15 are data; a doubled DLE is data; 3964 has no BCC
    assert tokens(bytes.fromhex("15 03 10 10 10 03"), "3964") == ["15", "03", "10", "10", "DLE", "ETX"]
    assert tokens(bytes.fromhex("41 10 03 52"), "3964R") == ["41", "DLE", "ETX", "BCC=52"]
    # the view names the bytes by the case's procedure; 3964R where its params name none
    assert VIEW.tokens(bytes.fromhex("41 10 03 52"), {"procedure": "3964"}) == ["41", "DLE", "ETX", "52"]
    assert VIEW.tokens(bytes.fromhex("41 10 03 52"), {}) == ["41", "DLE", "ETX", "BCC=52"]
    data = bytes([0x31, 0x10, 0x10, 0x32] + [0x41] * 1020 + [0x10, 0x03, 0x06])
    a = H.Arrow("tester", "byte", 0.0, 1.0, bytearray(data), 2)
    lab = H.arrow_label(a, VIEW, {"procedure": "3964R"})
    assert lab.startswith("31 10 10 32 41 41 … ") and lab.endswith("DLE ETX BCC=06 (1027 bytes)")
    assert len(lab) < 80
    # a character error
    e = H.Arrow("tester", "char_error", 0.0, 0.0, bytearray([0x32]), 3)
    assert H.arrow_label(e, VIEW, {"procedure": "3964R", "parity": "even"}) == "parity error 32"
    # RK 512 runs on the 3964R link: its blocks are named as 3964R names them
    rk = by_id("rk512").report_view()
    assert rk.tokens(bytes.fromhex("41 10 03 52"), {"link": "3964R"}) == ["41", "DLE", "ETX", "BCC=52"]
    assert rk.tokens(bytes([0x02]), {}) == ["STX"] and rk.cut_last is VIEW.cut_last


def test_bursts_are_grouped_and_single_control_characters_stay_alone():
    tr = [byte(0.001 * k, "iut", 0x41, 5) for k in range(2000)]       # 2000 bytes, 1 ms apart
    tr += [byte(2.5, "tester", 0x15, 6), byte(2.6, "iut", 0x02, 7), byte(2.601, "tester", 0x10, 8)]
    ev = H.group_events(tr, view=VIEW)
    assert [len(e.data) for e in ev] == [2000, 1, 1, 1]
    # a block cut short, then the sender's STX right after: the STX is its own arrow
    tr = [byte(0.001 * k, "iut", 0x41, 5) for k in range(5)] + [byte(0.005, "iut", 0x02, 5),
                                                                 byte(0.006, "tester", 0x10, 6)]
    ev = H.group_events(tr, view=VIEW)
    assert [bytes(e.data) for e in ev] == [b"AAAAA", b"\x02", b"\x10"]
    # a gap >= 20 ms splits a burst
    tr = [byte(0.0, "tester", 0x31, 2), byte(0.001, "tester", 0x32, 2), byte(0.030, "tester", 0x33, 2)]
    assert [len(e.data) for e in H.group_events(tr, view=VIEW)] == [2, 1]


def test_a_run_without_a_view_shows_each_byte_in_hex_and_the_groups_as_they_come(tmp_path):
    """No procedure's view: the report names no byte, cuts no burst and orders the groups
    as they appear in the run; JUnit and the header name no procedure."""
    div = R.Divergence(step=5, time=0.001146 * 14, expected="10", observed="received 15")
    cases = [made_case("TEST.T1", group="timing"), made_case("TEST.R", verdict=R.FAIL, divergence=div, group="receive"),
             made_case("TEST.S", group="start-up"), made_case("TEST.T2", group="timing")]
    svg = render_one(cases[0], view=None)
    assert [(a.get("data-dir"), label(a)) for a in groups(svg, "arrow")] == [
        ("iut", "15"), ("tester", "02"), ("iut", "10"), ("tester", "31 10 10 32 10 03 23"), ("iut", "10"),
        ("tester", "02"), ("iut", "15")]
    run = R.RunResult(tool_version="t", started="now", cases=cases)
    text = H.render(run)
    assert re.findall(r'<details class="group" data-group="([^"]+)"', text) == ["timing", "receive", "start-up"]
    assert "<h1>ptpcert conformance report</h1>" in text
    (mark,) = groups(case_svgs(text)[anchor("TEST.R")], "divergence")
    assert "expected 10; observed received 15" in " ".join(mark.itertext())
    # a block cut short by a new STX stays one burst
    tr = [byte(0.001 * k, "iut", 0x41, 5) for k in range(5)] + [byte(0.005, "iut", 0x02, 5),
                                                                 byte(0.006, "tester", 0x10, 6)]
    assert [bytes(e.data) for e in H.group_events(tr)] == [b"AAAAA\x02", b"\x10"]
    # with the procedure's view: its names and the manual's order of the groups
    text = H.render(run, VIEW)
    assert re.findall(r'<details class="group" data-group="([^"]+)"', text) == ["start-up", "receive", "timing"]
    (mark,) = groups(case_svgs(text)[anchor("TEST.R")], "divergence")
    assert "expected 10 (DLE); observed received 15 (NAK)" in " ".join(mark.itertext())
    # the JUnit suite is named by the run's procedure, neutrally without one
    from ptpcert.report import write_junit
    write_junit(run, tmp_path / "j.xml")
    assert ET.parse(tmp_path / "j.xml").getroot().find("testsuite").get("name") == "ptpcert conformance"
    write_junit(dataclasses.replace(run, procedure="ASCII driver"), tmp_path / "j.xml")
    assert ET.parse(tmp_path / "j.xml").getroot().find("testsuite").get("name") == "ptpcert ASCII driver conformance"


def test_ascii_bytes_are_named_as_the_cases_settings_give_them():
    flow = {"flow_control": "xon_xoff", "xon": 0x11, "xoff": 0x13, "end_criterion": "cdt", "end_chars": [0x03]}
    assert ascii_tokens.tokens(bytes.fromhex("11 41 03 13"), flow) == ["XON", "41", "03", "XOFF"]
    # other XON/XOFF codes; no flow control: no XON/XOFF; no 3964 names (02, 10, 15 are data)
    assert ascii_tokens.tokens(bytes.fromhex("05 11 06"), dict(flow, xon=0x05, xoff=0x06)) == ["XON", "11", "XOFF"]
    assert ascii_tokens.tokens(bytes.fromhex("11 13"), dict(flow, flow_control="none")) == ["11", "13"]
    assert ascii_tokens.tokens(bytes.fromhex("02 10 15"), flow) == ["02", "10", "15"]
    # end characters under the end-character criterion: two only as the pair in order
    end = {"flow_control": "none", "end_criterion": "end_chars", "end_chars": [0x0D, 0x0A]}
    assert ascii_tokens.tokens(b"AB\r\nC\n\r", end) == ["41", "42", "CR", "LF", "43", "0A", "0D"]
    assert ascii_tokens.tokens(b"A$", dict(end, end_chars=[0x24])) == ["41", "END=24"]
    assert ascii_tokens.tokens(b"A\x03", dict(end, end_chars="03")) == ["41", "03"]   # not codes: nothing named
    # the view in a report: arrow labels and the divergence's words
    view = by_id("ascii").report_view()
    params = dict(flow, end_criterion="end_chars")
    tr = [byte(0.0, "iut", 0x11, -1), byte(0.010, "tester", 0x41, 0), byte(0.011, "tester", 0x03, 0),
          byte(0.050, "iut", 0x13, 1)]
    div = R.Divergence(step=1, time=0.050, expected="41 03", observed="received 13")
    c = made_case("ASCII.X", verdict=R.FAIL, transcript=tr, divergence=div, group="flow-control")
    c.params = params
    svg = render_one(c, view)
    assert [label(a) for a in groups(svg, "arrow")] == ["XON", "41 ETX", "XOFF"]
    (mark,) = groups(svg, "divergence")
    assert "expected 41 03; observed received 13 (XOFF)" in " ".join(mark.itertext())
    assert view.groups == by_id("ascii").groups


def test_break_and_character_error_are_marked():
    C = 0.001146
    tr = [byte(C, "tester", 0x02, 0), byte(2 * C, "iut", 0x10, 1), byte(3 * C, "tester", 0x31, 2),
          {"t": 4 * C, "dir": "tester", "kind": "char_error", "byte": 0x32, "step": 3},
          {"t": 5 * C, "dir": "tester", "kind": "break", "duration": 0.02, "step": 4},
          byte(0.2, "tester", 0x02, 5)]
    svg = render_one(made_case("TEST.LINE", transcript=tr))
    lc = groups(svg, "line-condition")
    kinds = [g.get("data-kind") for g in lc]
    assert kinds == ["char_error", "break"]
    assert label(lc[0]) == "parity error 32"
    assert "BREAK" in label(lc[1]) and "20.0 ms" in label(lc[1])
    assert lc[1].find("polyline") is not None     # the zig-zag
    # parity "none": a framing error
    c = made_case("TEST.LINE2", transcript=tr)
    c.params["parity"] = "none"
    assert label(groups(render_one(c), "line-condition")[0]) == "framing error 32"


def test_long_quiet_gaps_are_compressed():
    tr = exchange_transcript()
    tr.append(byte(0.420, "tester", 0x02, 6))     # ~400 ms later
    tr.append(byte(0.421, "iut", 0x10, 7))
    svg = render_one(made_case("TEST.GAP", transcript=tr))
    (gap,) = groups(svg, "gap")
    assert 390 < float(gap.get("data-ms")) < 410
    assert "≈" in "".join(gap.itertext())
    assert int(svg.get("height")) < 500           # 400 ms drawn in well under 1000 px


def test_very_long_case_stays_compact_and_keeps_the_divergence():
    tr, t = [], 0.0
    for k in range(400):                          # 800 arrows: STX / NAK ping-pong, 30 ms apart
        tr.append(byte(t, "tester", 0x02, 2 * k))
        tr.append(byte(t + 0.002, "iut", 0x15, 2 * k + 1))
        t += 0.030
    t_div = tr[401]["t"]                          # an IUT NAK in the middle
    div = R.Divergence(step=401, time=t_div, expected="10", observed="received 15")
    svg = render_one(made_case("TEST.LONG", verdict=R.FAIL, transcript=tr, divergence=div))
    assert int(svg.get("height")) <= H.MAX_H + 200
    assert groups(svg, "elided")
    arrows = groups(svg, "arrow")
    assert 20 < len(arrows) < 100
    ts = [float(a.get("data-t")) for a in arrows]
    assert ts == sorted(ts)
    assert any(abs(x - t_div) < 1e-6 and a.get("data-diverged") for x, a in zip(ts, arrows))
    assert ts[0] == 0.0 and abs(ts[-1] - tr[-1]["t"]) < 1e-6   # the start and the end are kept


# ------------------------------------------------------------------ the whole report
def test_report_of_every_kind_of_case(full_run, tmp_path):
    run = mixed_run(full_run)
    out = tmp_path / "sub" / "report.html"
    H.write_html(run, out, VIEW)
    text = out.read_text("utf-8")
    page = Page(text)

    # every case once, anchored as the console and JUnit views link to it
    assert sorted(cid for cid, _ in page.cases) == sorted(anchor(c.id) for c in run.cases)
    assert len(set(page.ids)) == len(page.ids)
    for href in page.hrefs:
        assert href.startswith("#") and href[1:] in page.ids, href
    # failures first (fail, xpass, error), then the rest
    verdicts = [v for _, v in page.cases]
    n_bad = sum(v in (R.FAIL, R.XPASS, R.ERROR) for v in verdicts)
    assert n_bad == 3
    assert set(verdicts[:n_bad]) == {R.FAIL, R.XPASS, R.ERROR}
    # header: tool, IUT, profile, vector set hash, overall verdict, counts, wall time
    for s in ("ptpcert test", "sim:", "3964R", run.vector_set_hash, "vector set hash", "wall time", "interrupted"):
        assert s in text, s
    # the profile in its file's words: each key with its value as the profile writes it
    for key, value in (("character_delay_ms", "20"), ("acknowledgement_delay_ms", "20"), ("baud_rate", "9600"),
                       ("data_bits", "8"), ("parity", "&quot;even&quot;"), ("stop_bits", "1")):
        assert f"<tr><th>{key}</th><td>{value}</td></tr>" in text, key
    assert re.search(r"overall verdict <span class=\"v v-fail overall\">fail</span>", text)
    # a summary by manual section, each expandable, with a filter by verdict
    for g in {c.group for c in run.cases}:
        assert f'<details class="group" data-group="{g}">' in text
    assert '<nav id="filter" hidden>' in text and 'data-v="xpass"' in text

    svgs = case_svgs(text)
    fail = next(c for c in run.cases if c.verdict == R.FAIL)
    # the divergence mark: exactly once, in the failing case, at the divergence's time
    marks = {a: groups(s, "divergence") for a, s in svgs.items()}
    assert [a for a, m in marks.items() if m] == [anchor(fail.id)]
    (mark,) = marks[anchor(fail.id)]
    assert float(mark.get("data-t")) == pytest.approx(fail.divergence.time, abs=1e-6)
    assert float(mark.get("data-t0")) == pytest.approx(fail.divergence.window[0], abs=1e-6)
    text_of_mark = " ".join(mark.itertext())
    assert "expected 10 (DLE)" in text_of_mark and "observed received 15 (NAK)" in text_of_mark
    # ... drawn where that time is: on the arrow that diverged, between its neighbours
    fsvg = svgs[anchor(fail.id)]
    arrows = groups(fsvg, "arrow")
    (hit,) = [a for a in arrows if a.get("data-diverged")]
    assert hit.get("data-dir") == "iut" and label(hit) == "NAK"
    y_mark = float(re.match(r"M[\d.]+ ([\d.]+)", mark.find("path").get("d")).group(1))
    assert y_mark == pytest.approx(path_points(hit)[1], abs=0.11)
    before = [path_points(a)[1] for a in arrows if float(a.get("data-t")) < fail.divergence.time]
    after = [path_points(a)[1] for a in arrows if float(a.get("data-t")) > fail.divergence.time]
    assert max(before) < y_mark < min(after)

    # real passing cases: arrows in time order, labels with the control characters named
    fig = svgs[anchor("3964R.FIG2-6.RECEIVE")]
    labs = [(a.get("data-dir"), label(a)) for a in groups(fig, "arrow")]
    assert ("tester", "STX") in labs and ("iut", "DLE") in labs
    assert any(d == "tester" and "DLE ETX BCC=" in lab for d, lab in labs)
    for s in svgs.values():
        ts = [float(a.get("data-t")) for a in groups(s, "arrow")]
        assert ts == sorted(ts)
    # an unsupported case has no diagram, but says why
    unsup = next(c for c in run.cases if c.verdict == R.UNSUPPORTED)
    assert anchor(unsup.id) not in svgs
    assert H.esc(unsup.message) in text
    # the errored case: its message, notes and stderr, escaped
    assert "harness timing fault" in text and "RuntimeError: &lt;boom&gt;" in text
    assert "&lt;b&gt;not html&lt;/b&gt;" in text and "<b>not html</b>" not in text
    assert "a rule & <more>" not in text
    # STATUS codes with the catalogue's short names
    assert "Block check character mismatch" in text or "16#0" in text


def test_status_events_expected_and_observed():
    c = made_case("TEST.STATUS", observed_status=["16#0808", "16#7777"], status_checked=True,
                  expected_status="16#0808 (may also raise 16#0801)", expected_status_codes=[["16#0808"]],
                  tester_status="16#0706")
    text = H.render(R.RunResult(tool_version="t", started="now", cases=[c]))
    assert "Block check character mismatch" in text       # 16#0808's short name
    assert "not in the catalogue" in text                  # an unknown code is tolerated
    assert '<span class="st unexpected"' in text           # 16#7777 was not expected
    assert "16#0706" in text and "tester" in text
    assert '<section id="status">' in text                 # the legend with the full texts


def test_self_contained_and_escaped(full_run, tmp_path):
    run = mixed_run(full_run)
    run.iut = "exec:./iut --name '<script>alert(1)</script>'"
    text = H.render(run)
    assert "http://" not in text and "https://" not in text
    assert not re.search(r"<(link|img|iframe|object|embed)\b", text)
    assert not re.search(r"\bsrc=", text) and "@import" not in text and "url(" not in text
    assert "<script>alert(1)</script>" not in text
    assert text.count("<script>") == 1                     # ours: the filter


def test_full_suite_and_large_cases_stay_under_2mb(full_run):
    run = copy.deepcopy(full_run)
    big = [c for c in run.cases if len(R.wire_events(c.transcript)) > 1000]
    assert big, "the suite has cases with 1000-byte blocks"
    # about 100 cases, a quarter of them with 2000-byte transcripts, some failing
    while len(run.cases) < 100:
        run.cases.append(copy.deepcopy(big[len(run.cases) % len(big)]))
        run.cases[-1].id += f".COPY{len(run.cases)}"
    for i, c in enumerate(run.cases[:25]):
        c.transcript = copy.deepcopy(big[i % len(big)].transcript)
        if i % 3 == 0:
            c.verdict = R.FAIL
            c.divergence = R.Divergence(step=3, time=c.transcript[-1].get("t", 0.1), expected="41 " * 1000,
                                        observed="nothing received")
            c.message = "step 4: expected " + "41 " * 1000
    text = H.render(run)
    size = len(text.encode("utf-8"))
    print(f"report of {len(run.cases)} cases: {size} bytes")
    assert size < MB2, f"{size} bytes"
    assert len(case_svgs(text)) >= 100 - sum(c.verdict == R.UNSUPPORTED for c in run.cases)


def test_cli_report_renders_saved_results(full_run, tmp_path):
    from ptpcert.cli.reports import cmd_report

    j = tmp_path / "r.json"
    mixed_run(full_run).write_json(j)
    out = tmp_path / "r.html"
    assert cmd_report(Namespace(results=str(j), html=str(out), junit=None)) == 0
    text = out.read_text("utf-8")
    assert text.startswith("<!DOCTYPE html>") and "3964R.FIG2-6.RECEIVE-BROKEN" in text
    assert len(case_svgs(text)) >= 8


@pytest.mark.parametrize("title,named", [("3964/3964R", True), ("RK 512", True), ("", False), ("no such", False)])
def test_cli_report_shows_saved_results_with_the_view_of_their_procedure(tmp_path, title, named):
    """``ptpcert report`` finds the procedure by the title the results carry; without one it
    falls back to the neutral view."""
    from ptpcert.cli.reports import cmd_report

    run = R.RunResult(tool_version="t", started="now", procedure=title, cases=[made_case()])
    j, out = tmp_path / "r.json", tmp_path / "r.html"
    run.write_json(j)
    assert cmd_report(Namespace(results=str(j), html=str(out), junit=None)) == 0
    labs = [label(a) for a in groups(case_svgs(out.read_text("utf-8"))[anchor("TEST.EXCHANGE")], "arrow")]
    assert labs[3] == ("31 10 10 32 DLE ETX BCC=23" if named else "31 10 10 32 10 03 23")


def test_interrupted_run_and_empty_cases():
    c = R.CaseResult("X.NOT-RUN", "not reached", "§1", "rule", "timing", "receiver",
                     verdict=R.NOT_RUN, message="run interrupted")
    run = R.RunResult(tool_version="t", started="now", cases=[c], interrupted=True)
    text = H.render(run)
    assert "interrupted" in text and "no transcript" in text
    assert Page(text).cases == [(anchor("X.NOT-RUN"), R.NOT_RUN)]


# ------------------------------------------------------------------ a person's view
@pytest.mark.realtime
def test_screenshot_in_headless_chromium(full_run):
    if not CHROMIUM.exists():
        pytest.skip("/usr/bin/chromium is not installed (Debian package 'chromium'); "
                    "no screenshot of the HTML report taken")
    run = mixed_run(full_run)
    reports = ROOT / "reports"
    reports.mkdir(exist_ok=True)
    page = reports / "report-sample.html"
    png = reports / "report-screenshot.png"
    H.write_html(run, page, VIEW)
    if png.exists():
        png.unlink()
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             "--hide-scrollbars"]
    with tempfile.TemporaryDirectory() as profile_dir:
        p = subprocess.run([str(CHROMIUM), *flags, f"--user-data-dir={profile_dir}", f"--screenshot={png}",
                            "--window-size=1400,2600", page.as_uri()],
                           capture_output=True, text=True, timeout=60)
        assert png.exists(), p.stderr[-2000:]
    # the script ran: the filter bar is shown once the page has loaded, and a link to a
    # case (here a passing one, collapsed by default) opens it
    target = anchor("3964R.D21.BREAK-DURING-RECEPTION")
    with tempfile.TemporaryDirectory() as profile_dir:
        dom = subprocess.run([str(CHROMIUM), *flags, f"--user-data-dir={profile_dir}", "--dump-dom",
                              page.as_uri() + "#" + target], capture_output=True, text=True, timeout=60).stdout
    head = png.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
    assert width == 1400 and height == 2600
    assert png.stat().st_size > 20_000                      # not a blank page
    assert '<nav id="filter">' in dom
    assert re.search(f'id="{target}" data-verdict="pass"><details open', dom)


#: run in the page before its own script: collects what would go to the console as errors
PROBE_HEAD = """<script>window.__errors=[];
window.addEventListener('error',function(e){window.__errors.push('error: '+e.message);});
window.addEventListener('unhandledrejection',function(e){window.__errors.push('rejection: '+e.reason);});
(function(){var ce=console.error;console.error=function(){window.__errors.push('console.error: '+
Array.prototype.join.call(arguments,' '));return ce.apply(console,arguments);};})();</script>"""

#: run after the page's own script: opens every case, measures the sequence diagrams, works
#: the verdict filter as a person would (a click on a check box), and writes what it saw
PROBE_TAIL = """<script>(function(){
function shown(el){return el.getClientRects().length>0;}
function count(v){return Array.prototype.filter.call(document.querySelectorAll('section.case[data-verdict="'+v+'"]'),shown).length;}
var out={errors:window.__errors,filterShown:shown(document.getElementById('filter'))};
document.getElementById('expand-all').click();
var svgs=document.querySelectorAll('svg.seq');out.svgs=svgs.length;
out.sized=Array.prototype.filter.call(svgs,function(s){var r=s.getBoundingClientRect();return r.width>=200&&r.height>=40;}).length;
out.before={pass:count('pass'),fail:count('fail')};
var box=document.querySelector('#filter input[data-v="pass"]');box.click();
out.after={pass:count('pass'),fail:count('fail')};
box.click();out.again={pass:count('pass'),fail:count('fail')};
out.errors=window.__errors;
var pre=document.createElement('pre');pre.id='probe';pre.textContent=JSON.stringify(out);document.body.appendChild(pre);
})();</script>"""


def probe_in_chromium(text: str, tail: str, tmp_path: Path) -> tuple[dict, str]:
    """The page ``text`` opened in headless Chromium with :data:`PROBE_HEAD` before its own
    script and ``tail`` after it; what the probe wrote (its ``<pre id="probe">``, JSON) and
    Chromium's standard error."""
    import html as _html
    import json as _json

    page = tmp_path / "probe.html"
    page.write_text(text.replace("<head>", "<head>" + PROBE_HEAD).replace("</body>", tail + "</body>"), "utf-8")
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", "--window-size=1400,1000",
             "--enable-logging=stderr", "--v=0"]
    with tempfile.TemporaryDirectory() as profile_dir:
        p = subprocess.run([str(CHROMIUM), *flags, f"--user-data-dir={profile_dir}", "--dump-dom", page.as_uri()],
                           capture_output=True, text=True, timeout=90)
    m = re.search(r'<pre id="probe">(.*?)</pre>', p.stdout, re.S)
    assert m, "the probe did not run: " + p.stderr[-2000:]
    return _json.loads(_html.unescape(m.group(1))), p.stderr


#: after the certificate: what a person sees (the verdict, the digest, the tables) and the errors
CERTIFICATE_TAIL = """<script>(function(){
function shown(el){return !!el&&el.getClientRects().length>0;}
var d=document.getElementById('bundle-digest');
var out={errors:window.__errors,digest:d?d.textContent:'',digestShown:shown(d),
verdict:(document.querySelector('.verdict')||{}).textContent||'',tables:document.querySelectorAll('table').length,
height:document.body.scrollHeight};
var pre=document.createElement('pre');pre.id='probe';pre.textContent=JSON.stringify(out);document.body.appendChild(pre);
})();</script>"""


@pytest.mark.realtime
def test_the_certificate_renders_in_headless_chromium(full_run, tmp_path):
    """The evidence bundle's one-page certificate in a real browser: no console errors, the
    verdict and the bundle's digest shown, short enough to print."""
    if not CHROMIUM.exists():
        pytest.skip("/usr/bin/chromium is not installed (Debian package 'chromium'; .ci/run installs it)")
    from ptpcert.evidence.facts import tool_facts
    from ptpcert.report.html.certificate import render_certificate

    run = mixed_run(full_run)
    run.iut_identity = {"vendor": "ACME <Automation>", "product": "PtP-9"}
    profile = load_profile(PROFILE)
    digest = "ab" * 32
    text = render_certificate(run, tool=tool_facts(load_suite(profile, load_vector_sets())), digest=digest)
    assert "<script" not in text and "http" not in text                 # self-contained, nothing to fetch
    assert "ACME &lt;Automation&gt;" in text
    seen, stderr = probe_in_chromium(text, CERTIFICATE_TAIL, tmp_path)
    assert seen["errors"] == [] and "Uncaught" not in stderr, (seen["errors"], stderr[-2000:])
    assert seen["digest"] == digest and seen["digestShown"]
    assert seen["verdict"] == run.verdict.upper() and seen["tables"] >= 3
    assert seen["height"] < 4000                                          # a page or two, printable


@pytest.mark.realtime
def test_the_report_works_in_headless_chromium(full_run, tmp_path):
    """In a real browser (headless Chromium, its DOM dumped after a script that works the
    page): no console errors, every sequence diagram has a visible size once its case is
    open, and the verdict filter hides the cases of a verdict and shows them again."""
    if not CHROMIUM.exists():
        pytest.skip("/usr/bin/chromium is not installed (Debian package 'chromium'; .ci/run installs it)")
    text = H.render(mixed_run(full_run))
    assert text.count("<head>") == 1 and text.count("</body>") == 1
    seen, stderr = probe_in_chromium(text, PROBE_TAIL, tmp_path)
    assert seen["errors"] == [] and "Uncaught" not in stderr, (seen["errors"], stderr[-2000:])
    assert seen["filterShown"]                                  # the script ran and showed the filter
    want = len(case_svgs(text))
    assert want >= 8 and seen["svgs"] == want and seen["sized"] == want, seen
    verdicts = [v for _, v in Page(text).cases]
    assert seen["before"] == {"pass": verdicts.count("pass"), "fail": verdicts.count("fail")}, seen
    assert seen["before"]["pass"] > 0 and seen["before"]["fail"] > 0
    assert seen["after"] == {"pass": 0, "fail": seen["before"]["fail"]}, seen   # only the passes hidden
    assert seen["again"] == seen["before"], seen


def test_traceability_section_gives_each_rule_this_runs_verdict():
    from ptpcert.report.html.rules import rule_verdicts, traceability_section
    from ptpcert.rules import for_procedure

    cat = for_procedure("p3964")
    run = R.RunResult(tool_version="t", started="", procedure="3964/3964R",
                      profile={"procedure": "3964R", "priority": "low", "data_bits": 8})
    run.cases = [
        R.CaseResult("SUITE.A", "passes", "§1", "r.", "idle", "idle", verdict=R.PASS, rules=["3964.IDLE.STRAY-NAK"]),
        R.CaseResult("SUITE.B", "fails", "§1", "r.", "idle", "idle", verdict=R.FAIL,
                     rules=["3964.IDLE.STRAY-NAK", "3964.START.NAK"]),
        R.CaseResult("SUITE.C", "grades", "§1", "r.", "receive", "receiver", verdict=R.NON_STRICT,
                     rules=["3964.RX.LENGTH"]),
    ]
    v = rule_verdicts(run, cat)
    assert v["3964.IDLE.STRAY-NAK"][0] == R.FAIL and [c.id for c in v["3964.IDLE.STRAY-NAK"][1]] == ["SUITE.A", "SUITE.B"]
    assert v["3964.START.NAK"][0] == R.FAIL and v["3964.RX.LENGTH"][0] == R.NON_STRICT
    assert v["3964.RX.ACK"][0] == "not run" and v["3964.FRAME.INTERFACE"][0] == "untestable"
    assert v["3964.RX.ANSWER-AT-ETX"][0] == "does not apply"   # 3964 only; this IUT is 3964R
    section = traceability_section(run)
    assert 'id="traceability"' in section and "3964.IDLE.STRAY-NAK" in section
    assert '<a href="#' in section and "A17" in section and "docs/readings.md" in section
    from ptpcert.report.html import render
    page = render(run)
    assert page.index('id="summary"') < page.index('id="traceability"') < page.index('id="cases"')
    # a run of a procedure without a catalogue has no such section
    other = R.RunResult(tool_version="t", started="", procedure="no such procedure")
    assert traceability_section(other) == ""


def test_json_results_carry_each_cases_rule_ids(tmp_path):
    run = R.RunResult(tool_version="t", started="")
    run.cases = [R.CaseResult("SUITE.A", "t", "§1", "r.", "idle", "idle", verdict=R.PASS, rules=["3964.START.NAK"])]
    run.write_json(tmp_path / "r.json")
    back = R.RunResult.read_json(tmp_path / "r.json")
    assert back.cases[0].rules == ["3964.START.NAK"]


def test_each_procedure_s_settings_show_as_its_profile_keys(tmp_path):
    """The HTML and JUnit reports show a run's profile as the profile file writes it, for
    every procedure: each key of the procedure's schema that the run's profile has, as
    ``table.key``, character codes in hex, booleans as true/false; no Python dict, no None."""
    import re
    import subprocess
    import sys

    from ptpcert.profile import load_profile
    from ptpcert.registry import by_id

    root = Path(__file__).resolve().parents[2] / "conformance" / "profiles"
    for name, pid, glob in (("ascii-reference", "ascii", "ASCII.BUF*"), ("rk512-reference", "rk512", "RK512.ERR*"),
                            ("reference-20ms", "p3964", "3964R.D06*")):
        h, x = tmp_path / f"{name}.html", tmp_path / f"{name}.xml"
        p = subprocess.run([sys.executable, "-m", "ptpcert.cli", "run", "--iut", "sim:", "--profile",
                            str(root / f"{name}.toml"), "-q", "--html", str(h), "--junit", str(x), "--select", glob],
                           capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, p.stderr
        html, xml = h.read_text(), x.read_text()
        header = html[html.index("IUT profile"):html.index("</header>")]
        for bad in ("None", "{'", "{&#x27;", "True", "False", "priority ?"):
            assert bad not in header and f'value="{bad}' not in xml, (name, bad)
        prof = load_profile(root / f"{name}.toml")
        for key in by_id(pid).profile_schema():
            shown = key.name if key.table == "iut" else f"{key.table}.{key.name}"
            if key.default in (None, []) and not prof.to_dict().get(key.table, prof.to_dict()).get(key.name):
                continue   # left out, and its silence says it ("either is accepted", none): nothing to show
            if key.applies({**{k.name: k.default for k in by_id(pid).profile_schema() if not k.required},
                            **prof.to_dict(), **prof.to_dict().get(key.table, {})}):
                assert f"<th>{shown}</th>" in header, (name, shown)
                assert f'name="profile.{shown}"' in xml, (name, shown)
        if pid == "ascii":
            assert re.search(r"<th>ascii\.xon</th><td>0x[0-9A-F]{2}</td>", header)
            assert "<th>ascii.end_chars</th><td>[0x03]</td>" in header
