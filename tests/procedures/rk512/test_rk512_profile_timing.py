"""Issue 25, items 3 and 7: the suite under the profile's T_RES and baud rate.

* T_RES defaults to 10 s (§2.2.3 prose); where the profile declares none, a case whose outcome
  hinges on T_RES accepts an IUT that uses the figures' shorter value (Figs. 2-18, 2-19:
  "5 s (7 s, 10 s)") as well as one that uses 10 s (open point AMB-02).
* A case whose frames cannot cross the line within the IUT's T_RES (a short T_RES, a slow
  baud rate) is unsupported with the figures, never failed; pauses are derived from T_RES.
* The documented RK 512 profile is the bundled one (the site shows the file itself).
"""


import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rk512_profiles import ROOT, rk_profile_dict

import sys
sys.path.insert(0, str(ROOT / "tests" / "core"))
from profile_property import judge, vectors  # noqa: E402

from ptpcert import results as R  # noqa: E402
from ptpcert.profile import profile_from_dict  # noqa: E402
from ptpcert.runner import Runner, RunOptions  # noqa: E402
from ptpcert.suite import load_suite  # noqa: E402
from ptpcert.transport import make_factory  # noqa: E402

OK = (R.PASS, R.NON_STRICT, R.INFORMATIONAL, R.UNSUPPORTED)
#: the cases whose outcome hinges on the IUT's T_RES
TRES_CASES = ["SUITE.RK512.A-04.*", "SUITE.RK512.A-05.*", "SUITE.RK512.A-07.SHORT-RESPONSE", "SUITE.RK512.P-10.*",
              "SUITE.RK512.P-15.*", "SUITE.RK512.P-03.*", "RK512.TRES.*", "RK512.ERR0A.0A05"]


def silent(baud=9600, **rk):
    raw = rk_profile_dict(**rk)
    del raw["rk512"]["response_time_ms"]
    raw["iut"]["baud_rate"] = baud
    return raw


def run(raw, url="sim:", select=None):
    prof = profile_from_dict(raw)
    res = R.RunResult(tool_version="test", started="")
    factory = make_factory(url, prof)
    try:
        Runner(factory, prof, RunOptions(check_status=True)).run(load_suite(prof, vectors(), select=select), res)
    finally:
        factory.shutdown()
    return res


def test_the_default_t_res_is_ten_seconds():
    assert profile_from_dict(silent()).params.t_res == 10.0


@pytest.mark.parametrize("baud,iut_ms", [(9600, 5000), (9600, 10000), (600, 7000), (600, 10000), (300, 10000)])
def test_where_the_profile_is_silent_both_readings_of_t_res_pass(baud, iut_ms):
    # the IUT's own T_RES is the figures' value for the rate, or the prose's 10 s
    raw = silent(baud, cdt=60, adt=60)
    res = run(raw, f"sim:?response_time_ms={iut_ms}", TRES_CASES)
    assert len(res.cases) >= 8
    assert {c.id: c.message for c in res.cases if c.verdict not in OK} == {}
    assert [c.id for c in res.cases if c.verdict == R.UNSUPPORTED] == []


def test_a_declared_t_res_is_required():
    # the profile says 10 s: an IUT that gives up after 5 s fails the case that answers late
    raw = rk_profile_dict(t_res=10000)
    res = run(raw, "sim:?response_time_ms=5000", ["SUITE.RK512.A-05.RESPONSE-AT-0.8-TRES"])
    assert [c.verdict for c in res.cases] == [R.FAIL]


@pytest.mark.parametrize("change", [dict(t_res=100), dict(baud_rate=300, t_res=1000)])
def test_the_issues_profiles_pass_or_are_unsupported_with_the_figures(change):
    baud = change.pop("baud_rate", 9600)
    raw = rk_profile_dict(**change)
    raw["iut"]["baud_rate"] = baud
    if baud == 300:
        raw["iut"]["character_delay_ms"] = raw["iut"]["acknowledgement_delay_ms"] = 60
    kind, problems = judge(raw)
    assert (kind, problems) == ("run", [])
    res = run(raw)
    short = [c for c in res.cases if c.verdict == R.UNSUPPORTED and "the vector is for link" not in c.message]
    assert short and all("T_RES" in c.message and "bit/s" in c.message for c in short)
    assert sum(c.verdict == R.PASS for c in res.cases) > 150


@settings(max_examples=6, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(baud=st.sampled_from([300, 600, 1200, 2400, 9600, 76800]), t_res=st.integers(10, 12000), big=st.booleans())
def test_any_t_res_at_any_baud_rate(baud, t_res, big):
    floor = {300: 60, 600: 40, 1200: 30}.get(baud, 20)
    raw = rk_profile_dict(cdt=floor, adt=floor, t_res=t_res)
    raw["iut"]["baud_rate"] = baud
    if not big:
        for k in ("db_bytes", "byte_area_bytes", "cell_area_cells"):
            del raw["rk512"][k]
    kind, problems = judge(raw)
    if kind == "refused":   # shorter than the shortest response takes at the rate: refused in one line
        assert len(problems) == 1 and "rk512.response_time_ms" in problems[0] and "\n" not in problems[0]
        assert t_res < 12 * 12 * 1000 / baud
    else:
        assert problems == []


def test_the_documented_profile_is_the_bundled_one():
    # the RK 512 guide shows the bundled file itself: the site's build hook replaces this line by
    # it (tests/core/test_docs.py checks the built page); the README shows no RK 512 profile
    assert "<!-- ptpcert:profile rk512-reference -->" in (ROOT / "docs" / "procedure-rk-512.md").read_text("utf-8")
    assert 'procedure = "RK512"' not in (ROOT / "README.md").read_text("utf-8")


def test_the_long_runs_shrunk_profile_a_first_command_where_a_continuation_is_due():
    # benchmarks/profile_property.py (seed 11): T_RES 15 ms at 9600 bit/s; P-09B's new first SEND
    # arrives after the responder's T_RES ran out: the case does not fit that T_RES (unsupported)
    raw = {"iut": {"procedure": "RK512", "send_trigger": "none", "line_conditions": "parmrk",
                   "status_from_stderr": True, "priority": "low", "character_delay_ms": 20,
                   "acknowledgement_delay_ms": 20, "setup_attempts": 1, "transmission_attempts": 1, "data_bits": 8,
                   "parity": "none"},
           "rk512": {"response_time_ms": 15, "memory": "pattern", "dx_range": [], "db_bytes": 65536,
                     "cell_fetch_limit_bytes": 2, "serves_dx_fetch": False}}
    assert judge(raw) == ("run", [])
