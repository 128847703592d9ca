"""Every golden vector replayed against the reference model, the schema's error messages,
and the coverage of the wire-observable STATUS codes (Table 8-1)."""


from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ptpcert.check import check_vector
from ptpcert.scenario import (SINCE, ZERO, Expr, ExprError, Step, VectorError, dump_vector, load_dir, load_vector,
                              load_vector_sets, parse_vector_hex, vector_from_dict, vector_hex)

ROOT = Path(__file__).resolve().parents[2]
VECTORS = load_vector_sets()
GOLDEN = [v for v in VECTORS if v.group != "regression"]


@pytest.mark.parametrize("v", VECTORS, ids=lambda v: v.id)
def test_vector_replays_against_model(v):
    for outcome in check_vector(v):
        r = outcome.result
        assert outcome.ok, f"[app={outcome.app}] {r.verdict}: {r.message}"


def test_at_least_forty_golden_vectors_with_stable_ids():
    assert len(GOLDEN) >= 40
    assert len({v.id for v in VECTORS}) == len(VECTORS)
    for v in GOLDEN:
        assert v.reference and v.rule and v.title
        assert "§" in v.reference or "Fig." in v.reference or "Table" in v.reference


def test_the_manuals_figures_and_derived_vectors_are_all_there():
    ids = " ".join(v.id for v in VECTORS)
    for fig in ("FIG2-5", "FIG2-6", "FIG2-7", "FIG2-8"):
        assert fig in ids
    for n in range(1, 24):
        assert f".D{n:02d}." in ids, f"D{n} missing"
    for neg in ("NEG-DLE-ONCE", "NEG-STX", "NEG-NO-END"):
        assert neg in ids


# Table 8-1: codes a tester on the wire can induce or see. Informational ones (0701, 0801),
# 0815 (partly observable, its trigger open: A19) and 0816 (a block longer than agreed: the
# manual states no reaction on the line, and an IUT that accepts one raises nothing, A17) must
# be anticipated by a vector in which the model raises them; the others must be required by
# at least one vector.
OBSERVABLE = [0x0702, 0x0703, 0x0704, 0x0706, 0x0707, 0x0709, 0x070A, 0x0802, 0x0805, 0x0806,
              0x0808, 0x080A, 0x080C, 0x080D]
ANTICIPATED = [0x0701, 0x0801, 0x0815, 0x0816]


def test_every_wire_observable_status_is_an_expected_outcome():
    required = set()
    for v in GOLDEN:
        for group in v.expected.iut_status.required:
            required |= group
    missing = [f"16#{c:04X}" for c in OBSERVABLE if c not in required]
    assert not missing, f"no vector requires {missing}"


def test_informational_codes_raised_and_anticipated():
    for code in ANTICIPATED:
        found = False
        for v in GOLDEN:
            if code not in v.expected.iut_status.allowed:
                continue
            for o in check_vector(v):
                if f"16#{code:04X}" in o.result.observed_status:
                    found = True
        assert found, f"16#{code:04X}"


# -- the schema ----------------------------------------------------------------------
BASE = {
    "id": "T.X", "title": "t", "reference": "§1", "rule": "r", "group": "idle", "procedure": "3964R",
    "iut_role": "idle", "params": {}, "steps": [{"send": "15"}, {"silence": "CDT"}],
}


def broken(**changes):
    d = {**BASE, **changes}
    with pytest.raises(VectorError) as e:
        vector_from_dict({k: v for k, v in d.items() if v is not None}, "vectors/x.toml")
    return e.value


