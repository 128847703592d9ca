"""The ASCII driver as a procedure of the core: its profile (refused settings name the key and
the rule), the generated suite passing the reference model in every end criterion, with and
without XON/XOFF, at 7 and 8 data bits, every broken variant caught, the golden vectors, the
reference implementation's command line and the frames drawn for reports."""

import subprocess
import sys
from pathlib import Path

import pytest

import ptpcert.conformance as conformance
from ptpcert import results as R
from ptpcert.procedures.ascii.description import GROUPS, AsciiProcedure, reference_profile
from ptpcert.procedures.ascii.mutants import MUTANTS
from ptpcert.profile import ProfileError, load_profile
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[3]
PY = sys.executable
VECTORS = load_vector_sets()
OK = (R.PASS, R.NON_STRICT, R.INFORMATIONAL)

EC1 = dict(end_criterion="end_chars", end_chars=[0x03])
EC2 = dict(end_criterion="end_chars", end_chars=[0x0D, 0x0A])
XX = dict(flow_control="xon_xoff", xon_wait_ms=2000)
#: every end criterion, with and without XON/XOFF, at 7 and 8 data bits; the send variants,
#: the buffer settings and a few frames besides
COMBOS = {
    "cdt-none-8": dict(end_criterion="cdt"),
    "cdt-none-7": dict(end_criterion="cdt", data_bits=7),
    "cdt-xon-8": dict(end_criterion="cdt", **XX),
    "cdt-xon-7": dict(end_criterion="cdt", data_bits=7, **XX),
    "ec-none-8-a": dict(EC1, send_variant="up_to_end"),
    "ec-none-7-b": dict(EC1, send_variant="len_with_end", data_bits=7),
    "ec-xon-8-c": dict(EC1, send_variant="len_append_end", **XX),
    "ec-xon-7-a": dict(EC1, send_variant="up_to_end", data_bits=7, **XX),
    "ec2-none-8-c": dict(EC2, send_variant="len_append_end"),
    "ec2-xon-7-a": dict(EC2, send_variant="up_to_end", data_bits=7, **XX),
    "fl8-none-8": dict(end_criterion="fixed_length", fixed_length=8),
    "fl240-none-7": dict(end_criterion="fixed_length", fixed_length=240, data_bits=7),
    "fl100-xon-8": dict(end_criterion="fixed_length", fixed_length=100, **XX),
    "fl5-xon-7-nopause": dict(end_criterion="fixed_length", fixed_length=5, send_pause=False, data_bits=7, **XX),
    "ec-overwrite": dict(EC1, buffer_frames=1, prevent_overwrite=False),
    "cdt-3-frames-2stop-odd": dict(end_criterion="cdt", buffer_frames=3, parity="odd", stop_bits=2, baud_rate=19200),
    "ec-xon-4-frames": dict(EC1, buffer_frames=4, **XX),
    "cdt-rts-cts": dict(end_criterion="cdt", flow_control="rts_cts"),
}


def run_sim(url: str, profile, *, vectors=VECTORS) -> R.RunResult:
    res = R.RunResult(tool_version="test", started="")
    Runner(make_factory(url, profile), profile, RunOptions(check_model_events=True)).run(load_suite(profile, vectors), res)
    return res


# ------------------------------------------------------------------ the profile
PROFILE = """
[iut]
procedure = "ASCII"
character_delay_ms = {cdt}
baud_rate = 9600
data_bits = {bits}
send_trigger = "echo"
line_conditions = "parmrk"
status_from_stderr = true

[ascii]
end_criterion = "end_chars"
end_chars = [{end}]
flow_control = "xon_xoff"
xon = 0x11
xoff = {xoff}
xon_wait_ms = 2000
buffer_frames = {frames}
prevent_overwrite = {prevent}

[iut.setups]
slow_reader = "--echo-delay-ms 5000"
"""
GOOD = dict(cdt=20, bits=8, end="0x03", xoff="0x13", frames=250, prevent="true")


def test_the_issues_profile_is_read(tmp_path):
    f = tmp_path / "p.toml"
    f.write_text(PROFILE.format(**GOOD))
    prof = load_profile(f)
    assert prof.procedure.id == "ascii" and prof.params.end_chars == (3,) and prof.params.cdt_ms == 20
    assert prof.setups == {"slow_reader": "--echo-delay-ms 5000"}
    assert prof.to_dict()["ascii"]["flow_control"] == "xon_xoff"


