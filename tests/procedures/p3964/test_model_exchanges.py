"""Two model stations wired together in virtual time, through every retry and conflict path
(§2.2.2; Figs. 2-9 to 2-12). Each test names the rule it checks."""

import pytest

from ptpcert.model.codes import Code
from ptpcert.model.events import Delivered, SendDone, SendFailed, Status
from ptpcert.model.hexbytes import parse_hex
from ptpcert.model.link import CORRUPT, DELIVER, DROP, Link
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model.codec import DLE, NAK, STX
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964

P1 = parse_hex("31 10 32 15 03")
P2 = parse_hex("41 42 10")


def pair(proc="3964R", a_prio="low", b_prio="high", hook=None, **kw):
    a = Station3964(Params3964(procedure=proc, priority=a_prio, **kw), name="a")
    b = Station3964(Params3964(procedure=proc, priority=b_prio, **kw), name="b")
    link = Link(a, b, hook=hook)
    link.power_on(0.0)
    link.run_until(0.05)
    link.events.clear()
    link.wire.clear()
    return link, a, b


def codes(link, st, side=None):
    return [e.code for e in link.events_of(st, Status) if side is None or e.side == side]


def bytes_from(link, name):
    return bytes(w.byte for w in link.wire if w.src == name)


@pytest.mark.parametrize("proc", ["3964", "3964R"])
@pytest.mark.parametrize("payload", [P1, P2, b"\x10", b"\x10" * 7, bytes(range(256)) * 4])
def test_block_exchange(proc, payload):
    link, a, b = pair(proc)
    link.request(a, payload)
    assert link.run_until_quiet(60)
    assert [e.payload for e in link.events_of(b, Delivered)] == [payload]
    assert [e.payload for e in link.events_of(a, SendDone)] == [payload]
    assert bytes_from(link, "a") == codec.frame(payload, proc)
    assert bytes_from(link, "b") == bytes([DLE, DLE])
    assert codes(link, a) == codes(link, b) == []


def test_startup_nak_is_ignored_by_idle_partner():
    # §6: one NAK at start-up; §8.1 item 2: NAK in idle is ignored
    a = Station3964(name="a")
    b = Station3964(name="b")
    link = Link(a, b)
    link.power_on(0.0, b_at=1.0)
    assert link.run_until_quiet(10)
    assert [(w.src, w.byte) for w in link.wire] == [("a", NAK), ("b", NAK)]
    assert link.events == []


def test_fig_2_8_initialization_conflict():
    # §9 / Fig. 2-8: low-priority a defers, acknowledges b's STX, receives, then retries
    link, a, b = pair()
    link.request(a, P1, at=0.1)
    link.request(b, P2, at=0.1)
    assert link.run_until_quiet(30)
    assert link.transcript() == [
        ("a", b"\x02"), ("b", b"\x02"), ("a", b"\x10"),
        ("b", parse_hex("41 42 10 10 10 03 10")), ("a", b"\x10\x02"), ("b", b"\x10"),
        ("a", parse_hex("31 10 10 32 15 03 10 03 06")), ("b", b"\x10")]
    assert [e.payload for e in link.events_of(a, Delivered)] == [P2]
    assert [e.payload for e in link.events_of(b, Delivered)] == [P1]
    assert codes(link, a) == codes(link, b) == []


@pytest.mark.parametrize("offset_chars", [0, 1, 5, 50])
def test_conflict_at_offsets_inside_adt(offset_chars):
    # the partner's STX arrives at several offsets inside the low station's ADT
    link, a, b = pair()
    link.request(a, P1, at=0.1)
    link.request(b, P2, at=0.1 + offset_chars * a.params.char_time)
    assert link.run_until_quiet(30)
    assert [e.payload for e in link.events_of(a, Delivered)] == [P2]
    assert [e.payload for e in link.events_of(b, Delivered)] == [P1]


