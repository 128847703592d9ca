"""Seeded random line traffic against one ASCII model station (every criterion, with and
without XON/XOFF, readers fast and slow): the model must never fail, and its bookkeeping must
add up. Every intact character it received ends up in exactly one stored or discarded frame,
in order; every character of its send jobs goes on the line once, in order."""

import random

import pytest
from ascii_bench import Bench

from ptpcert.model.codes import Code
from ptpcert.procedures.ascii.model import AsciiParams, send_bytes
from ptpcert.procedures.ascii.model import events as aev

RX_CODES = {Code.CDT_EXCEEDED, Code.CHARACTER_ERROR, Code.LINE_BREAK, Code.NO_RECEIVE_BUFFER,
            Code.FRAME_TOO_LONG}
TX_CODES = {Code.XON_CTS_WAIT_EXPIRED}


def random_params(rng: random.Random) -> AsciiParams:
    crit = rng.choice(["cdt", "end_chars", "fixed_length"])
    kw = dict(end_criterion=crit, flow_control=rng.choice(["none", "xon_xoff"]),
              buffer_frames=rng.choice([1, 2, 5, 250]), xon_wait_ms=rng.choice([50, 2000]))
    if crit == "end_chars":
        kw["end_chars"] = rng.choice([(0x03,), (0x0D, 0x0A), (0x0D, 0x0D)])
        kw["send_variant"] = rng.choice(["up_to_end", "len_with_end", "len_append_end"])
    if crit == "fixed_length":
        kw["fixed_length"] = rng.choice([1, 3, 8, 300])
        kw["send_pause"] = rng.choice([True, False])
    if kw["buffer_frames"] == 1:
        kw["prevent_overwrite"] = rng.choice([True, False])
    return AsciiParams(**kw)


ALPHABET = bytes([0x03, 0x0D, 0x0A, 0x11, 0x13, 0x41, 0x42, 0x00, 0xFF])


@pytest.mark.parametrize("seed", range(60))
def test_random_traffic_keeps_the_books(seed):
    rng = random.Random(seed)
    p = random_params(rng)
    app = rng.choice(["none", "no_read", "echo"])
    b = Bench(p, app, read_delay=rng.choice([0.0, 0.0, 0.03]))
    flow = (p.xon, p.xoff) if p.flow_control == "xon_xoff" else ()
    received = bytearray()
    jobs = []
    for _ in range(rng.randint(5, 40)):
        what = rng.random()
        gap = rng.choice([0.0, 0.0005, p.cdt * 0.9, p.cdt * 1.1, 0.02])
        at = max(b.t, b.line_free) + gap
        if what < 0.6:
            data = bytes(rng.choice(ALPHABET) for _ in range(rng.randint(1, 30)))
            if rng.random() < 0.05:
                data = bytes(rng.choice(ALPHABET) for _ in range(rng.randint(900, 1100)))
            b.send(data, at=at)
            received += bytes(x for x in data if x not in flow)
        elif what < 0.7:
            b.send_bad(0x41, at=at)
        elif what < 0.75:
            b.brk(at=at)
        elif what < 0.9 and app != "echo":
            payload = bytes(rng.choice(b"ABC\x03\x0D\x0A") for _ in range(rng.randint(1, 12)))
            b.request(payload, at=max(at, b.t))
            jobs.append(payload)
        else:
            b.run(b.t + rng.choice([0.001, 0.01, 0.1]))
    b.idle(3.0)
    while b.st.frames_stored and app == "no_read":
        b.read()
        b.idle(1.0)
    for _ in range(10_000):   # let every timer run out (held echo jobs fail one by one)
        d = b.st.next_deadline()
        if d is None:
            break
        b.run(d)
    # the receive side's books
    got = bytearray()
    for e in b.events:
        if isinstance(e, aev.FrameStored):
            got += e.payload
        elif isinstance(e, aev.FrameDiscarded) and e.reason != aev.OVERWRITTEN:
            got += e.data
    assert bytes(got) == bytes(received)
    assert set(b.codes("receive")) <= RX_CODES
    assert set(b.codes("send")) <= TX_CODES
    # the send side's books: each job's characters once, in order, unless it failed
    if app != "echo":
        ok = {bytes(x) for x in b.done()}
        wire = bytes(x for x in b.wire() if x not in flow)
        expect = b"".join(send_bytes(j, p) for j in jobs if j in ok)
        if not b.failed():
            assert wire == expect
        else:
            assert len(wire) >= len(expect)
    # quiet at the end: nothing to send; a frame can only still be coming in when the
    # station holds its partner (d_hold) and nobody reads
    st = b.st
    assert st.next_deadline() is None
    assert st.idle or (st.rx_state.name == "RECEIVE" and st.holding_partner)
