"""The kill matrix of the ASCII driver's rules catalogue (harness/procedures/ascii/rules.toml):
for each testable rule, a broken variant (harness/procedures/ascii/mutants*.py) that breaks
it fails a case or golden vector citing that rule, in a setting of the traceability matrix
(settings.py) or the variant's own profile, while the bundled reference passes the same case
there - in virtual time (sim:). Rules no variant reaches are listed with the reason.

The whole suite against every variant is test_ascii_suite.py::test_every_mutant_is_caught."""

import pytest

from ptpcert import results as R
from ptpcert.procedures.ascii.description import reference_profile
from ptpcert.procedures.ascii.mutants import MUTANTS
from ptpcert.procedures.ascii.settings import SETTINGS
from ptpcert.rules import for_procedure
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

CATALOGUE = for_procedure("ascii")
SETTING = dict(SETTINGS)
VECTORS = [v for v in load_vector_sets() if v.procedure == "ascii"]

#: rule (without "ASCII.") -> (the broken variant that breaks it, a case citing the rule (a
#: suite case without "SUITE.ASCII.", or a golden vector's id), the setting it runs in: a
#: label of settings.SETTINGS, or None for the variant's own profile)
KILLS = {
    "FRAME.ALL-CODES": ("nul-dropped", "LINE.ALL-CODES", None),
    "FRAME.SEVEN-BIT": ("nul-dropped", "LINE.ALL-CODES", "fixed_length 40 no pause 7 bits"),
    "RX-CDT.FRAME-END": ("cdt-double", "CDT.ONE-FRAME", None),
    "RX-CDT.GAP-UNDER": ("cdt-half", "CDT.EDGE-UNDER", None),
    "RX-CDT.GAP-OVER": ("cdt-double", "CDT.EDGE-OVER", None),
    "RX-CDT.CHARACTER-ERROR": ("char-error-delivered", "CDT.CHARACTER-ERROR", None),
    "RX-EC.END-INCLUDED": ("end-char-not-stored", "EC.END-INCLUDED", None),
    "RX-EC.COMPLETES-AT-ONCE": ("end-char-waits-cdt", "EC.COMPLETES-AT-ONCE", None),
    "RX-EC.GAP-UNDER": ("cdt-half", "EC.EDGE-UNDER", "end_chars 03 up_to_end"),
    "RX-EC.NO-END-DISCARDED": ("fragment-delivered", "EC.NO-END-DISCARDED", "end_chars 03 up_to_end"),
    "RX-EC.NO-END-MERGED": ("cdt-quarter", "EC.NO-END-MERGED", None),
    "RX-EC.TRAILING-DISCARDED": ("trailing-kept", "EC.TRAILING-DISCARDED", None),
    "RX-EC.TRAILING-MERGED": ("trailing-dropped", "EC.TRAILING-MERGED", None),
    "RX-EC.CHARACTER-ERROR": ("error-ends-frame-at-once", "EC.CHARACTER-ERROR", None),
    "RX-EC2.SEQUENCE": ("either-end-char", "EC2.REVERSED", None),
    "RX-EC2.SPLIT": ("pair-across-cdt", "EC2.SPLIT-ACROSS-CDT", None),
    "RX-FL.FRAME-END": ("fixed-length-plus-one", "FL.EXACT", None),
    "RX-FL.GAP-UNDER": ("cdt-half", "FL.EDGE-UNDER", "fixed_length 40 no pause 7 bits"),
    "RX-FL.SHORT-DISCARDED": ("fragment-delivered", "FL.SHORT-DISCARDED", None),
    "RX-FL.SHORT-MERGED": ("cdt-quarter", "FL.SHORT-MERGED", "fixed_length 40 no pause 7 bits"),
    "RX-FL.SURPLUS-DISCARDED": ("trailing-kept", "FL.SURPLUS-DISCARDED", "fixed_length 40 no pause 7 bits"),
    "RX-FL.SURPLUS-MERGED": ("trailing-dropped", "FL.SURPLUS-MERGED", "fixed_length 40 no pause 7 bits"),
    "RX-FL.CHARACTER-ERROR": ("char-error-delivered", "FL.CHARACTER-ERROR-ENDS-AT-N", "fixed_length 40 no pause 7 bits"),
    "RX.TRANSPARENT": ("nul-dropped", "CDT.TRANSPARENT", None),
    "RX.MAX-FRAME": ("frame-limit-1000", "CDT.MAX-1024", None),
    "RX.TOO-LONG": ("overlong-spoils-next", "CDT.TOO-LONG", None),
    "TX.FRAME-AS-GIVEN": ("last-byte-not-sent", "CDT.ONE-FRAME", None),
    "TX.CDT-PAUSE": ("no-send-pause", "TX.PAUSE", None),
    "TX.FL-PAUSE": ("fixed-length-no-pause", "TX.PAUSE", None),
    "TX.VARIANT-UP-TO-END": ("up-to-end-not-cut", "TX.UP-TO-END-CUTS", None),
    "TX.VARIANT-LEN-WITH-END": ("len-with-end-appends", "TX.VARIANT-LEN-WITH-END", None),
    "TX.VARIANT-APPEND-END": ("append-end-missing", "TX.VARIANT-APPEND-END", None),
    "TX.LEN-MAX": ("send-limit-1000", "CDT.MAX-1024", None),
    "TX.LEN-ILLEGAL": ("len-over-1024-sent", "TX.LEN-1025-REFUSED", None),
    "FLOW.XON-AT-START-UP": ("no-start-up-xon", "FC.XON-AT-START-UP", None),
    "FLOW.XOFF-STOPS": ("xoff-ignored", "FC.XOFF-MIDDLE", None),
    "FLOW.XON-RESUMES": ("xon-wait-half", "FC.XON-WITHIN-WAIT", None),
    "FLOW.XON-WAIT": ("xon-wait-endless", "FC.XON-WAIT-EXPIRES", None),
    "FLOW.CODES-NOT-DATA": ("flow-code-ends-frame", "FC.CODES-NOT-DATA", None),
    "FLOW.XOFF-AT-FRAME-COUNT": ("no-xoff-when-full", "FC.XOFF-AT-FRAME-COUNT", "end_chars 0D 0A len_with_end xon_xoff"),
    "FLOW.XOFF-AT-974": ("no-xoff-when-full", "FC.XOFF-AT-974-BYTES", "end_chars 0D 0A len_with_end xon_xoff"),
    "FLOW.XON-AFTER-READ": ("no-xon-after-read", "FC.XOFF-AT-FRAME-COUNT", "end_chars 0D 0A len_with_end xon_xoff"),
    "FLOW.OVERFLOW": ("buffer-2048", "FC.OVERFLOW", "cdt xon_xoff 7 bits 12 frames"),
    "BUFFER.FIFO": ("newest-first", "BUF.FIFO", None),
    "BUFFER.FULL-PREVENT": ("overwrite-when-prevented", "BUF.FULL-PREVENT-OVERWRITE", None),
    "BUFFER.OVERWRITE": ("no-overwrite", "BUF.OVERWRITE", None),
    "BUFFER.BYTES": ("buffer-2048", "BUF.BYTES-FULL", None),
    "LINE.BREAK": ("break-ignored", "LINE.BREAK-IDLE", None),
    "LINE.BREAK-WHILE-SENDING": ("break-ignored", "LINE.BREAK-WHILE-SENDING", None),
    "STATUS.0806": ("fragment-silent", "EC.NO-END-DISCARDED", None),
    "STATUS.080A": ("buffer-2048", "BUF.BYTES-FULL", None),
    "STATUS.080C": ("char-error-delivered", "CDT.CHARACTER-ERROR", None),
    "STATUS.080D": ("break-ignored", "LINE.BREAK-IDLE", None),
    "STATUS.0708": ("xon-wait-endless", "FC.XON-WAIT-EXPIRES", None),
    "STATUS.1E41": ("len-over-1024-sent", "TX.LEN-1025-REFUSED", None),
}

