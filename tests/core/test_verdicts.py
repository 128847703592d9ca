"""Verdicts a certifier can sign (issue 10, the harness side): no false alarm from the
harness's own timing, a declared accuracy of the IUT's timers, the readings of the manual's
open points grading divergences, and one finding per defect in the reports."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from ptpcert.profile import ProfileError
from ptpcert.procedures.p3964.description import reference_profile

ROOT = Path(__file__).resolve().parents[2]
PY = sys.executable
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
FAKES = ROOT / "tests" / "fakes"


def ptpcert(*args, timeout=240, **kw):
    return subprocess.run([PY, "-m", "ptpcert.cli", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, **kw)


def profile_with(tmp_path, **iut) -> Path:
    text = PROFILE.read_text()
    extra = "".join(f"{k} = {json.dumps(v)}\n" for k, v in iut.items())
    text = text.replace("status_from_stderr = true\n", "status_from_stderr = true\n" + extra, 1)
    path = tmp_path / "profile.toml"
    path.write_text(text)
    return path


def without_setups(tmp_path) -> Path:
    """The reference profile for a stand-in that knows none of the reference's setups."""
    text = PROFILE.read_text()
    start = text.index("[iut.setups]")
    path = tmp_path / "no-setups.toml"
    path.write_text(text[:start] + text[text.index("[", start + 1):])
    return path


def run(tmp_path, iut, profile, *select):
    j = tmp_path / "r.json"
    p = ptpcert("run", "--iut", iut, "--profile", str(profile), "--json", str(j),
                *sum((["--select", s] for s in select), []))
    return p, (json.loads(j.read_text()) if j.exists() else None)


# -- [iut] timer_tolerance_ms ---------------------------------------------------------------

def test_timer_tolerance_is_a_profile_key_with_a_default_of_zero():
    assert reference_profile().timer_tolerance_ms == 0
    p = reference_profile(timer_tolerance_ms=280)
    assert p.timer_tolerance_ms == 280 and p.to_dict()["timer_tolerance_ms"] == 280
    for bad in (-1, "300", True, float("nan"), 1e9):
        with pytest.raises(ProfileError, match="iut.timer_tolerance_ms"):
            reference_profile(timer_tolerance_ms=bad)


def test_timer_tolerance_widens_only_the_late_side_of_windows_on_an_iut_timer():
    from ptpcert.runner import RunOptions, Runner
    from ptpcert.scenario import Expr, Step, Vector
    from ptpcert.transport import sim_factory

    prof = reference_profile(timer_tolerance_ms=300)
    proc = prof.procedure

    def case(*steps):
        return Vector(procedure="p3964", id="T", title="t", reference="r", rule="r", group="receive", iut_role="receiver",
                      params=prof.params, steps=tuple(steps), binds=())

    def verdict(profile, v):
        return Runner(sim_factory(proc), profile, RunOptions(check_status=False)).run_case(v).verdict

    def nak(after, within):
        return case(Step("send", b"\x02"), Step("expect", b"\x10", within=Expr("ADT")),
                    Step("expect", b"\x15", after=Expr(after), within=Expr(within)))

    # the model's NAK comes one character (the timer's grace) plus its own character time
    # after its CDT has run out: a window closing at CDT is too short for it ...
    assert verdict(reference_profile(), nak("CDT", "CDT + 2*CHAR")) == "pass"
    assert verdict(reference_profile(), nak("CDT", "CDT")) == "fail"
    # ... unless the IUT declares that its timers may act late: the window ends on its CDT
    assert verdict(prof, nak("CDT", "CDT")) == "pass"
    # a window whose lower bound is no IUT timer is not widened
    assert verdict(prof, nak("0", "5ms")) == "fail"
    # and the early side never: a NAK due no earlier than twice the CDT still fails
    assert verdict(prof, nak("2*CDT", "3*CDT")) == "fail"


def test_every_report_shows_the_timer_tolerance(tmp_path):
    prof = profile_with(tmp_path, timer_tolerance_ms=250)
    j, x, h = tmp_path / "r.json", tmp_path / "j.xml", tmp_path / "r.html"
    p = ptpcert("run", "--iut", "sim:", "--profile", str(prof), "--json", str(j), "--junit", str(x),
                "--html", str(h), "--select", "3964R.D06.*")
    assert p.returncode == 0, p.stdout + p.stderr
    assert "IUT timer tolerance: 250 ms" in p.stdout
    assert json.loads(j.read_text())["profile"]["timer_tolerance_ms"] == 250
    assert 'name="profile.timer_tolerance_ms" value="250"' in x.read_text()
    assert "<tr><th>timer_tolerance_ms</th><td>250</td></tr>" in h.read_text()
    # in virtual time, with none declared, the line would mean nothing: it is left out
    p = ptpcert("run", "--iut", "sim:", "--profile", str(PROFILE), "--select", "3964R.D06.*")
    assert "IUT timer tolerance" not in p.stdout and "harness scheduling: virtual time" in p.stdout