def test_conflict_resumes_as_second_setup_attempt():
    # A21: the collided STX counts as attempt 1; with setup_attempts=2 the deferred job
    # gets exactly one more STX, which the partner refuses: final NAK, 16#0709
    link, a, b = pair(setup_attempts=2)
    b.set_buffer_free(link.now, False)  # b will refuse a's deferred STX (NAK after 400 ms)
    link.request(a, P1, at=0.1)
    link.request(b, P2, at=0.1)
    assert link.run_until_quiet(30)
    assert [e.payload for e in link.events_of(a, Delivered)] == [P2]
    assert bytes_from(link, "a").count(STX) == 2
    assert bytes_from(link, "a").endswith(b"\x02\x15")
    assert codes(link, a) == [Code.SETUP_REFUSED, Code.SETUP_ATTEMPTS_EXCEEDED]


def test_setup_timeout_exhausts_setup_attempts():
    # §7.1: N STX at ADT spacing, then NAK; 16#0703 each time, 16#0709 at the end
    link, a, b = pair(hook=lambda w: DROP if w.src == "a" else DELIVER, setup_attempts=4)
    link.request(a, P1, at=0.1)
    assert link.run_until_quiet(60)
    assert bytes_from(link, "a") == b"\x02" * 4 + b"\x15"
    starts = [w.start for w in link.wire if w.byte == STX]
    gaps = [t2 - t1 for t1, t2 in zip(starts, starts[1:])]
    adt, char = a.params.adt, a.params.char_time
    assert all(abs(g - (adt + 2 * char)) < 1e-9 for g in gaps)  # STX end + ADT + 1 char grace
    assert codes(link, a) == [Code.SETUP_TIMEOUT] * 4 + [Code.SETUP_ATTEMPTS_EXCEEDED]
    assert isinstance(link.events_of(a)[-1], SendFailed)


def test_setup_refused_when_partner_has_no_buffer():
    # §8.2 item 2: no free buffer -> NAK after T_NAKTIM (16#080A); sender: 16#0702 per
    # attempt, 16#0709 after the last
    link, a, b = pair(setup_attempts=3)
    b.set_buffer_free(link.now, False)
    link.request(a, P1, at=0.1)
    assert link.run_until_quiet(60)
    assert bytes_from(link, "a") == b"\x02\x02\x02\x15"
    assert bytes_from(link, "b") == b"\x15\x15\x15"
    assert codes(link, a) == [Code.SETUP_REFUSED] * 3 + [Code.SETUP_ATTEMPTS_EXCEEDED]
    assert codes(link, b) == [Code.NO_RECEIVE_BUFFER] * 3
    naks = [w.start for w in link.wire if w.src == "b"]
    stxs = [w.start for w in link.wire if w.src == "a" and w.byte == STX]
    assert naks[0] - stxs[0] == pytest.approx(0.4 + a.params.char_time)


def test_buffer_freed_during_naktim():
    link, a, b = pair()
    b.set_buffer_free(link.now, False)
    link.request(a, P1, at=0.1)
    link.run_until(0.3)
    b.set_buffer_free(0.3, True)
    assert link.run_until_quiet(10)
    assert [e.payload for e in link.events_of(b, Delivered)] == [P1]


def corrupt_nth(byte_value, src, which):
    """Corrupt the which-th (set of indices) occurrence of ``byte_value`` sent by ``src``."""
    seen = {"n": 0}

    def hook(w):
        if w.src == src and w.byte == byte_value:
            seen["n"] += 1
            if seen["n"] in which:
                return CORRUPT
        return DELIVER
    return hook


def test_repetition_after_bad_block():
    # Fig. 2-7: a corrupted data byte; the receiver NAKs after the BCC (not at the byte),
    # reports 16#080C and 16#0801; the sender reports 16#0706 and 16#0701 and repeats
    link, a, b = pair(hook=corrupt_nth(0x32, "a", {1}))
    link.request(a, P1, at=0.1)
    assert link.run_until_quiet(30)
    t = link.transcript()
    assert t[:4] == [("a", b"\x02"), ("b", b"\x10"), ("a", codec.body(P1, "3964R")), ("b", b"\x15")]
    assert t[4:] == [("a", b"\x02"), ("b", b"\x10"), ("a", codec.body(P1, "3964R")), ("b", b"\x10")]
    assert codes(link, b) == [Code.CHARACTER_ERROR, Code.EXPECT_REPETITION]
    assert codes(link, a) == [Code.RELEASE_REFUSED, Code.FIRST_REPETITION]
    assert [e.payload for e in link.events_of(b, Delivered)] == [P1]


