"""The kill matrix of the cases added for the rules catalogue: each case fails the broken
variant made for it (a mutant of ptpcert.procedures.p3964.mutants that breaks exactly the rule the case checks)
and passes the bundled reference, in the setting the variant needs. The whole suite against
every variant is tests/procedures/p3964/test_suite.py::test_every_mutant_is_caught; the matrix with every case
that catches each variant is benchmarks/kill_matrix.py."""

import pytest

from ptpcert import results as R
from ptpcert.procedures.p3964.mutants import MUTANTS
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.runner import Runner, RunOptions
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

#: case -> the broken variant made for it
KILLS = {
    "SUITE.RECEIVE.DATA-DLE-THEN-ETX": "dle-pair-rescanned",
    "SUITE.RECEIVE.DATA-DLE-THEN-STX": "dle-pair-rescanned",
    "SUITE.RECEIVE.DATA-DLE-THEN-NAK": "dle-pair-rescanned",
    "SUITE.RECEIVE.BCC-CHARACTER-ERROR": "bcc-character-error-ignored",
    "SUITE.SEND.DLE-DURING-DATA": "dle-during-data-is-acknowledgement",
    "SUITE.SEND.STX-DURING-DATA": "stx-during-data-is-conflict",
    "SUITE.SEND.CHARACTER-ERROR-DURING-DATA": "character-error-during-data-ignored",
    "SUITE.SEND.SETUP-ATTEMPTS-MIXED": "setup-counter-per-cause",
    "SUITE.RELEASE.ATTEMPTS-MIXED": "transmission-counter-per-cause",
    "SUITE.SEND.SETUP-EXHAUSTED-ENDS-JOB": "setup-exhaustion-retries-block",
    "SUITE.IDLE.CORRUPTED-STX": "corrupted-stx-accepted",
    "SUITE.BREAK.WAITING-FOR-ETX": "break-ignored-waiting-for-etx",
    "SUITE.BREAK.WAITING-FOR-BCC": "break-ignored-waiting-for-bcc",
    "SUITE.BREAK.IDLE-QUIET-WAIT": "break-ignored-in-idle-quiet-wait",
    "SUITE.BREAK.SENDER-QUIET-WAIT": "break-ignored-in-sender-quiet-wait",
    "SUITE.BREAK.WAITING-FOR-BUFFER": "break-ignored-waiting-for-buffer",
    "SUITE.CONFLICT.LOW-RECEPTION-BROKEN-BY-BREAK": "nak-after-break",
    "SUITE.RECEIVE.CHARACTER-ERROR-AFTER-DATA-DLE": "character-error-after-dle-nak-at-once",
    "SUITE.RECEIVE.CHARACTER-ERROR-ON-ETX": "corrupted-etx-ends-block",
    "SUITE.RECEIVE.FROM-3964R-PARTNER": "3964-waits-for-bcc",
    "SUITE.CONFLICT.HIGH-NO-DLE": "partner-stx-refuses-setup",
    "SUITE.CONFLICT.HIGH-THREE-QUARTERS-ADT": "high-priority-yields",
    "SUITE.RECEIVE.REPETITION-LIMIT": "receiver-locked-after-limit",
    "SUITE.RECEIVE.AFTER-T-BLOCK": "receiver-locked-after-t-block",
    "SUITE.RECEIVE.PARTNER-GAVE-UP": "receiver-locked-after-partner-nak",
    "SUITE.TIMING.GAP-AT-80-CDT-IN-DLE-PAIR": "cdt-half-after-data-dle",
    "SUITE.IDLE.QUIET-RESTARTS": "stray-nak-per-character",
    "SUITE.SEND.QUIET-RESTARTS": "sender-nak-per-character",
    "SUITE.RECEIVE.MAX-STUFFING": "line-length-overflow-unanswered",
    "SUITE.RECEIVE.TOO-LONG-1025": "overlong-block-unanswered",
    "SUITE.RECEIVE.ZERO-LENGTH": "zero-length-unanswered",
    "SUITE.RECEIVE.NO-FREE-BUFFER": "buffer-wait-too-short",
    "SUITE.RECEIVE.GARBAGE-DURING-BUFFER-WAIT": "buffer-wait-garbage-accepted",
    "SUITE.FRAME.SEVEN-BIT": "bcc-eighth-bit-set",
    "SUITE.COUNTERS.SETUP-PER-JOB": "setup-counter-never-reset",
    "SUITE.COUNTERS.TRANSMISSION-PER-JOB": "transmission-counter-never-reset",
    "SUITE.COUNTERS.SETUP-PER-ATTEMPT": "setup-counter-spent-per-attempt",
    "SUITE.COUNTERS.RECEIVE-PER-BLOCK": "receive-counter-never-reset",
    "SUITE.SEND.ECHO-PLAIN": "bcc-includes-stx",
}


def run(case_id: str, url: str, profile) -> R.CaseResult:
    cases = load_suite(profile, [], select=[case_id])
    assert len(cases) == 1, f"{case_id} is not generated for {profile.params}"
    res = R.RunResult(tool_version="test", started="")
    Runner(make_factory(url, profile), profile, RunOptions()).run(cases, res)
    return res.cases[0]


@pytest.mark.parametrize("case_id,mutant", sorted(KILLS.items()))
def test_case_fails_its_broken_variant_and_passes_the_reference(case_id, mutant):
    profile = reference_profile(**MUTANTS[mutant].profile)
    ref = run(case_id, "sim:", profile)
    assert ref.verdict == R.PASS, f"the reference: {ref.verdict}: {ref.message}"
    broken = run(case_id, f"sim:?mutant={mutant}", profile)
    assert broken.verdict == R.FAIL, f"{mutant}: {broken.verdict} {broken.message}"


def test_every_variant_made_for_a_case_is_registered_with_a_manual_reference():
    for mutant in set(KILLS.values()):
        rule = MUTANTS[mutant].rule
        assert "§" in rule or "Fig." in rule or "Table" in rule


REAL_TIME = ["dle-pair-rescanned", "break-ignored-waiting-for-etx", "setup-counter-never-reset",
             "stray-nak-per-character", "partner-stx-refuses-setup", "receive-counter-never-reset"]


@pytest.mark.realtime
@pytest.mark.parametrize("mutant", REAL_TIME)
def test_in_real_time_over_exec(tmp_path, mutant):
    """The same over exec: with the bundled reference and the variant as real processes."""
    from test_suite import ptpcert_run, reference_iut

    profile = reference_profile(**MUTANTS[mutant].profile)
    cases = [c for c, m in KILLS.items() if m == mutant]
    select = [arg for c in cases for arg in ("--select", c)]
    p, data = ptpcert_run(tmp_path, reference_iut(profile), profile, *select)
    assert p.returncode == 0 and {c["id"]: c["verdict"] for c in data["cases"]} == {c: "pass" for c in cases}, \
        [(c["id"], c["verdict"], c["message"]) for c in data["cases"]]
    p, data = ptpcert_run(tmp_path, reference_iut(profile, mutant=mutant), profile, *select)
    assert p.returncode == 1 and {c["verdict"] for c in data["cases"]} == {"fail"}
