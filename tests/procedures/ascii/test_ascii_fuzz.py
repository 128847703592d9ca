"""The ASCII fuzzer. Level 1: two model stations wired together in virtual time, with
generated traffic, line faults and flow control: nothing deadlocks, every send job ends
once, and a clean line delivers every frame once, in order. Level 2 (``ptpcert fuzz`` with an
ASCII profile, the model as oracle): the generated examples agree with the model itself (no
false findings), a broken variant yields a finding that is written as a vector which fails
the variant and passes the model."""

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from ptpcert import results as R
from ptpcert.fuzz import Campaign, export
from ptpcert.model.codes import Code
from ptpcert.model.events import Delivered, SendDone, SendFailed
from ptpcert.model.link import CORRUPT, DELIVER, DROP, Link
from ptpcert.procedures.ascii.description import reference_profile
from ptpcert.procedures.ascii.fuzz import AsciiGenerator
from ptpcert.procedures.ascii.model import AsciiHost, AsciiParams, AsciiStation, send_bytes
from ptpcert.procedures.ascii.model.events import FrameDiscarded
from ptpcert.runner import Runner, RunOptions
from ptpcert.scenario import load_dir
from ptpcert.transport import make_factory

ROOT = Path(__file__).resolve().parents[3]
PY = sys.executable
QUICK = settings(max_examples=40, deadline=None, database=None, phases=[Phase.generate],
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

# ------------------------------------------------------------------ level 1: two model stations
CRITERIA = {
    "cdt": dict(end_criterion="cdt"),
    "ec": dict(end_criterion="end_chars", end_chars=(0x03,), send_variant="len_with_end"),
    "ec2-append": dict(end_criterion="end_chars", end_chars=(0x0D, 0x0A), send_variant="len_append_end"),
    "fl": dict(end_criterion="fixed_length", fixed_length=6),
}


def _payload(p: AsciiParams, body: bytes) -> bytes:
    """A job a user program would hand over in this criterion."""
    body = bytes(b for b in body if b not in (0x03, 0x0D, 0x0A, 0x11, 0x13)) or b"A"
    if p.end_criterion == "fixed_length":
        return (body * p.fixed_length)[:p.fixed_length]
    if p.end_criterion == "end_chars" and p.send_variant == "len_with_end":
        return body + p.end_sequence
    return body


@pytest.mark.parametrize("crit", sorted(CRITERIA))
@pytest.mark.parametrize("flow", ["none", "xon_xoff"])
def test_two_stations_never_deadlock_and_end_every_job(crit, flow):
    p = AsciiParams(cdt_ms=10, flow_control=flow, xon_wait_ms=200, **CRITERIA[crit])

    @QUICK
    @given(jobs=st.lists(st.tuples(st.sampled_from("ab"), st.binary(min_size=1, max_size=40),
                                   st.floats(0, 0.2)), min_size=1, max_size=8),
           faults=st.lists(st.sampled_from([DELIVER] * 8 + [DROP, CORRUPT]), max_size=60),
           read_delay=st.sampled_from([0.0, 0.05]))
    def run(jobs, faults, read_delay):
        fates = iter(faults)
        a, b = AsciiStation(p, name="a"), AsciiStation(p, name="b")
        link = Link(a, b, hook=lambda w: next(fates, DELIVER), echo=set(),
                    host_factory=lambda st_, app: AsciiHost(st_, "none", read_delay=read_delay))
        link.power_on(0.0)
        sent = {"a": [], "b": []}
        t = 0.01
        for who, body, dt in jobs:
            t += dt
            payload = _payload(p, body)
            sent[who].append(payload)
            link.request(a if who == "a" else b, payload, at=t)
        assert link.run_until_quiet(t + 60.0), "the two stations never went quiet"
        clean = not any(f != DELIVER for f in faults)
        for st_, peer in ((a, b), (b, a)):
            done = [e.payload for e in link.events_of(st_, SendDone)]
            failed = [(e.payload, e.code) for e in link.events_of(st_, SendFailed)]
            # every job ends once: done, or aborted because the XON did not come in time
            assert len(done) + len(failed) == len(sent[st_.name])
            assert all(code == Code.XON_CTS_WAIT_EXPIRED for _, code in failed)
            assert st_.idle and st_.pending_jobs == 0
            got = [e.payload for e in link.events_of(peer, Delivered)]
            if clean and not failed:
                # a clean line: every frame arrives once, in order, as the send variant put it
                # on the line (split by the receiver's criterion)
                want = [f for j in sent[st_.name] for f in _split(p, send_bytes(j, p))]
                assert got == want
            for f in got:       # whatever the line did, a delivered frame obeys the criterion
                assert 1 <= len(f) <= 1024
                if p.end_criterion == "end_chars":
                    assert f.endswith(p.end_sequence)
                if p.end_criterion == "fixed_length":
                    assert len(f) == p.fixed_length
            if not clean:
                assert len(got) <= sum(len(_split(p, send_bytes(j, p))) for j in sent[st_.name])
        # what was discarded had a reason the manual names
        for st_ in (a, b):
            for e in link.events_of(st_, FrameDiscarded):
                assert e.reason in ("cdt_expired", "character_error", "no_room", "too_long", "buffer_full",
                                    "overwritten", "break")

    run()


def _split(p: AsciiParams, wire: bytes) -> list[bytes]:
    from ptpcert.procedures.ascii.model import split_frames
    if p.end_criterion == "cdt":
        return [wire]
    return [x.data for x in split_frames(wire, p) if x.kind == "frame"]


# ------------------------------------------------------------------ level 2: the model as oracle
PROFILES = {
    "cdt": dict(end_criterion="cdt"),
    "ec-xon": dict(end_criterion="end_chars", end_chars=[0x03], flow_control="xon_xoff", xon_wait_ms=500),
    "ec2-append-7": dict(end_criterion="end_chars", end_chars=[0x0D, 0x0A], send_variant="len_append_end",
                         data_bits=7),
    "fl-xon": dict(end_criterion="fixed_length", fixed_length=20, flow_control="xon_xoff", xon_wait_ms=500),
}


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_generated_examples_agree_with_the_model(name):
    """Every example, run against the model itself, passes: the fuzzer reports no false
    findings."""
    prof = reference_profile(**PROFILES[name])
    gen = AsciiGenerator(prof)
    runner = Runner(make_factory("sim:", prof), prof, RunOptions(check_status=False))

    @settings(QUICK, max_examples=60)
    @given(st.data())
    def check(data):
        v = gen(data).vector("FUZZ.T", "t", "fuzz example")
        r = runner.run_case(v)
        assert r.verdict == R.PASS, r.message

    check()


def test_a_broken_variant_yields_a_finding_written_as_a_vector(tmp_path):
    prof = reference_profile(end_criterion="end_chars", end_chars=[0x03], send_variant="len_append_end")
    factory = make_factory("sim:?mutant=append-end-missing", prof)
    camp = Campaign(prof, Runner(factory, prof, RunOptions(check_status=False)), 20.0, 7)
    findings = camp.run()
    assert findings, "the fuzzer did not find the missing end character"
    paths = export(findings, tmp_path)
    vectors = load_dir(tmp_path)
    assert len(vectors) == len(paths) >= 1
    v = vectors[0]
    assert v.procedure == "ascii" and v.group == "regression" and v.id.startswith("FUZZ.")
    against_mutant = Runner(make_factory("sim:?mutant=append-end-missing", prof), prof, RunOptions()).run_case(v)
    against_model = Runner(make_factory("sim:", prof), prof, RunOptions()).run_case(v)
    assert against_mutant.verdict == R.FAIL and against_model.verdict == R.PASS, against_model.message


@pytest.mark.realtime
def test_ptpcert_fuzz_with_an_ascii_profile(tmp_path):
    prof = tmp_path / "p.toml"
    prof.write_text('[iut]\nprocedure = "ASCII"\ncharacter_delay_ms = 20\nsend_trigger = "echo"\n'
                    'line_conditions = "parmrk"\nstatus_from_stderr = true\n\n[ascii]\nend_criterion = "end_chars"\n'
                    'end_chars = [0x03]\nsend_variant = "len_append_end"\n')
    out = tmp_path / "found"

    def fuzz(iut):
        return subprocess.run([PY, "-m", "ptpcert.cli", "fuzz", "--iut", iut, "--profile", str(prof), "--budget",
                               "8", "--seed", "3", "--export", str(out)], cwd=ROOT, capture_output=True, text=True,
                              timeout=300)

    p = fuzz("sim:")
    assert p.returncode == 0 and "0 finding(s)" in p.stdout, p.stdout[-2000:] + p.stderr[-2000:]
    p = fuzz("sim:?mutant=append-end-missing")
    assert p.returncode == 1 and list(out.glob("*.toml")), p.stdout[-2000:] + p.stderr[-2000:]