@pytest.mark.realtime
def test_a_polling_iut_late_on_its_cdt_passes_only_with_its_declared_tolerance(tmp_path):
    """tests/fakes/polling.py answers its CDT timeout 280 ms late: beyond the harness's own
    tolerance, within a declared 300 ms."""
    iut = f"exec:{PY} {FAKES / 'polling.py'} 280"
    cases = ("SUITE.RECEIVE.CDT-AFTER-DLE", "3964R.D06.*", "3964R.FIG2-6.RECEIVE")
    p, data = run(tmp_path, iut, PROFILE, *cases)
    v = {c["id"]: c["verdict"] for c in data["cases"]}
    assert v == {"SUITE.RECEIVE.CDT-AFTER-DLE": "fail", "3964R.D06.NOTHING-AFTER-DLE": "fail",
                 "3964R.FIG2-6.RECEIVE": "pass"}, p.stdout
    p, data = run(tmp_path, iut, profile_with(tmp_path, timer_tolerance_ms=300), *cases)
    assert p.returncode == 0 and {c["verdict"] for c in data["cases"]} == {"pass"}, p.stdout


# -- what was on the wire when a stimulus went out (false alarm 2) ---------------------------

INTERRUPTING = ("SUITE.SEND.OTHER-DURING-DATA", "3964R.D15.OTHER-DURING-DATA", "SUITE.SEND.NAK-DURING-DATA",
                "3964R.D14.NAK-DURING-DATA")


@pytest.mark.realtime
def test_a_stimulus_that_finds_the_block_ended_is_judged_by_the_rule_for_that_state(tmp_path):
    """tests/fakes/whole_block.py writes its whole block, BCC included, in one write: the
    tester's "interrupting" character reaches it while it waits for the release DLE, where
    a new STX at once is right (§2.2.2 release). The case is not failed for that."""
    p, data = run(tmp_path, f"exec:{PY} {FAKES / 'whole_block.py'}", without_setups(tmp_path), *INTERRUPTING)
    v = {c["id"]: c for c in data["cases"]}
    assert set(v) == set(INTERRUPTING)
    assert p.returncode == 0 and {c["verdict"] for c in v.values()} == {"pass"}, p.stdout
    for cid in ("SUITE.SEND.OTHER-DURING-DATA", "3964R.D15.OTHER-DURING-DATA"):
        c = v[cid]
        assert "had ended" in c["message"] and "judged by the rule for that state" in c["message"], c["message"]
        # it first tried again with the stimulus after the block's first byte
        assert any("repeated with the stimulus after the block's first byte" in n for n in c["notes"])


@pytest.mark.realtime
def test_a_whole_block_iut_that_breaks_the_release_rule_still_fails(tmp_path):
    iut = f"exec:{PY} {FAKES / 'whole_block.py'} --ignore-other-in-release"
    cases = INTERRUPTING[:2]
    p, data = run(tmp_path, iut, without_setups(tmp_path), *cases)
    v = {c["id"]: c for c in data["cases"]}
    assert p.returncode == 1 and {c["verdict"] for c in v.values()} == {"fail"}, p.stdout
    assert all("judged by the rule for that state" in c["message"] for c in v.values())


#: every case of the 3964R suite whose stimulus is meant to land inside a block of the IUT
#: (a stimulus step followed by the rest of that block as a partial expectation)
EVERY_INTERRUPTING = INTERRUPTING + ("SUITE.SEND.CHARACTER-ERROR-DURING-DATA", "SUITE.SEND.DLE-DURING-DATA",
                                     "SUITE.SEND.STX-DURING-DATA", "SUITE.SEND.EVERY-ATTEMPT-INTERRUPTED",
                                     "SUITE.SEND.QUIET-RESTARTS", "3964R.TX.INTERRUPTED-EVERY-ATTEMPT",
                                     "SUITE.RELEASE.ATTEMPTS-MIXED", "SUITE.BREAK.DATA",
                                     "SUITE.BREAK.SENDER-QUIET-WAIT")


def test_every_interrupting_case_is_listed():
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    cases = load_suite(reference_profile(), load_vector_sets())
    found = {c.id for c in cases if any(s.kind == "expect" and s.partial for s in c.steps)}
    assert found == set(EVERY_INTERRUPTING)


@pytest.mark.realtime
@pytest.mark.parametrize("who", ["reference", "whole block"])
def test_no_interrupting_case_fails_a_correct_iut_over_a_pipe(tmp_path, who):
    """The reference paces its block as on the line; the whole-block stand-in writes it at
    once. Neither is failed by a case that interrupts its block: a pass, or at worst an error
    when the machine is too loaded for the harness to keep its own timing."""
    if who == "reference":
        iut, profile = f"exec:{PY} -m ptpcert.cli iut --cdt-ms 20 --adt-ms 20 --parmrk", PROFILE
    else:
        iut, profile = f"exec:{PY} {FAKES / 'whole_block.py'}", without_setups(tmp_path)
    p, data = run(tmp_path, iut, profile, *EVERY_INTERRUPTING)
    verdicts = {c["id"]: c["verdict"] for c in data["cases"]}
    assert set(verdicts) == set(EVERY_INTERRUPTING)
    assert "fail" not in verdicts.values(), p.stdout
    assert sum(v == "pass" for v in verdicts.values()) >= len(verdicts) // 2, p.stdout


