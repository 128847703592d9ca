"""The traceability matrix of every procedure that has a rules catalogue: every testable rule
is checked by a case or golden vector in every setting it applies to; untestable rules say
why and no case cites them; every rule id a case cites exists; the settings cover every value
of the catalogue's dimensions; ``ptpcert rules`` prints it (all catalogues without an option)
and ``--check`` gates on it; the HTML, JUnit and JSON reports carry each case's rule ids.

A procedure is picked up as soon as its package has a ``rules.toml``."""

import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import ptpcert.conformance as conformance
from ptpcert import results as R
from ptpcert.cli.rules import matrices
from ptpcert.profile import load_profile
from ptpcert.registry import by_id, procedures
from ptpcert.report import anchor
from ptpcert.report.html.rules import rule_anchor
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.rules import Rule, for_procedure
from ptpcert.traceability import CHECKED, MISSING, NOT_APPLICABLE, UNTESTABLE, Setting, build, render_text
from ptpcert.scenario import Expected, StatusSpec, Step, Vector, load_vector_sets

ROOT = Path(__file__).resolve().parents[2]
#: every procedure with a catalogue (3964, RK 512, and the ASCII driver once it has one)
WITH_CATALOGUE = [p.id for p in procedures() if len(for_procedure(p))]
PROFILES = ROOT / "conformance" / "profiles"


@pytest.fixture(scope="module", params=WITH_CATALOGUE)
def matrix(request):
    (m,) = matrices([by_id(request.param)])
    return m


def test_the_three_built_in_procedures_that_have_catalogues_are_found():
    assert {"p3964", "rk512"} <= set(WITH_CATALOGUE)


def test_every_testable_rule_has_a_case_in_every_setting_it_applies_to(matrix):
    missing = {e.rule.id: e.missing or ["everywhere"] for e in matrix.entries if e.status == MISSING}
    assert not missing, f"rules without a case: {missing}"
    assert not matrix.unknown, f"cases cite ids the catalogue does not have: {matrix.unknown}"
    assert not [e.rule.id for e in matrix.cited_untestable]
    # over all settings every testable rule applies somewhere (else it is in no setting)
    assert not [e.rule.id for e in matrix.entries if e.status == NOT_APPLICABLE]
    assert matrix.ok


def test_untestable_rules_carry_a_reason_and_every_rule_a_role_and_a_reference(matrix):
    cat = matrix.catalogue
    for e in matrix.entries:
        if e.status == UNTESTABLE:
            assert len(e.rule.untestable) > 30, e.rule.id
        assert e.rule.role in cat.roles and ("§" in e.rule.ref or "Table" in e.rule.ref or "Fig." in e.rule.ref)
        for a in e.rule.readings:
            assert a in cat.readings
    assert matrix.count(CHECKED) + matrix.count(UNTESTABLE) == len(matrix.entries)


def test_the_settings_cover_every_value_of_every_dimension(matrix):
    """rule_settings() computes the matrix for every setting a rule may be restricted to: a
    rule of 3964 only, of priority high, of the passive role ... is checked somewhere."""
    def has(setting, dim, value):
        got = setting.values.get(dim)
        return value in got if isinstance(got, (tuple, list)) else value == got

    for dim, values in matrix.catalogue.dimensions.items():
        for value in values:
            if any(has(s, dim, value) for s in matrix.settings):
                continue
            # a value left out only where every rule of its own cannot be seen on the line
            # (ASCII: RTS/CTS and automatic V.24 need modem lines)
            # (a rule that applies to other values too is checked under those)
            covered = {v for v in values if any(has(st, dim, v) for st in matrix.settings)}
            own = [r for r in matrix.catalogue if value in r.applies.get(dim, ()) and not covered & set(r.applies[dim])]
            assert not [r.id for r in own if r.testable], (dim, value)


def test_every_golden_vector_and_suite_case_cites_a_rule(matrix):
    proc = by_id(matrix.catalogue.procedure)
    golden = [v for v in load_vector_sets() if v.group != "regression" and v.procedure == proc.id]
    assert all(v.rules for v in golden), [v.id for v in golden if not v.rules]
    for _, _, profile in proc.rule_settings():
        cases = conformance.cases(profile)
        # a case the profile leaves no room for (built as unsupported, with the reason) checks nothing
        built = [c for c in cases if not c.not_buildable]
        assert built and all(c.rules for c in built), [c.id for c in built if not c.rules]


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
    # a matrix of one setting a rule does not apply to: not applicable, not missing
    m = build(cat, [(plain, [_v("Z", ["3964.A.B"])])])
    assert m.entry("3964.A.R").status == NOT_APPLICABLE and m.ok
    assert m.summary() == "3 rules, 1 checked, 1 untestable, 0 missing, 1 not applicable here"


