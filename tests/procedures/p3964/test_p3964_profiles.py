"""Issue 25 for 3964/3964R: the reference configured from a profile passes every case and
vector generated for it. Properties over the profile keys a case derives its steps from
(attempt counts, priority, timers, baud rate, send_trigger), and the vectors' tester events
checked by the model."""

from __future__ import annotations

import fnmatch
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from ptpcert import results as R
from ptpcert.model.codes import Code
from ptpcert.model.events import Status
from ptpcert.model.link import DELIVER, DROP, Link
from ptpcert.procedures.p3964.model.params import Params3964, min_timer_ms
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.profile import profile_from_dict
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_vector, load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[3]
_VECTORS: list = []


def _vectors():
    if not _VECTORS:
        _VECTORS.extend(load_vector_sets())
    return _VECTORS


BASE = {"procedure": "3964R", "send_trigger": "echo", "line_conditions": "parmrk", "status_from_stderr": True,
        "priority": "low", "baud_rate": 9600, "character_delay_ms": 20, "acknowledgement_delay_ms": 200,
        "setup_attempts": 6, "transmission_attempts": 6}


def profile(**iut):
    raw = {**BASE, **iut}
    for key in ("character_delay_ms", "acknowledgement_delay_ms"):   # the baud rate's floor (Table 2-4)
        if key not in iut:
            raw[key] = max(raw[key], min_timer_ms(raw["baud_rate"]))
    return profile_from_dict({"iut": raw}, "<test>")


def run(prof, *globs: str) -> list[R.CaseResult]:
    cases = [c for c in load_suite(prof, _vectors()) if any(fnmatch.fnmatchcase(c.id, g) for g in globs)]
    assert cases
    res = R.RunResult(tool_version="test", started="")
    factory = make_factory("sim:", prof)
    try:
        Runner(factory, prof, RunOptions(echo=prof.echo, check_status=prof.status_from_stderr)).run(cases, res)
    finally:
        factory.shutdown()
    return res.cases


def problems(results) -> list[str]:
    return [f"{c.id}: {c.verdict}: {c.message}" for c in results
            if c.verdict in (R.FAIL, R.ERROR) or (c.verdict == R.UNSUPPORTED and not c.message.strip())
            or (c.verdict == R.PASS and "other reading" in c.message)]


FEW = settings(max_examples=12, deadline=None, database=None, suppress_health_check=list(HealthCheck))
ATTEMPT_CASES = ("SUITE.SEND.*", "SUITE.RELEASE.*", "SUITE.CONFLICT.HIGH-NO-DLE", "SUITE.CONFLICT.LOW-AT-ONCE",
                 "*.D14.*", "*.D15.*", "*.D18.*")


@FEW
@given(st.sampled_from(["3964R", "3964"]), st.sampled_from(["low", "high"]), st.integers(1, 3), st.integers(1, 3))
def test_attempt_cases_follow_the_profiles_attempts(proc, prio, setups, transmissions):
    """Item 1: with one or two attempts the cases expect no repetition the profile does not
    allow: with one attempt the IUT gives up after the first failure (NAK, 16#0709/16#070A),
    and a case passes the reference on its own reading, not on the other reading of an
    open point."""
    prof = profile(procedure=proc, priority=prio, setup_attempts=setups, transmission_attempts=transmissions)
    results = run(prof, *ATTEMPT_CASES)
    assert not problems(results)
    if transmissions == 1 and proc == "3964R":
        d14 = [c for c in results if c.id == "3964R.D14.NAK-DURING-DATA"]
        assert d14 and all(c.verdict == R.UNSUPPORTED and "transmission_attempts >= 2" in c.message for c in d14)


def test_one_attempt_checks_the_give_up():
    by_id = {c.id: c for c in run(profile(setup_attempts=1, transmission_attempts=1), "SUITE.SEND.*",
                                  "SUITE.RELEASE.*")}
    for cid in ("SUITE.SEND.SETUP-REFUSED-BY-NAK", "SUITE.SEND.SETUP-TIMEOUT-RETRY", "SUITE.RELEASE.NAK-RETRY",
                "SUITE.SEND.NAK-DURING-DATA"):
        assert by_id[cid].verdict == R.PASS
        assert "NAK" in by_id[cid].title and "= 1" in by_id[cid].title


@FEW
@given(st.sampled_from([300, 600, 1200, 2400, 9600]), st.integers(0, 10))
def test_conflict_high_cases_fit_adt_or_are_unsupported(baud, steps):
    """Item 4: a partner STX at 3/4 ADT and a DLE after it do not fit into a short ADT at a
    low baud rate: unsupported with the reason, never a failure of the reference."""
    floor = min_timer_ms(baud)
    prof = profile(priority="high", baud_rate=baud, acknowledgement_delay_ms=floor + 10 * steps, character_delay_ms=floor)
    results = run(prof, "SUITE.CONFLICT.HIGH-*")
    assert not problems(results)


@FEW
@given(st.sampled_from(["3964R", "3964"]), st.sampled_from(["low", "high"]), st.sampled_from([300, 9600]))
def test_send_trigger_none_is_an_iut_that_never_sends(proc, prio, baud):
    """Item 2: sim: is the IUT the profile declares: with send_trigger = "none" it never
    echoes, so the receive cases pass and nothing that needs an echo is run."""
    prof = profile(procedure=proc, priority=prio, baud_rate=baud, send_trigger="none")
    factory = make_factory("sim:", prof)
    factory.shutdown()
    results = run(prof, "SUITE.RECEIVE.*", "SUITE.SEND.*", "*.D0*")
    assert not problems(results)
    assert all(c.verdict == R.UNSUPPORTED for c in results if c.id.startswith("SUITE.SEND."))
    assert any(c.verdict == R.PASS for c in results if c.id.startswith("SUITE.RECEIVE."))


