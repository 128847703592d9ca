"""One run split over N CI jobs (`ptpcert run --shard K/N`) and joined again (`ptpcert report
--merge`): the N shards together are the selection, each case once; the split is the same on
every machine and balanced by the cases' forced waits; the merged results are a serial run's,
verdict for verdict; what cannot be parts of one run is refused in one line."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ptpcert import results as R
from ptpcert.cli import main
from ptpcert.profile import load_profile
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import forced_waits, load_suite, plan_shards, shard_of

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
PROFILES = ROOT / "conformance" / "profiles"
#: each procedure's reference profile, and a broken variant whose run has failures to merge
PROCEDURES = {"3964R": ("reference-20ms.toml", "no-dle-doubling"),
              "RK 512": ("rk512-reference.toml", "continuation-without-request-ignored"),
              "ASCII": ("ascii-reference.toml", "append-end-missing")}


def cli(*args, env=None):
    return subprocess.run([PY, "-m", "ptpcert.cli", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=300, env=env)


@pytest.fixture(scope="module")
def suites():
    """Per procedure: the profile, its cases and their forced waits (measured once)."""
    out = {}
    for name, (file, _) in PROCEDURES.items():
        prof = load_profile(PROFILES / file)
        cases = load_suite(prof, load_vector_sets())
        out[name] = (prof, cases, forced_waits(prof, cases))
    return out


# -- the option ------------------------------------------------------------------------------
@pytest.mark.parametrize("value", ["0/3", "4/3", "x", "1/0", "2", "1/3/4"])
def test_a_bad_shard_is_a_one_line_error(value):
    p = cli("run", "--iut", "sim:", "--profile", str(PROFILES / "reference-20ms.toml"), "--shard", value)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "--shard" in lines[0] and repr(value) in lines[0] and "K/N" in lines[0], p.stderr


def test_shard_values():
    assert R.parse_shard("1/1") == (1, 1) and R.parse_shard(" 3/4 ") == (3, 4)
    for bad in ("0/3", "4/3", "x", "1/0", "", "1/", "/3", "a/b", "1.5/3", "-1/3"):
        with pytest.raises(ValueError, match="K/N"):
            R.parse_shard(bad)


# -- the split -------------------------------------------------------------------------------
def _check_plan(weights: dict[str, float], n: int) -> None:
    """Every case in exactly one of the n shards, and the stated bound: the heaviest shard is
    at most the heaviest case heavier than the lightest (so at most total/n + that case)."""
    shards = plan_shards(weights, n)
    assert len(shards) == n
    flat = [c for s in shards for c in s]
    assert sorted(flat) == sorted(weights) and len(set(flat)) == len(flat)
    loads = [sum(weights[c] for c in s) for s in shards]
    heaviest = max(weights.values(), default=0.0)
    assert max(loads) - min(loads) <= heaviest + 1e-9
    assert max(loads) <= sum(weights.values()) / n + heaviest + 1e-9


@settings(max_examples=200, deadline=None)
@given(st.dictionaries(st.text("ABCDEF.-", min_size=1, max_size=6),
                       st.floats(0, 100, allow_nan=False) | st.sampled_from([0.0, 1.5]), max_size=40),
       st.integers(1, 8))
def test_any_weights_split_into_a_partition_within_the_bound(weights, n):
    _check_plan(weights, n)
    # the order the cases come in does not matter: the same split
    assert plan_shards(dict(reversed(list(weights.items()))), n) == plan_shards(weights, n)


@pytest.mark.parametrize("proc", PROCEDURES)
def test_the_n_shards_together_are_the_whole_suite(suites, proc):
    """For N = 1..5: every case of the suite in exactly one shard, each shard in the suite's
    order, the split within the bound."""
    prof, cases, weights = suites[proc]
    ids = [v.id for v in cases]
    for n in range(1, 6):
        parts = [shard_of(prof, cases, k, n, weights)[0] for k in range(1, n + 1)]
        flat = [v.id for part in parts for v in part]
        assert sorted(flat) == sorted(ids) and len(flat) == len(ids), n
        for part in parts:
            assert [v.id for v in part] == [i for i in ids if i in {v.id for v in part}]
        _check_plan(weights, n)
    # the figures are the cases' own: the same measured in any order or any subset
    assert forced_waits(prof, cases[::-1][:40]) == {v.id: weights[v.id] for v in cases[::-1][:40]}
    assert shard_of(prof, cases[:30], 2, 3)[0] == shard_of(prof, cases[:30], 2, 3, weights)[0]


@settings(max_examples=30, deadline=None)
@given(st.data())
def test_any_selection_and_n_split_into_the_selection(suites, data):
    proc = data.draw(st.sampled_from(sorted(PROCEDURES)))
    prof, cases, weights = suites[proc]
    picked = data.draw(st.sets(st.sampled_from([v.id for v in cases]), min_size=1))
    n = data.draw(st.integers(1, 5))
    selection = [v for v in cases if v.id in picked]
    parts = [shard_of(prof, selection, k, n, weights)[0] for k in range(1, n + 1)]
    assert sorted(v.id for p in parts for v in p) == sorted(picked)
    _check_plan({i: weights[i] for i in picked}, n)


def test_the_split_is_the_same_in_another_process(suites):
    """Deterministic: another interpreter with another hash seed (another machine) splits
    the same profile and selection the same way."""
    prof, cases, weights = suites["3964R"]
    code = ("import json; from ptpcert.profile import load_profile; from ptpcert.scenario import load_vector_sets; "
            "from ptpcert.suite import load_suite, forced_waits, plan_shards; "
            f"p = load_profile({str(PROFILES / 'reference-20ms.toml')!r}); "
            "print(json.dumps(plan_shards(forced_waits(p, load_suite(p, load_vector_sets())), 4)))")
    for seed in ("1", "4242"):
        p = subprocess.run([PY, "-c", code], capture_output=True, text=True, timeout=120,
                           env=dict(os.environ, PYTHONHASHSEED=seed))
        assert p.returncode == 0, p.stderr
        assert json.loads(p.stdout) == plan_shards(weights, 4)


def test_the_shards_are_balanced_by_forced_waits(suites):
    """The suites as they are: with N = 2..5 no shard waits more than the heaviest case
    longer than another, and where no case dominates (RK 512) the shards are within 1 %."""
    for proc, (_, _, weights) in suites.items():
        for n in range(2, 6):
            _check_plan(weights, n)
    weights = suites["RK 512"][2]
    loads = [sum(weights[c] for c in s) for s in plan_shards(weights, 4)]
    assert max(loads) <= 1.01 * sum(loads) / 4


# -- merged = serial ---------------------------------------------------------------------------
def _run(tmp_path, name, iut, profile, *more):
    out = tmp_path / f"{name}.json"
    status = main(["run", "--iut", iut, "--profile", str(profile), "-q", "--json", str(out), *more])
    return status, out


@pytest.mark.parametrize("proc", PROCEDURES)
def test_merged_shards_are_a_serial_run(tmp_path, proc, capsys):
    """Virtual time (sim:), a broken variant (so there are failures to merge): the merged
    report has every case once, in the serial run's order, each with the serial run's
    verdict; the counts, verdict and vector set hash are the serial run's."""
    file, mutant = PROCEDURES[proc]
    profile, iut = PROFILES / file, f"sim:?mutant={mutant}"
    serial_status, serial = _run(tmp_path, "serial", iut, profile)
    shards = []
    for k in (1, 2, 3):
        status, out = _run(tmp_path, f"s{k}", iut, profile, "--shard", f"{k}/3")
        assert status in (0, 1)
        shards.append(out)
    merged = tmp_path / "merged.json"
    junit, html = tmp_path / "m.xml", tmp_path / "m.html"
    # given in another order than the shards': the order of the cases is the suite's
    assert main(["report", "--merge", str(shards[2]), str(shards[0]), str(shards[1]),
                 "--json", str(merged), "--junit", str(junit), "--html", str(html)]) == 0
    a, b = R.RunResult.read_json(serial), R.RunResult.read_json(merged)
    assert [(c.id, c.verdict) for c in b.cases] == [(c.id, c.verdict) for c in a.cases]
    assert b.counts() == a.counts() and b.verdict == a.verdict and b.counts()[R.FAIL] > 0
    assert b.exit_status() == serial_status == 1
    assert b.vector_set_hash == a.vector_set_hash
    assert b.merged_from == ["1/3", "2/3", "3/3"] and not b.shard
    # each shard's reports say which shard it is; the merged ones what they were merged from
    parts = [R.RunResult.read_json(s) for s in shards]
    assert [p.shard for p in parts] == ["1/3", "2/3", "3/3"]
    assert all(p.vector_set_hash == a.vector_set_hash for p in parts)
    props = {e.get("name"): e.get("value") for e in ET.parse(junit).iter("property")}
    assert props["merged_from"] == "1/3 2/3 3/3"
    assert "merged from" in html.read_text() and "1/3, 2/3, 3/3" in html.read_text()
    tests = [e for e in ET.parse(junit).iter("testcase")]
    assert len(tests) == len(a.cases)


