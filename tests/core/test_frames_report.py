"""Frames in the reports: the frames a procedure finds in a transcript (``CaseResult.frames``)
are drawn in the HTML sequence diagram (a band and bracket on the sender's side, the decoded
label, marks as ticks, windows as shaded spans, the divergence's frame marked), listed in the
text transcripts, named decoded in the JUnit failure message and the console summary, and
kept by the JSON results. RK 512 runs in ``sim:`` (virtual time): the reference and a broken
variant whose divergence falls in a frame."""

from __future__ import annotations

import html as _html
import json
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
from rk512_profiles import rk_profile

from ptpcert import report
from ptpcert import results as R
from ptpcert.registry import by_id
from ptpcert.procedures.rk512.frames import decode_blocks
from ptpcert.procedures.rk512.model import codec as rk
from ptpcert.report import html as H
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

RK = by_id("rk512")
SEND_200 = "SUITE.RK512.P-02.SEND-200"
FETCH_300 = "SUITE.RK512.P-05.FETCH-E-300"
MUTANT = "continuation-response-id-00"   # a continuation response begins 00h, not FFh


def run(url: str, select: list[str]) -> R.RunResult:
    profile = rk_profile()
    cases = load_suite(profile, load_vector_sets(), select=select)
    res = R.RunResult(tool_version="test", started="2026-01-01T00:00:00+00:00", iut=url,
                      procedure="RK 512", profile=profile.to_dict())
    factory = make_factory(url, profile)
    try:
        Runner(factory, profile, RunOptions()).run(cases, res)
    finally:
        factory.shutdown()
    return res


@pytest.fixture(scope="module")
def reference() -> R.RunResult:
    return run("sim:", [SEND_200, FETCH_300])


@pytest.fixture(scope="module")
def broken() -> R.RunResult:
    return run(f"sim:?mutant={MUTANT}", [SEND_200])


def case(res: R.RunResult, cid: str) -> R.CaseResult:
    return next(c for c in res.cases if c.id == cid)


def frame_groups(c: R.CaseResult) -> list[ET.Element]:
    svg = ET.fromstring(H.sequence_svg(c))
    return [g for g in svg.iter("g") if g.get("class") == "frame"]


