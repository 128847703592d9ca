"""The RK 512 golden vectors (vectors/rk512/): exactly what tests/procedures/rk512/rk512_golden.py builds
from the rules (so every byte is derived from Tables 2-1, 2-2 and the 3964R block rule,
never from an implementation), the issue's list covered, each with its manual reference,
rule and STATUS outcome; their replay against the model is tests/core/test_vectors.py's."""

import pytest

from ptpcert.scenario import load_vector_sets
from ptpcert.status import lookup

import rk512_golden
from rk512_rules import TABLE_8_3

VECTORS = [v for v in load_vector_sets() if v.procedure == "rk512"]
IDS = {v.id for v in VECTORS}


def test_the_files_are_what_the_rules_build():
    built = {rk512_golden.file_name(v): rk512_golden.render(v) for v in rk512_golden.all_vectors()}
    on_disk = {f.name: f.read_text("utf-8") for f in rk512_golden.OUT.glob("*.toml")}
    assert sorted(on_disk) == sorted(built), "run: python tests/procedures/rk512/rk512_golden.py --write"
    for name, text in built.items():
        assert on_disk[name] == text, f"{name} differs from its rules (python tests/procedures/rk512/rk512_golden.py --write)"


def test_at_least_forty_each_with_reference_rule_and_outcome():
    assert len(VECTORS) >= 40
    for v in VECTORS:
        assert v.reference and v.rule.endswith(".") and v.title, v.id
        assert "§" in v.reference or "Table" in v.reference or "Fig." in v.reference, v.id
        assert ".md" not in v.reference, v.id
        assert v.binds and "link" in v.binds
        # the STATUS outcome: what the IUT must raise, or may, or nothing (an empty list)
        assert isinstance(v.expected.iut_status.required, tuple)


def test_the_issues_list_is_covered():
    for ex in ("EX1", "EX2", "EX3", "EX4", "EX5", "EX6"):
        assert any(f".{ex}." in i for i in IDS), ex
    for n in (1, 10, 128, 129, 200, 1024):
        assert f"RK512.SEND.DB-{n}" in IDS and f"RK512.SEND.DX-{n}" in IDS
    for typ in "DXEAMTZ":
        for n in (6, 128, 300, 1024):
            assert f"RK512.FETCH.{typ}-{n}" in IDS
    for reatel in TABLE_8_3:
        assert f"RK512.EX5.REATEL-{reatel:02X}" in IDS and f"RK512.EX5.REATEL-{reatel:02X}-CONTINUATION" in IDS
    assert "RK512.EX5.REATEL-42" in IDS     # an unknown one: 16#090E
    for n in range(1, 0x13):
        code = 0x0600 + n
        try:
            lookup(code)
        except Exception:
            continue
        assert f"RK512.ERR06.{code:04X}" in IDS, f"16#{code:04X}"
    for n in range(1, 6):
        assert f"RK512.ERR0A.0A{n:02X}" in IDS
    assert {"RK512.QFD.CROSSING-IUT-LOW", "RK512.TRES.ACTIVE-EXPIRY", "RK512.TRES.PASSIVE-EXPIRY"} <= IDS
    assert {"RK512.DLE.HEADER", "RK512.DLE.DATA", "RK512.DLE.REATEL", "RK512.DLE.BCC"} <= IDS


@pytest.mark.parametrize("reatel,code", sorted(TABLE_8_3.items()))
def test_every_reatel_vector_expects_its_table_8_3_event(reatel, code):
    v = next(v for v in VECTORS if v.id == f"RK512.EX5.REATEL-{reatel:02X}")
    assert v.expected.iut_status.required == (frozenset({code}),)
    assert v.extra["results"][-1].endswith(f"STATUS 16#{code:04X}")


def test_the_worked_examples_carry_the_manuals_bccs():
    # Example 1: 42h and 13h; Example 3: FBh and 3Dh; Example 6: E4h, 9Ah, 48h, F9h, F8h, EFh, E9h, E3h
    def last_bytes(vid):
        v = next(v for v in VECTORS if v.id == vid)
        return [s.data[-1] for s in v.steps if s.kind in ("send", "expect") and len(s.data) > 3]
    assert last_bytes("RK512.EX1.SEND-10.PASSIVE") == [0x42, 0x13]
    assert last_bytes("RK512.EX3.FETCH-6.ACTIVE") == [0xFB, 0x3D]
    assert last_bytes("RK512.EX1.SEND-10-NO-CPU.ACTIVE")[0] == 0xA2
    for vid, bcc in (("SEND-DX", 0x9A), ("FLAG-CPU-2", 0x48), ("SEND-ODD-LEN", 0xF9), ("FETCH-ODD-LEN", 0xF8),
                     ("FETCH-DX", 0xEF), ("FETCH-FLAGS", 0xE9), ("FETCH-COUNTERS", 0xE3)):
        assert last_bytes(f"RK512.EX6.{vid}.ACTIVE")[0] == bcc, vid
    assert last_bytes("RK512.EX6.DLE-IN-HEADER-AND-DATA.PASSIVE")[0] == 0xE4