def test_transmission_attempts_exhausted():
    # §7.4/7.5: N complete blocks all refused, then the sender's NAK and 16#070A
    link, a, b = pair(hook=corrupt_nth(0x32, "a", set(range(1, 100))), transmission_attempts=3)
    link.request(a, P1, at=0.1)
    assert link.run_until_quiet(60)
    assert bytes_from(link, "a") == (codec.frame(P1, "3964R") * 3) + b"\x15"
    assert codes(link, a) == [Code.RELEASE_REFUSED, Code.FIRST_REPETITION, Code.RELEASE_REFUSED,
                              Code.RELEASE_REFUSED, Code.TX_ATTEMPTS_EXCEEDED]
    # the receiver gives up after its own N receptions (A18): final report of the first error
    assert codes(link, b) == [Code.CHARACTER_ERROR, Code.EXPECT_REPETITION, Code.CHARACTER_ERROR,
                              Code.CHARACTER_ERROR, Code.CHARACTER_ERROR]
    assert b.state == "IDLE"


def test_release_timeout_then_duplicate_delivery():
    # §7.3: no DLE within ADT after the block (16#0707): the sender repeats; the receiver,
    # which had accepted the first copy, accepts the repetition too (a known limit, §4.4)
    link, a, b = pair(hook=corrupt_nth(DLE, "b", {2}))
    link.request(a, P1, at=0.1)
    assert link.run_until_quiet(30)
    assert codes(link, a)[:2] == [Code.CHARACTER_ERROR, Code.FIRST_REPETITION]
    count = {"b": 0}

    def drop_first_final_dle(w):
        if w.src == "b":
            count["b"] += 1
            if count["b"] == 3:  # start-up NAK, setup DLE, release DLE: drop the last
                return DROP
        return DELIVER
    link2, a2, b2 = pair(hook=drop_first_final_dle)
    link2.request(a2, P1, at=0.1)
    assert link2.run_until_quiet(30)
    assert codes(link2, a2) == [Code.RELEASE_TIMEOUT, Code.FIRST_REPETITION]
    assert [e.payload for e in link2.events_of(b2, Delivered)] == [P1, P1]


def test_character_delay_timeout_in_receiver():
    # §8.3 item 5: a gap longer than CDT inside the block -> NAK after CDT, 16#0806
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.receive(0.1, STX)
    a.pop_output()
    a.receive(0.11, parse_hex("31 32"))
    t = a.next_deadline()
    assert t == pytest.approx(0.11 + 0.22 + a.params.char_time)
    a.handle_timer(t)
    assert [b for _, b in a.pop_output()] == [NAK]
    assert [e.code for e in a.pop_events()] == [Code.CDT_EXCEEDED, Code.EXPECT_REPETITION]
    assert a.state == "WAIT_REPETITION"


def test_first_character_after_dle_timeout():
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.receive(0.1, STX)
    (start, dle), = a.pop_output()
    assert dle == DLE
    a.handle_timer(a.next_deadline())
    assert a.pop_output()[0][0] == pytest.approx(start + a.params.char_time + 0.22 + a.params.char_time)


def test_dle_followed_by_other_nak_deferred_to_end():
    # §8.3 item 3 / A11 (D8): 16#0805, NAK only after the BCC
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.receive(0.1, STX)
    a.pop_output()
    a.receive(0.11, parse_hex("31 10 41 32 10 03"))
    assert a.pop_output() == []
    a.receive(0.12, 0x41)
    assert [b for _, b in a.pop_output()] == [NAK]
    assert [e.code for e in a.pop_events()] == [Code.RX_LOGICAL_ERROR, Code.EXPECT_REPETITION]