def _tester_seat_event_without_bcc() -> list[int]:
    """What a CP 341 sending the block raises when its BCC is lost and the receiver NAKs
    CDT after DLE ETX: two 3964R model stations, the sender's BCC dropped on the line."""
    a = Station3964(Params3964(procedure="3964R", priority="low"), name="a")
    b = Station3964(Params3964(procedure="3964R", priority="high"), name="b")
    sent = []

    def drop_bcc(w):
        if w.src == "a":
            sent.append(w.byte)
            if len(sent) == 5:   # STX, 31, DLE, ETX, then the BCC
                return DROP
        return DELIVER
    link = Link(a, b, hook=drop_bcc)
    link.power_on(0.0)
    link.run_until(0.05)
    link.events.clear()
    sent.clear()
    link.request(a, b"\x31", at=0.1)
    link.run_until(0.1 + a.params.cdt + a.params.adt)
    return [e.code for e in link.events_of(a, Status)]


def test_d09_tester_event_is_the_models():
    """Item 10: the NAK comes one CDT after DLE ETX, inside the tester's ADT: a CP 341 in
    the tester's seat raises 16#0706 (partner refused the block with NAK), not 16#0707."""
    events = _tester_seat_event_without_bcc()
    assert events[:1] == [Code.RELEASE_REFUSED]
    v = load_vector(ROOT / "vectors/p3964/d09-bcc-missing.toml")
    assert [sorted(g) for g in v.expected.tester_status.required] == [[int(Code.RELEASE_REFUSED)]]


@settings(max_examples=10, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(st.sampled_from(["3964R", "3964"]), st.sampled_from(["low", "high"]), st.sampled_from([300, 600, 1200, 9600]),
       st.integers(0, 3), st.integers(0, 3), st.sampled_from([1, 2, 255]), st.sampled_from([1, 2, 255]))
def test_slow_lines_short_timers_and_many_attempts(proc, prio, baud, cdt_steps, adt_steps, setups, transmissions):
    """Item 4: at a low baud rate with timers at their floor (Table 2-4) a BREAK of 20
    characters outlasts 2*ADT + CDT (the harness must not call its own wait a late byte); the
    stray characters after a gap over CDT are NAKed CDT after the last of them; a partner
    window holds every attempt the profile allows; the receive counter case needs a
    deferred job that resumes (setup attempts >= 2)."""
    floor = min_timer_ms(baud)
    prof = profile(procedure=proc, priority=prio, baud_rate=baud, character_delay_ms=floor + 10 * cdt_steps,
                   acknowledgement_delay_ms=floor + 10 * adt_steps, setup_attempts=setups,
                   transmission_attempts=transmissions)
    results = run(prof, "SUITE.BREAK.*", "SUITE.TIMING.GAP-OVER-CDT-REFUSED", "SUITE.COUNTERS.*",
                  "SUITE.RECEIVE.FROM-3964R-PARTNER", "*.D18.*")
    assert not [p for p in problems(results) if "other reading" not in p]


@pytest.mark.realtime
def test_send_trigger_none_over_exec_ptpcert_iut(tmp_path):
    """Item 2 over exec:: ``ptpcert iut --profile`` with send_trigger = "none" is an IUT that
    receives and never echoes (an echo would fail every receive case: "the IUT sends 02")."""
    import subprocess
    import sys
    prof = tmp_path / "none.toml"
    prof.write_text("[iut]\n" + "".join(f"{k} = {v!r}\n".replace("'", '"').replace("True", "true")
                                         for k, v in {**BASE, "send_trigger": "none", "priority": "high"}.items()))
    iut = f"exec:{sys.executable} -m ptpcert.cli iut --profile {prof}"
    out = subprocess.run([sys.executable, "-m", "ptpcert.cli", "run", "--iut", iut, "--profile", str(prof),
                          "--select", "SUITE.RECEIVE.UNDOUBLE-*", "--select", "SUITE.RECEIVE.DLE-REPLY-TO-STX"],
                         capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "overall PASS" in out.stdout


@settings(max_examples=40, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(setup=st.integers(1, 8), tx=st.integers(1, 8), adt=st.sampled_from([20, 60, 200]),
       priority=st.sampled_from(["low", "high"]))
@example(setup=2, tx=2, adt=20, priority="low")   # the long run's profile
def test_the_mismatch_vector_allows_what_few_attempts_lead_to(setup, tx, adt, priority):
    """D18 (a 3964R IUT, a 3964 partner): with few setup attempts the IUT has given up when the
    partner's DLE for its last STX comes, and a character other than STX in idle raises
    16#0802 (found by the long run with setup_attempts = 2, ADT 20 ms). Allowing 16#0802 would
    let an IUT that answers a NAK in idle pass, so the vector needs three setup attempts or
    more: unsupported below, passed by the reference under every attempt count above."""
    prof = profile(setup_attempts=setup, transmission_attempts=tx, acknowledgement_delay_ms=adt, priority=priority)
    for c in run(prof, "3964R.D18.*"):
        assert c.verdict not in (R.FAIL, R.ERROR), (c.id, c.message)
        assert (c.verdict == R.UNSUPPORTED) == (setup < 3), (c.id, c.verdict, c.message)