# -- readings decide grading (issue 16) -------------------------------------------------------

D18 = "3964R.D18.MISMATCH-3964R-TO-3964"


def run_d18(options, **run_options):
    from ptpcert.runner import RunOptions, Runner
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite
    from ptpcert.transport import sim_factory

    prof = reference_profile()
    (case,) = load_suite(prof, load_vector_sets(), select=[D18])
    assert "A10" in case.readings
    factory = sim_factory(prof.procedure, options, readings=options.pop("readings", None))
    return Runner(factory, prof, RunOptions(**run_options)).run_case(case)


def other_a10():
    return reference_profile().procedure.other_reading("A10")


def test_the_other_reading_of_a_tagged_open_point_is_graded_by_the_procedures_data():
    # A 3964R sender facing a 3964 receiver (D18): a DLE in its end sequence is "too early"
    # (16#0706) in the model's reading of A10, "other character" (16#0704) in the other.
    # An IUT taking the other reading fails the case as written; the procedure grades A10 pass.
    proc = reference_profile().procedure
    assert proc.reading_grade("A10") == "pass" and other_a10() is not None
    strict = run_d18({"app": "echo", "readings": other_a10()}, grade_readings=False)
    assert strict.verdict == "fail" and "16#0704" in strict.message
    res = run_d18({"app": "echo", "readings": other_a10()})
    assert res.verdict == "pass", res.message
    assert "other reading of open point A10" in res.message and any("16#0704" in n for n in res.notes)


@pytest.mark.parametrize("grade", ["non-strict", "informational"])
def test_the_grade_comes_from_the_reading_not_from_the_case(monkeypatch, grade):
    proc = type(reference_profile().procedure)
    monkeypatch.setattr(proc, "reading_grades", {**proc.reading_grades, "A10": grade})
    assert run_d18({"app": "echo", "readings": other_a10()}).verdict == grade


def test_a_reading_the_procedure_does_not_grade_down_fails(monkeypatch):
    proc = type(reference_profile().procedure)
    monkeypatch.setattr(proc, "reading_grades", {k: v for k, v in proc.reading_grades.items() if k != "A10"})
    assert run_d18({"app": "echo", "readings": other_a10()}).verdict == "fail"


@pytest.mark.parametrize("mutant", ["no-dle-doubling", "nak-in-idle-answered", "dle-pair-rescanned"])
def test_a_defect_the_other_reading_does_not_explain_still_fails(mutant):
    res = run_d18({"app": "echo", "mutant": mutant})
    assert res.verdict == "fail" and "other reading" not in res.message


# -- a harness stalled under load (false alarm 5): an error, never a fail ---------------------

def realtime_sim(options: dict, fit):
    """The model IUT of ``sim:`` (with the echo application and ``options``) behind a
    transport the runner takes for a real-time one; ``fit(transport, attempt)`` changes each
    transport made, ``attempt`` counting from 1 (a case's attempts each make one)."""
    from ptpcert.transport import Factory, sim_factory

    base = sim_factory(reference_profile().procedure, {"app": "echo", **options})
    made = [0]

    def make(v, params):
        tr = base(v, params)
        tr.virtual = False
        made[0] += 1
        fit(tr, made[0])
        return tr

    return Factory(make, base.capabilities, virtual=False)


def stalling_factory(at_byte: int, stall: float, **options):
    """The model IUT of ``sim:`` behind a transport the runner takes for a real-time one
    (a pipe: bytes are timed when read): when the IUT's byte ``at_byte`` comes, the harness
    is descheduled for ``stall`` seconds, and reads it, and what the IUT sent meanwhile, only
    then. The IUT model runs on in the meantime, as a process on the other core would."""
    def fit(tr, attempt):
        seen = [0]
        read = tr.read

        def stalled_read(deadline):
            items = read(deadline)
            if items and seen[0] < at_byte <= seen[0] + len(items):
                until = tr.now() + stall
                while tr.now() < until:
                    items += read(until)
            seen[0] += len(items)
            return [(tr.now(), b) for _, b in items]

        tr.read = stalled_read

    return realtime_sim(options, fit)


@pytest.fixture(autouse=True)
def _harness_never_waits_for_a_cpu(request, monkeypatch):
    """The transports of these tests pretend to be real-time over the model in virtual
    time: the harness's own run-queue wait (the test process's, under whatever load the
    machine has) is not part of what they simulate. A test that wants it sets its own.
    Tests with real processes (marked realtime) measure the real one."""
    import ptpcert.runner.disturbance as disturbance_mod

    if request.node.get_closest_marker("realtime"):
        return
    monkeypatch.setattr(disturbance_mod, "OwnCpuWait", type("Waits", (_HarnessWaits,), {"jump": 0.0}))


