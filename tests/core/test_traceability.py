"""The traceability matrix: every testable rule of the 3964(R) catalogue is checked by a case
or golden vector in every setting it applies to; untestable rules say why and no case cites
them; every rule id a case cites exists; ``ptpcert rules`` prints it and ``--check`` gates on it."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from ptpcert.cli.rules import matrices
from ptpcert.registry import by_id
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.rules import Rule
from ptpcert.traceability import CHECKED, MISSING, UNTESTABLE, Setting, build, render_text
from ptpcert.scenario import Expected, StatusSpec, Step, Vector, load_vector_sets

ROOT = Path(__file__).resolve().parents[2]
PROC = by_id("p3964")


@pytest.fixture(scope="module")
def matrix():
    (m,) = matrices([PROC])
    return m


def test_every_testable_rule_has_a_case_in_every_setting_it_applies_to(matrix):
    missing = {e.rule.id: e.missing or ["everywhere"] for e in matrix.entries if e.status == MISSING}
    assert not missing, f"rules without a case: {missing}"
    assert not matrix.unknown, f"cases cite ids the catalogue does not have: {matrix.unknown}"
    assert not [e.rule.id for e in matrix.cited_untestable]
    assert matrix.ok


def test_untestable_rules_carry_a_reason(matrix):
    for e in matrix.entries:
        if e.status == UNTESTABLE:
            assert len(e.rule.untestable) > 30


def test_every_golden_vector_and_suite_case_cites_a_rule():
    # the 3964(R) catalogue's vectors; RK 512 and the ASCII driver cite their checklists by case id
    golden = [v for v in load_vector_sets() if v.group != "regression" and v.procedure == PROC.id]
    assert golden
    assert all(v.rules for v in golden), [v.id for v in golden if not v.rules]
    import ptpcert.conformance as conformance
    for _, _, profile in PROC.rule_settings():
        cases = conformance.cases(profile)
        assert all(c.rules for c in cases), [c.id for c in cases if not c.rules]


def _v(id, rules, **params):
    return Vector(procedure="p3964", id=id, title=f"title of {id}", reference="§1", rule="r.", group="idle", iut_role="idle",
                  params=Params3964(**params), steps=(Step("send", b"\x15"),), expected=Expected(StatusSpec()),
                  rules=tuple(rules))


def test_a_rule_is_missing_in_a_setting_without_a_case():
    from ptpcert.rules import Catalogue
    cat = Catalogue("p3964", "t", "3964", "m", (
        Rule("3964.A.B", "§1", "Both.", "S", "any"),
        Rule("3964.A.R", "§1", "3964R only.", "S", "any", {"procedure": ("3964R",)}),
        Rule("3964.A.U", "§1", "Untestable.", "S", "any", untestable="a reason long enough to read well"),
    ))
    r_low, plain = Setting("3964R low", {"procedure": "3964R", "priority": "low"}), Setting(
        "3964 low", {"procedure": "3964", "priority": "low"})
    m = build(cat, [(r_low, [_v("X", ["3964.A.B", "3964.A.R"])]), (plain, [_v("Y", ["3964.NO.SUCH"])])])
    assert m.entry("3964.A.B").status == MISSING and m.entry("3964.A.B").missing == ["3964 low"]
    assert m.entry("3964.A.R").status == CHECKED and m.entry("3964.A.R").applies == ["3964R low"]
    assert m.entry("3964.A.U").status == UNTESTABLE
    assert m.unknown == [("Y", "3964.NO.SUCH")] and not m.ok
    assert m.summary() == "3 rules, 1 checked, 1 untestable, 1 missing"
    text = render_text(m, only_problems=True)
    assert "MISSING: no case in 3964 low" in text and "3964.A.R" not in text
    assert "Y cites 3964.NO.SUCH" in text


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "ptpcert.cli", "rules", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


def test_ptpcert_rules_prints_the_matrix_and_check_ends_with_the_counts(matrix, tmp_path):
    p = run_cli("--procedure", "3964", "--check")
    last = p.stdout.strip().splitlines()[-1]
    assert last == matrix.summary()
    assert p.returncode == (0 if matrix.ok else 1)
    p = run_cli("--procedure", "3964", "--select", "3964.RX.BCC-CHECK", "--json", str(tmp_path / "m.json"))
    assert p.returncode == 0 and "3964.RX.BCC-CHECK" in p.stdout and "SUITE.RECEIVE.BCC-DLE-ONCE" in p.stdout
    data = json.loads((tmp_path / "m.json").read_text())
    (rule,) = data["rules"]
    assert rule["status"] == "checked" and rule["scope"] == "3964R only"
    assert {c["id"] for c in rule["cases"]} >= {"SUITE.RECEIVE.BCC-DLE-ONCE", "3964R.BCC.NEG-STX"}
    p = run_cli("--profile", str(ROOT / "conformance/profiles/reference-20ms.toml"), "--select", "3964.START.*", "-q")
    assert p.returncode == 0 and "settings: this profile" in p.stdout
