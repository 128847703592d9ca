"""The RK 512 fuzzer, level 2 (ptpcert fuzz with an RK 512 profile): every generated
example, replayed against the model itself, passes (no false findings) for every link,
priority and role set; a broken variant yields a finding, shrunk and written as a vector
that fails the variant and passes the model; the run names its procedure's kit."""

import subprocess

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st
from rk512_profiles import PY, ROOT, rk_profile, rk_profile_dict, write_profile

from ptpcert import results as R
from ptpcert.registry import by_id
from ptpcert.procedures.rk512.fuzz import FUZZ_KIT, RkGenerator
from ptpcert.procedures.rk512.fuzz.rules import RULES, UNNAMED
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_dir, timer_env
from ptpcert.transport import make_factory

SMALL = dict(t_res=500, db_bytes=512, byte_area_bytes=256, cell_area_cells=256)


@pytest.mark.parametrize("link,prio,extra", [("3964R", "low", {}), ("3964", "high", {}),
                                             ("3964R", "high", {"roles": ["passive"]}),
                                             ("3964R", "low", {"memory": "unknown", "roles": ["active"]})])
def test_generated_examples_agree_with_the_model(link, prio, extra):
    prof = rk_profile(link, prio, **{**SMALL, **extra})
    gen = RkGenerator(prof)
    runner = Runner(make_factory("sim:", prof), prof, RunOptions(check_status=True))
    seen = {"frames": 0, "requests": 0}

    @settings(max_examples=60, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(st.data())
    def check(data):
        v = gen(data).vector("FUZZ.T", "t", "")
        r = runner.run_case(v)
        assert r.verdict == R.PASS, r.message
        env = timer_env(v)    # exported vectors have no negative offsets (README, "Fuzz it")
        for i, s in enumerate(v.steps):
            for key in ("at", "gap", "duration", "after", "within", "max_gap"):
                e = getattr(s, key)
                assert e is None or e.eval(env) >= 0.0, (i, key, e.text, s)
        # every expectation is named by a rule, not by a step's description (issue 27, item 14)
        for s in v.steps:
            if s.kind in ("expect", "receive", "silence"):
                assert FUZZ_KIT.rule_of_note(s.note)[0] in RULES, s.note
        seen["frames"] += sum(s.kind in ("prime", "receive") for s in v.steps)
        seen["requests"] += len(v.extra.get("requests", []))

    check()
    assert seen["frames"] > 60
    assert (seen["requests"] > 0) == ("active" in prof.params.roles)


def test_the_kit_is_the_procedures_and_knows_the_open_points():
    assert by_id("rk512").fuzz_kit() is FUZZ_KIT and FUZZ_KIT.check_reports
    fields = set(FUZZ_KIT.readings.__dataclass_fields__)
    for name, change in FUZZ_KIT.alternatives:
        assert name in by_id("rk512").readings and set(change) <= fields


def fuzz(*args, timeout=300):
    return subprocess.run([PY, "-m", "ptpcert.cli", "fuzz", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout)


@pytest.mark.realtime
@pytest.mark.parametrize("mutant", ["send-response-with-data", pytest.param("counter-letter-c", marks=pytest.mark.long)])
def test_a_broken_variant_yields_a_finding_saved_as_a_vector(tmp_path, mutant):
    raw = rk_profile_dict(**SMALL)
    prof_file = write_profile(tmp_path / "p.toml", raw)
    out = tmp_path / "found"
    p = fuzz("--iut", f"sim:?mutant={mutant}", "--profile", str(prof_file), "--budget", "20", "--seed", "2",
             "--export", str(out))
    assert p.returncode == 1, p.stdout[-3000:] + p.stderr
    assert "FINDING" in p.stdout and "transcript (shrunk)" in p.stdout
    # the blocks end the run (README, "Fuzz it"): after the summary line, each naming a rule
    assert p.stdout.index("finding(s)") < p.stdout.index("FINDING"), p.stdout[-3000:]
    vectors = load_dir(out)
    assert vectors
    for v in vectors:
        assert any(v.rule.startswith(r) for r in (*RULES, UNNAMED)), v.rule
        env = timer_env(v)
        assert all(e is None or e.eval(env) >= 0.0 for s in v.steps
                   for e in (s.at, s.gap, s.duration, s.after, s.within, s.max_gap)), v.steps
    prof = rk_profile(**SMALL)
    for v in vectors:
        assert v.procedure == "rk512" and v.group == "regression" and v.id.startswith("FUZZ.")
        for url, want in (("sim:", R.PASS), (f"sim:?mutant={mutant}", R.FAIL)):
            res = Runner(make_factory(url, prof), prof, RunOptions()).run_case(v)
            assert res.verdict == want, (url, res.message)
    chk = subprocess.run([PY, "-m", "ptpcert.cli", "vectors", "--check", "--dir", str(out)], cwd=ROOT,
                         capture_output=True, text=True)
    assert chk.returncode == 0, chk.stdout + chk.stderr


@pytest.mark.realtime
def test_the_unbroken_model_yields_nothing(tmp_path):
    raw = rk_profile_dict(**SMALL)
    prof_file = write_profile(tmp_path / "p.toml", raw)
    p = fuzz("--iut", "sim:", "--profile", str(prof_file), "--budget", "8", "--seed", "4", "--export", str(tmp_path))
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr
    assert "0 finding(s)" in p.stdout