def run_stalled(case_id, factory, **options):
    from ptpcert.runner import RunOptions, Runner
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    prof = reference_profile()
    (case,) = load_suite(prof, load_vector_sets(), select=[case_id])
    return Runner(factory, prof, RunOptions(retry_pause=(), timing_retries=1, **options)).run_case(case)


def test_a_tester_reply_stalled_past_the_iuts_adt_is_a_harness_error_not_a_fail():
    # Seen with two CPU-bound processes beside the run (load ~22 on 2 cores): 12 reference
    # cases failed "STATUS: unexpected 16#0701, 16#0703, 16#0706": the harness read the
    # IUT's echo STX after its ADT had run out, the IUT raised 16#0703 and tried again.
    adt = reference_profile().params.adt
    factory = stalling_factory(4, adt + 0.005)   # the IUT's 4th byte: the STX of its echo
    strict = run_stalled("3964R.FIG2-6.RECEIVE", factory, rejudge=False)
    assert strict.verdict == "fail" and "16#0703" in strict.message
    res = run_stalled("3964R.FIG2-6.RECEIVE", factory)
    assert res.verdict == "error" and "harness timing fault" in res.message, res.message
    assert res.attempts == 2 and any("16#0703" in n for n in res.notes)


def test_a_defect_fails_when_the_harness_keeps_its_timing_and_is_an_error_when_it_stalled():
    res = run_stalled("3964R.FIG2-6.RECEIVE", stalling_factory(10 ** 6, 0.0, mutant="no-dle-undoubling"))
    assert res.verdict == "fail" and "31 10 10 32 15 03" in res.message, res.message
    # a stall shorter than the IUT's shortest timer (20 ms): the stalled timeline is tried,
    # does not explain wrong data, so the defect stands
    res = run_stalled("3964R.FIG2-6.RECEIVE", stalling_factory(4, 0.010, mutant="no-dle-undoubling"))
    assert res.verdict == "fail" and "31 10 10 32 15 03" in res.message, res.message
    assert any("stalled" in n for n in res.notes), res.notes
    # a stall as long as that timer: the IUT process may have missed a whole timer window
    res = run_stalled("3964R.FIG2-6.RECEIVE", stalling_factory(4, 0.025, mutant="no-dle-undoubling"))
    assert res.verdict == "error" and "stalled" in res.message, res.message


# -- the IUT's process kept from a CPU by the machine's load: an error, never a fail ----------

def starving_factory(at_byte: int, stall: float, *, tells: bool = True, attempts_starved: int = 1,
                     share: float | None = None, **options):
    """The model IUT of ``sim:`` behind a transport the runner takes for a real-time one, whose
    IUT process is kept from a CPU for ``stall`` seconds from the tester's byte ``at_byte`` on
    (in the first ``attempts_starved`` attempts): it takes in what the tester sent meanwhile
    only then, while the harness keeps its own timing. With ``tells``, the transport reports
    the run-queue wait as a process transport reads it from /proc; without, it cannot tell
    (an IUT on another machine). With ``share``, the IUT instead waited for a CPU that share of
    every moment since the attempt began (never most of a moment: no stall, only a total)."""
    def fit(tr, attempt):
        starve = attempt <= attempts_starved
        written = [0]
        hold = [None, None]        # (from, until) of the stall
        write, push = tr.write, tr._push

        def held_write(data):
            t = tr.now()
            for i, b in enumerate(data):
                written[0] += 1
                at = t + i * tr._tester_char
                if starve and written[0] == at_byte:
                    hold[:] = [at, at + stall]
                if hold[0] is not None and at < hold[1]:
                    at = hold[1]          # the IUT reads its input only when it runs again
                push(at, "byte", b)
            return t

        opened = tr.now()

        def cpu_wait():
            if not tells:
                return None
            if share is not None:
                return share * (tr.now() - opened) if starve else 0.0
            if hold[0] is None:
                return 0.0
            return max(0.0, min(tr.now(), hold[1]) - hold[0])

        tr.write = held_write
        tr.cpu_wait = cpu_wait
        del write

    return realtime_sim(options, fit)


def test_an_iut_process_kept_from_a_cpu_past_its_cdt_is_repeated_not_failed():
    # Seen with two CPU-bound loops beside a run (load 2.7-4.2 on 2 cores): the reference IUT
    # failed SUITE.SEND.ECHO-MAX-1024 "expected 10; received 15". Its process did not run for
    # longer than its CDT inside the tester's block, so it answered NAK, while the harness kept
    # its own timing to the millisecond.
    cdt = reference_profile().params.cdt
    factory = starving_factory(5, cdt + 0.010)
    strict = run_stalled("3964R.FIG2-6.RECEIVE", factory, rejudge=False)
    assert strict.verdict == "fail" and "15" in strict.message, strict.message
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(5, cdt + 0.010))
    assert res.verdict == "pass" and res.attempts == 2, (res.verdict, res.message, res.notes)
    assert any("kept from a CPU" in n for n in res.notes), res.notes
    # starved in every attempt: an error, and the failed attempt is kept in the notes
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(5, cdt + 0.010, attempts_starved=9))
    assert res.verdict == "error" and "kept from a CPU" in res.message, res.message
    assert any("failed attempt" in n for n in res.notes), res.notes


