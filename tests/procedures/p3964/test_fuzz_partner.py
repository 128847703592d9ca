"""The fuzzer's partner (ptpcert fuzz, level 2) is reactive and its vectors are replayable:
it sends its next stimulus only after the replies the protocol requires are complete
(unless the stimulus deliberately interrupts the IUT's block), it keeps every stimulus
further from the IUT's timer edges than the runner's real-time tolerance can tell apart,
the vectors it writes have no negative offsets, and a finding stands only if its exported
vector fails on replay. All in virtual time (sim:)."""

from dataclasses import replace

import pytest
from hypothesis import Phase, given, settings
from hypothesis import strategies as st

from ptpcert import results as R
from ptpcert.fuzz import Campaign, Finding
from ptpcert.procedures.p3964.fuzz import CoSim, Generator
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.description import reference_profile
from ptpcert.runner import Runner, RunOptions, realtime_tolerance
from ptpcert.scenario import Expr, expand, timer_env
from ptpcert.transport import make_factory


def _profiles():
    return [reference_profile(procedure="3964R", priority="low"), reference_profile(procedure="3964", priority="high")]


def _examples(prof, n=120):
    """``n`` generated examples (co-simulations) for ``prof``."""
    gen = Generator(prof)
    out = []

    @settings(max_examples=n, deadline=None, database=None, phases=[Phase.generate])
    @given(st.data())
    def draw(data):
        out.append(gen(data))

    draw()
    return out


@pytest.fixture(scope="module", params=[0, 1], ids=["3964R-low", "3964-high"])
def drawn(request):
    prof = _profiles()[request.param]
    return prof, _examples(prof)


def test_exported_vectors_have_no_negative_offsets(drawn):
    prof, sims = drawn
    seen_mark = 0
    for sim in sims:
        v = sim.vector("FUZZ.T", "t", "")
        env = timer_env(v)
        for i, s in enumerate(v.steps):
            for key in ("at", "gap", "duration", "after", "within", "max_gap"):
                e = getattr(s, key) or Expr(v.proc.max_gap)   # no max_gap: the procedure's
                value = e.eval(env)
                assert value >= 0.0, (i, key, e.text, v.steps)
            seen_mark += s.since == "mark"
            if s.since == "mark":   # measured from a marked step before it
                assert any(p.mark for p in v.steps[:i]), v.steps
    assert sims


def test_partner_waits_for_the_iuts_replies_before_its_next_stimulus(drawn):
    """Run every example against the model: each tester byte that is not a deliberate
    violation starts only after every IUT byte begun before it has been received."""
    prof, sims = drawn
    runner = Runner(make_factory("sim:", prof), prof, RunOptions(check_status=False))
    char = prof.params.char_time
    checked = 0
    for sim in sims:
        v = sim.vector("FUZZ.T", "t", "")
        assert len(expand(v)) == len(v.steps)
        res = runner.run_case(v)
        assert res.verdict == R.PASS, res.message
        events = R.wire_events(res.transcript)
        iut = [t for t, d, kind, _, _ in events if d == "iut"]
        for t, d, kind, _, step in events:
            if d != "tester" or kind == "break" or step in sim.violations:
                continue
            start = t - char
            begun = [u for u in iut if u - char < start - 1e-9]
            assert all(u <= start + 1e-6 for u in begun), (step, v.steps[step], t, begun)
            checked += 1
    assert checked > 100


def test_no_stimulus_within_the_runners_tolerance_of_a_timer_edge(drawn):
    prof, sims = drawn
    tol = realtime_tolerance(prof.procedure, prof.params)
    p = prof.params
    before = tol.stimulus + tol.early + 2 * p.char_time
    after = tol.late(max(p.cdt, p.adt)) + 2 * p.char_time
    n = 0
    for sim in sims:
        assert sim.edge_before >= before and sim.edge_after >= after
        for arrival, edges in sim.stimuli:
            for e in edges:
                assert not (arrival - after < e < arrival + before), (arrival, e)
                n += 1
    assert n > 50


def test_the_margin_follows_the_runners_tolerance():
    p = reference_profile().params
    tight = replace(realtime_tolerance(reference_profile().procedure, p), late_abs=0.001, late_rel=0.0)
    loose = replace(tight, late_abs=0.300)
    assert CoSim(p, True, tolerance=loose).edge_after > CoSim(p, True, tolerance=tight).edge_after + 0.29


