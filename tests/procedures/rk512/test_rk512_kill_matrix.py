"""The kill matrix of the RK 512 rules catalogue: for every testable rule, a broken variant
made to break it (harness/procedures/rk512/mutants*.py) fails a case that cites the rule,
while the reference passes that case - in virtual time (sim:), in a setting of the matrix the
variant needs. A rule no variant reaches is listed in UNREACHED with the reason; the list is
checked against the catalogue, so a new rule without a variant fails here until it has one
or a reason."""

from functools import lru_cache

import pytest
from rk512_profiles import run_cases

from ptpcert import results as R
from ptpcert.registry import by_id
from ptpcert.rules import for_procedure
from ptpcert.scenario import load_vector_sets
from ptpcert.suite import load_suite

PROC = by_id("rk512")
CATALOGUE = for_procedure("rk512")
MUTANTS = PROC.mutants()

#: rule -> (the variant that breaks it, a case that cites the rule and fails the variant);
#: "SUITE.RK512." is left out of the suite's case ids, golden vectors keep their full id
KILLS = {
    # the link below
    "RK512.LINK.ONE-BLOCK": ("fetch-response-in-two-blocks", "P-04.FETCH-D-6"),
    "RK512.LINK.EIGHT-DATA-BITS": ("data-bit-7-cleared", "L-01.EIGHT-DATA-BITS"),
    "RK512.LINK.DLE-DOUBLING": ("link-no-dle-doubling", "L-02.DLE-IN-HEADER-AND-DATA"),
    "RK512.LINK.BCC": ("link-bcc-not-checked", "L-03.BCC-WRONG-NOT-ACTED-ON"),
    "RK512.LINK.PLAIN-3964": ("link-3964-waits-for-bcc", "P-01.SEND-10"),
    "RK512.LINK.REFUSED-BLOCK-NOT-ACTED-ON": ("link-bcc-not-checked", "L-03.BCC-WRONG-NOT-ACTED-ON"),
    "RK512.LINK.REPEATED-BLOCK-ANSWERED-ONCE": ("link-bcc-not-checked", "L-04.REPEAT-AFTER-NAK"),
    "RK512.LINK.CHARACTER-DELAY": ("link-cdt-half", "L-06.GAP-OVER-CDT"),
    "RK512.LINK.LARGEST-BLOCK": ("fetch-chunks-126", "L-07.LARGEST-BLOCKS"),
    "RK512.LINK.CONFLICT": ("link-high-priority-yields", "L-05.CONFLICT-IUT-HIGH"),
    "RK512.LINK.COMMAND-NOT-SENT": ("retry-after-link-failure", "A-10.COMMAND-REFUSED"),
    "RK512.LINK.RESPONSE-NOT-SENT": ("response-failure-not-reported", "L-08.RESPONSE-REFUSED"),
    # the command frame, data types and lengths
    "RK512.CMD.HEADER": ("continuation-full-header", "A-03.SEND-200"),
    "RK512.CMD.COMMAND-LETTERS": ("fetch-command-letter-f", "A-01.FETCH-DB"),
    "RK512.CMD.SEND-DX": ("send-dx-type-x", "A-01.SEND-DX"),
    "RK512.CMD.FETCH-NO-DATA": ("continuation-full-header", "A-03.FETCH-300"),
    "RK512.CMD.DB-ADDRESS": ("dw-sent-as-byte-offset", "A-09.SEND-ODD-LENGTH"),
    "RK512.CMD.BYTE-ADDRESS": ("counter-letter-c", "A-02.FETCH-COUNTERS"),
    "RK512.CMD.FLAG-AND-CPU": ("cpu-nibble-0", "A-01.SEND-DB"),
    "RK512.CPU.NUMBERS": ("cpu-nibble-0", "A-01.SEND-DB"),
    "RK512.TYPE.LETTERS": ("counter-letter-c", "A-02.FETCH-COUNTERS"),
    "RK512.TYPE.COUNTER-Z": ("counter-letter-c", "A-02.FETCH-COUNTERS"),
    "RK512.TYPE.FETCH-DX": ("fetch-dx-as-d", "A-01.FETCH-DX"),
    "RK512.LEN.UNITS": ("byte-length-in-words", "A-01.FETCH-FLAGS"),
    "RK512.LEN.WHOLE-REQUEST": ("length-of-first-frame", "A-03.SEND-200"),
    "RK512.LEN.MAX-1024": ("length-limit-512", "P-02.SEND-1024"),
    "RK512.LEN.ODD-SEND": ("odd-send-not-padded", "A-09.SEND-ODD-LENGTH"),
    "RK512.LEN.ODD-FETCH": ("odd-fetch-stores-pad", "A-09.FETCH-ODD-LENGTH"),
    "RK512.LEN.ODD-OFFSET": ("odd-offset-rounded-up", "A-09.SEND-ODD-LENGTH"),
    # continuation frames
    "RK512.SEG.SEND-FRAMES": ("continuation-full-header", "A-03.SEND-200"),
    "RK512.SEG.FETCH-FRAMES": ("continuation-full-header", "A-03.FETCH-300"),
    "RK512.SEG.CHUNK-128": ("fetch-chunks-126", "P-05.FETCH-D-300"),
    "RK512.SEG.SEND-SERVED": ("continuation-response-id-00", "P-02.SEND-200"),
    "RK512.SEG.FETCH-ON-REQUEST": ("fetch-chunks-unprompted", "P-05.FETCH-D-300"),
    "RK512.SEG.ERROR-ENDS-REQUEST": ("error-response-goes-on", "A-06.REATEL-14-FIRST-OF-THREE"),
    # responses
    "RK512.RESP.ONE-PER-COMMAND": ("response-sent-twice", "P-01.SEND-10"),
    "RK512.RESP.LAYOUT": ("error-response-byte3-01", "P-17.ERROR-RESPONSE-LAYOUT"),
    "RK512.RESP.MIRRORS-COMMAND": ("continuation-response-id-00", "P-02.SEND-200"),
    "RK512.RESP.SEND-NO-DATA": ("send-response-with-data", "P-18.SEND-RESPONSE-WITHOUT-DATA"),
    "RK512.RESP.FETCH-DATA": ("fetch-chunks-126", "P-05.FETCH-D-300"),
    "RK512.RESP.ERROR-NO-DATA": ("error-response-with-data", "P-17.ERROR-RESPONSE-LAYOUT"),
    "RK512.RESP.DATA-STORED": ("dw-as-byte-offset", "P-01.DATA-WORD-ADDRESSING"),
    "RK512.RESP.WORD-BYTE-ORDER": ("fetch-word-bytes-swapped", "P-04.FETCH-D-6"),
    "RK512.RESP.NOT-ANSWERED": ("response-to-response", "P-15.UNSOLICITED-RESPONSE"),
    "RK512.RESP.REATEL-VALUES": ("reatel-36-as-37", "P-09A.CONTINUATION-WITHOUT-REQUEST"),
    # the responder's checks
    "RK512.CHECK.BYTE1": ("byte1-reatel-16", "P-07A.BYTE1-01"),
    "RK512.CHECK.BYTE2": ("check-byte2-reatel-16", "P-07L.BYTE2-01"),
    "RK512.CHECK.BYTE3": ("check-byte3-reatel-10", "P-07B.BYTE3-43"),
    "RK512.CHECK.RESPONSE-OR-COMMAND": ("response-to-response", "P-07B.BYTE3-00"),
    "RK512.CHECK.BYTE4": ("check-byte4-reatel-16", "P-07C.E-51"),
    "RK512.CHECK.CONTINUATION-BYTE3": ("continuation-bytes-not-checked", "P-08.SEND-CONTINUATION-BYTE3"),
    "RK512.CHECK.CONTINUATION-BYTE4": ("continuation-bytes-not-checked", "P-08.SEND-CONTINUATION-BYTE4"),
    "RK512.CHECK.BLOCK-NUMBER": ("db-missing-reatel-0c", "P-07D.FETCH-DB200"),
    "RK512.CHECK.START-ADDRESS": ("check-address-reatel-14", "P-07E.INPUTS-BEYOND-AREA"),
    "RK512.CHECK.LENGTH": ("check-length-reatel-0c", "P-07F.FETCH-LENGTH-0"),
    "RK512.CHECK.FLAG": ("check-flag-reatel-34", "P-07G.FLAG-BIT-8"),
    "RK512.CHECK.CPU": ("check-cpu-reatel-14", "P-07H.CPU-5"),
    "RK512.CHECK.SEND-DATA-COUNT": ("send-count-not-checked", "P-07I.SEND-12-FOR-10"),
    "RK512.CHECK.FETCH-WITH-DATA": ("fetch-with-data-served", "P-07J.FETCH-WITH-DATA"),
    "RK512.CHECK.NOT-READY": ("cpu-stop-ignored", "P-12.CPU-STOP"),
    "RK512.CHECK.SEQUENCE": ("pipelined-command-served", "P-09C.COMMAND-BEFORE-RESPONSE"),
    "RK512.CHECK.FIRST-WHILE-CONTINUATION-EXPECTED": ("sequence-error-answered-ok",
                                                      "P-09B.FIRST-WHILE-CONTINUATION-EXPECTED"),
    "RK512.CHECK.TOO-SHORT": ("check-short-reatel-16", "P-07K.SHORT-6"),
    # the requester and the responses it gets
    "RK512.REQ.DONE": ("error-reatel-taken-as-success", "A-06.REATEL-14"),
    "RK512.REQ.REATEL-EVENT": ("error-reatel-taken-as-success", "A-06.REATEL-14"),
    "RK512.REQ.UNKNOWN-REATEL": ("unknown-reatel-0905", "A-06.REATEL-42"),
    "RK512.REQ.RESPONSE-STRUCTURE": ("response-byte1-not-checked", "A-07.BYTE1-01"),
    "RK512.REQ.RESPONSE-SEQUENCE": ("response-id-not-checked", "A-07.CONTINUATION-RESPONSE-TO-FIRST"),
    "RK512.REQ.FETCH-DATA-COUNT": ("fetch-length-not-checked", "A-07.FETCH-ONE-LONG"),
    "RK512.REQ.SEND-RESPONSE-WITH-DATA": ("send-response-data-ignored", "A-07.SEND-RESPONSE-WITH-DATA"),
    "RK512.REQ.ERROR-RESPONSE-WITH-DATA": ("error-reatel-taken-as-success", "A-07.ERROR-RESPONSE-WITH-DATA"),
    "RK512.REQ.SHORT-RESPONSE": ("short-response-taken", "A-07.SHORT-RESPONSE"),
    "RK512.REQ.FETCH-ERROR-NOTHING-STORED": ("error-reatel-taken-as-success", "A-12.FETCH-ERROR-NO-DATA"),
    # T_RES
    "RK512.TRES.REQUESTER-WAITS": ("tres-half", "A-05.RESPONSE-AT-0.8-TRES"),
    "RK512.TRES.REQUESTER-EXPIRES": ("no-tres-active", "A-05.NO-RESPONSE"),
    "RK512.TRES.RESPONDER-WAITS": ("passive-tres-quarter", "P-10.CONTINUATION-IN-TIME"),
    "RK512.TRES.RESPONDER-EXPIRES": ("passive-tres-ignored", "P-10.CONTINUATION-TOO-LATE"),
    # flags, quasi-full-duplex, local checks, areas, STATUS
    "RK512.FLAG.LOCKED": ("flag-lock-ignored", "P-11.FLAG-SET-REFUSES"),
    "RK512.FLAG.SET-AFTER-TRANSFER": ("flag-never-cleared", "P-11.FLAG-RESET-ALLOWS"),
    "RK512.QFD.SERVE-WHILE-WAITING": ("responses-held-while-requesting", "A-08.TESTER-SEND-BEFORE-RESPONSE"),
    "RK512.QFD.COMMAND-BEFORE-RESPONSE": ("responses-held-while-requesting", "A-08.FIGURE-2-17"),
    "RK512.LOCAL.LENGTH": ("local-checks-skipped", "A-11.LOCAL-CHECK-LEN-1025"),
    "RK512.LOCAL.DB-NUMBER": ("local-checks-skipped", "A-11.LOCAL-CHECK-DB-0"),
    "RK512.LOCAL.FLAG-BIT": ("local-checks-skipped", "A-11.LOCAL-CHECK-FLAG-BIT-8"),
    "RK512.LOCAL.CPU-NUMBER": ("local-checks-skipped", "A-11.LOCAL-CHECK-CPU-5"),
    "RK512.LOCAL.SEND-DESTINATION": ("local-checks-skipped", "A-11.LOCAL-CHECK-SEND-TO-FLAGS"),
    "RK512.AREA.FETCH-DESTINATION": ("fetched-data-reversed", "A-01.FETCH-DB"),
    "RK512.AREA.RECEIVE-DX": ("send-to-dx-refused", "P-14.SEND-TO-DX"),
    "RK512.AREA.PROVIDE": ("byte-areas-not-served", "P-04.FETCH-E-6"),
    "RK512.AREA.PROVIDE-DX": ("fetch-word-bytes-swapped", "P-04.FETCH-X-6"),
    "RK512.AREA.CELL-FETCH-32": ("cell-limit-ignored", "P-13.FETCH-COUNTERS-40"),
    "RK512.STATUS.RESPONDER-EVENTS": ("responder-events-not-reported", "P-07D.FETCH-DB0"),
}

