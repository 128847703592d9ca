"""The RK 512 conformance suite: it passes the reference model for every link and priority;
every case cites its rule; every broken variant is caught (and we say by which cases);
cases the profile cannot run are unsupported, never failed; the real-time reference
implementation passes a representative subset over exec: and pty:."""

import json
import subprocess

import pytest
from rk512_profiles import PY, ROOT, iut_command, rk_profile, rk_profile_dict, run_cases, write_profile

import ptpcert.conformance as conformance
from ptpcert import results as R
from ptpcert.registry import by_id
from ptpcert.procedures.rk512.description import GROUPS
from ptpcert.profile import profile_from_dict
from ptpcert.runner import Runner
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite

RK = by_id("rk512")
MUTANTS = RK.mutants()
COMBOS = [(link, prio) for link in ("3964R", "3964") for prio in ("low", "high")]
OK = (R.PASS, R.NON_STRICT, R.INFORMATIONAL)


def run(url: str, profile, select=None) -> R.RunResult:
    return run_cases(url, profile, load_suite(profile, load_vector_sets(), select=select))


@pytest.mark.parametrize("link,prio", COMBOS)
def test_suite_passes_the_model(link, prio):
    res = run("sim:", rk_profile(link, prio))
    bad = {c.id: c.message for c in res.cases if c.verdict not in OK + (R.UNSUPPORTED,)}
    assert not bad
    suite = [c for c in res.cases if c.id.startswith("SUITE.")]
    assert len(suite) > 140
    # the profile has every role, set-up and area: nothing of the suite is unsupported
    assert [c.id for c in suite if c.verdict == R.UNSUPPORTED] == []
    # every group of the checklist is there
    assert {c.group for c in suite} >= set(GROUPS) - {"regression"}
    # the model takes the main reading of every open point: nothing is graded down
    assert {c.verdict for c in suite} == {R.PASS}


def test_every_checklist_item_has_a_case():
    ids = {v.id for v in conformance.cases(rk_profile())}
    items = {i.split(".")[2].rstrip("ABCDEFGHIJKL") for i in ids}
    want = ({f"L-0{i}" for i in range(1, 8)} | {f"P-{i:02d}" for i in range(1, 19)}
            | {f"A-{i:02d}" for i in range(1, 13)})
    assert want <= items, sorted(want - items)


@pytest.mark.parametrize("link,prio", COMBOS)
def test_every_case_cites_the_manual_and_states_its_rule(link, prio):
    for v in conformance.cases(rk_profile(link, prio)):
        assert v.id.startswith("SUITE.RK512.") and v.group in GROUPS and v.procedure == "rk512"
        assert v.rule.endswith(".") and len(v.rule) > 40, v.id
        assert "§" in v.reference or "Table" in v.reference or "Fig." in v.reference, v.id
        assert ".md" not in v.reference and ".md" not in v.rule, v.id
        for r in v.readings:
            assert r in RK.readings


def test_cases_that_hinge_on_an_open_point_cannot_fail_on_its_other_reading():
    # every alternative answer a case allows is graded down, never failed; and every such
    # case names the open point it depends on
    for v in conformance.cases(rk_profile()):
        for s in v.steps:
            if s.alternatives and s.alt_grade != "pass":
                assert v.readings, v.id
            if s.optional and s.absent_grade != "pass":
                assert v.readings, v.id