@pytest.mark.parametrize("changes,field,fragment", [
    (dict(id=None), "id", "missing"),
    (dict(id="lower.case"), "id", "upper-case"),
    (dict(procedure=None), "procedure", "missing"),
    (dict(procedure="X.25"), "procedure", "not allowed"),
    (dict(steps=[{"prime": "31"}], procedure="ASCII", params={}, group="send"), "steps[0]", "exactly one of"),
    (dict(group="misc"), "group", "allowed values"),
    (dict(iut_role="master"), "iut_role", "allowed values"),
    (dict(params={"cdt_ms": 15}), "params.cdt_ms", "steps of 10"),
    (dict(params={"cdt": 20}), "params.cdt", "not a parameter"),
    (dict(steps=[]), "steps", "non-empty"),
    (dict(steps=[{"send": "0G"}]), "steps[0].send", "not a hex digit"),
    (dict(steps=[{"send": "02", "expect": "10", "within": "ADT"}]), "steps[0]", "exactly one"),
    (dict(steps=[{"expect": "10"}]), "steps[0].within", "needs a window"),
    (dict(steps=[{"expect": "10", "within": "CTD"}]), "steps[0].within", "unknown name 'CTD'"),
    (dict(steps=[{"expect": "10", "within": "5"}]), "steps[0].within", "bare number"),
    (dict(steps=[{"expect": "10", "within": "ADT", "gap": "CDT"}]), "steps[0].gap", "not allowed"),
    (dict(steps=[{"wait": "CDT + 5"}]), "steps[0].wait", "adds a duration"),
    (dict(expected={"iut_status": ["16#0705"]}), "expected.iut_status[0]", "not in the CP 341 catalogue"),
    (dict(expected={"delivered": "31"}), "expected.delivered", "list"),
    (dict(colour="red"), "colour", "unknown key"),
    (dict(steps=[{"send": "02"}, {"expect": "10", "within": "ADT", "since": "mark"}]), "steps[1].since", "no step before"),
    (dict(steps=[{"expect": "10", "within": "ADT", "since": "mark", "mark": True}]), "steps[0].since", "sets mark"),
])
def test_broken_vectors_name_path_field_and_problem(changes, field, fragment):
    e = broken(**changes)
    assert e.path == "vectors/x.toml" and e.field == field
    assert fragment in str(e) and str(e).startswith("vectors/x.toml: ")


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(("send", "wait", "expect")), st.booleans(),
                          st.sampled_from(SINCE)), min_size=1, max_size=8))
def test_a_window_since_the_mark_needs_a_mark_before_it(shape):
    """A step measuring since = "mark" with no step before it marking (its own mark counts
    only after it) is refused when the vector is built, in code and from TOML, naming the
    case and the step; every other sequence of steps builds."""
    steps = tuple(Step(kind, b"\x10" if kind != "wait" else b"", duration=Expr("1ms") if kind == "wait" else ZERO,
                       within=Expr("ADT") if kind == "expect" else ZERO, mark=mark,
                       since=since if kind == "expect" else "previous")
                  for kind, mark, since in shape)
    first_mark = next((i for i, s in enumerate(steps) if s.mark), len(steps))
    bad = next((i for i, s in enumerate(steps) if s.since == "mark" and i <= first_mark), None)
    base = vector_from_dict(BASE, "vectors/x.toml")
    if bad is None:
        assert replace(base, steps=steps).steps == steps
        return
    with pytest.raises(ValueError, match=rf"case {base.id}: steps\[{bad}\] \(expect\) measures since = \"mark\""):
        replace(base, steps=steps)
    with pytest.raises(VectorError) as e:
        vector_from_dict({**BASE, "steps": [s.to_toml() for s in steps]}, "vectors/x.toml")
    assert e.value.field == f"steps[{bad}].since"


