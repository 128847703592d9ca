"""The results object (harness/results.py): transcripts stored as runs and bounded by the
flood limit (schema ptpcert-results/2), saved results of schema 1 read as well, a saved
file that is not a results object refused with one clear error, and reports written whole
or not at all."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from ptpcert import results as R
from ptpcert.profile import load_profile
from ptpcert.report import html as H
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import Factory, make_factory
from ptpcert.transport.base import RESTART, Transport

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"


def sim_run(select) -> R.RunResult:
    profile = load_profile(PROFILE)
    cases = load_suite(profile, load_vector_sets(), select=select)
    factory = make_factory("sim:", profile)
    result = R.RunResult(tool_version="test", started="2026-01-01T00:00:00+00:00", iut="sim:",
                         profile=profile.to_dict(), profile_path=str(PROFILE), html_path="r.html")
    Runner(factory, profile, RunOptions()).run(cases, result)
    return result


def per_byte(transcript):
    """Runs back to one entry per byte, as schema 1 stored them."""
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


# ------------------------------------------------------------------ runs
def test_bytes_are_stored_as_runs_with_their_times():
    log = [{"t": 0.001, "dir": "iut", "kind": "byte", "byte": 0x15, "step": -1},
           {"kind": "start", "dir": "note", "t": 0.001, "step": -1}]
    log += [{"t": 0.002 + k * 0.001, "dir": "tester", "kind": "byte", "byte": b, "step": 2}
            for k, b in enumerate(b"\x02\x10\x10\x03")]
    log += [{"t": 0.009, "dir": "iut", "kind": "byte", "byte": b, "step": 3} for b in b"AAAA"]   # one read
    log += [{"t": 0.010, "dir": "tester", "kind": "char_error", "byte": 0x32, "step": 4},
            {"t": 0.011, "dir": "tester", "kind": "break", "duration": 0.02, "step": 5}]
    runs = R.pack_transcript(log)
    assert [e["kind"] for e in runs] == ["bytes", "start", "bytes", "bytes", "char_errors", "break"]
    tester = runs[2]
    assert R.run_bytes(tester) == b"\x02\x10\x10\x03" and tester["times"] == [0.002, 0.003, 0.004, 0.005]
    burst = runs[3]
    assert R.run_bytes(burst) == b"AAAA" and "times" not in burst and burst["t"] == 0.009
    # both forms give the same bytes at the same times
    assert R.wire_events(runs) == R.wire_events(log)
    assert [k for _, _, k, _, _ in R.wire_events(runs)].count("byte") == 9
    # a byte consumed by a later step starts a new run
    log[-3]["step"] = 9
    assert len(R.pack_transcript(log)) == len(runs) + 1


def test_a_suite_run_is_far_smaller_as_runs_and_renders_as_before():
    run = sim_run(["3964R.*"])
    v2 = run.to_json()
    v1 = json.loads(v2)
    v1["schema"] = R.SCHEMA_V1
    for c in v1["cases"]:
        c["transcript"] = per_byte(c["transcript"])
    v1_text = json.dumps(v1, indent=1)
    assert len(v2) * 2 < len(v1_text)
    old, new = R.RunResult.from_dict(v1), R.RunResult.from_dict(json.loads(v2))
    assert old.schema == new.schema == R.SCHEMA
    assert [c.transcript for c in old.cases] == [c.transcript for c in new.cases]
    assert H.render(old) == H.render(new)


def test_report_reads_schema_1_and_schema_2(tmp_path):
    from argparse import Namespace

    from ptpcert.cli.reports import cmd_report

    run = sim_run(["3964R.FIG2-6.*", "3964R.D0*"])
    data = json.loads(run.to_json())
    data["schema"] = R.SCHEMA_V1
    for c in data["cases"]:
        c["transcript"] = per_byte(c["transcript"])
    outs = {}
    for name, text in (("v1", json.dumps(data)), ("v2", run.to_json())):
        src = tmp_path / f"{name}.json"
        src.write_text(text)
        html, junit = tmp_path / f"{name}.html", tmp_path / f"{name}.xml"
        assert cmd_report(Namespace(results=str(src), html=str(html), junit=str(junit))) == 0
        outs[name] = (html.read_text().replace(f"{name}.html", "R"), junit.read_text().replace(f"{name}.html", "R"))
    assert outs["v1"] == outs["v2"]
    assert "31 10 10 32" in outs["v1"][0] or "DLE ETX BCC" in outs["v1"][0]


# ------------------------------------------------------------------ a flooding IUT, in virtual time
class Flooder(Transport):
    """An IUT on a virtual clock that answers with 64 kB at every read."""

    virtual = True
    capabilities = frozenset({RESTART})

    def __init__(self):
        self.t = 0.0

    def now(self):
        return self.t

    def write(self, data):
        return self.t

    def read(self, deadline):
        self.t += 0.001
        return [(self.t, 0x41)] * 65536


def test_a_flood_is_cut_at_the_flood_limit_with_a_marker():
    profile = load_profile(PROFILE)
    (case,) = load_suite(profile, load_vector_sets(), select=["3964R.D02.*"])
    runner = Runner(Factory(lambda v, p: Flooder(), Flooder.capabilities, virtual=True), profile,
                    RunOptions(flood_limit=5000))
    res = runner.run_case(case)
    assert res.verdict == R.FAIL and "more than 5000 bytes" in res.message
    iut = [b for _, d, k, b, _ in R.wire_events(res.transcript) if d == "iut" and k == "byte"]
    assert len(iut) == 5000
    (mark,) = [e for e in res.transcript if e["kind"] == "dropped"]
    assert mark["dir"] == "iut" and mark["kept"] == 5000 and mark["bytes"] == 65536 - 5000
    assert len(json.dumps([e for e in res.transcript])) < 10_000   # runs, not one entry per byte
    # every view says what was dropped
    text = H.render(R.RunResult(tool_version="t", started="now", cases=[res]))
    assert "60536 more byte(s) from the IUT not kept: the transcript keeps the first 5000" in text
    from ptpcert.report import transcript_text
    assert transcript_text(res).endswith("the transcript keeps the first 5000 (flood limit)")


# ------------------------------------------------------------------ saved files that are not results
@pytest.mark.parametrize("content,message", [
    ("[]", "the JSON is an array, not an object"),
    ('"x"', "the JSON is a str"),
    ('{"schema": "ptpcert-results/9", "cases": []}', "schema: 'ptpcert-results/9' is not a ptpcert results object"),
    ('{"schema": "ptpcert-results/2"}', "cases: missing"),
    ('{"schema": "ptpcert-results/2", "cases": [{"id": "A"}]}', "cases[0].title: missing"),
    ('{"schema": "ptpcert-results/2", "interrupted": "no", "cases": []}', "interrupted: must be true or false"),
    ('{"schema": "ptpcert-results/2", "wall_time": NaN, "cases": []}', "wall_time: must be a number"),
])
def test_a_file_that_is_not_a_results_object_is_refused(tmp_path, content, message):
    f = tmp_path / "r.json"
    f.write_text(content)
    with pytest.raises(R.ResultsError) as exc:
        R.RunResult.read_json(f)
    assert str(exc.value).startswith(f"{f}: ") and message in str(exc.value)


def _one_case(**changes):
    run = sim_run(["3964R.D02.*"])
    d = json.loads(run.to_json())
    d["cases"][0].update(changes)
    return d


@pytest.mark.parametrize("changes,message", [
    ({"verdict": "banana"}, "cases[0] (3964R.D02.NAK-IN-IDLE).verdict: 'banana' is not a verdict (allowed: fail, "),
    ({"transcript": [{"kind": "bytes", "t": 0.1, "dir": "iut", "base64": "%%%"}]}, ".transcript[0].base64: must be"),
    ({"transcript": [{"kind": "bytes", "t": 0.1, "dir": "iut", "base64": "QUE=", "times": [0.1]}]},
     ".transcript[0].times: must be a list of 2 times"),
    ({"transcript": [{"kind": "byte", "t": "soon", "dir": "iut", "byte": 1}]}, ".transcript[0].t: must be a number"),
    ({"transcript": [{"kind": "byte", "t": 0.1, "dir": "iut", "byte": 300}]}, ".transcript[0].byte: must be an integer 0..255"),
    ({"divergence": {"step": 1, "time": "x", "expected": "", "observed": ""}}, ".divergence.time: must be a number"),
    ({"attempts": "two"}, "cases[0].attempts: must be an integer"),
])
def test_a_broken_case_is_refused_naming_the_key(changes, message):
    with pytest.raises(R.ResultsError) as exc:
        R.RunResult.from_dict(_one_case(**changes))
    assert message in str(exc.value)


# ------------------------------------------------------------------ writing whole or not at all
def test_a_report_is_written_whole_or_not_at_all(tmp_path):
    target = tmp_path / "r.json"
    R.write_atomic(target, "old")
    with pytest.raises(UnicodeEncodeError):
        R.write_atomic(target, "new \ud800")     # fails while writing
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json"]   # no temporary file left
    R.write_atomic(tmp_path / "a" / "b" / "r.json", "new")
    assert (tmp_path / "a" / "b" / "r.json").read_text() == "new"
    mode = (tmp_path / "a" / "b" / "r.json").stat().st_mode & 0o777
    umask = os.umask(0)
    os.umask(umask)
    assert mode == 0o666 & ~umask     # as any file the user writes, not a private temporary file


def test_report_paths_are_checked_before_anything_runs(tmp_path):
    assert R.report_path_problem(tmp_path / "new" / "dir" / "r.json") is None
    assert (tmp_path / "new" / "dir").is_dir() and not list((tmp_path / "new" / "dir").iterdir())
    assert "is a directory" in R.report_path_problem(tmp_path)
    assert "not a regular file" in R.report_path_problem("/dev/null")
    (tmp_path / "file").write_text("")
    assert "cannot be created" in R.report_path_problem(tmp_path / "file" / "r.json")
    assert "no file can be written in /proc" in R.report_path_problem("/proc/r.json")


def test_stderr_without_end_of_line_and_a_flood_of_status_lines_stay_bounded():
    from ptpcert.transport.base import StatusParser

    sp = StatusParser()
    for _ in range(1000):
        sp.feed(0.0, b"x" * 65536)             # 64 MB without a newline
    assert len(sp._partial) <= 4096 and len(sp.text) <= sp.keep
    sp.feed(0.0, b"\nSTATUS 16#0808\n" * 10_000)
    assert len(sp.drain()) == sp.keep_lines and sp.dropped == 10_000 - sp.keep_lines