@pytest.mark.parametrize("change,key,rule", [
    (dict(prevent="false", frames=250), "ascii.prevent_overwrite", "Table 2-10"),
    (dict(xoff="0x11"), "ascii.xoff", "Table 2-9"),
    (dict(cdt=2), "iut.character_delay_ms", "Table 2-7"),
    (dict(bits=7, end="0x83"), "ascii.end_chars", "Tables 2-7/2-9"),
])
def test_a_profile_that_breaks_the_tables_is_refused_in_one_line(tmp_path, change, key, rule):
    f = tmp_path / "p.toml"
    f.write_text(PROFILE.format(**{**GOOD, **change}))
    with pytest.raises(ProfileError) as e:
        load_profile(f)
    msg = str(e.value)
    assert e.value.key == key and rule in msg and "\n" not in msg
    p = subprocess.run([PY, "-m", "ptpcert.cli", "run", "--iut", "sim:", "--profile", str(f)], cwd=ROOT,
                       capture_output=True, text=True)
    assert p.returncode == 2
    line, = p.stderr.strip().splitlines()
    assert key in line and rule in line


def test_unknown_keys_of_the_ascii_table_are_refused(tmp_path):
    f = tmp_path / "p.toml"
    f.write_text(PROFILE.format(**GOOD).replace("xon = 0x11", "xon = 0x11\ncolour = 1"))
    with pytest.raises(ProfileError, match="ascii.colour: unknown key"):
        load_profile(f)


# ------------------------------------------------------------------ the suite against the model
@pytest.mark.parametrize("combo", sorted(COMBOS))
def test_suite_passes_the_model(combo):
    prof = reference_profile(**COMBOS[combo])
    res = run_sim("sim:", prof)
    bad = {c.id: c.message for c in res.cases if c.verdict not in OK + (R.UNSUPPORTED,)}
    assert not bad
    suite = [c for c in res.cases if c.id.startswith("SUITE.")]
    assert len(suite) >= 10
    # nothing of the suite is unsupported in sim:, except what needs modem lines
    unsupported = {c.id: c.message for c in suite if c.verdict == R.UNSUPPORTED}
    # (and what the profile leaves no room for, with its reason: Vector.not_buildable)
    unbuilt = {v.id for v in conformance.cases(prof) if v.not_buildable}
    built = {cid: m for cid, m in unsupported.items() if cid not in unbuilt}
    assert all("modem lines" in m for m in built.values()), built
    assert bool(built) == (prof.params.flow_control == "rts_cts")
    # golden vectors that fit the profile run; the others are unsupported for their bound settings
    for c in res.cases:
        if c.verdict == R.UNSUPPORTED and not c.id.startswith("SUITE."):
            assert "the vector is for" in c.message or "needs" in c.message


def test_soft_grades_come_from_another_reading_only():
    """A model that takes another reading of the open points passes every case of the suite:
    what it does differently is graded informational or non-strict, never failed."""
    from dataclasses import replace

    from ptpcert.procedures.ascii.model.readings import READINGS
    from ptpcert.transport import sim_factory

    other = replace(READINGS, q10_trailing_discard_code=None, q12_cdt_also_reports_0806=True,
                    q14_xoff_frame_offset=-1, q15_xon_only_after_xoff=False, q16_xoff_while_idle_holds=False,
                    q17_overflow_code=0x0806, q18_full_buffer_code=0x080C, d_break_aborts_send=True)
    graded = set()
    for combo in ("ec-none-8-a", "ec-xon-7-a", "cdt-xon-8", "fl8-none-8"):
        prof = reference_profile(**COMBOS[combo])
        cases = [v for v in conformance.cases(prof)]
        res = R.RunResult(tool_version="test", started="")
        Runner(sim_factory(prof.procedure, {}, readings=other), prof, RunOptions()).run(cases, res)
        bad = {c.id: c.message for c in res.cases if c.verdict not in OK + (R.UNSUPPORTED,)}
        assert not bad
        graded |= {c.id for c in res.cases if c.verdict in (R.INFORMATIONAL, R.NON_STRICT)}
    assert any("TRAILING" in g for g in graded) and any("XOFF-WHILE-IDLE" in g for g in graded)


def test_every_case_cites_its_rule_and_groups_follow_the_manual():
    seen = set()
    for combo, settings in COMBOS.items():
        for v in conformance.cases(reference_profile(**settings)):
            assert v.id.startswith("SUITE.ASCII.") and v.group in GROUPS, v.id
            assert v.rule.endswith(".") and len(v.rule) > 30, v.id
            assert "§" in v.reference or "Table" in v.reference or "Fig." in v.reference, v.id
            assert "ascii.md" not in v.reference + v.rule + v.notes
            seen.add(v.group)
    assert {"start-up", "end-criterion", "send", "flow-control", "buffer", "line-conditions"} <= seen


def test_cases_depend_only_on_the_profile_interface():
    """The suite reaches the IUT only through the issue's interface: the echo convention,
    STATUS lines, the line conditions and the two setups."""
    setups = set()
    for settings in COMBOS.values():
        for v in conformance.cases(reference_profile(**settings)):
            assert v.requires <= {"echo", "modem_lines", "restart"}
            if v.setup:
                setups.add(v.setup[0])
    assert setups == {"slow_reader", "send_job"}