class _HarnessWaits:
    """The harness thread's run-queue wait as ptpcert.runner.disturbance.OwnCpuWait reads it: nothing,
    then ``jump`` seconds at once from the ``at``-th look on (a harness runnable but kept
    from a CPU that long while the IUT's bytes arrived)."""

    jump, at = 0.0, 5

    def __init__(self):
        self.looks = 0

    def __call__(self):
        self.looks += 1
        return 0.0 if self.looks < self.at else self.jump


def test_a_harness_kept_from_a_cpu_is_its_own_stall(monkeypatch):
    """The harness's own run-queue wait counts as its stall, also where every read came back
    in time by its clock: it stamped the IUT's bytes late. A defect seen in an attempt where
    the harness waited for a CPU as long as the IUT's shortest timer is an error, never a
    fail; where it did not wait, the same defect fails."""
    import ptpcert.runner.disturbance as disturbance_mod

    waits = type("Waits", (_HarnessWaits,), {"jump": reference_profile().params.cdt + 0.010})
    monkeypatch.setattr(disturbance_mod, "OwnCpuWait", waits)
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(10 ** 6, 0.0, mutant="no-dle-undoubling"))
    assert res.verdict == "error" and "the harness was stalled" in res.message, (res.verdict, res.message)
    assert any("31 10 10 32 15 03" in n for n in res.notes), res.notes     # the failed attempt is kept
    # a correct IUT passes all the same
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(10 ** 6, 0.0))
    assert res.verdict == "pass", (res.verdict, res.message)
    # no wait: the defect fails
    monkeypatch.setattr(disturbance_mod, "OwnCpuWait", type("Waits", (_HarnessWaits,), {"jump": 0.0}))
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(10 ** 6, 0.0, mutant="no-dle-undoubling"))
    assert res.verdict == "fail" and "31 10 10 32 15 03" in res.message, res.message


def test_an_iut_stall_is_not_an_excuse_where_nothing_shows_it():
    cdt = reference_profile().params.cdt
    # a transport that cannot see the IUT's process (a device behind a port): the IUT's own
    # stalls are the IUT's; the harness kept its timing, so the fail stands
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(5, cdt + 0.010, tells=False))
    assert res.verdict == "fail", (res.verdict, res.message)
    # a defect in a run where the IUT was never kept from a CPU still fails
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(10 ** 6, 0.0, mutant="no-dle-undoubling"))
    assert res.verdict == "fail" and "31 10 10 32 15 03" in res.message, res.message
    # ... and a short stall (under the IUT's shortest timer) does not explain wrong data away
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(5, 0.008, mutant="no-dle-undoubling"))
    assert res.verdict == "fail" and "31 10 10 32 15 03" in res.message, (res.message, res.notes)
    assert any("kept from a CPU" in n for n in res.notes), res.notes


def test_an_iut_process_that_waited_for_a_cpu_as_long_as_its_timer_within_its_timer_is_repeated_not_failed():
    # under a steady load the IUT's process waits a little at every moment, never long at
    # once: what it lost in all counts
    cdt = reference_profile().params.cdt
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(5, cdt + 0.040, share=0.45))
    assert res.verdict == "pass" and res.attempts == 2, (res.verdict, res.message, res.notes)
    assert any("in all within" in n for n in res.notes), res.notes
    # a little wait in all is no excuse
    res = run_stalled("3964R.FIG2-6.RECEIVE", starving_factory(5, cdt + 0.040, share=0.02))
    assert res.verdict == "fail", (res.verdict, res.message, res.notes)


@pytest.mark.realtime
@pytest.mark.parametrize("slow_attempts, verdict", [(0, "pass"), (1, "pass"), (9, "error")])
def test_a_reply_late_after_a_whole_block_read_late_is_the_harness_s_fault(tmp_path, monkeypatch, slow_attempts, verdict):
    """A harness that comes late to the whole-block stand-in's 2,000-byte echo block and then
    handles it slowly (as on a loaded machine) never fails the stand-in: the attempt it could
    not time is void and runs again, and an error where that keeps happening. In the first
    ``slow_attempts`` attempts the harness comes to the block 8 ms late and handles it 12 ms
    longer (with the stand-in's ADT of 20 ms). The deterministic check of the rule behind it
    is test_a_late_reply_counts_from_when_the_iuts_byte_may_have_left_it."""
    import time

    from ptpcert.runner import CaseRun, RunOptions, Runner
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite
    from ptpcert.profile import load_profile
    from ptpcert.transport import make_factory

    attempts = [0]
    expect, start = CaseRun._expect, CaseRun.__init__

    def counting(self, *a, **k):
        start(self, *a, **k)
        attempts[0] += 1

    def slow(self, step):
        late = len(step.data) > 500 and attempts[0] <= slow_attempts
        if late:
            time.sleep(0.008)       # the block is written meanwhile: the harness reads it late
        expect(self, step)
        if late:
            time.sleep(0.012)       # ... and handles its 2,000 bytes for a while
    monkeypatch.setattr(CaseRun, "__init__", counting)
    monkeypatch.setattr(CaseRun, "_expect", slow)
    prof = load_profile(without_setups(tmp_path))
    (case,) = load_suite(prof, load_vector_sets(), select=["SUITE.SEND.ECHO-MAX-1024"])
    factory = make_factory(f"exec:{PY} {FAKES / 'whole_block.py'}", prof)
    try:
        res = Runner(factory, prof, RunOptions(retry_pause=())).run_case(case)
    finally:
        factory.shutdown()
    assert res.verdict == verdict, (res.verdict, res.message, res.notes)
    if slow_attempts:
        assert any("went out" in n and "late" in n for n in res.notes + [res.message]), (res.message, res.notes)