#: testable rules no variant reaches yet, and why (empty: every rule has its variant)
_PIPELINING = ("a variant that sends its next frame before the response to the previous one runs into a "
               "state the model's table does not have (its early block meets the partner's response on the "
               "line, and the link's failure arrives while it waits for a response): the variant would end "
               "the case as a harness error, never as a fail; the cases (A-04, P-16) and the line analysis "
               "(findings 'nesting depth 1') check the rule")
UNREACHED: dict[str, str] = {
    "RK512.SEG.NEXT-AFTER-RESPONSE": _PIPELINING,
    "RK512.QFD.NESTING-DEPTH-1": _PIPELINING,
    "RK512.QFD.REQUEST-WHILE-SERVING": "a variant that defers its own request while it serves the partner's one "
                                       "would need a second scheduler in the model's active side; P-16 checks "
                                       "the rule against the reference and any IUT",
    "RK512.TRES.RESPONSE-IN-TIME": "a variant that answers late would hand its response to the link at a later "
                                   "time, and the link's clock cannot run ahead of the partner's characters "
                                   "(the model raises 'time went backwards' when the partner sends meanwhile); "
                                   "P-03 checks the rule against any IUT",
}


def _case_id(case: str) -> str:
    return case if case.startswith("RK512.") else "SUITE.RK512." + case


