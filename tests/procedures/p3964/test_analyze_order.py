"""The ordering rule of line analysis (ptpcert.analysis.order, issue 25 item 12): characters of
the two seats stamped within the capture's timing resolution of each other may have come in
either order, so a conforming exchange whose stamps are jittered within the resolution stays
free of failures; a violation further than the resolution from what it answers still fails.

The captures are what a run against a station on a pipe records (transport pipe, 9600 bit/s,
resolution three character times and 2 ms): seat b (the IUT, switched on at the case mark)
writes a block in one piece, the harness reads it a byte at a time, each read stamped up to
the resolution after the byte was written; seat a (the tester) is stamped when it writes."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings, strategies as st

from ptpcert import analysis as A
from ptpcert import capture as C
from ptpcert import results as R
from ptpcert.procedures.p3964.model import codec
from ptpcert.profile import load_profile
from ptpcert.registry import by_name

ROOT = Path(__file__).resolve().parents[3]
PROFILE = ROOT / "conformance" / "profiles" / "reference-20ms.toml"
PROC = by_name("3964R")
STX, DLE, NAK = codec.STX, codec.DLE, codec.NAK
CHAR = 11 / 9600
RES = C.run_timing("exec:x", CHAR).resolution          # about 5.4 ms
ADT = 0.020
BLOCK = codec.body(b"A" * 24, "3964R")

SETTINGS = settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _kit():
    prof = load_profile(PROFILE)
    return PROC.analyzer(PROC.tester_params(prof.params), prof.params, apps={"a": "none", "b": "echo"})


def _fails(chunks: list[C.Chunk]) -> list[A.Finding]:
    cap = C.Capture(sorted(chunks, key=lambda c: c.t), {"a": "tester", "b": "iut"},
                    C.LineSettings(9600, 8, "even", 1), marks=[C.Mark(0.0, "case T")])
    an = A.analyze(cap, _kit(), judge="b", resolution=RES, restart_at_cases={"b"})
    return [f for f in an.findings if f.grade == R.FAIL]


def _reads(t: float, data: bytes, lags: list[float]) -> list[C.Chunk]:
    """``data`` written at ``t`` in one piece, read a byte at a time: each read stamped up to
    the resolution later, in order."""
    out, last = [], t
    for i, b in enumerate(data):
        last = max(last + 0.000017, t + lags[i % len(lags)])
        out.append(C.Chunk(round(last, 6), "b", bytes([b])))
    return out


def _b(t: float, b: int) -> C.Chunk:
    return C.Chunk(round(t, 6), "b", bytes([b]))


def _a(t: float, b: int | None = None) -> C.Chunk:
    if b is None:
        return C.Chunk(round(t, 6), "a", b"", C.Cond.BREAK, 0.023)
    return C.Chunk(round(t, 6), "a", bytes([b]))


def _send_setup(lag: float) -> tuple[list[C.Chunk], float]:
    """b switched on (its NAK), a send job (its STX), a's DLE: when b writes its block."""
    stx = 0.040 + lag              # the read of b's STX; the tester answers it
    dle = stx + 0.0002
    return [_b(0.001, NAK), _b(stx, STX), _a(dle, DLE)], dle + 0.0002


lags = st.lists(st.floats(0.0, 0.8 * RES), min_size=1, max_size=8)


@SETTINGS
@given(lags=lags, into=st.floats(0.0, 1.0), setup_lag=st.floats(0.0, 0.8 * RES))
def test_a_break_sent_once_the_block_was_whole_is_no_failure(lags, into, setup_lag):
    """The tester sends its BREAK once the IUT's block is whole in the pipe; the reads of the
    block's tail are stamped after it (SUITE.BREAK.DATA): the IUT stops, nothing fails."""
    chunks, t = _send_setup(setup_lag)
    block = _reads(t, BLOCK, lags)
    brk = t + 0.00005 + into * (block[-1].t - t - 0.0001)      # stamped among the block's reads
    assert block[-1].t - brk < RES
    assert not _fails(chunks + block + [_a(brk)])


@SETTINGS
@given(lags=lags, beyond=st.floats(0.002, 0.010))
def test_a_byte_sent_well_after_the_break_still_fails(lags, beyond):
    """A station that sends a new STX further than the resolution after the BREAK did not
    return to its initial state at once: that is still found."""
    chunks, t = _send_setup(0.0)
    block = _reads(t, BLOCK, lags)
    brk = block[-1].t - 0.0002
    late = _b(brk + RES + beyond, STX)
    assert _fails(chunks + block + [_a(brk), late])


def _retry(lags: list[float], early: float, dle_after: float) -> list[C.Chunk]:
    """b's block gets no DLE: its ADT runs out ``early`` seconds before the model's (stamped
    from the block's last read) and it sends STX again; a's DLE is stamped ``dle_after`` after
    that STX; then b's block and a's DLE."""
    chunks, t = _send_setup(0.0)
    block = _reads(t, BLOCK, lags)
    stx = block[-1].t + ADT - early
    dle = stx + dle_after
    again = _reads(dle + 0.0002, BLOCK, lags)
    return chunks + block + [_b(stx, STX), _a(dle, DLE)] + again + [_a(again[-1].t + CHAR + 0.0003, DLE)]


@SETTINGS
@given(lags=lags, early=st.floats(0.0, 0.9 * RES), dle_after=st.floats(0.0001, 0.002))
def test_a_retry_whose_timer_ran_from_the_blocks_write_is_no_failure(lags, early, dle_after):
    """The IUT's ADT runs from when it wrote its block, up to the resolution before the
    block's last read; the tester's DLE answers the repeated STX (stamped just after it), and
    is not taken as arriving before it (SUITE.RELEASE.ATTEMPTS-MIXED, ATTEMPTS-TIMEOUT)."""
    assert not _fails(_retry(lags, early, dle_after))


@SETTINGS
@given(lags=lags, beyond=st.floats(0.003, 0.008))
def test_a_retry_well_before_its_timer_still_fails(lags, beyond):
    """A repeated STX further before ADT than a timer's tolerance and the resolution allow,
    and further from the tester's DLE than the resolution (with the DLE just after it, the
    order is not known: the DLE may have acknowledged the first block, and the STX begun a
    new job with the same data - a conforming reading the analysis must accept)."""
    early = CHAR + ADT / 20 + RES + beyond
    assert _fails(_retry(lags, early, RES + 0.002))