@pytest.mark.parametrize("floor_before_read, faults", [(0.0, False), (0.010, True)])
def test_a_late_reply_counts_from_when_the_iuts_byte_may_have_left_it(floor_before_read, faults):
    """The tester's reply (DLE after the IUT's block) goes out 12 ms late (3 ms allowed),
    13 ms after the harness read the block's last byte: under the 18 ms (0.9 ADT) that make
    lateness matter, counted from the read. But the block may have left the IUT up to the
    look before that read: 10 ms earlier, the IUT's ADT may have been 23 ms gone, and the
    attempt is the harness's fault (TimingFault: void, run again). Seen with the
    whole-block stand-in on a loaded machine under --priority normal."""
    from types import SimpleNamespace

    from ptpcert.runner import CaseRun, TimingFault
    from ptpcert.scenario import Expr

    read = 1.000
    clock = {"t": read}

    def writer(b):
        clock["t"] = read + 0.013       # handled the block for 13 ms, then wrote
        return clock["t"]

    run = SimpleNamespace(
        ev=lambda e: e.eval({}), tester_char=0.001, ref=read, _ref_floor=(read, read - floor_before_read),
        shortest=0.020, wait_until=lambda t: None, _stimulus=lambda: None, record=lambda e: None,
        rel=lambda t: t, max_stall=0.0, tol=SimpleNamespace(stimulus=0.003), step_index=4, forced=0.0)
    step = SimpleNamespace(at=Expr("0ms"), gap=Expr("0ms"))
    if faults:
        with pytest.raises(TimingFault, match="went out 12.0 ms late"):
            CaseRun._send_bytes(run, step, b"\x10", writer, "byte")
    else:
        CaseRun._send_bytes(run, step, b"\x10", writer, "byte")
        assert run.ref == read + 0.013
    assert run.max_stall == pytest.approx(0.012)


# -- the tester's reply as the IUT's partner goes out late ------------------------------------

def busy_partner_factory(busy: float, lag: float = 0.0, attempts_busy: int = 99, **options):
    """The model IUT of ``sim:`` behind a transport the runner takes for a real-time one.
    The tester's acknowledgement of each block the IUT sends (its DLE after the IUT's ETX and
    BCC) goes out ``busy`` seconds late in the first ``attempts_busy`` attempts: the harness
    was busy taking the block in, or kept from a CPU. Every byte of the IUT reaches the line
    ``lag`` seconds after its model sent it, as from an IUT that hands a block to its
    timers and then takes a while to write it whole; the harness reads it at once."""
    def fit(tr, attempt):
        busy_now = attempt <= attempts_busy
        got: list[int] = []
        queue: list[tuple[float, int]] = []      # sent by the model, not yet on the line
        read, write = tr.read, tr.write

        def read_lagging(deadline):
            while True:
                now = tr.now()
                out = [(t + lag, b) for t, b in queue if t + lag <= now + 1e-12]
                del queue[:len(out)]
                if out or now >= deadline:
                    got.extend(b for _, b in out)
                    return [(now, b) for _, b in out]
                until = min(deadline, queue[0][0] + lag) if queue else deadline
                queue.extend(read(until))

        def write_late(data):
            if busy_now and data == b"\x10" and len(got) >= 2 and got[-2] == 0x03:
                until = tr.now() + busy
                while tr.now() < until:
                    queue.extend(read(until))
            return write(data)

        tr.read, tr.write = read_lagging, write_late

    return realtime_sim(options, fit)


def test_a_partner_reply_late_past_the_iuts_adt_is_a_harness_error_not_a_fail():
    """The tester acknowledges the IUT's echo block after the IUT's ADT: the IUT times out
    and repeats its block. The harness's reply was late, not the IUT wrong."""
    adt = reference_profile().params.adt
    strict = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(adt + 0.005), rejudge=False)
    assert strict.verdict == "fail", (strict.message, strict.notes)
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(adt + 0.005))
    assert res.verdict == "error" and "harness timing fault" in res.message, (res.message, res.notes)
    assert res.attempts == 2 and any("failed attempt" in n for n in res.notes), res.notes


