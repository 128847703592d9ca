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


def _paced(t: float, data: bytes, gap: float) -> list[C.Chunk]:
    """``data`` relayed a byte per ``gap`` seconds from ``t`` (a station behind a relay that
    goes on sending what it was handed)."""
    return [_b(t + i * gap, b) for i, b in enumerate(data)]


TAIL_LIMIT = 0.023 + 4 * CHAR + 0.050   # the BREAK, four characters, the late tolerance (50 ms)


@SETTINGS
@given(gap=st.floats(0.0008, 0.0015), cut=st.integers(3, 20), tail=st.floats(0.0, 0.95))
def test_the_rest_of_a_block_relayed_after_the_break_within_the_tolerance_is_no_failure(gap, cut, tail):
    """The tester's BREAK comes while the IUT's block is relayed a byte per millisecond; the
    relay goes on with the block for up to the BREAK, four characters and the late tolerance
    (what the run grants in SUITE.BREAK.DATA), then stops: a note, not a failure."""
    chunks, t = _send_setup(0.0)
    block = _paced(t, BLOCK, gap)
    brk = block[cut].t + 0.0001
    limit = brk + tail * TAIL_LIMIT
    sent = [c for c in block if c.t <= brk or c.t - CHAR <= limit]
    assert not _fails(chunks + sent + [_a(brk)])


@SETTINGS
@given(gap=st.floats(0.0008, 0.0012), beyond=st.floats(0.003, 0.010))
def test_the_rest_of_a_block_long_after_the_break_still_fails(gap, beyond):
    """A station that goes on with its block further after the BREAK than that did not return
    to its initial state: the byte beyond the allowance is found."""
    chunks, t = _send_setup(0.0)
    long_block = codec.body(b"A" * 200, "3964R")
    block = _paced(t, long_block, gap)
    brk = block[3].t + 0.0001
    sent = [c for c in block if c.t <= brk + TAIL_LIMIT + CHAR + beyond]
    assert sent[-1].t > brk + TAIL_LIMIT + CHAR
    fails = _fails(chunks + sent + [_a(brk)])
    assert fails and fails[0].t > brk + TAIL_LIMIT


def test_a_busy_clean_link_is_told_exchange_by_exchange():
    """Two stations that exchange blocks with gaps shorter than the timing resolution (a
    monitor on a busy link, read live): rest points still come after each exchange (no
    interruption leaves a byte whose order is unknown), so the analysis tells the exchanges
    one by one while the line goes on, not all at the end, and finds nothing wrong."""
    res = 0.011
    chunks, t, n = [], 0.0, 12
    for i in range(n):
        s, r = ("a", "b") if i % 2 == 0 else ("b", "a")
        body = codec.body(b"12", "3964R")
        chunks += [C.Chunk(round(t, 6), s, bytes([STX])), C.Chunk(round(t + 2 * CHAR, 6), r, bytes([DLE])),
                   C.Chunk(round(t + (3 + len(body)) * CHAR, 6), s, body)]
        t += (4 + len(body)) * CHAR
        chunks.append(C.Chunk(round(t, 6), r, bytes([DLE])))
        t += 0.003

    class Told:
        def __init__(self):
            self.live, self.fails = 0, 0

        def exchange(self, line, e):
            self.live += not closed

        def finding(self, f):
            self.fails += f.grade == R.FAIL

    prof = load_profile(PROFILE)
    told = Told()
    line = A.LineAnalysis(PROC.analyzer(prof.params, prof.params), judge="ab", resolution=res, listener=told)
    closed = False
    for ch in chunks:
        line.feed(ch)
        line.advance(ch.t)
    closed = True
    line.close(t + 1.0)
    assert told.fails == 0
    assert told.live >= n - 3, f"only {told.live} of {n} exchanges told while the line went on"


@SETTINGS
@given(lag=st.floats(0.0002, 0.8 * RES), size=st.integers(2, 60))
def test_a_block_read_in_one_piece_just_after_the_dle_is_no_failure(lag, size):
    """A loaded harness reads the IUT's whole block in one read just after its own DLE: the
    read spread back at line pace puts the block's first bytes before the DLE they answer,
    and the ordering rule takes them after it (the resolution covers the read's lag)."""
    chunks, t = _send_setup(0.0)
    block = codec.body(b"A" * size, "3964R")
    chunks += [C.Chunk(round(t + lag, 6), "b", block), _a(t + lag + 0.0002, DLE)]
    assert not _fails(chunks)


@SETTINGS
@given(lag=st.floats(0.0001, 0.8 * RES), size=st.integers(3, 60), dle_at=st.floats(0.3, 0.8))
def test_a_block_read_in_one_piece_after_a_late_dle_is_no_failure(lag, size, dle_at):
    """The tester's DLE comes late in the IUT's ADT (SUITE.TIMING.SETUP-DLE-AT-80-ADT); the IUT
    writes its block whole and the harness reads it in one piece just after: spread back at
    the line's pace, the block's first bytes would fall before the DLE they answer by more
    than the resolution. A read is spread back no further than the other seat's last
    character; what is left to order is within the resolution."""
    stx = 0.040
    dle = stx + dle_at * ADT
    block = codec.body(b"A" * size, "3964R")
    chunks = [_b(0.001, NAK), _b(stx, STX), _a(dle, DLE), C.Chunk(round(dle + lag, 6), "b", block),
              _a(dle + lag + 0.0002, DLE)]
    assert not _fails(chunks)
