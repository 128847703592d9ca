"""Issue 25, RK 512: the suite and the golden vectors fit the IUT's memory, link and attempt
counts, whatever the profile says. A case is built from the profile's areas (a header check
FETCHes no more words than a DB holds), or it is unsupported with the reason (a SEND of 200
bytes into a 64-byte DB, a crossing STX with one setup attempt); a golden vector, fixed
bytes, says what it needs (its DBs and their size, its flag byte) and is unsupported where
the profile lacks it. The reference (sim:) passes everything else."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "core"))

from profile_property import judge, to_toml, vectors  # noqa: E402

from ptpcert import results as R  # noqa: E402
from ptpcert.conformance.rk512.active import LOCAL_CHECKS  # noqa: E402
from ptpcert.profile import ProfileError, profile_from_dict  # noqa: E402
from ptpcert.procedures.rk512.model.params import INVALID_REQUESTS  # noqa: E402
from ptpcert.runner import Runner, RunOptions  # noqa: E402
from ptpcert.suite import load_suite  # noqa: E402
from ptpcert.transport import make_factory  # noqa: E402


def raw_profile(*, priority="low", adt=200, setup_attempts=6, transmission_attempts=6, **rk) -> dict:
    """A profile as a user writes it; T_RES and the baud rate fixed (their cases are another
    item of issue 25)."""
    iut = dict(procedure="RK512", priority=priority, character_delay_ms=220, acknowledgement_delay_ms=adt,
               setup_attempts=setup_attempts, transmission_attempts=transmission_attempts, send_trigger="none",
               line_conditions="none", status_from_stderr=True,
               setups={"cpu_stop": "--cpu-stop", "flag_set": "--cf-set {flag}@{reset_ms}"})
    return {"iut": iut, "rk512": {"response_time_ms": 10000, **rk}}


def run(raw: dict, select=None) -> list[R.CaseResult]:
    profile = profile_from_dict(raw, "<test>")
    cases = load_suite(profile, vectors(), select=select)
    factory = make_factory("sim:", profile)
    try:
        result = R.RunResult(tool_version="test", started="now")
        Runner(factory, profile, RunOptions(echo=False, check_status=True)).run(cases, result)
    finally:
        factory.shutdown()
    return result.cases


def assert_passes(raw: dict) -> None:
    kind, problems = judge(raw)
    assert kind == "run", problems
    assert not problems, to_toml(raw) + "\n" + "\n".join(problems[:20])


# -- the profiles of the issue ------------------------------------------------------------------
@pytest.mark.parametrize("rk", [
    {"link": "3964", "memory": "unknown"},
    {"link": "3964", "roles": ["passive"]},
    {"db_bytes": 64}, {"db_bytes": 256, "memory": "unknown"}, {"db_bytes": 2, "dx_range": [1, 1]},
    {"db_range": [1, 1]}, {"db_range": [200, 255]}, {"db_range": [1, 1], "db_bytes": 2, "byte_area_bytes": 1},
    {"byte_area_bytes": 12}, {"byte_area_bytes": 1, "cell_area_cells": 1},
])
def test_memory_of_the_issue(rk):
    assert_passes(raw_profile(**rk))


@pytest.mark.parametrize("iut", [{"adt": 50, "setup_attempts": 1},
                                 {"setup_attempts": 1, "transmission_attempts": 1},
                                 {"adt": 60_000},                  # 2 ADT longer than T_RES
                                 {"priority": "high", "setup_attempts": 1}])
def test_attempts_and_timers_of_the_issue(iut):
    assert_passes(raw_profile(**iut))


def test_a_crossing_needs_a_second_setup_attempt():
    by_id = {c.id: c for c in run(raw_profile(setup_attempts=1), select=["*CONFLICT*", "*P-09C*", "*CROSSING*"])}
    for cid in ("SUITE.RK512.L-05.CONFLICT-IUT-LOW", "SUITE.RK512.P-09C.COMMAND-BEFORE-RESPONSE",
                "RK512.QFD.CROSSING-IUT-LOW"):
        assert by_id[cid].verdict == R.UNSUPPORTED and "setup_attempts >= 2" in by_id[cid].message
    again = {c.id: c for c in run(raw_profile(setup_attempts=2), select=["*CONFLICT*", "*CROSSING*"])}
    assert {c.verdict for c in again.values()} == {R.PASS}


def test_cases_that_do_not_fit_say_why():
    by_id = {c.id: c for c in run(raw_profile(db_bytes=64, db_range=[1, 1]))}
    assert by_id["RK512.EX2.SEND-200.PASSIVE"].verdict == R.UNSUPPORTED
    assert "db_bytes >= 200" in by_id["RK512.EX2.SEND-200.PASSIVE"].message
    assert "DB 10" in by_id["RK512.ERR06.0608"].message       # the vector's DB is not in [1, 1]
    assert by_id["SUITE.RK512.P-07G.FLAG-BIT-8"].verdict == R.PASS  # built to fit
    tiny = {c.id: c for c in run(raw_profile(byte_area_bytes=12), select=["RK512.ERR06.060F"])}
    assert "byte_area_bytes >= 13" in tiny["RK512.ERR06.060F"].message


# -- the property over the keys of the IUT's memory and link ----------------------------------------
def _range(lo: int, hi: int):
    return st.tuples(st.integers(lo, hi), st.integers(lo, hi)).map(sorted).map(list)


memory = st.fixed_dictionaries({}, optional={
    "link": st.sampled_from(["3964R", "3964"]),
    "roles": st.sampled_from([["passive"], ["active"], ["passive", "active"]]),
    "memory": st.sampled_from(["pattern", "unknown"]),
    "db_range": st.one_of(_range(1, 255), st.sampled_from([[1, 1], [200, 255], [255, 255]])),
    "dx_range": st.one_of(st.just([]), _range(1, 255)),
    "db_bytes": st.one_of(st.sampled_from([2, 4, 64, 128, 130, 256]), st.integers(1, 700).map(lambda n: 2 * n)),
    "byte_area_bytes": st.one_of(st.integers(1, 20), st.integers(1, 1200)),
    "cell_area_cells": st.integers(1, 600),
})
link = st.fixed_dictionaries({"priority": st.sampled_from(["low", "high"]), "adt": st.sampled_from([20, 50, 2000]),
                              "setup_attempts": st.integers(1, 3), "transmission_attempts": st.integers(1, 3)})


@settings(max_examples=12, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(rk=memory, line=link)
def test_every_memory_and_attempt_count(rk, line):
    raw = raw_profile(**line, **rk)
    if rk.get("roles") == ["active"]:
        raw["rk512"]["requests"] = "script"
    assert_passes(raw)


# -- item 13: the local checks, one case each --------------------------------------------------------
def test_one_local_check_case_per_invalid_request():
    assert [name for name, *_ in LOCAL_CHECKS] == list(INVALID_REQUESTS)
    cases = [c for c in run(raw_profile(), select=["*A-11.*"])]
    assert len(cases) == len(INVALID_REQUESTS) and {c.verdict for c in cases} == {R.PASS}


def test_inexpressible_requests_are_unsupported_with_the_reason():
    raw = raw_profile(inexpressible_requests=["send-to-flags", "cpu-5"])
    by_id = {c.id: c for c in run(raw, select=["*A-11.*"])}
    for name in INVALID_REQUESTS:
        c = by_id[f"SUITE.RK512.A-11.LOCAL-CHECK-{name.upper()}"]
        if name in ("send-to-flags", "cpu-5"):
            assert c.verdict == R.UNSUPPORTED and name in c.message and "inexpressible_requests" in c.message
        else:
            assert c.verdict == R.PASS


@pytest.mark.parametrize("value,ok", [([], True), (["db-0"], True), (list(INVALID_REQUESTS), True),
                                      (["db-1"], False), (["db-0", "db-0"], False), ("db-0", False)])
def test_the_inexpressible_requests_key(value, ok):
    raw = raw_profile(inexpressible_requests=value)
    if ok:
        assert profile_from_dict(raw, "p.toml").params.inexpressible_requests == tuple(value)
    else:
        with pytest.raises(ProfileError, match="inexpressible_requests"):
            profile_from_dict(raw, "p.toml")
