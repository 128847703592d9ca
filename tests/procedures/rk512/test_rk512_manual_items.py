"""Issue 25, items 6, 8, 9 and 11: the RK 512 cases and vectors against the manual's own text.

* 11: a continuation command with no request open is answered with REATEL 36h (Table 8-1
  16#060E; Table 8-3 pairs it with the requester's 16#0908): a responder that stays silent
  fails.
"""

import pytest
from rk512_profiles import rk_profile

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
