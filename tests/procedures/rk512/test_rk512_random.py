"""Random partners against an RK 512 station, in virtual time: frames mutated from valid
ones (one header byte, a length, a cut, an extension) sent by a bare 3964R tester, while the
station runs requests of its own. Invariants (R5.1, R5.11, R8.2): the station never fails,
answers every command frame exactly once and no response, never has two commands of its own
unanswered, and moves no data for a frame it refused."""

import random

import pytest
from rk512_helpers import delivered, of, with_tester
from rk512_rules import continuation, header, response

from ptpcert.procedures.rk512.model.events import FrameNotSent, FrameReceived, FrameSent, RequestResult, Served

VALID = [
    header("A", "D", 10, 0, 2) + bytes(4),
    header("A", "D", 10, 0, 100) + bytes(128),
    header("O", "D", 5, 3, 1) + b"\x10\x10",
    header("E", "D", 10, 0, 3),
    header("E", "M", 0, 4, 7),
    header("E", "Z", 0, 1, 70),
    continuation("A", "D", bytes(72)),
    continuation("E", "Z"),
    response(0),
    response(0x34, first=False),
]
REQUESTS = ["send DB20:DW0:LEN=200", "fetch E:0:LEN=6", "fetch T:0:LEN=140", "send DX3:DW1:LEN=3"]


def mutate(rnd: random.Random, frame: bytes) -> bytes:
    f = bytearray(frame)
    k = rnd.randrange(6)
    if k == 0 and f:
        f[rnd.randrange(min(len(f), 10))] = rnd.choice([0x00, 0x01, 0x10, 0x41, 0x43, 0x45, 0x4F, 0x58, 0xFF,
                                                         rnd.randrange(256)])
    elif k == 1 and len(f) >= 10:
        f[9] = rnd.randrange(256)
    elif k == 2 and f:
        del f[rnd.randrange(len(f)):]
    elif k == 3:
        f += bytes(rnd.randrange(1, 4))
    return bytes(f)


@pytest.mark.parametrize("seed", range(40))
def test_random_partner(seed):
    rnd = random.Random(seed)
    link, a, t = with_tester(tester_prio=rnd.choice(["low", "high"]), response_time_ms=2000)
    for _ in range(12):
        if rnd.random() < 0.3:
            a.request(link.now, rnd.choice(REQUESTS))
        frame = mutate(rnd, rnd.choice(VALID)) if rnd.random() < 0.7 else rnd.choice(VALID)
        if frame:
            link.request(t, frame)
        link.run_until(link.now + rnd.choice([0.0, 0.01, 0.05, 0.3, 2.5]))
    assert link.run_until_quiet(link.now + 300)
    assert a.idle
    got = [e.frame for e in of(link, a, FrameReceived)]
    handed = [e.frame for e in of(link, a, FrameSent)] + [e.frame for e in of(link, a, FrameNotSent)]
    answers = [f for f in handed if f[2] == 0]
    commands = sum(1 for f in got if len(f) >= 3 and f[2] != 0)
    shorts = sum(1 for f in got if len(f) < 3)      # a command, or a response if one was awaited
    # every command answered exactly once, no response answered (R5.1, R5.11)
    assert commands <= len(answers) <= commands + shorts
    # depth 1: after a command of ours, its answer (or the end of its request) comes before
    # the next one (R8.2)
    waiting = False
    for n, e in link.events:
        if n != "a":
            continue
        if isinstance(e, FrameSent) and e.frame[2] != 0:
            assert not waiting, "a second command before the answer to the first"
            waiting = True
        elif (isinstance(e, FrameReceived) and len(e.frame) >= 3 and e.frame[2] == 0) or isinstance(e, RequestResult):
            waiting = False
    # data moved only for commands answered with REATEL 00 (sent or given up by the link)
    assert len(of(link, a, Served)) <= sum(1 for f in answers if f[3] == 0)
    assert len(delivered(link, t)) == len(of(link, a, FrameSent))


# -- two model stations, requests on both sides, a clean or a noisy line ----------------------------
from rk512_helpers import codes, pair  # noqa: E402

from ptpcert.model.link import CORRUPT, DELIVER, DROP, DUPLICATE  # noqa: E402

BOTH = ["send DB20:DW0:LEN=300", "fetch E:0:LEN=6", "fetch T:0:LEN=140", "send DX3:DW1:LEN=3",
        "send DB5:DW0:LEN=1", "fetch DB9:DW100:LEN=130", "send DB0:DW0:LEN=2", "fetch Z:0:LEN=1024"]


@pytest.mark.parametrize("seed", range(30))
def test_two_stations_random_requests(seed):
    rnd = random.Random(seed)
    p_err = [0, 0.002, 0.01][seed % 3]
    link, a, b = pair(baud=rnd.choice([None, 9600]), response_time_ms=3000, db_bytes=1024)
    link.hook = lambda w: rnd.choice([DROP, CORRUPT, DUPLICATE]) if rnd.random() < p_err else DELIVER
    asked = {"a": 0, "b": 0}
    for _ in range(8):
        st = rnd.choice([a, b])
        st.request(link.now, rnd.choice(BOTH))
        asked[st.name] += 1
        link.run_until(link.now + rnd.choice([0.0, 0.01, 0.1, 0.5]))
    assert link.run_until_quiet(link.now + 2000)
    assert a.idle and b.idle
    for st in (a, b):
        link.events.extend((st.name, e) for e in st.pop_events())
        rs = of(link, st, RequestResult)
        assert len(rs) == asked[st.name]                 # every request ends, once
        if p_err == 0:
            # a clean line: only the requests the rules refuse fail (DB 0 locally; 1024 bytes of
            # counters beyond the 512 of the area), and no sequence error ever shows
            assert all(r.ok or r.code in (0x0514, 0x090C) for r in rs)
            assert not set(codes(link, st)) & {0x060E, 0x0A01, 0x0A05, 0x0612, 0x051A}
