"""Issue 25, items 6, 8, 9 and 11: the RK 512 cases and vectors against the manual's own text.

* 6: a CP 341 serves a partner no DX and at most 32 bytes of timers or counters (§6.3.2
  "Providing data", Table 6-10): the profile declares it (cell_fetch_limit_bytes,
  serves_dx_fetch); where it is silent, service and refusal both pass.
* 9: every vector gives the tester's side of Table 8-3.
* 11: a continuation command with no request open is answered with REATEL 36h (Table 8-1
  16#060E; Table 8-3 pairs it with the requester's 16#0908): a responder that stays silent
  fails.
"""

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rk512_profiles import rk_profile

from ptpcert.registry import by_id
from ptpcert import results as R
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

VECTORS = load_vector_sets()


def run(url, profile, select):
    res = R.RunResult(tool_version="test", started="")
    factory = make_factory(url, profile)
    try:
        Runner(factory, profile, RunOptions(check_status=True)).run(load_suite(profile, VECTORS, select=select), res)
    finally:
        factory.shutdown()
    return {c.id: c for c in res.cases}


# -- item 11 ------------------------------------------------------------------------------------
SILENT_CASES = ["SUITE.RK512.P-09A.CONTINUATION-WITHOUT-REQUEST", "RK512.ERR06.060E"]


def test_a_continuation_without_request_must_be_answered_36h():
    prof = rk_profile()
    good = run("sim:", prof, SILENT_CASES)
    assert {i: c.verdict for i, c in good.items()} == {i: R.PASS for i in SILENT_CASES}
    silent = run("sim:?mutant=continuation-without-request-ignored", prof, SILENT_CASES)
    assert {i: c.verdict for i, c in silent.items()} == {i: R.FAIL for i in SILENT_CASES}
    for c in silent.values():
        assert "36" in c.message or "nothing received" in c.message


def test_the_060e_vector_gives_both_sides_of_table_8_3():
    v = next(v for v in VECTORS if v.id == "RK512.ERR06.060E")
    assert v.expected.iut_status.required == (frozenset({0x060E}),)
    assert frozenset({0x0908}) in v.expected.tester_status.required
    assert not any(s.optional for s in v.steps)


# -- item 9 -------------------------------------------------------------------------------------
def _error_responses(v):
    """(sender, REATEL) of every error response on the vector's wire, read from its expanded
    steps with the link's codec."""
    from ptpcert.procedures.p3964.model import codec
    from ptpcert.scenario import expand
    out = []
    for s in expand(v):
        if s.kind not in ("expect", "send"):
            continue
        for data in (s.data,) + tuple(s.alternatives):
            try:
                f = codec.parse_body(data, v.params.procedure)
            except Exception:
                continue
            if len(f) >= 4 and f[0] in (0x00, 0xFF) and f[1] == f[2] == 0 and f[3]:
                out.append(("iut" if s.kind == "expect" else "tester", f[3]))
    return out


@pytest.mark.parametrize("v", [v for v in VECTORS if v.procedure == "rk512"], ids=lambda v: v.id)
def test_every_vector_gives_the_testers_side_of_table_8_3(v):
    from rk512_rules import RESPONDER_8_3, TABLE_8_3, UNKNOWN_REATEL
    spec = v.expected.tester_status
    named = set().union(*spec.required) | set(spec.optional) if spec.required else set(spec.optional)
    for who, reatel in _error_responses(v):
        if who == "iut":
            assert TABLE_8_3.get(reatel, UNKNOWN_REATEL) in named, (v.id, hex(reatel))
        elif reatel in RESPONDER_8_3:
            assert set(RESPONDER_8_3[reatel]) & named, (v.id, hex(reatel))


@pytest.mark.parametrize("vid,code", [("RK512.ERR06.060D", 0x090D), ("RK512.ERR06.060F", 0x0909),
                                      ("RK512.ERR06.0606", 0x0903), ("RK512.ERR06.0608", 0x090C),
                                      ("RK512.EX5.REATEL-2A", 0x060D), ("RK512.EX5.REATEL-32", 0x060F)])
def test_the_issues_vectors_name_the_testers_event(vid, code):
    v = next(v for v in VECTORS if v.id == vid)
    assert any(code in g for g in v.expected.tester_status.required)


# -- item 6 -------------------------------------------------------------------------------------
AMB20 = ["SUITE.RK512.P-04.FETCH-X-*", "SUITE.RK512.P-05.FETCH-[TZX]-*", "SUITE.RK512.P-04.FETCH-[TZ]-*",
         "SUITE.RK512.P-13.*", "SUITE.RK512.P-14.FETCH-FROM-DX", "RK512.FETCH.[TZX]-*"]


def _cp341(reatel):
    """A station that serves a partner as a CP 341 does (§6.3.2 'Providing data', Table 6-10)."""
    from ptpcert.procedures.rk512.model.readings import RK512_READINGS
    from dataclasses import replace
    return replace(RK512_READINGS, amb20_cell_fetch_limit_bytes=32, amb20_cell_limit_reatel=reatel,
                   amb20_serve_dx_fetch=False)


def _run_with(profile, select, readings=None, mutant=None):
    from ptpcert.registry import by_id
    from ptpcert.transport import sim_factory
    options = {"app": "script", **({"mutant": mutant} if mutant else {})}
    factory = sim_factory(by_id("rk512"), options, readings=readings)
    res = R.RunResult(tool_version="test", started="")
    try:
        Runner(factory, profile, RunOptions(check_status=True)).run(load_suite(profile, VECTORS, select=select), res)
    finally:
        factory.shutdown()
    return {c.id: c for c in res.cases}


