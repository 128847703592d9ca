"""The profile schema (ptpcert.schema): each procedure declares every key its profile takes,
the loader checks each key against it, and its defaults and edges are what the procedures'
own checks allow (the schema and the validation cannot drift apart)."""

from __future__ import annotations

import pytest

from ptpcert import schema
from ptpcert.profile import ProfileError, profile_from_dict
from ptpcert.registry import procedures
from ptpcert.schema import Key, problem

PROCS = [p for p in procedures() if p.suite]


def test_problem_names_the_allowed_values_and_the_table():
    timer = Key("t", "iut", "int", "a timer", ref="Table 2-4", lo=20, hi=100, step=10, unit=" ms".strip())
    assert problem(timer, 30) is None and problem(timer, 100) is None
    for bad in (10, 25, 110, "30", True, 30.0):
        why = problem(timer, bad)
        assert why and "20..100" in why and "Table 2-4" in why
    choice = Key("c", "iut", "choice", "c", choices=("low", "high"))
    assert problem(choice, "low") is None and "allowed values" in problem(choice, "mid")
    codes = Key("b", "x", "bytes", "b", size=(1, 2))
    assert problem(codes, [3]) is None and problem(codes, [13, 10]) is None
    assert problem(codes, []) and problem(codes, [1, 2, 3]) and problem(codes, [256]) and problem(codes, "03")
    pair = Key("r", "x", "pair", "r", lo=1, hi=255, size=(0, 2))
    assert problem(pair, []) is None and problem(pair, [3, 3]) is None and problem(pair, [4, 3])
    sub = Key("s", "x", "subset", "s", choices=("a", "b"))
    assert problem(sub, ["b"]) is None and problem(sub, []) and problem(sub, ["a", "a"]) and problem(sub, ["c"])
    maybe_none = Key("s", "x", "subset", "s", choices=("a", "b"), size=(0, 2))   # [] allowed (issue 25, item 13)
    assert problem(maybe_none, []) is None and problem(maybe_none, ["a", "b"]) is None
    assert problem(maybe_none, ["a", "a"]) and problem(maybe_none, "a") and "a list of" in problem(maybe_none, ["c"])


@pytest.mark.parametrize("proc", PROCS, ids=lambda p: p.id)
def test_the_schema_names_every_key_the_procedure_reads(proc):
    keys = proc.profile_schema()
    assert {k.name for k in keys if k.table == "iut"} == set(proc.profile_keys())
    assert {k.table for k in keys} <= {"iut", *proc.tables}
    for k in keys:
        assert k.doc and k.kind in schema.KINDS
        if not k.required and k.default is not None:
            assert problem(k, k.default) is None, (k.name, k.default)


@pytest.mark.parametrize("proc", PROCS, ids=lambda p: p.id)
def test_the_loader_refuses_what_the_schema_refuses_naming_the_key(proc):
    """Each key set to a value of the wrong kind, in a profile otherwise the reference's:
    refused in one line naming the key."""
    base = proc.reference_profile()
    good = {"iut": {"procedure": proc.names[0], "send_trigger": base.send_trigger,
                    "line_conditions": base.line_conditions, "status_from_stderr": base.status_from_stderr}}
    for k in proc.profile_schema():
        if k.required:
            good.setdefault(k.table, {})[k.name] = base.to_dict()[k.name]
    profile_from_dict(good)   # the base is accepted
    for k in proc.profile_schema():
        raw = {t: dict(v) for t, v in good.items()}
        raw.setdefault(k.table, {})[k.name] = "not a value" if k.kind != "str" else 1
        with pytest.raises(ProfileError) as e:
            profile_from_dict(raw)
        assert e.value.key == k.path and "\n" not in str(e.value), str(e.value)