def test_idle_garbage_nak_after_quiet_cdt_retriggered():
    # §8.1 item 3 and A7: a burst of stray bytes gets one NAK once the line is quiet for CDT
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.receive(1.0, 0x41)
    a.receive(1.1, 0x42)
    a.receive(1.2, 0x43)
    t = a.next_deadline()
    assert t == pytest.approx(1.2 + 0.22 + a.params.char_time)
    a.handle_timer(t)
    assert [b for _, b in a.pop_output()] == [NAK]
    assert [e.code for e in a.pop_events()] == [Code.RX_SETUP_ERROR]


def test_max_block_length():
    # §8.3 item 6, A17: 1024 bytes accepted, 1025 refused with NAK at the end (16#0816)
    for n, ok in [(1024, True), (1025, False)]:
        a = Station3964(Params3964(), name="a")
        a.power_on(0.0)
        a.receive(0.1, STX)
        a.pop_output()
        a.receive(0.2, codec.body(bytes([0x41]) * n, "3964R"))
        assert [b for _, b in a.pop_output()] == [DLE if ok else NAK]
        evs = a.pop_events()
        if ok:
            assert isinstance(evs[0], Delivered) and len(evs[0].payload) == 1024
        else:
            assert [e.code for e in evs] == [Code.FRAME_TOO_LONG, Code.EXPECT_REPETITION]


def test_3964_receiver_acknowledges_at_etx():
    # Table 2-3: 3964 stops at DLE ETX
    a = Station3964(Params3964(procedure="3964"), name="a")
    a.power_on(0.0)
    a.receive(0.1, STX)
    a.pop_output()
    a.receive(0.2, parse_hex("31 10 10 10 03"))
    assert [b for _, b in a.pop_output()] == [DLE]
    assert a.pop_events()[0].payload == b"\x31\x10"


def test_nak_during_data_phase_sender_stops_and_restarts_without_nak():
    # §7.2 item 3 (D14): stop, no NAK of its own, new STX; 16#0704 then 16#0701
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    payload = bytes(range(0x40, 0x80))
    a.request_send(0.1, payload)
    a.pop_output()
    a.receive(0.11, DLE)
    char = a.params.char_time
    t = 0.11 + 10.5 * char
    a.handle_timer(t)
    sent = a.pop_output(t)
    assert len(sent) == 11
    a.receive(t, NAK)
    rest = a.pop_output()
    assert [b for _, b in rest] == [STX]
    assert [e.code for e in a.pop_events()] == [Code.SEND_INTERRUPTED, Code.FIRST_REPETITION]


def test_other_character_during_data_phase():
    # §7.2 item 4 (D15): stop, quiet for CDT, NAK, then a new STX
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.request_send(0.1, bytes(range(0x40, 0x80)))
    a.pop_output()
    a.receive(0.11, DLE)
    t = 0.11 + 10.5 * a.params.char_time
    a.handle_timer(t)
    a.pop_output(t)
    a.receive(t, 0x41)
    assert a.pop_output(t + 0.1) == []
    a.receive(t + 0.1, 0x42)  # restarts the quiet wait (A7)
    d = a.next_deadline()
    assert d == pytest.approx(t + 0.1 + 0.22 + a.params.char_time)
    a.handle_timer(d)
    assert [b for _, b in a.pop_output()] == [NAK, STX]
    assert [e.code for e in a.pop_events()] == [Code.SEND_INTERRUPTED, Code.FIRST_REPETITION]


def test_dle_too_early_during_bcc():
    # A10 (D18): a DLE that arrives while the BCC is still being sent -> 16#0706, retry
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.request_send(0.1, P1)
    a.pop_output()
    a.receive(0.11, DLE)
    out = a.pop_output()
    bcc_start = out[-1][0]
    a.receive(bcc_start + a.params.char_time / 2, DLE)
    assert [e.code for e in a.pop_events()] == [Code.RELEASE_REFUSED, Code.FIRST_REPETITION]
    assert [b for _, b in a.pop_output()] == [STX]