def _wrong_bcc_vector(prof):
    """STX, DLE, a block whose BCC is wrong: a conforming receiver refuses it with NAK."""
    sim = CoSim(prof.params, prof.echo)
    sim.send(b"\x02", note="STX")
    sim.run_until_output(1)
    body = codec.body(b"ABC", prof.params.procedure)
    sim.send(body[:-1] + bytes([body[-1] ^ 0x55]), note="block (wrong-bcc)")
    sim.run_until_output(1)
    return sim.vector("FUZZ.WRONGBCC", "t", "a block with a wrong BCC is refused")


def test_a_finding_stands_only_if_its_exported_vector_fails_on_replay():
    prof = reference_profile()
    v = _wrong_bcc_vector(prof)
    broken = Runner(make_factory("sim:?mutant=bcc-not-checked", prof), prof, RunOptions(check_status=False))
    res = broken.run_case(v)
    assert res.verdict == R.FAIL
    finding = Finding(v, res, "rule", "")
    # against the variant that does not check the BCC the exported vector fails again
    assert Campaign(prof, broken, 1.0, 1).reproduces(finding)
    # against a conforming IUT it passes on replay: the finding does not stand
    clean = Runner(make_factory("sim:", prof), prof, RunOptions(check_status=False))
    assert not Campaign(prof, clean, 1.0, 1).reproduces(Finding(v, res, "rule", ""))


def _interrupted(viol_at: float, stopped: bool):
    """A vector in which the tester interrupts the IUT's 40-byte block after 10 bytes with
    another character, and a failing result whose transcript has the interruption go out
    ``viol_at`` s after the tester's DLE; the IUT sends the whole rest unless ``stopped``."""
    from ptpcert.scenario import Expr, Step, Vector

    prof = reference_profile()
    char = prof.params.char_time
    block = bytes(range(0x20, 0x20 + 37)) + b"\x10\x03\x42"
    steps = (Step("send", b"\x10", note="DLE"), Step("expect", block[:10], within=Expr("CDT"), mark=True),
             Step("send", b"\x42", note="another character"),
             Step("expect", block[10:], partial=True, since="mark", within=Expr("4*CHAR")),
             Step("expect", b"\x15", within=Expr("CDT + 2*CHAR")))
    v = _wrong_bcc_vector(prof)
    v = replace(v, steps=steps)
    log = [{"t": 0.010, "dir": "tester", "kind": "byte", "byte": 0x10, "step": 0}]
    log += [{"t": 0.010 + (k + 1) * char, "dir": "iut", "kind": "byte", "byte": b, "step": 1}
            for k, b in enumerate(block[:10])]
    log.append({"t": 0.010 + viol_at, "dir": "tester", "kind": "byte", "byte": 0x42, "step": 2})
    rest = block[10:12] if stopped else block[10:]
    log += [{"t": 0.010 + (k + 11) * char, "dir": "iut", "kind": "byte", "byte": b, "step": 3}
            for k, b in enumerate(rest)]
    res = R.CaseResult("X", "t", "r", "r", "g", "both", verdict=R.FAIL, message="m",
                       transcript=R.pack_transcript(log),
                       divergence=R.Divergence(4, 0.2, "15", "15 came 1.9 ms after the reference, too early"))
    return v, res, char


def test_an_interruption_that_may_have_come_after_the_block_voids_the_example():
    from ptpcert.fuzz import late_violation

    # sent after 11 characters, the IUT kept sending all 40: it ignored the interruption
    v, res, char = _interrupted(11 * _char(), stopped=False)
    assert not late_violation(v, res, {2}, char)
    # the IUT stopped: it saw the interruption inside its block
    v, res, char = _interrupted(11 * _char(), stopped=True)
    assert not late_violation(v, res, {2}, char)
    # the harness interrupted only when the block may already have ended (it read late)
    v, res, char = _interrupted(40 * _char(), stopped=False)
    assert late_violation(v, res, {2}, char)
    # no deliberate violation in the example: nothing to void
    assert not late_violation(v, res, set(), char)


def _char():
    return reference_profile().params.char_time


def test_an_iut_that_stops_its_block_only_late_is_no_finding():
    from ptpcert.fuzz import late_violation

    v, res, char = _interrupted(11 * _char(), stopped=True)
    res.divergence = R.Divergence(3, 0.08, "the IUT to stop sending within 1.146ms + 4*CHAR",
                                  "it still sent 2E 64.6 ms after the reference")
    assert late_violation(v, res, {2}, char)
    # one that never stops (it sent the whole rest at once after the interruption) is judged
    v, res, char = _interrupted(11 * _char(), stopped=False)
    assert not late_violation(v, res, {2}, char)