def test_each_shard_names_itself_in_every_report(tmp_path, capsys):
    junit, html = tmp_path / "s.xml", tmp_path / "s.html"
    status, out = _run(tmp_path, "s", "sim:", PROFILES / "reference-20ms.toml", "--shard", "2/5",
                       "--junit", str(junit), "--html", str(html))
    assert status == 0
    said = capsys.readouterr().out
    assert said.startswith("shard 2/5: ") and " of 148 cases" in said.splitlines()[0]
    assert json.loads(out.read_text())["shard"] == "2/5"
    props = {e.get("name"): e.get("value") for e in ET.parse(junit).iter("property")}
    assert props["shard"] == "2/5"
    assert "<td>2/5 (ptpcert run --shard" in html.read_text()


def test_a_shard_without_cases_passes_and_merges(tmp_path, capsys):
    """More shards than cases: the empty shard writes its reports and passes; the merge is
    the one case."""
    prof = PROFILES / "reference-20ms.toml"
    runs = [_run(tmp_path, f"s{k}", "sim:", prof, "--select", "3964R.FIG2-5.SEND", "--shard", f"{k}/2")
            for k in (1, 2)]
    assert [s for s, _ in runs] == [0, 0]
    sizes = sorted(len(R.RunResult.read_json(out).cases) for _, out in runs)
    assert sizes == [0, 1]
    assert main(["report", "--merge", str(runs[0][1]), str(runs[1][1]), "--json", str(tmp_path / "m.json")]) == 0
    assert [c.id for c in R.RunResult.read_json(tmp_path / "m.json").cases] == ["3964R.FIG2-5.SEND"]