def test_a_rule_of_several_roles_applies_where_the_iut_plays_all_of_them():
    both = Rule("X.A.B", "§1", "Both roles.", "S", "any", {"roles": ("passive", "active")})
    one = Rule("X.A.P", "§1", "Passive.", "S", "any", {"roles": ("passive",)})
    assert both.applies_to({"roles": ("passive", "active")}) and not both.applies_to({"roles": ("passive",)})
    assert one.applies_to({"roles": ("active", "passive")}) and not one.applies_to({"roles": ("active",)})
    assert one.applies_to({"link": "3964R"})     # a dimension the setting does not name matches


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "ptpcert.cli", "rules", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


def _profile_of(pid: str) -> Path:
    """A bundled profile of the procedure (conformance/profiles)."""
    for f in sorted(PROFILES.glob("*.toml")):
        if load_profile(f).procedure.id == pid:
            return f
    raise AssertionError(f"no bundled profile of {pid}")


def test_ptpcert_rules_check_exits_0_with_the_counts_and_works_for_a_profile(matrix):
    proc = by_id(matrix.catalogue.procedure)
    p = run_cli("--procedure", proc.names[0], "--check")
    assert p.stdout.strip().splitlines()[-1] == matrix.summary()
    assert p.returncode == 0, p.stdout[-2000:]
    p = run_cli("--procedure", proc.names[0], "--json", "-")
    data = json.loads(p.stdout)
    assert p.returncode == 0 and data["procedure"] == proc.id and len(data["rules"]) == len(matrix.entries)
    assert {r["status"] for r in data["rules"]} <= {CHECKED, UNTESTABLE}
    p = run_cli("--profile", str(_profile_of(proc.id)), "-q")
    assert p.returncode == 0 and "settings: this profile" in p.stdout, p.stderr
    assert f"{len(matrix.entries)} rules," in p.stdout.strip().splitlines()[-1]


def test_ptpcert_rules_without_an_option_prints_every_catalogue():
    p = run_cli("-q")
    summaries = [line for line in p.stdout.splitlines() if line.endswith(" missing") or "not applicable" in line]
    assert p.returncode == 0 and len(summaries) == len(WITH_CATALOGUE)
    for pid in WITH_CATALOGUE:
        assert f"{for_procedure(pid).title} rules (" in p.stdout


def test_ptpcert_rules_select_and_json_file_for_3964(tmp_path):
    p = run_cli("--select", "3964.RX.BCC-CHECK", "--json", str(tmp_path / "m.json"))
    assert p.returncode == 0 and "3964.RX.BCC-CHECK" in p.stdout and "SUITE.RECEIVE.BCC-DLE-ONCE" in p.stdout
    data = json.loads((tmp_path / "m.json").read_text())
    (rule,) = [r for m in data for r in m["rules"]]
    assert rule["status"] == "checked" and rule["scope"] == "3964R only"
    assert {c["id"] for c in rule["cases"]} >= {"SUITE.RECEIVE.BCC-DLE-ONCE", "3964R.BCC.NEG-STX"}
    p = run_cli("--profile", str(PROFILES / "reference-20ms.toml"), "--select", "3964.START.*", "-q")
    assert p.returncode == 0 and "settings: this profile" in p.stdout


# ------------------------------------------------------------------ the reports carry the rule ids
@pytest.mark.parametrize("pid", WITH_CATALOGUE)
def test_the_reports_carry_each_cases_rules_and_a_failed_case_links_to_them(pid, tmp_path):
    """A short run of the procedure's suite in virtual time, one case marked failed: the HTML
    report's traceability section has a row per rule, the failed case links to the rows of its
    rules (which show the failure); the JUnit and JSON results carry each case's rule ids."""
    from ptpcert.report.html import render
    from ptpcert.report.junit import write_junit
    from ptpcert.runner import Runner, RunOptions
    from ptpcert.suite import load_suite
    from ptpcert.transport import make_factory

    proc = by_id(pid)
    profile = proc.rule_settings()[0][2]
    ids = [c.id for c in conformance.cases(profile)[:3]]
    cases = load_suite(profile, [], select=ids)
    run = R.RunResult(tool_version="t", started="", procedure=proc.title, profile=profile.to_dict())
    factory = make_factory("sim:", profile)
    try:
        Runner(factory, profile, RunOptions()).run(cases, run)
    finally:
        factory.shutdown()
    assert len(run.cases) == 3 and all(c.rules for c in run.cases)
    failed = run.cases[0]
    failed.verdict = R.FAIL
    page = render(run)
    cat = for_procedure(pid)
    assert 'id="traceability"' in page and page.count('<tr id="rule-') == len(cat)
    section = page[page.index(f'id="{anchor(failed.id)}"'):]
    for rid in failed.rules:
        assert f'href="#{rule_anchor(rid)}"' in section
        assert f'<tr id="{rule_anchor(rid)}" data-verdict="fail"' in page
    write_junit(run, tmp_path / "r.xml")
    props = [{p.get("name"): p.get("value") for p in tc.iter("property")}
             for tc in ET.parse(tmp_path / "r.xml").getroot().iter("testcase")]
    assert [p.get("rules", "").split() for p in props] == [c.rules for c in run.cases]
    run.write_json(tmp_path / "r.json")
    back = json.loads((tmp_path / "r.json").read_text())
    assert [c["rules"] for c in back["cases"]] == [c.rules for c in run.cases]