def test_broken_file_reports_its_path(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text("id = \n")
    with pytest.raises(VectorError, match="bad.toml: not valid TOML"):
        load_vector(f)
    (tmp_path / "a.toml").write_text((ROOT / "vectors" / "p3964" / "d02-nak-in-idle.toml").read_text())
    (tmp_path / "b.toml").write_text((ROOT / "vectors" / "p3964" / "d02-nak-in-idle.toml").read_text())
    f.unlink()
    with pytest.raises(VectorError, match="also the id of"):
        load_dir(tmp_path)


def test_expressions():
    env = {"CDT": 0.22, "ADT": 2.0, "CHAR": 0.001, "NAKTIM": 0.4, "BLOCK": 4.0, "STARTUP": 1.0}
    assert Expr("CDT + 2*CHAR").eval(env) == pytest.approx(0.222)
    assert Expr("0.5*ADT - 150ms").eval(env) == pytest.approx(0.85)
    assert Expr("-6*CHAR").eval(env) == pytest.approx(-0.006)
    assert Expr("2s/4").eval(env) == pytest.approx(0.5)
    for bad in ("CDT*ADT", "1/CDT", "__import__('os')", "CDT +", "CDT ** 2"):
        with pytest.raises(ExprError):
            Expr(bad)


def test_hex_repeat_tokens_roundtrip():
    data = parse_vector_hex("02 41*12 10 10")
    assert data == b"\x02" + b"A" * 12 + b"\x10\x10"
    assert vector_hex(data) == "02 41*12 10 10"
    assert parse_vector_hex(vector_hex(bytes(range(256)) * 2)) == bytes(range(256)) * 2


@pytest.mark.parametrize("v", VECTORS, ids=lambda v: v.id)
def test_dump_and_load_roundtrip(v, tmp_path):
    f = tmp_path / "v.toml"
    f.write_text(dump_vector(v, header="written back"))
    w = load_vector(f)
    assert w.to_toml() == v.to_toml()


def test_both_sides_of_the_conflict_figures_are_checked():
    from dataclasses import replace

    from ptpcert.check import check_both_sides
    fig = next(v for v in VECTORS if v.id == "3964R.FIG2-8.CONFLICT-IUT-LOW")
    ok = check_both_sides(fig)
    assert ok is not None and ok.ok, ok.result.message
    # the check can fail: with a tester of the same (low) priority both stations defer,
    # and the bytes on the line are no longer the figure's
    same = replace(fig, tester_params=fig.params)
    bad = check_both_sides(same)
    assert bad is not None and not bad.ok and "byte" in bad.result.message
    assert check_both_sides(next(v for v in VECTORS if v.id == "3964R.D03.GARBAGE-IN-IDLE")) is None


def test_time_expressions_are_parsed_once_and_never_by_two_threads_at_once(monkeypatch):
    """run --jobs judges cases in threads. CPython 3.11's ast module must not parse in two
    threads at once (gh-106905: "SystemError: AST constructor recursion depth mismatch",
    seen as a harness fault in a --jobs run), and a text parsed before is not parsed again."""
    import ast
    import threading
    import time

    from ptpcert.scenario import expr

    expr.parse_expr.cache_clear()
    inside, most, calls = 0, 0, []
    guard = threading.Lock()
    real = ast.parse

    def parse(src, *a, **kw):
        nonlocal inside, most
        with guard:
            inside += 1
            most = max(most, inside)
            calls.append(src)
        time.sleep(0.002)          # a thread switch in the middle of a parse
        try:
            return real(src, *a, **kw)
        finally:
            with guard:
                inside -= 1

    monkeypatch.setattr(expr.ast, "parse", parse)
    texts = [f"{k}*CDT + {i}*CHAR" for k in range(4) for i in range(10)]

    def work(k):
        for t in texts[k::4] + texts:
            assert Expr(t).eval({"CDT": 1.0, "CHAR": 0.5}) >= 0

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert most == 1, f"{most} threads parsed at once"
    assert set(calls) == set(texts)
    calls.clear()
    work(0)
    assert calls == [], "a text parsed before is not parsed again"


def test_a_case_that_cannot_be_built_is_unsupported_with_its_reason():
    """A suite's case that the profile leaves no room for stays listed (Vector.not_buildable):
    the runner reports it unsupported with that reason and runs none of its steps."""
    from dataclasses import replace

    from ptpcert import results as R
    from ptpcert.profile import load_profile
    from ptpcert.runner import Runner
    from ptpcert.suite import load_suite
    from ptpcert.transport import make_factory

    prof = load_profile(ROOT / "conformance" / "profiles" / "reference-20ms.toml")
    v = load_suite(prof, [])[0]
    why = "the profile leaves no room for it (a test's reason)"
    factory = make_factory("sim:", prof)
    try:
        res = Runner(factory, prof).run_case(replace(v, not_buildable=why))
        ok = Runner(factory, prof).run_case(v)
    finally:
        factory.shutdown()
    assert (res.verdict, res.message) == (R.UNSUPPORTED, why) and not res.transcript
    assert ok.verdict != R.UNSUPPORTED
