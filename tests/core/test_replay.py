"""ptpcert.replay: the reference model fed the line as it really was, in virtual time. It
tells a divergence the harness's own timing explains (a reply timed from a late read) from
one no timing explains, and judges an exchange by the rule for the state the IUT was in."""

import pytest

from ptpcert import replay as RP
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.runner import Runner, RunOptions, realtime_tolerance
from ptpcert.scenario import Vector, load_vector_sets
from ptpcert.suite import load_suite
from ptpcert.transport import sim_factory

PROF = reference_profile()
PROC, P = PROF.procedure, PROF.params
CHAR = P.char_time
TOL = realtime_tolerance(PROC, P)
MARGIN = RP.Margin(early=lambda d: TOL.early + TOL.early_rel * max(d, 0.0), late=TOL.late)
NAK, STX, DLE = 0x15, 0x02, 0x10
CASE = Vector(procedure="p3964", id="T", title="t", reference="r", rule="r", group="receive", iut_role="receiver", params=P,
              steps=(), binds=())


def model(wire, late, case=CASE, stall=0.0):
    return RP.replay(sim_factory(PROC, {"app": "echo"})(case, P), wire, MARGIN, late=late, startup_on_line=True,
                     longest=max(P.cdt, P.adt), char=CHAR, stall=stall)


def iut(r, b, lb=None):
    return RP.IutByte(r, r - 0.001 if lb is None else lb, b)


def block_events(t0, data, seen):
    return [RP.TesterEvent(t0 + i * CHAR, "byte", b, seen=seen) for i, b in enumerate(data)]


BLOCK = codec.body(b"A", "3964R")   # 41 10 03 BCC


def test_every_suite_case_run_in_virtual_time_is_reproduced_by_the_model():
    # the model fed its own transcripts (IUT byte times exact) agrees on both timelines
    cases = load_suite(PROF, load_vector_sets(), select=["3964R.FIG2-*", "3964R.D1*", "SUITE.SEND.*"])
    assert len(cases) > 20
    for case in cases:
        r = Runner(sim_factory(PROC), PROF, RunOptions())
        res = r.run_case(case)
        if res.verdict == "unsupported":
            continue
        run = r.last_run
        wire = RP.Wire.from_log(run.log, {}, run.rel(run.tr.now()))
        for late, stall in ((False, 0.0), (True, 0.0), (False, 0.005)):
            rep = model(wire, late, case, stall)
            assert rep.agrees, (case.id, res.verdict, late, stall, rep.why)


def test_a_reply_timed_from_a_late_read_explains_the_iuts_timeout():
    # The harness, descheduled from 11 ms to 34 ms, reads the IUT's DLE late and sends the
    # block at once; the IUT's CDT had already run out when the block reached it. On the
    # observed timeline the model accepts the block, so the NAK is not explained; fed the
    # block as late after the DLE as it may have reached the IUT, the model NAKs too.
    wire = RP.Wire(iut=[iut(0.001, NAK, 0.0), iut(0.034, DLE, 0.011)], end=0.060)
    wire.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)]
    wire.tester += block_events(0.0352, BLOCK[:2], seen=2)
    wire.iut.append(iut(0.0365, NAK, 0.0364))
    wire.tester += block_events(0.0352 + 2 * CHAR, BLOCK[2:], seen=3)
    observed, late = model(wire, late=False), model(wire, late=True)
    assert not observed.agrees and "15" in observed.why
    assert late.agrees, late.why


def test_an_iut_byte_read_before_the_reply_went_out_is_explained_as_observed():
    # the NAK was already in the pipe when the block went out (read together with the DLE)
    wire = RP.Wire(iut=[iut(0.001, NAK, 0.0), iut(0.040, DLE, 0.011), iut(0.040, NAK, 0.011)], end=0.070)
    wire.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)] + block_events(0.041, BLOCK, seen=3)
    assert model(wire, late=False).agrees


def test_an_early_timeout_is_explained_by_no_timeline():
    # the harness looked every millisecond; the IUT NAKed 10 ms after its DLE (half its
    # CDT), before the tester's block went out at 0.8 CDT
    wire = RP.Wire(iut=[iut(0.001, NAK, 0.0), iut(0.0135, DLE, 0.0125), iut(0.0237, NAK, 0.0227)], end=0.060)
    wire.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)] + block_events(0.0295, BLOCK, seen=3)
    for late in (False, True):
        rep = model(wire, late)
        assert not rep.agrees and "came" in rep.why, rep.why


def test_a_wrong_byte_is_explained_by_no_timeline():
    wire = RP.Wire(iut=[iut(0.001, NAK, 0.0), iut(0.0125, NAK, 0.0115)], end=0.050)   # NAK, not DLE, to STX
    wire.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)]
    for late in (False, True):
        rep = model(wire, late)
        assert not rep.agrees and "is 15; the model sends 10" in rep.why