#: testable rules no broken variant reaches, and why
UNREACHED = {
    "FRAME.SETTINGS": "the simulated line carries characters, not bits: a variant cannot put a wrong start bit, "
                      "parity or stop bit on it; on a real line the tester's UART, set to the profile's frame, "
                      "turns such characters into character errors, which every case fails",
    "FLOW.XOFF-WHILE-IDLE": "an open point (Q16) whose case accepts both readings, holding the frame until XON or "
                            "ignoring the XOFF (graded informational): only a variant that garbles or repeats the "
                            "held frame fails it, and that breaks ASCII.TX.FRAME-AS-GIVEN, not this rule",
    "STATUS.0816": "an open point (Q13): its cases accept any receive error or none for a frame over 1024 bytes, "
                   "so no code a variant raises can fail them (ASCII.RX.TOO-LONG, the frames after it, is reached)",
}


def _profile(mutant: str, label: str | None):
    return reference_profile(**(MUTANTS[mutant].profile if label is None else SETTING[label]))


def _case_id(case: str) -> str:
    return case if case.startswith("ASCII.") else "SUITE.ASCII." + case


def run(case_id: str, url: str, profile) -> tuple[R.CaseResult, tuple[str, ...]]:
    cases = load_suite(profile, VECTORS, select=[case_id])
    assert len(cases) == 1, f"{case_id} is not generated for {profile.params}"
    res = R.RunResult(tool_version="test", started="")
    Runner(make_factory(url, profile), profile, RunOptions()).run(cases, res)
    return res.cases[0], cases[0].rules


@pytest.mark.parametrize("rule", sorted(KILLS))
def test_a_broken_variant_fails_a_case_of_the_rule_that_the_reference_passes(rule):
    mutant, case, label = KILLS[rule]
    profile = _profile(mutant, label)
    ref, cited = run(_case_id(case), "sim:", profile)
    assert "ASCII." + rule in cited, f"{case} does not cite ASCII.{rule} (it cites {cited})"
    assert ref.verdict == R.PASS, f"the reference: {ref.verdict}: {ref.message}"
    broken, _ = run(_case_id(case), f"sim:?mutant={mutant}", profile)
    assert broken.verdict == R.FAIL, f"{mutant}: {broken.verdict} {broken.message}"


def test_every_testable_rule_is_reached_by_a_variant_or_says_why_not():
    testable = {r.id.removeprefix("ASCII.") for r in CATALOGUE if r.testable}
    assert set(KILLS) | set(UNREACHED) == testable, (
        sorted(testable - set(KILLS) - set(UNREACHED)), sorted((set(KILLS) | set(UNREACHED)) - testable))
    assert not set(KILLS) & set(UNREACHED)
    for rule, why in UNREACHED.items():
        assert len(why) > 60, rule
    print(f"rules no variant reaches: {sorted(UNREACHED)}")


def test_every_variant_of_the_matrix_is_registered_with_a_manual_reference():
    for mutant, _case, label in KILLS.values():
        rule = MUTANTS[mutant].rule
        assert "§" in rule or "Fig." in rule or "Table" in rule
        assert label is None or label in SETTING