@pytest.mark.parametrize("where", ["idle", "setup", "data", "release", "receive", "repetition", "junk"])
def test_break_returns_to_idle_without_nak(where):
    # §10 item 5: BREAK from every state: idle, no NAK, no retry, 16#080D; a new block works
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    t = 0.1
    if where in ("setup", "data", "release"):
        a.request_send(t, P1)
        if where != "setup":
            a.receive(t + 0.01, DLE)
        if where == "release":
            a.handle_timer(a._tx_done_at)
            assert a.state == "WAIT_RELEASE_ACK"
    elif where == "receive":
        a.receive(t, STX)
        a.receive(t + 0.01, parse_hex("31 32"))
    elif where == "repetition":
        a.receive(t, STX)
        a.receive(t + 0.01, parse_hex("31 10 03 00"))
        assert a.state == "WAIT_REPETITION"
    elif where == "junk":
        a.receive(t, 0x41)
    t = max(a.now, t) + 0.02
    before = len(a.pop_output(t))
    a.pop_events()
    a.line_break(t)
    assert a.state == "IDLE" and a.job is None
    assert a.pop_output() == []  # nothing more: no NAK, no retry
    codes_ = [e.code for e in a.pop_events() if isinstance(e, Status)]
    assert codes_ and set(codes_) == {Code.LINE_BREAK}
    a.receive(t + 1, STX)
    assert [b for _, b in a.pop_output()] == [DLE]
    assert before >= 0


