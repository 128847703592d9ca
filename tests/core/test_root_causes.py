"""One defect, one finding: the console summary, the JUnit file and the HTML report list the
failures grouped by root cause (the signature of each case's first divergence) before the
cases; the groups are kept in the results JSON, so ``ptpcert report`` re-renders them.
In virtual time (sim:) against the broken variants of the reference model."""

import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from ptpcert import results as R
from ptpcert.procedures.p3964.tokens import control_names
from ptpcert.report import summary
from ptpcert.report.html import render

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"


def _run(tmp: Path, iut: str, *extra: str) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp / "r.json"
    p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", iut, "--profile", str(PROFILE),
                        "--json", str(out), "--junit", str(tmp / "j.xml"), "--html", str(tmp / "r.html"), *extra],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    return p, out


@pytest.fixture(scope="module")
def mutant_run(tmp_path_factory):
    """The suite against a variant whose one defect is: after a NAK during its block, it
    answers with a NAK of its own instead of starting the next attempt with STX."""
    tmp = tmp_path_factory.mktemp("nak")
    p, out = _run(tmp, "sim:?mutant=nak-after-data-nak")
    assert p.returncode == 1, p.stdout[-2000:] + p.stderr
    return p, tmp, R.RunResult.read_json(out)


def test_one_systematic_defect_is_shown_once_at_the_top_with_its_count(mutant_run):
    p, tmp, run = mutant_run
    failed = [c for c in run.cases if c.verdict == R.FAIL]
    assert len(failed) >= 3   # the defect fails several cases...
    groups = run.deviations()
    assert len(groups) == 1   # ...and is one deviation
    g = groups[0]
    assert g["count"] == len(failed) and sorted(g["cases"]) == sorted(c.id for c in failed)
    # what was due (STX, 02) and what the IUT sent instead (NAK, 15), after the tester's NAK
    # in one sentence, with the first case's real bytes and time
    first = next(c for c in run.cases if c.id == g["cases"][0])
    assert g["description"].startswith(f"{len(failed)} cases (first: {first.id}): at {1000 * first.divergence.time:.1f} ms")
    assert "after the tester's NAK (15), the IUT sent 15 where 02" in g["description"], g["description"]
    # console: the deviation before the case list, once
    out = p.stdout
    assert out.count(g["description"]) == 1
    assert out.index("distinct deviations (1") < out.index(g["description"]) < out.index("not passed:")


def test_junit_and_html_list_the_deviation_before_the_cases(mutant_run):
    _, tmp, run = mutant_run
    g = run.deviations()[0]
    suite = ET.parse(tmp / "j.xml").getroot().find("testsuite")
    props = {e.get("name"): e.get("value") for e in suite.iter("property")}
    assert props["deviation.1"] == g["description"] and "deviation.2" not in props
    assert g["description"] in suite.find("system-out").text
    failures = [tc.find("failure") for tc in suite.iter("testcase") if tc.find("failure") is not None]
    assert len(failures) == g["count"]
    assert all(f.get("message").startswith("[deviation 1 of 1]") for f in failures)
    html = (tmp / "r.html").read_text("utf-8")
    i = html.index('id="deviations"')
    assert i < html.index('id="summary"') and i < html.index(f'id="case-{g["cases"][0].replace(".", "-")}"')
    assert html.count('id="deviation-') == 1