# ------------------------------------------------------------------ the diagram
def test_each_frame_of_the_reference_is_drawn_with_its_decoded_label(reference):
    for cid in (SEND_200, FETCH_300):
        c = case(reference, cid)
        assert c.verdict == R.PASS, c.message
        # SEND 200: the first frame and one continuation, each answered, then the same for
        # the FETCH that reads the data back; FETCH 300: the command and a continuation
        # FETCH for each further chunk, each answered (§2.2.3: 128 bytes a frame)
        chunks = len(rk.chunk_sizes(200 if cid == SEND_200 else 300))
        assert len(c.frames) == (2 * 2 * chunks if cid == SEND_200 else 2 * chunks)
        groups = frame_groups(c)
        assert len(groups) == len(c.frames)
        for f, g in zip(c.frames, groups):
            # the label is the decoder's reading of the frame's content
            assert f["label"].startswith(rk.describe(bytes.fromhex(f["frame"])))
            assert g.get("data-dir") == f["dir"]
            assert abs(float(g.get("data-t0")) - f["t0"]) < 1e-6
            assert f["label"] in g.find("title").text
            shown = [t.text for t in g.iter("text") if t.get("class") == "flabel"]
            assert shown and shown[0].rstrip("…") in f["label"]
            assert g.get("data-diverged") is None
        senders = [f["dir"] for f in c.frames]
        assert senders == ["tester", "iut"] * (len(c.frames) // 2)


def test_the_send_is_labelled_as_the_manual_lays_out_its_frames(reference):
    c = case(reference, SEND_200)
    first, _, cont, _ = (f["label"] for f in c.frames[:4])
    # 200 bytes: 128 in the first frame, 72 in the continuation (§2.2.3)
    size = rk.chunk_sizes(200)
    assert size[0] == 128 and sum(size) == 200
    assert first.startswith("SEND DB") and "200 bytes" in first and f"({size[0]} in this frame)" in first
    assert cont.startswith(f"continuation SEND {size[1]} bytes")
    page = H.render(reference)
    for f in c.frames:
        assert _html.escape(f["label"], quote=True) in page


def test_the_divergences_frame_is_drawn_marked_with_what_was_expected(broken):
    c = case(broken, SEND_200)
    assert c.verdict == R.FAIL and c.divergence is not None
    hit = [f for f in c.frames if f.get("diverged")]
    assert len(hit) == 1 and hit[0]["dir"] == "iut"
    f = hit[0]
    assert f["t0"] - 1e-6 <= c.divergence.time <= f["t1"] + 1e-6
    # what the step expected there: the continuation response of §2.2.3, decoded
    assert f["expected"] == rk.describe(rk.response(first=False))
    assert f["label"] != f["expected"]
    groups = frame_groups(c)
    marked = [g for g in groups if g.get("data-diverged") == "1"]
    assert len(marked) == 1 and abs(float(marked[0].get("data-t0")) - f["t0"]) < 1e-6
    assert f["expected"] in marked[0].find("title").text
    # the frames before it are drawn too, unmarked
    assert len(groups) == len(c.frames) >= 3
    page = H.render(broken)
    assert _html.escape(R.divergence_frame_text(c), quote=True) in page


def test_marks_and_windows_are_drawn_as_ticks_and_shaded_spans():
    c = R.CaseResult(id="X", title="t", reference="r", rule="r", group="g", iut_role="receiver")
    c.transcript = [{"t": 0.001 * i, "dir": "tester", "kind": "byte", "byte": b, "step": 0}
                    for i, b in enumerate(b"AB\x03")]
    c.frames = [{"dir": "tester", "t0": 0.0, "t1": 0.002, "label": "frame 'AB' ETX",
                 "marks": [{"t": 0.002, "name": "ETX"}],
                 "windows": [{"t0": 0.002, "t1": 0.022, "name": "CDT"}]}]
    c.case_time = 0.03
    (g,) = frame_groups(c)
    marks = [m for m in g.iter("g") if m.get("class") == "mark"]
    wins = [w for w in g.iter("g") if w.get("class") == "fwindow"]
    assert [m.find("text").text for m in marks] == ["ETX"]
    assert float(marks[0].get("data-t")) == pytest.approx(0.002)
    assert [w.find("text").text for w in wins] == ["CDT"]
    rect = wins[0].find("rect")
    assert float(rect.get("height")) > 3          # a span, not a line
    assert "ETX at 2.000 ms" in g.find("title").text and "CDT 2.000–22.000 ms" in g.find("title").text
    # the text transcripts name them too
    assert "ETX at 2.000 ms; CDT 2.000–22.000 ms" in H.transcript_section(c)
    assert "[ETX at 2.000 ms; CDT 2.000-22.000 ms]" in "\n".join(report.frame_lines(c))


# ------------------------------------------------------------------ text views
def test_the_junit_message_and_the_summary_name_the_decoded_frame(broken, tmp_path):
    c = case(broken, SEND_200)
    f = next(f for f in c.frames if f.get("diverged"))
    path = tmp_path / "junit.xml"
    report.write_junit(broken, path)
    (failure,) = ET.parse(path).getroot().iter("failure")
    msg = failure.get("message")
    assert f"in the IUT's frame \"{f['label']}\"" in msg
    assert f"expected \"{rk.describe(rk.response(first=False))}\"" in msg
    assert c.message in msg
    # the detail lists the frames, the divergence's marked
    assert "frames:" in failure.text and f">>" in failure.text
    for g in c.frames:
        assert g["label"] in failure.text
    assert R.divergence_frame_text(c) in report.summary(broken)


def test_a_case_without_frames_keeps_its_message():
    c = R.CaseResult(id="X", title="t", reference="r", rule="r", group="g", iut_role="receiver",
                     verdict=R.FAIL, message="step 1: expected 10; silence")
    c.divergence = R.Divergence(0, 0.01, "10", "silence")
    assert R.divergence_frame_text(c) == ""
    assert report.failure_text(c).splitlines()[1].startswith("first divergence")
    assert "frames:" not in report.transcript_text(c)


def test_an_unmarked_result_finds_the_frame_by_time():
    """Results written before runs marked the frame: the IUT's frame whose span holds the
    divergence's time."""
    c = R.CaseResult(id="X", title="t", reference="r", rule="r", group="g", iut_role="receiver")
    c.divergence = R.Divergence(3, 0.015, "00 00 00 00 10 03 10", "byte 4 is 0C")
    c.frames = [{"dir": "tester", "t0": 0.0, "t1": 0.016, "label": "A"},
                {"dir": "iut", "t0": 0.012, "t1": 0.018, "label": "B"},
                {"dir": "iut", "t0": 0.020, "t1": 0.030, "label": "C"}]
    assert R.divergence_frame(c)["label"] == "B"
    c.divergence.time = 0.005
    assert R.divergence_frame(c)["label"] == "A"
    c.divergence.time = 0.019
    assert R.divergence_frame(c) is None


# ------------------------------------------------------------------ the decoder
def test_a_block_the_transcript_ends_in_is_a_frame():
    """A case stops at its first divergence, often inside the IUT's block: that block is a
    frame too, decoded as far as it came."""
    head = rk.response(first=True, reatel=0x14)[:3]
    tr = [{"t": 0.001, "dir": "iut", "kind": "byte", "byte": 0x02},
          {"t": 0.002, "dir": "tester", "kind": "byte", "byte": 0x10}]
    tr += [{"t": 0.003 + 0.001 * i, "dir": "iut", "kind": "byte", "byte": b} for i, b in enumerate(head)]
    (f,) = decode_blocks(tr, bcc=True)
    assert f["dir"] == "iut" and f["t0"] == 0.002 and f["t1"] == pytest.approx(0.005)
    assert f["label"] == f"{rk.describe(head)}, unfinished after 3 bytes"


# ------------------------------------------------------------------ JSON
def test_frames_survive_the_json_round_trip_and_the_report_command(broken, tmp_path):
    path = tmp_path / "results.json"
    broken.write_json(path)
    back = R.RunResult.from_dict(json.loads(path.read_text()))
    assert [c.frames for c in back.cases] == [c.frames for c in broken.cases]
    assert any(f.get("diverged") and f.get("expected") for c in back.cases for f in c.frames)
    assert H.render(back) == H.render(broken)
    html, junit = tmp_path / "r.html", tmp_path / "r.xml"
    p = subprocess.run([sys.executable, "-m", "ptpcert.cli", "report", str(path), "--html", str(html),
                        "--junit", str(junit)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    c = case(broken, SEND_200)
    page = html.read_text()
    assert page.count('<g class="frame"') == len(c.frames)
    assert R.divergence_frame_text(c) in _html.unescape(junit.read_text())


@pytest.mark.parametrize("bad,where", [
    ({"dir": "iut", "t0": "x", "t1": 0.1, "label": "L"}, "frames[0].t0"),
    ({"dir": "line", "t0": 0.0, "t1": 0.1, "label": "L"}, "frames[0].dir"),
    ({"dir": "iut", "t0": 0.0, "t1": 0.1, "label": "L", "marks": [{"name": "ETX"}]}, "frames[0].marks[0]"),
    ({"dir": "iut", "t0": 0.0, "t1": 0.1, "label": "L", "windows": {"t0": 0}}, "frames[0].windows"),
])
def test_a_malformed_frame_is_refused_naming_it(broken, bad, where):
    d = json.loads(broken.to_json())
    d["cases"][0]["frames"] = [bad]
    with pytest.raises(R.ResultsError) as exc:
        R.RunResult.from_dict(d)
    assert where in str(exc.value)


# ------------------------------------------------------------------ ASCII: end characters and the CDT
def test_ascii_frames_name_their_end_characters_and_show_the_cdt():
    from test_ascii_suite import COMBOS, reference_profile

    from ptpcert.procedures.ascii.model.codec import char_name

    prof = reference_profile(**COMBOS["ec-xon-8-c"])
    p = prof.params
    cases = [v for v in load_suite(prof, load_vector_sets()) if v.id == "SUITE.ASCII.EC.TRAILING-DISCARDED"]
    factory = make_factory("sim:", prof)
    try:
        c = Runner(factory, prof, RunOptions()).run_case(cases[0])
    finally:
        factory.shutdown()
    end = set(p.end_sequence)
    assert end
    # where each end character ended on the line, per side, from the transcript itself
    on_line = {(e["dir"], round(e["t"], 6)) for e in R.unpack_transcript(c.transcript)
               if e.get("kind") == "byte" and e["byte"] in end}
    framed = [f for f in c.frames if f["label"].startswith("frame")]
    assert framed and all(f.get("marks") for f in framed)
    for f in framed:
        for m in f["marks"]:
            assert m["name"] == char_name(p.end_sequence[-1]) == "ETX"
            assert (f["dir"], m["t"]) in on_line
        assert f["marks"][-1]["t"] == pytest.approx(f["t1"])
        (w,) = f["windows"]
        assert w["name"] == "CDT" and w["t0"] == f["t1"] and w["t1"] - w["t0"] == pytest.approx(p.cdt)
    # a fragment has no end character, but its CDT
    frag = [f for f in c.frames if f["label"].startswith("fragment")]
    assert frag and all(not f.get("marks") and f["windows"][0]["name"] == "CDT" for f in frag)
    groups = frame_groups(c)
    names = [m.get("data-name") for g in groups for m in g.iter("g") if m.get("class") == "mark"]
    assert names.count("ETX") == sum(len(f["marks"]) for f in framed)
    wins = [m for g in groups for m in g.iter("g") if m.get("class") == "fwindow"]
    assert wins and all(w.get("data-name") == "CDT" for w in wins)