def test_high_priority_ignores_partner_stx_and_keeps_adt():
    # §9 item 4, A23: no DLE, no NAK; T_ADT not restarted
    a = Station3964(Params3964(priority="high"), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.request_send(0.1, P1)
    a.pop_output()
    d = a.next_deadline()
    a.receive(0.2, STX)
    assert a.pop_output() == [] and a.next_deadline() == d and a.state == "WAIT_SETUP_ACK"
    a.receive(0.3, DLE)
    assert bytes(b for _, b in a.pop_output()) == codec.body(P1, "3964R")


def test_release_refused_by_stx_is_not_a_conflict():
    # §9 item 6: STX while waiting for the release DLE is a release failure (16#0706)
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.request_send(0.1, P1)
    a.receive(0.11, DLE)
    a.handle_timer(a._tx_done_at)
    a.pop_output()
    a.receive(a.now + 0.01, STX)
    assert [e.code for e in a.pop_events()] == [Code.RELEASE_REFUSED, Code.FIRST_REPETITION]
    assert [b for _, b in a.pop_output()] == [STX]


def test_send_request_validation():
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    assert not a.request_send(0.1, b"")
    assert not a.request_send(0.1, bytes(1025))
    assert [e.code for e in a.pop_events() if isinstance(e, Status)] == [Code.LEN_ILLEGAL] * 2


def test_jobs_queue_until_idle():
    # §8.1 item 6: a job raised during a reception waits for idle, then goes out at once
    a = Station3964(Params3964(), name="a")
    a.power_on(0.0)
    a.pop_output()
    a.receive(0.1, STX)
    a.request_send(0.105, P2)
    a.receive(0.11, codec.body(P1, "3964R"))
    assert [b for _, b in a.pop_output()] == [DLE, DLE, STX]


# ------------------------------------------------------------------ runs carried at once
def _scripted(streams: bool, script, baud, proc, hook_while_faults: bool = False):
    """Run ``script`` (a list of actions) on a fresh pair; with ``streams`` False the link
    carries every character as an event of its own; with ``hook_while_faults`` the hook is
    attached only while a fault is pending (as the level-1 fuzzer does). Returns everything
    observable."""
    faults: list[str] = []
    seen: list[tuple] = []

    def hook(w):
        seen.append((round(w.start, 9), w.src, w.byte))
        fate = faults.pop(0) if faults and w.byte not in (STX,) else DELIVER
        if hook_while_faults and not faults:
            link.hook = None
        return fate

    a = Station3964(Params3964(procedure=proc, priority="low", baud_rate=baud, cdt_ms=20, adt_ms=200), name="a")
    b = Station3964(Params3964(procedure=proc, priority="high", baud_rate=baud, cdt_ms=20, adt_ms=200), name="b")
    link = Link(a, b, hook=None if hook_while_faults else hook, echo={"b"})
    link._streams = link._group_instant = streams
    link.power_on(0.0)
    for what, arg in script:
        if what == "request":
            link.request(a if arg[0] == "a" else b, arg[1])
        elif what == "run":
            link.run_until(link.now + arg)
        elif what == "fault":
            faults.append(arg)
            link.hook = hook
        elif what == "break":
            link.inject_break(b, at=link.now)
    link.run_until_quiet(link.now + 30.0)
    length = link.wire_length       # counted before the wire is built from its runs
    assert length == len(link.wire)
    return (seen, [(round(w.start, 9), w.src, w.byte, w.fate) for w in link.wire],
            [(n, type(e).__name__, round(e.time, 9), getattr(e, "code", getattr(e, "payload", None)))
             for n, e in link.events],
            (a.state, b.state, round(link.now, 9)))


def test_runs_carried_at_once_change_nothing():
    """A block's data towards a receiver that only stores it is handed over in one call
    (Link._stream, Station3964.quiet_run/receive_run): the wire, the hook's view, every
    event and its time are those of the link that carries each character as an event of
    its own, also when a run is cut by ``run_until``, a fault, a BREAK or a DLE. With no
    line timing the characters of an instant go over as one "bytes" event (Link._collect),
    with a hook too."""
    import random
    rnd = random.Random(3964)
    for trial in range(120):
        # the last trials with dense control characters: DLE pairs in runs, lone DLEs
        dense = 0.05 if trial < 80 else 0.4
        proc = rnd.choice(["3964", "3964R"])
        baud = rnd.choice([9600, 19200, 2400, None])
        script = []
        for _ in range(rnd.randint(1, 6)):
            kind = rnd.random()
            if kind < 0.45:
                size = rnd.choice([1, 5, 64, 300, 1024])
                data = bytes(rnd.choice([0x10, 0x02, 0x03, 0x15]) if rnd.random() < dense else rnd.randrange(256)
                             for _ in range(size))
                script.append(("request", (rnd.choice("ab"), data)))
            elif kind < 0.75:
                script.append(("run", rnd.choice([0.0005, 0.003, 0.02, 0.1, 0.5])))
            elif kind < 0.95:
                script.append(("fault", rnd.choice([DROP, CORRUPT, "duplicate"])))
            else:
                script.append(("break", None))
        slow, fast = _scripted(False, script, baud, proc), _scripted(True, script, baud, proc)
        assert fast == slow, (trial, script)
        # the wire (built from runs) is every character the hook saw, in the same order
        assert [w[:3] for w in fast[1]] == fast[0]
        # a hook that leaves every character alone is no hook: attached only while a fault
        # is pending, it sees fewer characters, and the wire and the events are the same
        detached = _scripted(True, script, baud, proc, hook_while_faults=True)
        assert detached[1:] == fast[1:], (trial, script)
        assert set(detached[0]) <= set(fast[0])


def test_a_long_block_at_9600_is_carried_in_few_steps():
    """The point of carrying runs at once: a 1024-byte block at 9600 baud takes a handful
    of the link's instants, not one per character."""
    link, a, b = pair(baud_rate=9600)
    calls = []
    orig = b.receive_run
    b.receive_run = lambda now, data, spacing: (calls.append(len(data)), orig(now, data, spacing))
    payload = bytes(range(1, 256)) * 4
    link.request(a, payload[:1024].replace(b"\x10", b"\x11"))
    assert link.run_until_quiet(60)
    assert [e.payload for e in link.events_of(b, Delivered)] == [payload[:1024].replace(b"\x10", b"\x11")]
    assert sum(calls) >= 1000 and len(calls) <= 10
    # the same with the DLEs left in: each is sent doubled and the pair is taken with the run
    calls.clear()
    link.request(a, payload[:1024])
    assert link.run_until_quiet(120)
    assert [e.payload for e in link.events_of(b, Delivered)][-1] == payload[:1024]
    assert sum(calls) >= 1000 and len(calls) <= 10
    # a block of nothing but DLE (2048 characters of data on the line) too
    calls.clear()
    link.request(a, bytes([DLE]) * 1024)
    assert link.run_until_quiet(180)
    assert [e.payload for e in link.events_of(b, Delivered)][-1] == bytes([DLE]) * 1024
    assert sum(calls) >= 2000 and len(calls) <= 10