def test_the_conflict_case_follows_the_profiles_priority():
    low = [v.id for v in conformance.cases(rk_profile(priority="low")) if "CONFLICT" in v.id]
    high = [v.id for v in conformance.cases(rk_profile(priority="high")) if "CONFLICT" in v.id]
    assert low == ["SUITE.RK512.L-05.CONFLICT-IUT-LOW"] and high == ["SUITE.RK512.L-05.CONFLICT-IUT-HIGH"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_every_mutant_is_caught(name, record_property):
    m = MUTANTS[name]
    res = run(f"sim:?mutant={name}", rk_profile(**m.profile))
    caught = sorted(c.id for c in res.cases if c.verdict == R.FAIL)
    record_property("caught_by", " ".join(caught))
    print(f"{name}: caught by {', '.join(caught)}")
    assert caught, f"mutant {name} ({m.rule}) is not caught by any case"
    assert not [c.id for c in res.cases if c.verdict == R.ERROR]


def test_mutants_are_many_and_listed_with_their_rule():
    p = subprocess.run([PY, "-m", "ptpcert.cli", "iut", "--procedure", "RK512", "--list-mutants"], cwd=ROOT,
                       capture_output=True, text=True)
    assert p.returncode == 0
    assert len(p.stdout.splitlines()) == len(MUTANTS) >= 20
    for name, m in MUTANTS.items():
        assert name in p.stdout and ("§" in m.rule or "Table" in m.rule or "Fig" in m.rule)


# -- what the profile cannot run is unsupported, never failed ------------------------------------
@pytest.mark.parametrize("change,reason", [
    (dict(roles=["passive"]), "active role"),
    (dict(roles=["active"]), "passive role"),
    (dict(requests="none"), "request script"),
    (dict(db_bytes=512, byte_area_bytes=256, cell_area_cells=256), ">="),
    (dict(memory="unknown"), "pattern"),
])
def test_cases_the_profile_cannot_run_are_unsupported(change, reason):
    res = run("sim:", rk_profile(**change))
    bad = {c.id: c.message for c in res.cases if c.verdict not in OK + (R.UNSUPPORTED,)}
    assert not bad
    unsupported = [c for c in res.cases if c.verdict == R.UNSUPPORTED]
    assert unsupported and all(reason in c.message for c in unsupported if reason in c.message)
    assert any(reason in c.message for c in unsupported)
    assert sum(c.verdict == R.PASS for c in res.cases) > 20


def test_memory_unknown_writes_before_it_reads():
    cases = {v.id: v for v in conformance.cases(rk_profile(memory="unknown"))}
    v = cases["SUITE.RK512.P-04.FETCH-D-6"]
    assert "pattern" not in v.extra.get("needs", {})
    assert [s.kind for s in v.steps][:2] == ["prime", "receive"] and v.steps[0].data[2] == ord("A")


def test_a_transport_that_does_not_start_the_iut_makes_active_cases_unsupported():
    prof = rk_profile()
    from ptpcert.transport import Factory
    runner = Runner(Factory(None, frozenset({"status"})), prof)
    active = [v for v in conformance.cases(prof) if v.extra.get("requests")]
    assert active
    for v in active:
        assert "does not start the IUT" in runner.unsupported_reason(v, frozenset({"status"}))


def test_the_issues_example_profile_is_read(tmp_path):
    text = """
[iut]
procedure = "RK512"
priority = "low"
character_delay_ms = 220
acknowledgement_delay_ms = 2000
setup_attempts = 6
transmission_attempts = 6
send_trigger = "none"
line_conditions = "parmrk"
status_from_stderr = true

[rk512]
link = "3964R"
response_time_ms = 5000
roles = ["passive", "active"]
requests = "script"
memory = "pattern"
db_range = [1, 199]
dx_range = [1, 199]
db_bytes = 512
byte_area_bytes = 256
cell_area_cells = 256

[iut.setups]
cpu_stop = "--cpu-stop"
flag_set = "--cf-set {flag}@{reset_ms}"
"""
    from ptpcert.profile import load_profile
    f = tmp_path / "p.toml"
    f.write_text(text)
    prof = load_profile(f)
    assert prof.procedure is RK and prof.params.t_res == 5.0 and prof.params.db_bytes == 512
    assert prof.params.line.adt_ms == 2000 and prof.setups["flag_set"].startswith("--cf-set")


def test_the_bundled_rk512_profile_is_read_and_runs_the_whole_suite_in_sim():
    import tomllib

    from ptpcert.paths import bundled_profiles
    from ptpcert.profile import profile_from_dict
    raw = tomllib.loads(bundled_profiles().joinpath("rk512-reference.toml").read_text("utf-8"))
    prof = profile_from_dict(raw)
    assert prof.procedure is RK and prof.params.t_res == 1.0 and set(prof.setups) == {"cpu_stop", "flag_set"}
    res = run("sim:", prof)
    assert not [c.id for c in res.cases if c.verdict not in OK + (R.UNSUPPORTED,)]


@pytest.mark.parametrize("change,key", [
    (lambda d: d["rk512"].update(link="3964X"), "rk512.link"),
    (lambda d: d["rk512"].update(db_bytes=7), "rk512.db_bytes"),
    (lambda d: d["rk512"].update(colour="red"), "rk512.colour"),
    (lambda d: d["iut"].update(send_trigger="echo"), "iut.send_trigger"),
    (lambda d: d["iut"]["setups"].update(no_buffer="--x"), "iut.setups.no_buffer"),
])
def test_profile_errors_name_the_key(change, key):
    from ptpcert.profile import ProfileError
    d = rk_profile_dict()
    change(d)
    with pytest.raises(ProfileError) as e:
        profile_from_dict(d)
    assert e.value.key == key


# -- real time: the reference IUT over exec: and pty: ---------------------------------------------
# The whole suite against the real-time reference IUT (both links, both priorities, exec: and
# pty:) is tests/procedures/rk512/test_rk512_independent.py::test_the_whole_suite_passes_the_real_time_reference.


#: timers for real processes on a loaded machine: where the IUT sends first (its requests,
#: its responses) the tester must answer its STX within the IUT's ADT
REALTIME = dict(cdt=100, adt=100, t_res=1000)


def ptpcert_run(tmp_path, url, raw, *extra):
    prof = write_profile(tmp_path / "p.toml", raw)
    j = tmp_path / "r.json"
    p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", url, "--profile", str(prof), "--json", str(j), "-q",
                        *extra], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert j.exists(), p.stderr[-2000:]
    return p, json.loads(j.read_text())


@pytest.mark.realtime
@pytest.mark.parametrize("mutant,case", [("counter-letter-c", "*A-02.FETCH-COUNTERS"),
                                         ("continuation-response-id-00", "*P-02.SEND-200"),
                                         ("tres-half", "*A-05.RESPONSE-AT*"),
                                         ("flag-lock-ignored", "*P-11.FLAG-SET*")])
def test_real_time_mutants_are_caught(tmp_path, mutant, case):
    raw = rk_profile_dict(**REALTIME)
    p, data = ptpcert_run(tmp_path, iut_command(raw, mutant=mutant), raw, "--select", case)
    assert p.returncode == 1
    assert [c["verdict"] for c in data["cases"]] == ["fail"]
