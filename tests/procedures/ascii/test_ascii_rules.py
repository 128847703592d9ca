"""The ASCII driver's traceability: every testable rule of its catalogue
(harness/procedures/ascii/rules.toml) is checked by a case or golden vector in every setting
of the matrix it applies to (settings.py), untestable rules say why and no case cites them,
every case, vector and analyzer finding cites rules the catalogue has, and ``ptpcert rules``
prints and checks the matrix for the procedure and for an ASCII profile."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

import ptpcert.conformance as conformance
from ptpcert import analysis as A
from ptpcert.cli.rules import matrices
from ptpcert.procedures.ascii.description import reference_profile
from ptpcert.procedures.ascii.settings import buffer_limit
from ptpcert.registry import by_id
from ptpcert.rules import for_procedure
from ptpcert.scenario import load_vector_sets
from ptpcert.traceability import MISSING, UNTESTABLE, render_text

ROOT = Path(__file__).resolve().parents[3]
PROC = by_id("ascii")
CATALOGUE = for_procedure("ascii")


@pytest.fixture(scope="module")
def matrix():
    (m,) = matrices([PROC])
    return m


def test_every_testable_rule_has_a_case_in_every_setting_it_applies_to(matrix):
    # ok: no rule missing in a setting, no unknown id cited, no untestable rule cited
    assert matrix.ok, render_text(matrix, only_problems=True, verbose=False)
    assert matrix.count(MISSING) == 0 and len(matrix.settings) == len(PROC.rule_settings())
    # each value of each dimension occurs in some setting
    for dim, values in CATALOGUE.dimensions.items():
        seen = {s.values[dim] for s in matrix.settings}
        assert set(values) - {"rts_cts", "auto_v24"} <= seen, (dim, set(values) - seen)


def test_untestable_rules_carry_a_reason_and_the_modem_lines_are_among_them(matrix):
    untestable = [e.rule for e in matrix.entries if e.status == UNTESTABLE]
    assert untestable and all(len(r.untestable) > 30 for r in untestable)
    modem = [r for r in CATALOGUE if set(r.applies.get("flow_control", ())) & {"rts_cts", "auto_v24"}
             and not set(r.applies["flow_control"]) & {"none", "xon_xoff"}]
    assert modem and all(not r.testable and "modem line" in r.untestable for r in modem)


def _cases_of_every_setting():
    for label, _values, profile in PROC.rule_settings():
        for v in conformance.cases(profile):
            yield label, v
    for settings in ({"flow_control": "rts_cts"}, {"flow_control": "auto_v24"}):
        for v in conformance.cases(reference_profile(**settings)):
            yield str(settings), v


def test_every_case_and_vector_cites_rules_of_the_catalogue():
    vectors = [v for v in load_vector_sets() if v.procedure == "ascii"]
    assert vectors and all(v.rules for v in vectors), [v.id for v in vectors if not v.rules]
    cases = list(_cases_of_every_setting())
    for label, v in cases:
        placeholder = bool(v.not_buildable) or "modem_lines" in v.requires
        # a case the profile leaves no room for, or one that needs the modem lines, checks
        # nothing and cites nothing; every other case cites what it checks
        assert bool(v.rules) != placeholder, (label, v.id, v.rules)
    for v in vectors + [v for _, v in cases]:
        assert not CATALOGUE.unknown(v.rules), (v.id, CATALOGUE.unknown(v.rules))
        assert all(CATALOGUE.get(r).testable for r in v.rules), v.id


def test_every_testable_rule_is_cited_somewhere_and_every_rule_id_has_the_prefix():
    cited = {r for _, v in _cases_of_every_setting() for r in v.rules}
    cited |= {r for v in load_vector_sets() if v.procedure == "ascii" for r in v.rules}
    assert {r.id for r in CATALOGUE if r.testable} <= cited
    assert all(r.id.startswith("ASCII.") for r in CATALOGUE)


def test_the_settings_give_each_dimension_as_the_profile_writes_it():
    p = reference_profile(end_criterion="end_chars", end_chars=[0x0D, 0x0A], buffer_frames=1,
                          prevent_overwrite=False).params
    v = PROC.setting_values(p)
    assert v["end_criterion"] == "end_chars" and v["end_chars"] == 2 and v["buffer_frames"] == 1
    assert v["prevent_overwrite"] is False and v["buffer_limit"] == "either"
    assert v["buffer_frames"] in CATALOGUE.dimensions["buffer_frames"]
    fl = lambda n, b: reference_profile(end_criterion="fixed_length", fixed_length=n, buffer_frames=b).params  # noqa: E731
    assert buffer_limit(fl(100, 8)) == "frame count" and buffer_limit(fl(100, 9)) == "1024 bytes"
    assert buffer_limit(fl(8, 250)) == "1024 bytes" and PROC.setting_values(fl(8, 2))["buffer_frames"] == "2..250"


def test_the_analyzers_findings_cite_rules_of_the_catalogue():
    """A pause between frames 5 ms short (§2.2.4 'sending', CDT criterion) is flagged with the
    rule it breaks; so is each broken variant's capture, with ids the catalogue has."""
    from test_analyze_ascii import _two_frames, _variant_capture, fails, kit_for

    p, short = _two_frames(0.015)
    bad = fails(A.analyze(short, kit_for(p, p, {"a": "none", "b": "none"}), judge="b"))
    assert bad and "ASCII.TX.CDT-PAUSE" in bad[0].rules
    for name in ("end-char-not-stored", "xoff-ignored"):
        cap, pa, pb, failed = _variant_capture(name)
        an = A.analyze(cap, kit_for(pa, pb), judge="b", restart_at_cases={"b"} if failed is not None else set())
        bad = fails(an, "b")
        assert bad and all(f.rules and not CATALOGUE.unknown(f.rules) for f in bad), \
            (name, [(f.message, f.rules) for f in bad])


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "ptpcert.cli", "rules", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