# ------------------------------------------------------------------ broken variants
@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_every_mutant_is_caught(name, record_property):
    m = MUTANTS[name]
    res = run_sim(f"sim:?mutant={name}", reference_profile(**m.profile))
    caught = sorted(c.id for c in res.cases if c.verdict == R.FAIL)
    record_property("caught_by", " ".join(caught))
    assert caught, f"mutant {name} ({m.rule}) is not caught by any case"
    assert any(c.startswith("SUITE.") for c in caught), f"{name}: only golden vectors catch it"
    assert not [c.id for c in res.cases if c.verdict == R.ERROR]


def test_at_least_twenty_mutants_one_rule_each_listed():
    assert len(MUTANTS) >= 20
    p = subprocess.run([PY, "-m", "ptpcert.cli", "iut", "--procedure", "ASCII", "--list-mutants"], cwd=ROOT,
                       capture_output=True, text=True)
    assert p.returncode == 0 and len(p.stdout.splitlines()) == len(MUTANTS)
    for name, m in MUTANTS.items():
        assert name in p.stdout and ("§" in m.rule or "Table" in m.rule or "Fig." in m.rule)
    p = subprocess.run([PY, "-m", "ptpcert.cli", "iut", "--procedure", "ASCII", "--mutant", "cdt-halve"], cwd=ROOT,
                       capture_output=True, text=True)
    assert p.returncode == 2 and "unknown mutant" in p.stderr


# ------------------------------------------------------------------ vectors
def test_forty_golden_ascii_vectors_cover_the_manuals_rows():
    ascii_ = [v for v in VECTORS if v.procedure == "ascii"]
    assert len(ascii_) >= 40
    ids = " ".join(v.id for v in ascii_)
    for prefix, n in (("RX-CDT-", 7), ("RX-EC-", 10), ("RX-EC2-", 6), ("RX-FL-", 9)):
        for i in range(1, n + 1):
            assert f"{prefix}{i:02d}" in ids, f"{prefix}{i:02d}"
    for tx in ("TX-CDT-01", "TX-CDT-02", "TX-EC-A1", "TX-EC-A2", "TX-EC-B1", "TX-EC-C1", "TX-EC-C2", "TX-FL-01",
               "TX-FL-02", "TX-ANY-01"):
        assert tx in ids
    for fc in (1, 2, 4, 5, 6, 7):
        assert f"FC-X-{fc:02d}" in ids
    # both edges of the CDT, each send variant, the buffer with and without overwrite protection
    assert "EDGE.UNDER" in ids and "EDGE.OVER" in ids
    assert {v.params.send_variant for v in ascii_ if v.params.end_criterion == "end_chars"} == \
        {"up_to_end", "len_with_end", "len_append_end"}
    assert "BUF.FULL-PREVENT-OVERWRITE" in ids and "BUF.OVERWRITE" in ids


def test_a_vector_of_the_suite_writes_and_reads_back():
    from ptpcert.scenario import dump_vector, load_vector_text

    for v in conformance.cases(reference_profile(**COMBOS["ec-xon-8-c"]))[:40]:
        back = load_vector_text(dump_vector(v), "x.toml")
        assert back.steps == v.steps and back.expected == v.expected and back.setup == v.setup


# ------------------------------------------------------------------ reports
def test_frames_are_drawn_with_end_characters_xon_and_cdt_windows():
    prof = reference_profile(**COMBOS["ec-xon-8-c"])
    case = next(v for v in conformance.cases(prof) if v.id == "SUITE.ASCII.EC.TRAILING-DISCARDED")
    res = Runner(make_factory("sim:", prof), prof, RunOptions()).run_case(case)
    labels = [f["label"] for f in res.frames]
    assert any("<ETX>" in lab and lab.startswith("frame") for lab in labels)
    assert any(lab.startswith("fragment") for lab in labels)          # the trailing characters
    assert all("cdt_until" in f for f in res.frames if f["label"].startswith(("frame", "fragment")))
    assert any(f["dir"] == "iut" for f in res.frames) and any(f["dir"] == "tester" for f in res.frames)


def test_describe_frames_names_xon_and_xoff():
    p = reference_profile(**COMBOS["ec-xon-8-c"]).params
    log = [{"dir": "iut", "kind": "byte", "byte": b, "t": 0.01 + i * p.char_time} for i, b in enumerate(b"\x11AB\x03\x13")]
    labels = [f["label"] for f in AsciiProcedure().describe_frames(log, p)]
    assert labels[0].startswith("XON") and labels[-1].startswith("XOFF") and "41 42 <ETX>" in labels[1]