def test_a_byte_the_model_would_have_sent_is_missing():
    # no NAK after the DLE although the observation went on well past CDT and the late
    # tolerance (50 ms plus a quarter)
    wire = RP.Wire(iut=[iut(0.001, NAK, 0.0), iut(0.0125, DLE, 0.0115)], end=0.0125 + 0.200)
    wire.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)]
    rep = model(wire, late=False)
    assert not rep.agrees and "the model sends 15" in rep.why and "nothing more" in rep.why


@pytest.mark.parametrize("what,agrees", [("release rule", True), ("data-phase rule", False)])
def test_a_whole_block_judged_by_the_state_the_iut_was_in(what, agrees):
    # The IUT (echoing) writes its whole block at once; the tester's "interrupting" 42 goes
    # out after it has been read, so it reaches an IUT waiting for the release DLE: a new
    # STX at once is the rule (§2.2.2 release); a NAK after CDT (the data-phase rule) is not.
    payload = b"A" * 40
    body = codec.body(payload, "3964R")
    w = RP.Wire(iut=[iut(0.001, NAK, 0.0)])
    w.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)]
    w.iut.append(iut(0.0125, DLE, 0.0115))
    w.tester += block_events(0.014, body, seen=2)
    t = 0.014 + len(body) * CHAR
    w.iut += [iut(t + 0.001, DLE), iut(t + 0.002, STX)]              # block acknowledged; the echo's STX
    w.tester.append(RP.TesterEvent(t + 0.004, "byte", DLE, seen=4))   # setup acknowledged
    t += 0.005
    w.iut += [iut(t, b, t - 0.0005) for b in body]                     # the echo, in one write
    w.tester.append(RP.TesterEvent(t + 0.0002, "byte", 0x42, seen=len(w.iut)))
    if what == "release rule":
        w.iut.append(iut(t + 0.0015, STX))
    else:
        w.iut.append(iut(t + 0.0002 + P.cdt + 2 * CHAR, NAK))
    w.end = w.iut[-1].r + 0.002
    rep = model(w, late=False)
    assert rep.agrees == agrees, rep.why


def echo_interrupted(sent_after: int, reply: bool):
    """The IUT echoes a 40-byte block; the tester's 42 goes out 1.05 characters after the
    harness read the IUT's 10th data byte; the IUT then sends ``sent_after`` more bytes and,
    if ``reply``, its NAK a CDT after the 42 (Fig. 2-10: another character during the data
    ends the attempt)."""
    body = codec.body(b"A" * 40, "3964R")
    w = RP.Wire(iut=[iut(0.001, NAK, 0.0)])
    w.tester = [RP.TesterEvent(0.010, "byte", STX, seen=1)]
    w.iut.append(iut(0.0125, DLE, 0.0115))
    w.tester += block_events(0.014, body, seen=2)
    t = 0.014 + len(body) * CHAR
    w.iut += [iut(t + 0.001, DLE), iut(t + 0.002, STX)]
    w.tester.append(RP.TesterEvent(t + 0.004, "byte", DLE, seen=4))
    t += 0.004
    w.iut += [iut(t + (i + 1) * CHAR, b, t + i * CHAR) for i, b in enumerate(body[:10])]
    at = t + 10 * CHAR + 1.05 * CHAR
    w.tester.append(RP.TesterEvent(at, "byte", 0x42, seen=len(w.iut)))
    # the stalled IUT writes what it still sends 10 ms later, in a burst
    w.iut += [iut(at + 0.010, b, at) for b in body[10:10 + sent_after]]
    if reply:
        w.iut.append(iut(at + P.cdt + 0.002, NAK, at + P.cdt))
    w.end = w.iut[-1].r + 0.050
    return w


def test_a_stalled_iut_stops_its_block_with_fewer_bytes_out_than_the_observed_timeline_says():
    # Seen under load (SUITE.SEND.QUIET-RESTARTS against the reference, load ~20 on 2 cores):
    # on the observed timeline the model has a second byte on the line when the 42 reaches
    # it and sends it; the IUT, stalled, had only one more. With the stall the harness
    # measured, the model takes the 42 while that one byte is on the line, and agrees.
    w = echo_interrupted(sent_after=1, reply=True)
    for late in (False, True):
        rep = model(w, late)
        assert not rep.agrees and "the model sends 41" in rep.why, rep.why
    rep = model(w, False, stall=0.015)
    assert rep.agrees and rep.timeline == "stalled", rep.why


def test_a_stall_does_not_explain_an_iut_that_ignores_the_interruption():
    w = echo_interrupted(sent_after=33, reply=False)   # the rest of its block, no NAK
    for late, stall in ((False, 0.0), (True, 0.0), (False, 0.015)):
        assert not model(w, late, stall=stall).agrees