def test_ptpcert_rules_check_passes_for_the_ascii_driver_and_prints_the_counts(matrix, tmp_path):
    p = run_cli("--procedure", "ASCII", "--check")
    assert p.returncode == 0, p.stdout[-2000:]
    assert p.stdout.strip().splitlines()[-1] == matrix.summary()
    n = len(CATALOGUE)
    assert matrix.summary() == f"{n} rules, {n - matrix.count(UNTESTABLE)} checked, {matrix.count(UNTESTABLE)} untestable, 0 missing"
    p = run_cli("--procedure", "ASCII", "--select", "ASCII.RX-EC2.*", "--json", str(tmp_path / "m.json"))
    assert p.returncode == 0 and "SUITE.ASCII.EC2.REVERSED" in p.stdout
    data = json.loads((tmp_path / "m.json").read_text())
    assert {r["id"] for r in data["rules"]} == {"ASCII.RX-EC2.SEQUENCE", "ASCII.RX-EC2.SPLIT"}
    assert all(r["status"] == "checked" and "end chars 2" in r["scope"] for r in data["rules"])


@pytest.mark.parametrize("table", [
    None,   # the bundled ascii-reference profile
    "end_criterion = \"cdt\"\nflow_control = \"none\"\nbuffer_frames = 1\nprevent_overwrite = false",
    "end_criterion = \"fixed_length\"\nfixed_length = 100\nflow_control = \"xon_xoff\"\nbuffer_frames = 8",
])
def test_ptpcert_rules_profile_gives_the_matrix_of_an_ascii_iut(tmp_path, table):
    path = ROOT / "conformance/profiles/ascii-reference.toml"
    if table is not None:
        path = tmp_path / "p.toml"
        path.write_text('[iut]\nprocedure = "ASCII"\ncharacter_delay_ms = 20\nbaud_rate = 9600\nsend_trigger = "echo"\n'
                        f'line_conditions = "parmrk"\nstatus_from_stderr = true\n\n[ascii]\n{table}\n')
    p = run_cli("--profile", str(path), "--json", "-")
    data = json.loads(p.stdout)
    assert data["procedure"] == "ascii" and [s["label"] for s in data["settings"]] == ["this profile"]
    by = {r["id"]: r for r in data["rules"]}
    assert by["ASCII.FRAME.ALL-CODES"]["status"] == "checked"
    assert by["ASCII.FLOW.RTS-CTS-SEND"]["status"] == "untestable"
    crit = data["settings"][0]["end_criterion"]
    own = {"cdt": "ASCII.RX-CDT.FRAME-END", "end_chars": "ASCII.RX-EC.END-INCLUDED",
           "fixed_length": "ASCII.RX-FL.FRAME-END"}[crit]
    assert by[own]["status"] == "checked" and by[own]["applies"] == ["this profile"]