def test_a_partner_reply_late_within_the_adt_on_the_wire_after_a_lagging_iut_is_not_a_fail():
    """Seen with the whole-block stand-in under --priority normal and two CPU-bound
    processes: its 2,051-byte echo of SUITE.RECEIVE.MAX-STUFFING reached the line up to 7 ms
    after its model handed it over (and started its ADT), and the tester, as its partner,
    acknowledged it 17-22 ms after reading it: within the ADT on the wire, past it for the
    stand-in. The case failed "STATUS: unexpected 16#0701, 16#0707, 16#0802" on a correct
    IUT. Here: 16 ms of lag and a reply 6 ms late (ADT 20 ms): a stall of the harness as long
    as its reply was late does not explain it, the IUT's unseen lag added does."""
    strict = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.006, lag=0.016), rejudge=False)
    assert strict.verdict == "fail", (strict.message, strict.notes)
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.006, lag=0.016))
    assert res.verdict == "error" and "partner went out 6.0 ms later" in res.message, (res.message, res.notes)
    # the same, late in the first attempt only: the second attempt judges the IUT, and it passes
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.006, lag=0.016, attempts_busy=1))
    assert res.verdict == "pass" and res.attempts == 2, (res.verdict, res.message, res.notes)
    # a reply late by no more than the harness keeps its timing to is not an excuse: the
    # same lag with a reply 2 ms late passes (nothing ran out), and a defect fails
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.002, lag=0.016))
    assert res.verdict == "pass" and res.attempts == 1, (res.verdict, res.message, res.notes)
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.002, lag=0.016, mutant="adt-half"))
    assert res.verdict == "fail", (res.verdict, res.message, res.notes)


def test_a_data_defect_fails_even_when_the_partner_replied_late():
    """A late partner reply voids only what timing can explain: an IUT that echoes a
    well-formed block with the wrong bytes (it kept the tester's doubled DLE) fails, however
    late the tester acknowledged it."""
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.006, lag=0.016, mutant="no-dle-undoubling"))
    assert res.verdict == "fail" and "31 10 10 32 15 03" in res.message, (res.verdict, res.message, res.notes)
    assert any("partner went out" in n or "however late" in n for n in res.notes), res.notes


# -- a failure in an attempt the machine disturbed is reproduced before it stands ------------

def flaky_factory(broken_attempts: int, mutant: str):
    """The model IUT of ``sim:`` as a process on this machine (it tells its run-queue wait,
    always none) behind a transport the runner takes for a real-time one; its first
    ``broken_attempts`` attempts run the broken variant ``mutant``, the later ones the
    correct model: what a correct IUT that the machine disturbed once looks like."""
    from ptpcert.transport import Factory, sim_factory

    proc = reference_profile().procedure
    broken, correct = sim_factory(proc, {"app": "echo", "mutant": mutant}), sim_factory(proc, {"app": "echo"})
    made = [0]

    def make(v, params):
        made[0] += 1
        tr = (broken if made[0] <= broken_attempts else correct)(v, params)
        tr.virtual = False
        tr.cpu_wait = lambda: 0.0
        return tr

    return Factory(make, correct.capabilities, virtual=False)


def fake_steal(monkeypatch, every: int | None, ticks: int = 2):
    """The hypervisor's steal time as /proc/stat would show it on two CPUs: ``ticks`` clock
    ticks of 10 ms on the second CPU at the third look (``every`` None: once), or at every
    ``every``-th look."""
    from ptpcert import priority

    looks = [0]

    def steal_time():
        looks[0] += 1
        times = (looks[0] >= 3) if every is None else looks[0] // every
        return (0.0, 0.010 * ticks * times)
    monkeypatch.setattr(priority, "steal_time", steal_time)
    return looks


def test_a_failure_in_an_attempt_the_hypervisor_disturbed_is_reproduced_before_it_stands(monkeypatch):
    """Steal time (the hypervisor ran other work on a CPU) shows on no run queue: the IUT's
    process may have lost its CPU unseen. It excuses nothing, but a failure in an attempt with
    steal is run once more before it stands: a correct IUT that the machine disturbed passes
    the second attempt; a defect fails both."""
    looks = fake_steal(monkeypatch, every=None)
    res = run_stalled("3964R.FIG2-6.RECEIVE", flaky_factory(1, "no-dle-undoubling"))
    assert looks[0] > 3, looks            # steal was looked at, in the IUT's attempts only
    assert res.verdict == "pass" and res.attempts == 2, (res.verdict, res.message, res.notes)
    assert "passed on attempt 2 after 1 failed attempt" in res.message
    assert any("steal time" in n and "20 ms" in n for n in res.notes), res.notes
    assert any("disturbed" in n and "31 10 10 32 15 03" in n for n in res.notes), res.notes
    # a defect: it fails again, with steal in every attempt, and its failure stands
    fake_steal(monkeypatch, every=3)
    res = run_stalled("3964R.FIG2-6.RECEIVE", flaky_factory(99, "no-dle-undoubling"))
    assert res.verdict == "fail" and res.attempts == 2 and "31 10 10 32 15 03" in res.message, (res.message,
                                                                                                 res.notes)