@pytest.mark.parametrize("reatel", [0x34, 0x0C])
def test_where_the_profile_is_silent_a_cp341_and_a_full_server_both_pass(reatel):
    prof = rk_profile()
    assert prof.params.cell_fetch_limit_bytes is None and prof.params.serves_dx_fetch is None
    full = _run_with(prof, AMB20)
    cp341 = _run_with(prof, AMB20, readings=_cp341(reatel))
    assert len(full) == len(cp341) >= 25
    assert {i: c.message for i, c in full.items() if c.verdict != R.PASS} == {}
    assert {i: c.message for i, c in cp341.items() if c.verdict not in (R.PASS, R.INFORMATIONAL)} == {}
    # the CP 341 refused the timers/counters over 32 bytes and every DX: graded informational
    refused = {i for i, c in cp341.items() if c.verdict == R.INFORMATIONAL}
    assert {"RK512.FETCH.T-300", "RK512.FETCH.Z-1024", "RK512.FETCH.X-6", "SUITE.RK512.P-04.FETCH-T-128", "SUITE.RK512.P-05.FETCH-Z-300",
            "SUITE.RK512.P-04.FETCH-X-6", "SUITE.RK512.P-13.FETCH-COUNTERS-40"} <= refused
    assert "SUITE.RK512.P-04.FETCH-T-6" not in refused


@pytest.mark.parametrize("limit,dx", [(32, False), (1024, True), (2, None), (None, False)])
def test_where_the_profile_declares_it_the_declared_behaviour_is_required(limit, dx, monkeypatch):
    rk = {k: v for k, v in (("cell_fetch_limit_bytes", limit), ("serves_dx_fetch", dx)) if v is not None}
    prof = rk_profile(**rk)
    res = _run_with(prof, AMB20)
    assert {i: c.message for i, c in res.items() if c.verdict not in (R.PASS, R.UNSUPPORTED)} == {}
    for i, c in res.items():   # the vectors that accept either step aside for the suite's cases
        cells = i[:14] in ("RK512.FETCH.T-", "RK512.FETCH.Z-")
        steps_aside = (("RK512.FETCH.X" in i and dx is not None)
                       or (cells and limit is not None and (not i.endswith("-6") or limit < 6)))
        assert (c.verdict == R.UNSUPPORTED) == steps_aside, (i, c.message)
        if steps_aside:
            assert "[rk512]" in c.message
    # an IUT that does otherwise than the profile declares fails the suite's cases
    opposite = {"cell_fetch_limit_bytes": 1024 if (limit or 1024) < 1024 else 32}
    if dx is not None:
        opposite["serves_dx_fetch"] = not dx
    proc = by_id("rk512")
    monkeypatch.setattr(proc, "sim_params", lambda params, options: params.with_(**opposite))
    wrong = _run_with(prof, AMB20)
    failed = {i for i, c in wrong.items() if c.verdict == R.FAIL}
    if limit is not None:
        assert any("FETCH-T" in i or "FETCH-Z" in i or "P-13" in i for i in failed), failed
    if dx is not None:
        assert any("FETCH-X" in i or "FROM-DX" in i for i in failed), failed


@settings(max_examples=5, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(limit=st.one_of(st.none(), st.integers(1, 512).map(lambda n: 2 * n)), dx=st.sampled_from([None, True, False]),
       cells=st.sampled_from([None, 16, 1024]))
def test_every_declaration_passes_the_reference(limit, dx, cells):
    import sys
    from rk512_profiles import ROOT, rk_profile_dict
    sys.path.insert(0, str(ROOT / "tests" / "core"))
    from profile_property import judge
    raw = rk_profile_dict()
    for k, v in (("cell_fetch_limit_bytes", limit), ("serves_dx_fetch", dx), ("cell_area_cells", cells)):
        if v is not None:
            raw["rk512"][k] = v
    assert judge(raw) == ("run", [])


# -- item 8 -------------------------------------------------------------------------------------
@pytest.mark.parametrize("status", [0x0517, 0x1E41])
def test_len_1025_may_be_refused_with_0517_or_1e41(status):
    # Table 8-1 16#0517 ("transmission length > 1 KB") and Table 8-2 16#1E41 ("LEN 1..1024")
    # both fit a request of 1025 bytes: either passes, nothing reaches the wire
    from dataclasses import replace

    from ptpcert.procedures.rk512.model.readings import RK512_READINGS
    readings = replace(RK512_READINGS, n5_len_over_1024_status=status)
    prof = rk_profile()
    cases = [v for v in load_suite(prof, VECTORS) if any("LEN=1025" in line for line in v.extra.get("requests", []))]
    assert cases
    res = _run_with(prof, [v.id for v in cases], readings=readings)
    assert {i: c.message for i, c in res.items() if c.verdict != R.PASS} == {}
    for v in cases:
        results = " ".join(v.extra["results"])
        assert "16#0517" in results and "16#1E41" in results


def test_or_end_needs_alternatives_and_survives_the_toml():
    from ptpcert.scenario import VectorError, dump_vector, load_vector_text, vector_from_dict
    v = next(v for v in VECTORS if v.id == "RK512.FETCH.T-300")
    again = load_vector_text(dump_vector(v), "again.toml")
    assert [s.or_end for s in again.steps] == [s.or_end for s in v.steps] and v.steps[1].or_end == 0
    raw = {"id": "X", "procedure": "RK512", "title": "t", "reference": "§2.2.3", "rule": "r.", "group": "link",
           "iut_role": "receiver", "params": {"link": "3964R"},
           "steps": [{"receive": "00 00 00 00", "within": "TRES", "or_end": 0}]}
    with pytest.raises(VectorError, match="or_end"):
        vector_from_dict(raw, "X")
