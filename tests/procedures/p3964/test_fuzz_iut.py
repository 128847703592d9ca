"""Fuzzer level 2 (ptpcert fuzz): the model as oracle against an IUT. In virtual time
(sim:) so that it runs in seconds: the unbroken model yields no finding, a broken variant
yields a finding shrunk to a few steps, the finding is written as a vector that fails the
variant and passes the model, and a run can be replayed from its seed."""

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import Phase, given, settings, strategies as st

from ptpcert import results as R
from ptpcert.procedures.p3964.fuzz import Generator, rule_for
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.runner import RunOptions, Runner
from ptpcert.scenario import load_dir
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[3]
PY = sys.executable
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"


def fuzz(*args, timeout=300):
    return subprocess.run([PY, "-m", "ptpcert.cli", "fuzz", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout)


@pytest.mark.parametrize("proc,prio", [("3964R", "low"), ("3964", "high")])
def test_generated_examples_agree_with_the_model(proc, prio):
    """The generator and the runner agree: every example, run against the model itself,
    passes (otherwise the fuzzer would report false findings)."""
    prof = reference_profile(procedure=proc, priority=prio)
    gen = Generator(prof)
    runner = Runner(make_factory("sim:", prof), prof, RunOptions(check_status=False))

    @settings(max_examples=150, deadline=None, database=None, phases=[Phase.generate])
    @given(st.data())
    def check(data):
        v = gen(data).vector("FUZZ.T", "t", "")
        r = runner.run_case(v)
        assert r.verdict == R.PASS, r.message

    check()


@pytest.mark.realtime
def test_unbroken_model_yields_nothing(tmp_path):
    p = fuzz("--iut", "sim:", "--profile", str(PROFILE), "--budget", "6", "--seed", "5", "--export", str(tmp_path))
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr
    assert "0 finding(s)" in p.stdout and "seed 5" in p.stdout and "replay: ptpcert fuzz" in p.stdout
    assert not list(tmp_path.glob("*.toml"))


@pytest.mark.realtime
@pytest.mark.parametrize("mutant", ["bcc-not-checked"] + [pytest.param(m, marks=pytest.mark.long)
                                                            for m in ("setup-attempts-plus-one", "no-quiet-before-nak")])
def test_broken_variant_yields_a_shrunk_finding_saved_as_a_vector(tmp_path, mutant):
    p = fuzz("--iut", f"sim:?mutant={mutant}", "--profile", str(PROFILE), "--budget", "12", "--seed", "3",
             "--export", str(tmp_path))
    assert p.returncode == 1, p.stdout[-3000:] + p.stderr
    assert "FINDING" in p.stdout and "transcript (shrunk)" in p.stdout
    files = sorted(tmp_path.glob("*.toml"))
    assert files
    vectors = load_dir(tmp_path)
    prof = reference_profile()
    for v in vectors:
        assert v.group == "regression" and v.id.startswith("FUZZ.")
        assert len(v.steps) <= 60
        for url, want in (("sim:", R.PASS), (f"sim:?mutant={mutant}", R.FAIL)):
            res = Runner(make_factory(url, prof), prof, RunOptions()).run_case(v)
            assert res.verdict == want, (url, res.message)
    # ordinary vectors: `ptpcert vectors --check` loads them and the model passes them
    chk = subprocess.run([PY, "-m", "ptpcert.cli", "vectors", "--check", "--dir", str(tmp_path)], cwd=ROOT,
                         capture_output=True, text=True)
    assert chk.returncode == 0 and f"{len(files)} passed, 0 failed" in chk.stdout


@pytest.mark.realtime
def test_a_run_replays_from_its_seed(tmp_path):
    outs = []
    for d in ("a", "b"):
        p = fuzz("--iut", "sim:?mutant=bcc-includes-stx", "--profile", str(PROFILE), "--budget", "5", "--seed", "42",
                 "--export", str(tmp_path / d))
        assert p.returncode == 1
        outs.append(sorted(f.read_text() for f in (tmp_path / d).glob("*.toml")))
    assert outs[0] and outs[0] == outs[1]


@pytest.mark.realtime
def test_bad_usage(tmp_path):
    assert fuzz("--iut", "sim:", "--profile", str(tmp_path / "none.toml")).returncode == 2
    assert fuzz("--iut", "sim:", "--profile", str(PROFILE), "--budget", "0").returncode == 2
    assert fuzz("--iut", "exec:no-such-command-xyz", "--profile", str(PROFILE), "--budget", "1").returncode == 2


def test_rules_named_for_the_divergence():
    assert "3964.RX.SETUP-DLE" in rule_for(["begin_reception", "RECEIVE_ENTRY"], 0x10)
    assert "3964.IDLE.STRAY-NAK" in rule_for(["quiet_nak"], 0x15)
    assert "3964.TX.SETUP-FINAL-NAK" in rule_for(["setup_timeout", "SETUP_CHECK"], 0x15)
    assert "3964.TX.ATTEMPTS" in rule_for(["release_refused", "TX_CHECK"], 0x02)
    assert "Fig. 2-10" in rule_for(["release_refused", "TX_CHECK"], 0x02)
