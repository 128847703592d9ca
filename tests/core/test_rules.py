"""The rules catalogue: its form (stable ids, a manual reference and one sentence per rule,
untestable rules with a reason), its open points, and the schema field that cites it."""

import pytest

from ptpcert.registry import procedures
from ptpcert.rules import CatalogueError, for_procedure, for_rule, parse
from ptpcert.scenario import VectorError, vector_from_dict

CAT = for_procedure("p3964")


def test_the_3964_catalogue_is_the_procedures_own():
    assert CAT.procedure == "p3964" and CAT.prefix == "3964" and len(CAT) >= 80
    assert for_procedure("p3964") is CAT and for_rule("3964.RX.BCC-CHECK") is CAT
    assert for_rule("NOSUCH.X.Y") is None and for_rule("RK512.SEG.ERROR-ENDS-REQUEST") is for_procedure("rk512")
    # every procedure answers: a catalogue of its own, or the empty one
    for p in procedures():
        assert for_procedure(p).procedure in (p.id, "")


def test_every_rule_cites_the_manual_in_one_sentence_of_our_own():
    for r in CAT:
        assert r.id.startswith("3964.") and r.id == r.id.upper()
        assert any(k in r.ref for k in ("§", "Fig.", "Table")), r.id
        assert ".md" not in r.ref and ".md" not in r.text and "item" not in r.ref, r.id
        assert r.text.endswith(".") and 30 <= len(r.text) <= 320, r.id
        assert r.text.count(". ") == 0 or "e.g." in r.text, f"{r.id}: one sentence"


def test_untestable_rules_say_why():
    untestable = [r for r in CAT if not r.testable]
    assert untestable and len(untestable) < len(CAT) / 5
    for r in untestable:
        assert len(r.untestable) > 30, r.id


def test_every_open_point_has_a_reading_and_rules_cite_known_ones():
    assert sorted(CAT.readings, key=lambda a: int(a[1:])) == [f"A{i}" for i in range(1, 28)]
    for r in CAT:
        assert all(a in CAT.readings for a in r.readings)


def test_scope_and_applicability():
    bcc = CAT.get("3964.RX.BCC-CHECK")
    assert bcc.applies_to({"procedure": "3964R", "priority": "low"})
    assert not bcc.applies_to({"procedure": "3964", "priority": "low"})
    assert bcc.scope() == "3964R only"
    assert CAT.get("3964.RX.ACK").scope() == ""
    with pytest.raises(KeyError, match="not a rule"):
        CAT.get("3964.NO.SUCH")


@pytest.mark.parametrize("change,fragment", [
    ({"id": "3964.rx.lower"}, "capitals"),
    ({"id": "RK.X.Y"}, "capitals"),
    ({"text": "no full stop"}, "full stop"),
    ({"role": "master"}, "role"),
    ({"provenance": "X"}, "provenance"),
    ({"procedure": ["3964RR"]}, "procedure"),
    ({"readings": ["A99"]}, "reading A99"),
    ({"colour": "red"}, "unknown field"),
    ({"ref": ""}, "ref missing"),
])
def test_broken_catalogue_entries_are_named(change, fragment):
    rule = {"id": "3964.RX.X", "ref": "§1", "text": "A sentence.", "provenance": "S", "role": "any", **change}
    raw = {"procedure": "x", "title": "x", "prefix": "3964", "manual": "m", "rule": [rule],
           "reading": {"A1": {"question": "q", "model": "m", "grade": "pass"}}}
    with pytest.raises(CatalogueError, match=fragment):
        parse(raw, "t.toml")


BASE = {"id": "T.X", "title": "t", "reference": "§1", "rule": "r", "group": "idle", "procedure": "3964R",
        "iut_role": "idle", "params": {}, "steps": [{"send": "15"}, {"silence": "CDT"}]}


def test_vectors_cite_rule_ids_of_their_procedures_catalogue():
    v = vector_from_dict({**BASE, "rules": ["3964.IDLE.NAK-IGNORED"]})
    assert v.rules == ("3964.IDLE.NAK-IGNORED",) and v.to_toml()["rules"] == ["3964.IDLE.NAK-IGNORED"]
    assert vector_from_dict(BASE).rules == ()
    for bad, fragment in (("3964.IDLE.NO-SUCH", "not a rule of the 3964/3964R catalogue"), (3, "a list")):
        with pytest.raises(VectorError, match=fragment) as e:
            vector_from_dict({**BASE, "rules": [bad] if isinstance(bad, str) else bad})
        assert e.value.field == "rules"


def test_every_open_point_is_documented_in_docs_readings_and_linked_from_the_readme():
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    doc = (root / "docs" / "readings.md").read_text("utf-8")
    for a in CAT.readings:
        assert f"### {a}. " in doc, f"{a} has no section in docs/readings.md"
    assert "](docs/readings.md)" in (root / "README.md").read_text("utf-8")
    for text in (doc, (root / "README.md").read_text("utf-8"), (root / "vectors" / "README.md").read_text("utf-8")):
        assert "3964r.md" not in text and "../shared" not in text


def test_nothing_users_have_cites_our_notes():
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    files = [*(root / "harness").rglob("*.py"), *(root / "harness").rglob("*.toml"), *(root / "conformance").rglob("*.py"),
             *(root / "vectors").rglob("*.toml"), root / "README.md", root / "vectors" / "README.md",
             *(root / "docs").rglob("*.md"), *(root / "docs").rglob("*.py"), root / "mkdocs.yml",
             *(root / "benchmarks").rglob("*.py"),
             *(f for f in (root / "tests" / "independent").rglob("*") if f.suffix in (".py", ".md", ".toml"))]
    for f in files:
        text = f.read_text("utf-8")
        for note in ("3964r.md", "status-codes.md", "rk512.md", "ascii.md", "../shared", "/work/shared"):
            assert note not in text, f"{f.relative_to(root)} cites {note}"


def test_a_catalogue_declares_its_own_dimensions():
    # the same form serves RK 512 and the ASCII driver: their settings are other profile keys
    raw = {"procedure": "ascii", "title": "ASCII driver", "prefix": "ASCII", "manual": "m",
           "dimensions": {"flow_control": ["none", "xon_xoff"]},
           "rule": [{"id": "ASCII.RX.XOFF", "ref": "§2.2.4", "text": "XOFF stops the sender.", "provenance": "S",
                     "role": "receiver", "flow_control": ["xon_xoff"]}]}
    cat = parse(raw, "ascii.toml")
    r = cat.get("ASCII.RX.XOFF")
    assert cat.dimensions == {"flow_control": ("none", "xon_xoff")}
    assert r.applies_to({"flow_control": "xon_xoff"}) and not r.applies_to({"flow_control": "none"})
    assert r.scope() == "flow control xon_xoff"
    with pytest.raises(CatalogueError, match="unknown field priority"):
        parse({**raw, "rule": [{**raw["rule"][0], "priority": ["low"]}]}, "ascii.toml")
    assert CAT.dimensions["priority"] == ("low", "high")