def test_the_groups_are_in_the_json_and_report_re_renders_them(mutant_run, tmp_path):
    _, tmp, run = mutant_run
    raw = json.loads((tmp / "r.json").read_text("utf-8"))
    assert raw["root_causes"] == run.deviations() and raw["root_causes"][0]["count"] >= 3
    # the stored groups are what a re-rendering shows (not recomputed from the cases)
    raw["root_causes"][0]["description"] = "7 cases: a description kept in the file"
    (tmp_path / "edited.json").write_text(json.dumps(raw), "utf-8")
    p = subprocess.run([PY, "-m", "ptpcert.cli", "report", str(tmp_path / "edited.json"),
                        "--html", str(tmp_path / "r.html"), "--junit", str(tmp_path / "j.xml")],
                       cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert "a description kept in the file" in (tmp_path / "r.html").read_text("utf-8")
    assert "a description kept in the file" in (tmp_path / "j.xml").read_text("utf-8")


def test_two_different_defects_give_two_groups(mutant_run, tmp_path):
    """The cases of two variants with different defects, in one run: two deviations, each
    with the count of the cases it explains."""
    _, _, nak_run = mutant_run
    p, out = _run(tmp_path, "sim:?mutant=repetition-refused")
    assert p.returncode == 1
    rep_run = R.RunResult.read_json(out)
    rep = [c for c in rep_run.cases if c.verdict == R.FAIL]
    nak = [c for c in nak_run.cases if c.verdict == R.FAIL]
    assert len(R.root_causes(rep)) == 1
    for c in rep:
        c.id += "/B"
    both = R.RunResult(tool_version="t", started="now", cases=nak + rep)
    groups = both.deviations()
    assert sorted(g["count"] for g in groups) == sorted([len(nak), len(rep)])
    assert {frozenset(g["cases"]) for g in groups} == {frozenset(c.id for c in nak), frozenset(c.id for c in rep)}
    text = summary(both)
    assert "distinct deviations (2" in text
    assert render(both).count('id="deviation-') == 2


def _failed(cid: str, expected_hex: str, observed: str, tester: bytes, t: float = 0.05) -> R.CaseResult:
    c = R.CaseResult(cid, "t", "ref", "rule", "g", "both", verdict=R.FAIL, message="m")
    c.steps = [{"kind": "send", "data": tester.hex(" ").upper()},
               {"kind": "expect", "data": expected_hex, "expect": expected_hex}]
    c.transcript = R.pack_transcript([{"t": 0.01 + i * 0.001, "dir": "tester", "kind": "byte", "byte": b, "step": 0}
                                      for i, b in enumerate(tester)])
    c.divergence = R.Divergence(1, t, expected_hex, observed)
    return c


def test_the_signature_survives_other_payloads_and_timings():
    a = _failed("A", "31 32 33 10 03 23", "byte 6 is 21 (after 31 32 33 10 03)", b"\x10")
    b = _failed("B", "41 10 10 42 10 03 10", "byte 7 is 12 (after 41 10 10 42 10 03)", b"\x10", t=0.3)
    c = _failed("C", "15", "15 came 12.5 ms after the reference, too early", b"\x41")
    d = _failed("D", "15", "15 came 3.1 ms after the reference, too early", b"\x02\x41\x42\x43")
    e = _failed("E", "02", "received 15", b"\x15")
    f = _failed("F", "02", "received 15", b"\x10")   # same bytes, another situation
    groups = R.root_causes([a, b, c, d, e, f], control_names)   # 3964's names of its bytes
    assert [sorted(g["cases"]) for g in groups] == [["A", "B"], ["C", "D"], ["E"], ["F"]]
    assert R.failure_signature(e, control_names) != R.failure_signature(f, control_names)
    # without a procedure's names a lone stimulus is "a character": one situation
    assert R.failure_signature(e) == R.failure_signature(f)
    # a passing case is in no group
    ok = R.CaseResult("OK", "t", "ref", "rule", "g", "both", verdict=R.PASS)
    assert R.root_causes([ok]) == []


# ------------------------------------------------------------------ the sentences (issue 25, item 14)


def test_the_sentence_says_what_the_iut_sent_with_real_bytes_and_times():
    e = _failed("E", "02", "received 15", b"\x15", t=0.0123)
    silence = _failed("S", "", "received 15 at 1.0 ms", b"\x02\x41\x42\x43\x10\x03\x13", t=0.2)
    silence.divergence = R.Divergence(1, 0.2, "silence for 2.5*ADT", "received 15 at 1.0 ms")
    model = _failed("M", "", "", b"\x42", t=0.3247)
    model.divergence = R.Divergence(-1, 0.3247, "what the reference model does on the same line",
                                    "the IUT's byte 55 is 41; the model sends 15 (after 41 41 41 41)")
    texts = {g["cases"][0]: g["description"] for g in R.root_causes([e, silence, model], control_names)}
    assert texts["E"] == "1 case (first: E): at 12.3 ms, after the tester's NAK (15), the IUT sent 15 where 02 is due"
    assert texts["S"] == ("1 case (first: S): at 200.0 ms, after the tester's character 13, the IUT sent "
                          "15 at 1.0 ms where silence for 2.5*ADT is due")
    assert texts["M"] == ("1 case (first: M): at 324.7 ms, after the tester's character 42, the IUT sent 41 as its "
                          "byte 55 (after 41 41 41 41) where the reference model fed the same line sends 15")
    for t in texts.values():   # none of the masked words the issue quotes
        assert " N " not in t and "the IUT the IUT" not in t and "received" not in t


def test_the_groups_still_mask_numbers_for_grouping():
    a = _failed("A", "02", "received 15", b"\x15", t=0.01)
    b = _failed("B", "02", "received 15", b"\x15", t=0.5)
    groups = R.root_causes([a, b], control_names)
    assert len(groups) == 1 and groups[0]["description"].startswith("2 cases (first: A): at 10.0 ms")
