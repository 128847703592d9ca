"""Issue 25, the ASCII driver: profiles the manual allows under which the reference (sim:)
failed cases of its own suite. For each, a hypothesis property over the keys involved: the
suite builds for the profile (no internal error), the cases in question pass the reference,
and where a case cannot be built its absence or its outcomes follow from the profile."""

from __future__ import annotations

from fnmatch import fnmatch

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ptpcert.conformance as conformance
from ptpcert import results as R
from ptpcert.procedures.ascii.model.params import BAUD_RATES
from ptpcert.profile import profile_from_dict
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector_sets
from ptpcert.status import lookup
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

VECTORS = load_vector_sets()
BAD = (R.FAIL, R.ERROR)
SETTINGS = settings(max_examples=12, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def profile(ascii: dict, **iut):
    raw = {"iut": {"procedure": "ASCII", "send_trigger": "echo", "line_conditions": "parmrk",
                   "status_from_stderr": True, "baud_rate": 9600, **iut,
                   "setups": {"slow_reader": "--echo-delay-ms {ms}", "send_job": "--send={jobs}"}},
           "ascii": ascii}
    return profile_from_dict(raw, "<test>")


def failures(prof, *globs: str) -> list[str]:
    """The cases (suite and vectors) matching ``globs`` that the reference does not pass,
    with why; and a note when none of them ran."""
    cases = [c for c in load_suite(prof, VECTORS) if any(fnmatch(c.id, g) for g in globs)]
    res = R.RunResult(tool_version="test", started="")
    factory = make_factory("sim:", prof)
    try:
        Runner(factory, prof, RunOptions(check_model_events=True)).run(cases, res)
    finally:
        factory.shutdown()
    return [f"{c.id}: {c.verdict}: {c.message[:200]}" for c in res.cases
            if c.verdict in BAD or (c.verdict == R.UNSUPPORTED and not c.message.strip())]


def suite_ids(prof) -> set[str]:
    return {v.id for v in conformance.cases(prof)}


# ---------------------------------------------------------------- fixed length and XON/XOFF
@SETTINGS
@given(n=st.one_of(st.sampled_from([975, 980, 990, 1000, 1010, 1024]), st.integers(900, 1024)), frames=st.sampled_from([2, 10, 250]))
def test_a_fixed_length_near_1024_with_xon_xoff_builds_and_passes(n, frames):
    """fixed_length 980-1000 with XON/XOFF ended the suite in an IndexError; 1010-1024 failed
    21 cases: one frame reaches the XOFF threshold, the IUT holds its partner in the middle
    of it, and the tester's seat held the IUT's echo in the middle of it."""
    prof = profile({"end_criterion": "fixed_length", "fixed_length": n, "flow_control": "xon_xoff",
                    "buffer_frames": frames})
    assert not failures(prof, "SUITE.ASCII.FL.*", "SUITE.ASCII.TX.*", "SUITE.ASCII.FC.*", "ASCII.RX-FL-*")


# ---------------------------------------------------------------- XOFF at the frame count
@SETTINGS
@given(frames=st.integers(1, 12), crit=st.sampled_from(["cdt", "end_chars", "fixed_length"]),
       baud=st.sampled_from([2400, 9600, 38400]))
def test_xoff_at_the_frame_count_is_awaited_from_a_mark(frames, crit, baud):
    """The window for the XOFF opens at a mark set by the case (before the last two frames,
    or where the first starts), never at the case's origin, and under the CDT criterion it
    includes the CDT that completes the last frame."""
    prof = profile({"end_criterion": crit, "fixed_length": 4, "flow_control": "xon_xoff", "buffer_frames": frames}
                   if crit == "fixed_length" else {"end_criterion": crit, "flow_control": "xon_xoff",
                                                   "buffer_frames": frames}, baud_rate=baud)
    for v in conformance.cases(prof):
        marked = False
        for s in v.steps:
            assert s.since != "mark" or marked, f"{v.id}: since = mark without a mark"
            marked = marked or s.mark
    assert not failures(prof, "SUITE.ASCII.FC.XOFF-AT-*", "ASCII.FC-X-02.*")


# ---------------------------------------------------------------- frames back to back
@SETTINGS
@given(frames=st.integers(1, 6), prevent=st.booleans(), ends=st.sampled_from([[0x03], [0x0D, 0x0A]]))
def test_back_to_back_sends_no_more_frames_than_the_buffer_holds(frames, prevent, ends):
    """With a buffer of one or two frames a correct driver whose application has not yet read
    the first frame refuses (16#080A) or overwrites a third: the case sends at most as many
    frames as the buffer holds (none with one frame), and the vector is bound to its buffer."""
    keys = {"end_criterion": "end_chars", "end_chars": ends, "buffer_frames": frames}
    if frames == 1:
        keys["prevent_overwrite"] = prevent
    prof = profile(keys)
    cases = {v.id: v for v in conformance.cases(prof)}
    b2b = cases.get("SUITE.ASCII.EC.BACK-TO-BACK")
    if frames == 1:   # listed, unsupported with the reason, never left out without a word
        assert b2b.not_buildable and "buffer_frames = 1" in b2b.not_buildable
    else:
        assert not b2b.not_buildable
        assert 2 <= len(b2b.expected.delivered) <= frames
    assert not failures(prof, "*BACK-TO-BACK")


# ---------------------------------------------------------------- the wait time for XON
@SETTINGS
@given(wait=st.integers(2, 30).map(lambda k: 10 * k), baud=st.sampled_from(BAUD_RATES),
       crit=st.sampled_from(["cdt", "end_chars", "fixed_length"]), cdt=st.sampled_from([None, 40, 200]))
def test_short_xon_wait_times_pass(wait, baud, crit, cdt):
    """xon_wait_ms = 20 made 4 FC cases fail: the tester cannot lift an XOFF within a wait time
    shorter than the IUT's stop takes to see (a CDT of quiet) plus the XON itself; those cases
    are built only where it can, and the vectors timed for 2 s bind the XON wait."""
    iut = {"baud_rate": baud}
    if cdt is not None:
        iut["character_delay_ms"] = cdt
    keys = {"end_criterion": crit, "flow_control": "xon_xoff", "xon_wait_ms": wait}
    if crit == "fixed_length":
        keys["fixed_length"] = 100
    try:
        prof = profile(keys, **iut)
    except ValueError:
        return   # a CDT under the baud rate's minimum: refused, another test's business
    assert not failures(prof, "*FC*")
    # the cases that hold the IUT with XOFF are always listed: run, or unsupported with why
    ids = {v.id: v for v in conformance.cases(prof)}
    for name in ("XOFF-AFTER-FIRST", "XOFF-MIDDLE", "XOFF-NEAR-END", "XON-WITHIN-WAIT", "XON-WAIT-EXPIRES"):
        v = ids.get(f"SUITE.ASCII.FC.{name}")
        if v is None:   # the frame or the quiet flow the cases need is not there at all
            assert not any(k.startswith("SUITE.ASCII.FC.XOFF-") and "FIRST" in k for k in ids)
            continue
        assert not v.not_buildable or f"xon_wait_ms = {wait}" in v.not_buildable, v.not_buildable


# ---------------------------------------------------------------- automatic V.24
@SETTINGS
@given(dow=st.integers(0, 300).map(lambda k: 10 * k), rts=st.integers(0, 300).map(lambda k: 10 * k),
       crit=st.sampled_from(["cdt", "end_chars"]), baud=st.sampled_from([2400, 9600, 76800]))
def test_automatic_v24_transmissions_start_a_data_output_waiting_time_later(dow, rts, crit, baud):
    """With the automatic use of the V.24 signals each send job sets RTS, waits the data
    output waiting time, and ends the time to RTS OFF after its last character (Fig. 2-24):
    the echo and send cases wait for it instead of taking the line for quiet."""
    prof = profile({"end_criterion": crit, "flow_control": "auto_v24", "data_output_wait_ms": dow,
                    "rts_off_delay_ms": rts}, baud_rate=baud)
    assert not failures(prof, "*CDT*", "*EC*", "*TX*", "*BUF*", "*LINE*")


def test_len_1025_accepts_either_code_of_the_manual():
    """LEN = 1025 fits Table 8-2's 16#1E41 and Table 8-1's 16#0517: the case and the vector
    accept each, and no other."""
    prof = profile({"end_criterion": "cdt"})
    found = [v for v in load_suite(prof, VECTORS) if "LEN-1025" in v.id]
    assert {v.id for v in found} == {"SUITE.ASCII.TX.LEN-1025-REFUSED", "ASCII.TX-ANY-01.LEN-1025"}
    for v in found:
        spec = v.expected.iut_status
        for code in ("16#1E41", "16#0517"):
            assert spec.judge([lookup(code).code]) == [], (v.id, code)
        assert spec.judge([lookup("16#080A").code]) != []
        assert spec.judge([]) != []


# ---------------------------------------------------------------- a slow application at a low rate
@pytest.mark.parametrize("baud", [300, 1200, 2400, 9600])
@pytest.mark.parametrize("crit", ["cdt", "end_chars"])
def test_buffer_cases_fill_the_buffer_before_the_slow_application_reads(baud, crit):
    """The buffer cases fill the receive buffer while a slow application waits 5 s before its
    first read: at 300 bit/s 1100 bytes take 40 s, so the golden vector timed at 9600 bit/s
    binds its baud rate and the suite's cases are built only where the filling fits."""
    prof = profile({"end_criterion": crit}, baud_rate=baud, data_bits=7, parity="none")
    assert not failures(prof, "*BUF*", "*FC*")


# ---------------------------------------------------------------- XON/XOFF codes among a vector's data
@SETTINGS
@given(codes=st.lists(st.integers(0x20, 0x7E), min_size=2, max_size=2, unique=True),
       crit=st.sampled_from(["cdt", "end_chars", "fixed_length"]))
def test_a_vector_whose_data_hold_the_profiles_xon_or_xoff_is_unsupported(codes, crit):
    """A golden vector written without flow control sends 41 42; with xoff = 0x41 those bytes
    are flow control, not data (§2.2.4 'code transparency'): such a vector is unsupported with
    that reason, never failed; the others still run."""
    xon, xoff = codes
    keys = {"end_criterion": crit, "flow_control": "xon_xoff", "xon": xon, "xoff": xoff}
    if crit == "end_chars":
        keys["end_chars"] = [next(c for c in (0x03, 0x0D, 0x04) if c not in codes)]
    prof = profile(keys)
    assert not failures(prof, "ASCII.*")