@lru_cache(maxsize=None)
def _setting(keys: tuple):
    """The matrix's setting a variant needs: 3964R at low priority with the large areas of
    rule_settings(), the variant's own profile keys changed (its priority, link, limits);
    with every case and vector of it, generated once."""
    profile = PROC.reference_profile(**PROC._RULE_AREAS, **dict(keys))
    vectors = [v for v in load_vector_sets() if v.procedure == "rk512"]
    return profile, {v.id: v for v in load_suite(profile, vectors)}


def _run(url: str, keys: tuple, cases: list[str]) -> dict[str, R.CaseResult]:
    profile, suite = _setting(keys)
    res = run_cases(url, profile, [suite[c] for c in cases if c in suite])
    return {c.id: c for c in res.cases}


def test_every_testable_rule_has_a_variant_or_a_reason():
    testable = {r.id for r in CATALOGUE if r.testable}
    assert set(KILLS) | set(UNREACHED) == testable, sorted(testable ^ (set(KILLS) | set(UNREACHED)))
    assert not set(KILLS) & set(UNREACHED)
    assert all(len(why) > 30 for why in UNREACHED.values())


def test_each_kill_names_a_registered_variant_with_a_manual_reference():
    for rule, (mutant, _) in KILLS.items():
        m = MUTANTS[mutant]
        assert "§" in m.rule or "Table" in m.rule or "Fig" in m.rule, (rule, mutant)


BY_MUTANT: dict[str, list[tuple[str, str]]] = {}
for _rule, (_mutant, _case) in KILLS.items():
    BY_MUTANT.setdefault(_mutant, []).append((_rule, _case_id(_case)))


@pytest.mark.parametrize("mutant", sorted(BY_MUTANT))
def test_the_variant_fails_a_case_citing_each_rule_it_breaks_and_the_reference_passes_it(mutant):
    keys = tuple(sorted(MUTANTS[mutant].profile.items()))
    cases = sorted({c for _, c in BY_MUTANT[mutant]})
    ref = _run("sim:", keys, cases)
    broken = _run(f"sim:?mutant={mutant}", keys, cases)
    for rule, case in BY_MUTANT[mutant]:
        assert case in ref, f"{case} is not generated for the variant's setting"
        assert rule in ref[case].rules, f"{case} does not cite {rule}"
        assert ref[case].verdict == R.PASS, f"the reference: {case} {ref[case].verdict}: {ref[case].message}"
        assert broken[case].verdict == R.FAIL, f"{mutant} on {case}: {broken[case].verdict} {broken[case].message}"