def test_a_failure_in_an_attempt_the_machine_left_alone_is_not_run_again(monkeypatch):
    # no steal, no stall: a failure in the bytes stands at once, even one that the next
    # attempt would not repeat (the machine did nothing that could explain it)
    fake_steal(monkeypatch, every=10 ** 9)
    res = run_stalled("3964R.FIG2-6.RECEIVE", flaky_factory(1, "no-dle-undoubling"))
    assert res.verdict == "fail" and res.attempts == 1, (res.verdict, res.message, res.notes)
    # one clock tick of steal (10 ms, as often a little steal at a tick's edge; this host's
    # CPUs show one every few hundred milliseconds) is not enough to cost an IUT a timer window
    fake_steal(monkeypatch, every=None, ticks=1)
    res = run_stalled("3964R.FIG2-6.RECEIVE", flaky_factory(1, "no-dle-undoubling"))
    assert res.verdict == "fail" and res.attempts == 1, (res.verdict, res.message, res.notes)
    # and without confirmation (RunOptions.confirm_late off), a disturbed failure stands at once
    fake_steal(monkeypatch, every=None)
    res = run_stalled("3964R.FIG2-6.RECEIVE", flaky_factory(1, "no-dle-undoubling"), confirm_late=False)
    assert res.verdict == "fail" and res.attempts == 1, (res.verdict, res.message, res.notes)


@pytest.mark.realtime
@pytest.mark.parametrize("busy_attempts, verdict", [(1, "pass"), (9, "error")])
def test_a_partner_reply_late_to_a_slow_whole_block_iut_is_never_a_fail(tmp_path, monkeypatch, busy_attempts, verdict):
    """The false alarm as it was seen, made certain: the whole-block stand-in hands its
    2,051-byte echo of SUITE.RECEIVE.MAX-STUFFING over, starts its ADT (20 ms) and writes
    the block 8 ms later (--lag-ms 8); the harness, as its partner, takes 15 ms longer than it
    should to acknowledge the first ``busy_attempts`` blocks. The stand-in's ADT runs
    out, it repeats its block and the partner's late DLEs cross its repetition: a sequence no
    model paced like a line replays. The attempt is void, never a fail."""
    import time

    from ptpcert.profile import load_profile
    from ptpcert.runner import CaseEndpoint, RunOptions, Runner
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite
    from ptpcert.transport import make_factory

    poll, blocks = CaseEndpoint.poll, [0]

    def busy(self, deadline):
        items = poll(self, deadline)
        if len(items) > 500:        # a block of the IUT's (its repetitions too): the first ones slow
            blocks[0] += 1
            if blocks[0] <= busy_attempts:
                time.sleep(0.015)
        return items
    monkeypatch.setattr(CaseEndpoint, "poll", busy)
    prof = load_profile(without_setups(tmp_path))
    (case,) = load_suite(prof, load_vector_sets(), select=["SUITE.RECEIVE.MAX-STUFFING"])
    factory = make_factory(f"exec:{PY} {FAKES / 'whole_block.py'} --lag-ms 8", prof)
    try:
        res = Runner(factory, prof, RunOptions(retry_pause=())).run_case(case)
    finally:
        factory.shutdown()
    # never a fail; a pass needs an attempt the machine let the harness and the stand-in time
    # (on a machine that keeps the harness or the stand-in from a CPU for tens of
    # milliseconds, that may not come: an error that names the stall is then right too)
    assert res.verdict != "fail", (res.verdict, res.message, res.notes)
    assert res.verdict == verdict or ("harness timing fault" in res.message and "kept from" in " ".join(res.notes)
                                      + res.message), (res.verdict, res.message, res.notes)
    assert any("the tester's reply as the IUT's partner" in n or "partner went out" in n
               for n in res.notes + [res.message]), (res.message, res.notes)


@pytest.mark.parametrize("model_differs_at, verdict", [(0.0, "fail"), (None, "error")])
def test_an_attempt_that_diverged_only_after_a_late_partner_reply_was_due_is_void(monkeypatch, model_differs_at, verdict):
    """The rule itself, with a model that explains nothing (the replay is replaced by one
    that always differs): the IUT repeats its echo block (the case's divergence, step 5)
    after the tester's DLE went out 6 ms late. Where the model fed the line as it was first
    differs only after that DLE was due, the attempt is void (an error when every attempt
    is so); where it differs before (at 0 ms), something was wrong before the harness was
    late, and the fail stands."""
    import ptpcert.replay as RP

    def differs(transport, wire, margin, **kw):
        at = model_differs_at if model_differs_at is not None else wire.end
        return RP.Replay(False, "differs (a stand-in for the model)", at, b"", [], "observed")
    monkeypatch.setattr(RP, "replay", differs)
    res = run_stalled("3964R.FIG2-6.RECEIVE", busy_partner_factory(0.006, lag=0.016))
    assert res.verdict == verdict, (res.verdict, res.message, res.notes)
    if verdict == "error":
        assert "due at" in res.message and "came after it" in res.message, res.message
    else:
        assert not any("re-judging by the model failed" in n for n in res.notes), res.notes