# -- what is refused ------------------------------------------------------------------------
def _result(shard="", ids=("A", "B"), procedure="3964/3964R", profile=None, hash_="h", version="1"):
    r = R.RunResult(tool_version=version, started="2026-01-01T00:00:00+00:00", procedure=procedure,
                    profile=profile if profile is not None else {"procedure": "3964R", "character_delay_ms": 20},
                    vector_set="bundled", vector_set_hash=hash_, shard=shard)
    r.cases = [R.CaseResult(i, i, "ref", "rule", "idle", "receiver", verdict=R.PASS) for i in ids]
    return r


@pytest.mark.parametrize("inputs, words", [
    ([_result("1/2", ["A"]), _result("2/2", ["B"], procedure="RK 512")], "different procedures"),
    ([_result("1/2", ["A"]), _result("2/2", ["B"], profile={"procedure": "3964R", "character_delay_ms": 220})],
     "different profiles (character_delay_ms = 220 and 20)"),
    ([_result("1/2", ["A"]), _result("2/2", ["B"], hash_="other")], "different vector sets"),
    ([_result("1/2", ["A"]), _result("2/2", ["B"], version="2")], "different ptpcert versions"),
    ([_result("1/2", ["A", "B"]), _result("2/2", ["B"])], "case B is in both"),
    ([_result("1/3", ["A"]), _result("3/3", ["B"])], "shard 2/3 missing"),
    ([_result("1/3", ["A"])], "shards 2/3, 3/3 missing"),
    ([_result("1/2", ["A"]), _result("1/2", ["B"])], "both shard 1/2"),
    ([_result("1/2", ["A"]), _result("2/3", ["B"])], "one of 2"),
    ([_result("1/2", ["A"]), _result("", ["B"])], "a whole run"),
    ([_result("x", ["A"])], "is not a shard"),
])
def test_what_is_not_one_run_is_refused(inputs, words):
    named = [(f"r{i}.json", r) for i, r in enumerate(inputs)]
    with pytest.raises(R.ResultsError) as exc:
        R.merge_runs(named)
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_a_refused_merge_is_one_line_and_exit_2(tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    _result("1/3", ["A"]).write_json(a)
    _result("3/3", ["B"]).write_json(b)
    out = tmp_path / "m.json"
    p = cli("report", "--merge", str(a), str(b), "--json", str(out))
    assert p.returncode == 2 and not out.exists()
    assert p.stderr.strip().splitlines() == ["ptpcert report: --merge: shard 2/3 missing (given: 1/3, 3/3)"]
    p = cli("report", str(a), "--merge", str(b))
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and "not both" in p.stderr
    p = cli("report", "--merge", str(a), str(b), "--json", str(a))   # never over a file read
    assert p.returncode == 2 and "the file read" in p.stderr and len(p.stderr.strip().splitlines()) == 1


def test_a_merge_of_whole_runs_keeps_their_names_and_counts():
    """Whole runs of one selection cannot be parts of one run (their cases overlap); two
    that share no case (merged by hand) keep their file names."""
    merged = R.merge_runs([("a.json", _result("", ["A"])), ("b.json", _result("", ["B"]))])
    assert merged.merged_from == ["a.json", "b.json"]
    assert Counter(c.verdict for c in merged.cases) == {R.PASS: 2}


# -- real time -----------------------------------------------------------------------------
@pytest.mark.realtime
def test_shards_against_real_processes_merge_into_the_serial_verdicts(tmp_path):
    """exec: (a process per case, in real time), a few cases, N = 2: the merged verdicts
    are the serial run's."""
    iut = f"exec:{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk"
    prof = str(PROFILES / "reference-20ms.toml")
    sel = ["--select", "3964R.FIG2-5.*", "--select", "3964R.D0[1-3]*"]
    verdicts = {}
    for name, more in (("serial", []), ("s1", ["--shard", "1/2"]), ("s2", ["--shard", "2/2"])):
        p = cli("run", "--iut", iut, "--profile", prof, "-q", "--json", str(tmp_path / f"{name}.json"), *sel, *more)
        assert p.returncode == 0, p.stdout[-2000:] + p.stderr
    p = cli("report", "--merge", str(tmp_path / "s1.json"), str(tmp_path / "s2.json"), "--json",
            str(tmp_path / "m.json"))
    assert p.returncode == 0, p.stderr
    for name in ("serial", "m"):
        verdicts[name] = [(c.id, c.verdict) for c in R.RunResult.read_json(tmp_path / f"{name}.json").cases]
    assert verdicts["m"] == verdicts["serial"] and len(verdicts["m"]) >= 3
    assert all(len(R.RunResult.read_json(tmp_path / f"s{k}.json").cases) for k in (1, 2))
