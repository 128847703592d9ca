"""Fuzzer level 1: two model stations wired together in virtual time, driven by hypothesis
through a program of steps (requests on either side or both at once, delivering bytes,
dropping / corrupting / duplicating a byte in flight, time steps biased to just under and
just over CDT, ADT, 400 ms and 4 s, BREAK, waiting for quiet), with the protocol's
invariants checked after every step:

* attempts never exceed the parameters (setup and transmission counters);
* after an initialization conflict exactly one side sends: never both in the data phase;
* no deadlock: once the longest chain of timers has run out, both are idle;
* every requested block is delivered exactly once and unchanged, or its failure is
  reported with a STATUS code the situation allows; with faults on the line a block may
  arrive twice (a lost final DLE) or altered in a way the BCC cannot see (§2.2.1 Limits of 3964R).
  One disturbance needs no fault: a station's final NAK that crosses the partner's STX
  (see ``disturbed``), which the procedure itself cannot tell from a refusal.

How an example is drawn (``scenarios``): the stations' settings, the set of step kinds the
example may use (swarm testing, as hypothesis's state machines do it: an example without
faults holds the clean-line checks, one without settles keeps the line busy), and a fixed
number of steps (the settings profile's ``stateful_step_count``), each decoded from seven
raw bytes. Hypothesis's own bookkeeping of every choice costs far more than the model's
exchange, so an example is a handful of choices rather than hundreds: about three times the
examples per second of the rule-based state machine this replaced, with the same checks
after every step (benchmarks/bench_model.py). A failure shrinks as bytes do: steps become
no-ops (first byte 00) and leave the printed program, kinds and arguments go toward the
simplest, payloads toward one byte.

Settings: the "ptpcert-quick" profile (extends hypothesis's "ci" profile) unless
--hypothesis-profile says otherwise (see tests/conftest.py).
"""

import random
import sys
from bisect import bisect_right
from collections import Counter

import pytest
from hypothesis import given, note, settings
from hypothesis import seed as fixed_seed
from hypothesis import strategies as st

from ptpcert.model.events import Delivered, SendDone, SendFailed, Status
from ptpcert.model.link import CORRUPT, DELIVER, DROP, DUPLICATE, Link
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.params import T_BLOCK, T_NAKTIM, Params3964
from ptpcert.procedures.p3964.model.station import Station3964

CONTROL = [0x10, 0x02, 0x03, 0x15, 0x00]

# for a pick byte s: the control character it puts in place of the value (s >= 128), and
# whether it does (a mask byte FF)
_PICK_CONTROL = bytes(CONTROL[s % len(CONTROL)] if s >= 128 else 0 for s in range(256))
_PICK_MASK = bytes(0xFF if s >= 128 else 0 for s in range(256))


def _picked(raw: bytes) -> bytes:
    """The payload that ``raw`` (pick, value, pick, value, ...) stands for: byte i is
    CONTROL[pick % 5] where the i-th pick is >= 128 (about half the bytes, the DLE-rich
    bias), and the i-th value (any of 0-255) otherwise. A trailing odd byte is not used."""
    picks, values = raw[0::2][:len(raw) // 2], raw[1::2]
    v = int.from_bytes(values, "big")
    mask = int.from_bytes(picks.translate(_PICK_MASK), "big")
    control = int.from_bytes(picks.translate(_PICK_CONTROL), "big")
    return (((v | mask) ^ mask) | control).to_bytes(len(values), "big")


def _long_payload(size: int, seed: int) -> bytes:
    """``size`` bytes, about half of them control characters and the rest any value, as
    ``_picked`` makes them, from a seeded generator."""
    return _picked(random.Random(seed).randbytes(2 * size))


def _payload(size_pick: int, seed_hi: int, seed_lo: int) -> bytes:
    """A payload from three raw bytes: a quarter of them blocks of 1000 to 1024 bytes
    (size_pick % 4 == 3), the others 1 to 24 bytes; its bytes from a seeded generator as
    ``_picked`` makes them. A payload shrinks by its size and seed (toward one byte), not
    byte by byte."""
    seed = seed_hi << 8 | seed_lo
    if size_pick % 4 == 3:
        return _long_payload(1000 + seed_hi % 25, seed)
    return _long_payload(1 + size_pick // 4 % 24, seed)


ALLOWED_FAILURES = {0x0709, 0x070A, 0x080D}


class TwoStations:
    # setup attempts >= 2: with one attempt, our reading of A21 (the collided STX counts as
    # attempt 1) makes a low-priority station give up its job after any conflict, a
    # legitimate 16#0709 that the manual's test advice says not to test (docs/readings.md, A21).
    # With more attempts it still happens after that many conflicts in a row (see starved).
    def start(self, procedure, a_high, setup, tx, baud):
        common = dict(procedure=procedure, setup_attempts=setup, transmission_attempts=tx, baud_rate=baud,
                      cdt_ms=220, adt_ms=550 if procedure == "3964" else 2000)
        self.p = Params3964(priority="high" if a_high else "low", **common)
        self.a = Station3964(self.p, name="a")
        self.b = Station3964(self.p.with_(priority="low" if a_high else "high"), name="b")
        self.faults: list[tuple[str, str]] = []
        self.faulted = False       # a byte was dropped, corrupted or duplicated, or a BREAK sent
        # a fault or a BREAK since both stations were last idle (one_sender_at_a_time)
        self.unsettled = False
        self.requests = {"a": [], "b": []}
        # the hook is attached only while a fault is pending (fault, _hook): without one it
        # would leave every character alone, which is what the link does with no hook
        self.link = Link(self.a, self.b)
        # STX and NAK start times per (side, byte), and how many runs of the wire they cover (starts)
        self._starts = {(side, c): [] for side in "ab" for c in (0x02, 0x15)}
        self._scanned = 0
        self._passed = None        # check_outcomes: what the last check that passed looked at
        # check_outcomes: job results and deliveries per side, from the first _events_seen events
        self._done, self._delivered, self._events_seen = {"a": [], "b": []}, {"a": [], "b": []}, 0
        # crossing(): per question, how many characters of each side it has looked at, and
        # which characters of the asking side have crossed
        self._crossings: dict[tuple, list] = {}
        self.link.power_on(0.0)
        # both start-up NAKs are out before the first job: a start-up NAK that crosses a
        # setup is a line event of its own (it refuses the STX), exercised by line_break/fault
        self.link.run_until_quiet(1.0)
        self.char = self.p.char_time

    def _hook(self, w):
        for i, (src, kind) in enumerate(self.faults):
            if src == w.src:
                del self.faults[i]
                if not self.faults:
                    self.link.hook = None
                self.faulted = self.unsettled = True
                note(f"fault: {kind} {w.byte:02X} from {w.src} at {w.start:.6f}")
                return kind
        return DELIVER

    def station(self, side):
        return self.a if side == "a" else self.b

    # -- rules --------------------------------------------------------------------
    def request(self, side, payload):
        self.requests[side].append(payload)
        self.link.request(self.station(side), payload)

    def both_at_once(self, pa, pb):
        t = self.link.now
        self.requests["a"].append(pa)
        self.requests["b"].append(pb)
        self.link.request(self.a, pa, at=t)
        self.link.request(self.b, pb, at=t)

    def deliver(self, n):
        target = self.link.wire_length + n
        while self.link.wire_length < target:
            t = self.link.next_time()
            if t == float("inf"):
                break
            self.link.run_until(t)

    TIMERS = ("CDT", "CDT + 2 characters", "ADT", "ADT + 2 characters", "T_NAKTIM", "T_BLOCK")

    def advance(self, timer, edge):
        """Time passes: as long as one of the timers, give or take ``edge`` seconds."""
        p, c = self.p, self.char
        base = {"CDT": p.cdt, "CDT + 2 characters": p.cdt + 2 * c, "ADT": p.adt,
                "ADT + 2 characters": p.adt + 2 * c, "T_NAKTIM": T_NAKTIM, "T_BLOCK": T_BLOCK}[timer]
        self.link.run_until(self.link.now + max(0.0, base + edge))

    def fault(self, src, kind):
        self.faults.append((src, kind))
        self.link.hook = self._hook

    def line_break(self, side):
        self.faulted = self.unsettled = True
        self.link.inject_break(self.station(side), at=self.link.now)

    def settle(self):
        """No deadlock: with no fault pending, the longest chain of timers ends in quiet
        (with one pending, nothing: the fault would hit whatever comes next)."""
        if self.faults:
            return
        p = self.p
        jobs = len(self.requests["a"]) + len(self.requests["b"]) + 1
        block = 2 * 1030 * self.char
        bound = jobs * ((p.setup_attempts * p.transmission_attempts + 2) * (p.adt + p.cdt + block + T_NAKTIM)
                        + T_BLOCK) + 10.0
        assert self.link.run_until_quiet(self.link.now + bound), "no quiet after the longest chain of timers"
        self.check_outcomes(final=True)

    # -- invariants ---------------------------------------------------------------------
    def protocol_holds(self):
        """All the invariants after every step, as one: hypothesis spends more per invariant
        it calls (about 50 us on its own bookkeeping) than these checks take."""
        self.attempts_bounded()
        self.one_sender_at_a_time()
        self.check_outcomes(final=False)

    def attempts_bounded(self):
        for st_ in (self.a, self.b):
            for job in (st_.job, st_.deferred):
                if job is not None:
                    assert job.x <= st_.params.setup_attempts + 1
                    assert job.w <= st_.params.transmission_attempts + 1
                    assert job.stx_sent <= st_.params.setup_attempts * st_.params.transmission_attempts + 1

    def one_sender_at_a_time(self):
        """After an initialization conflict one side sends, never both (§2.2.3). A fault
        or a BREAK can make both send until the stations are idle again: a receiver that a
        BREAK stopped inside a block, given a job at that instant, sends its STX, and the
        partner's next data character DLE is its acknowledgement (found by bench_model,
        seed 0; test_a_break_inside_a_block_can_leave_both_sides_sending)."""
        if self.unsettled and self.a.idle and self.b.idle:
            self.unsettled = False
        assert self.unsettled or not (self.a.state is T.SEND_DATA and self.b.state is T.SEND_DATA)

    def check_outcomes(self, final: bool):
        disturbed = self.disturbed()
        # What is checked depends only on the events and the requests (both only grow),
        # ``disturbed`` and ``starved`` (both, once true, stay true): with none of them
        # changed since a check that passed, this one passes too.
        key = (final, disturbed, len(self.link.events), len(self.requests["a"]), len(self.requests["b"]))
        if key == self._passed:
            return
        # each side's job results and deliveries so far, in order (the events only grow)
        events = self.link.events
        for name, e in events[self._events_seen:]:
            if isinstance(e, (SendDone, SendFailed)):
                self._done[name].append(e)
            elif isinstance(e, Delivered):
                self._delivered[name].append(e.payload)
        self._events_seen = len(events)
        for src, dst in (("a", "b"), ("b", "a")):
            sender = self.station(src)
            requested = self.requests[src]
            done, delivered = self._done[src], self._delivered[dst]
            assert len(done) <= len(requested)
            for req, outcome in zip(requested, done):
                assert outcome.payload == req                      # jobs end in the order they were given
                if isinstance(outcome, SendFailed):
                    assert disturbed or self.starved(sender, outcome), \
                        f"a job failed on a clean line: 16#{outcome.code:04X}"
                    assert outcome.code in ALLOWED_FAILURES, f"16#{outcome.code:04X}"
            sent = Counter(e.payload for e in done if isinstance(e, SendDone))
            failed = Counter(e.payload for e in done if isinstance(e, SendFailed))
            got = Counter(delivered)
            if not disturbed:
                for payload in got:
                    assert payload in requested, "delivered a block that was never sent"
                for payload, n in sent.items():
                    # every job of this payload whose failure was not reported: delivered once
                    assert got[payload] == requested.count(payload) - failed[payload] if final else got[payload] >= n
            else:
                for payload in got:
                    if payload not in requested and self.p.has_bcc:
                        # only an alteration the XOR cannot see may pass (§4.4)
                        assert any(codec.payload_bcc(payload) == codec.payload_bcc(r) for r in requested), payload
                # a DONE no longer proves delivery: a duplicated setup DLE, for one, can pass
                # for the acknowledgement of the block (the procedure cannot tell them apart)
            if final:
                assert len(done) == len(requested), "every job ends, with success or a reported failure"
                if not disturbed:
                    # on a clean line the only STATUS events are of a conflict-free exchange,
                    # or the final 16#0709 of a low-priority job starved by conflicts
                    codes = [e.code for e in self.link.events_of(sender, Status)]
                    starved = [e for e in done if isinstance(e, SendFailed)]
                    assert codes == [0x0709] * len(starved), codes
        self._passed = key

    def starts(self, side, byte) -> list[float]:
        """The start times of the ``byte`` characters (STX or NAK) ``side`` put on the line,
        in line order. The wire only grows: each call looks at the runs of characters added
        since the last one (one pass over the wire per example, not one per step)."""
        runs, seen = self.link.wire_runs, self._starts
        for run in runs[self._scanned:]:
            data = run.data
            for c in (0x02, 0x15):
                i = data.find(c)
                while i >= 0:
                    seen[run.src, c].append(run.start + i * run.char)   # as on link.wire
                    i = data.find(c, i + 1)
        self._scanned = len(runs)
        return seen[side, byte]

    def disturbed(self) -> bool:
        """A fault was injected, or a NAK crossed an STX of the partner on the line. The
        second needs no fault: a low-priority station starved by conflicts (``starved``)
        sends its final NAK at once, and the partner may start a setup at that instant.
        The STX's sender reads the NAK as a refusal and repeats its STX; the other side
        answers the first STX with DLE, which the sender takes for the answer to the
        repetition, and the repeated STX lands in the block as its first data byte. 3964
        (no BCC) delivers the block with an extra 02; 3964R refuses it (BCC) and jobs fail
        with 16#070A. Both are within the rules (A8: no guard times); from there on the
        line is treated as disturbed."""
        return self.faulted or any(self.crossing(side, 0x15, 0x02, self.char / 2) for side in "ab")

    def starved(self, station, outcome) -> bool:
        """A job may fail on a clean line in one way: the low-priority station lost the
        initialization conflict so often that its setup attempts ran out (A21 counts each
        collided STX as an attempt; A8: no guard time, so a high-priority partner with jobs
        back to back collides again at once). 16#0709, with no error of its own, and at
        least ``setup_attempts`` STX of this station crossed one of the partner's."""
        if station.params.priority != "low" or outcome.code != 0x0709 or outcome.first_error is not None:
            return False
        return self.crossing(station.name, 0x02, 0x02, self.char) >= station.params.setup_attempts

    def crossing(self, side, byte, partner_byte, window) -> int:
        """How many ``byte`` characters of ``side`` started less than ``window`` seconds
        from a ``partner_byte`` of the other side: those at t with a partner's character at
        u where u > t - window and u - t < window. Each side's characters are on the wire
        in time order. Counted as characters come: a new one of ``side`` against all the
        partner's, a new one of the partner against those of ``side`` near it."""
        mine, theirs = self.starts(side, byte), self.starts("b" if side == "a" else "a", partner_byte)
        state = self._crossings.setdefault((side, byte, partner_byte, window), [0, 0, set()])
        seen_mine, seen_theirs, hit = state
        for j in range(seen_mine, len(mine)):
            t = mine[j]
            i = bisect_right(theirs, t - window)   # the first one later than t - window
            if i < len(theirs) and theirs[i] - t < window:
                hit.add(j)
        for u in theirs[seen_theirs:]:
            # the characters of ``side`` near u (a wider range, then the exact test)
            j = bisect_right(mine, u - 2 * window)
            while j < len(mine) and mine[j] < u + 2 * window:
                t = mine[j]
                if u > t - window and u - t < window:
                    hit.add(j)
                j += 1
        state[0], state[1] = len(mine), len(theirs)
        return len(hit)


# ------------------------------------------------------------------ the examples
STEP_KINDS = ("deliver", "request", "both_at_once", "advance", "fault", "line_break", "settle")
EDGES = (-0.001, -0.0001, 0.0, 0.0001, 0.001)
FAULTS = (DROP, CORRUPT, DUPLICATE)
RAW_STEP = 7     # raw bytes per step


def decode_step(raw: bytes, kinds: tuple[str, ...]) -> tuple[str, dict] | None:
    """The step that seven raw bytes stand for among ``kinds``: (method of TwoStations,
    its arguments), or None (a no-op) where the first byte is 00."""
    if raw[0] == 0:
        return None
    kind = kinds[raw[0] % len(kinds)]
    side = "ab"[raw[1] & 1]
    if kind == "request":
        return kind, {"side": side, "payload": _payload(raw[2], raw[3], raw[4])}
    if kind == "both_at_once":
        return kind, {"pa": _payload(raw[1], raw[2], raw[3]), "pb": _payload(raw[4], raw[5], raw[6])}
    if kind == "deliver":
        return kind, {"n": 1 + raw[1] % 40}
    if kind == "advance":
        return kind, {"timer": TwoStations.TIMERS[raw[1] % len(TwoStations.TIMERS)], "edge": EDGES[raw[2] % len(EDGES)]}
    if kind == "fault":
        return kind, {"src": side, "kind": FAULTS[raw[2] % len(FAULTS)]}
    if kind == "line_break":
        return kind, {"side": side}
    return kind, {}


class Scenario:
    """One example: the stations' settings, the step kinds it may use (``mask``, a bit per
    entry of STEP_KINDS) and its steps; printed as the program it runs."""

    def __init__(self, config: dict, mask: int, raws: list[bytes]):
        self.config = config
        self.kinds = tuple(k for i, k in enumerate(STEP_KINDS) if mask >> i & 1)
        self.steps = [st_ for st_ in (decode_step(r, self.kinds) for r in raws) if st_ is not None]

    def run(self) -> TwoStations:
        """Run the program with every invariant checked at the start and after each step."""
        m = TwoStations()
        m.start(**self.config)
        m.protocol_holds()
        for name, args in self.steps:
            getattr(m, name)(**args)
            m.protocol_holds()
        m.check_outcomes(final=False)
        return m

    def __repr__(self) -> str:
        def arg(v):
            r = repr(v)
            return r if len(r) <= 80 else f"{r[:60]}...({len(v)} bytes)"
        lines = ["", "state = TwoStations()",
                 "state.start(" + ", ".join(f"{k}={v!r}" for k, v in self.config.items()) + ")"]
        lines += [f"state.{name}(" + ", ".join(f"{k}={arg(v)}" for k, v in args.items()) + ")"
                  for name, args in self.steps]
        return "\n".join(lines)


def scenarios(steps: int) -> st.SearchStrategy[Scenario]:
    config = st.fixed_dictionaries({"procedure": st.sampled_from(["3964", "3964R"]), "a_high": st.booleans(),
                                    "setup": st.integers(2, 3), "tx": st.integers(1, 3),
                                    "baud": st.sampled_from([9600, 76800, None])})
    raw = st.binary(min_size=RAW_STEP, max_size=RAW_STEP)
    return st.builds(Scenario, config, st.integers(1, 2 ** len(STEP_KINDS) - 1),
                     st.lists(raw, min_size=steps, max_size=steps))


def fuzz(s: settings | None = None, seed: int | None = None) -> None:
    """Run level 1 under the settings ``s`` (the loaded profile by default; its
    ``stateful_step_count`` is the number of steps of an example), from ``seed`` if given."""
    s = s or settings()

    @s
    @given(scenarios(s.stateful_step_count))
    def two_model_stations(scenario):
        scenario.run()

    if seed is not None:
        two_model_stations = fixed_seed(seed)(two_model_stations)
    two_model_stations()


def test_two_model_stations_keep_the_invariants():
    fuzz()


def test_level_1_finds_a_station_that_counts_a_data_dle_once_in_the_bcc(monkeypatch):
    """The driver and the invariants together catch a broken model: both stations built
    from the variant that counts a doubled data DLE once in the BCC (harness/procedures/p3964/mutants/)."""
    from hypothesis import Phase

    from ptpcert.procedures.p3964.mutants import MUTANTS

    monkeypatch.setattr(sys.modules[__name__], "Station3964", MUTANTS["bcc-dle-counted-once"].make)
    with pytest.raises(AssertionError):
        fuzz(settings(settings(), max_examples=300, phases=[Phase.generate], database=None), seed=0)


def test_a_program_decodes_as_it_is_printed_and_runs_its_steps():
    """The decoding of raw steps: 00 first is a no-op, the kinds come from the mask, and the
    printed program is the one that runs."""
    sc = Scenario({"procedure": "3964R", "a_high": True, "setup": 2, "tx": 1, "baud": None}, 0b0000011,
                  [bytes(7), bytes([1, 1, 4, 0, 9, 0, 0]), bytes([2, 5, 0, 0, 0, 0, 0])])
    assert sc.kinds == ("deliver", "request")
    assert [name for name, _ in sc.steps] == ["request", "deliver"]
    (_, req), (_, dlv) = sc.steps
    assert req["side"] == "b" and len(req["payload"]) == 2 and dlv == {"n": 6}
    assert "state.request(side='b', payload=" in repr(sc) and "state.deliver(n=6)" in repr(sc)
    m = sc.run()
    assert m.requests["b"] == [req["payload"]]
    assert _payload(3, 0, 0) == _long_payload(1000, 0) and len(_payload(0, 0, 0)) == 1



def test_payloads_follow_the_byte_rule():
    """A payload byte is CONTROL[pick % 5] where its pick is >= 128, and its value
    otherwise: short blocks from hypothesis's raw bytes, long ones from a seeded generator."""
    for raw in [b"\x00\x41", b"\x80\x41", b"\x81\x41\x7f\x42\xff", bytes(range(256))]:
        expected = bytes(CONTROL[s % len(CONTROL)] if s >= 128 else b for s, b in zip(raw[0::2], raw[1::2]))
        assert _picked(raw) == expected
    assert _picked(b"\x82\x41") == b"\x10" and _picked(b"\x00\x41\x99") == b"A"
    for size, seed in [(1, 0), (7, 1), (1000, 2), (1017, 3), (1024, 2**32 - 1)]:
        assert _long_payload(size, seed) == _picked(random.Random(seed).randbytes(2 * size))
        assert len(_long_payload(size, seed)) == size
    block = _long_payload(1024, 5)
    assert 400 < sum(b in CONTROL for b in block) < 700   # about half control characters


def test_a_break_inside_a_block_can_leave_both_sides_sending():
    """Found by bench_model (seed 0): a BREAK stops the low-priority receiver inside the
    high-priority side's block (16#080D); a job given to each at that instant makes the
    receiver send its STX, and the sender's next data character, a DLE, acknowledges it:
    both send. No conforming station can tell that DLE from an acknowledgement, so the
    invariant allows both to send only after a fault or a BREAK, until both are idle."""
    m = TwoStations()
    m.start(procedure="3964", a_high=False, setup=2, tx=1, baud=9600)
    dles = bytes([0x10] * 1000)               # every data DLE is doubled on the line
    m.request(payload=dles, side="b")
    m.link.run_until(m.link.now + m.p.cdt - 0.001)
    assert m.b.state is T.SEND_DATA
    m.line_break(side="a")
    m.both_at_once(pa=b"A" * 1000, pb=b"B" * 1000)
    m.deliver(n=1)                           # a's STX is out, b's next DLE takes it
    assert m.a.state is T.SEND_DATA and m.b.state is T.SEND_DATA
    assert m.unsettled
    m.protocol_holds()                       # allowed: the line was disturbed
    m.settle()
    assert m.a.idle and m.b.idle
    m.protocol_holds()
    assert not m.unsettled                   # and strict again once both are idle
    m.unsettled, m.faulted = False, False
    m.a.state = m.b.state = T.SEND_DATA      # on a clean line both sending is a failure
    with pytest.raises(AssertionError):
        m.one_sender_at_a_time()


def test_low_priority_job_starved_by_back_to_back_conflicts_is_allowed():
    """Found by the thorough profile: the high-priority side sends two jobs back to back
    while the low-priority side has one; both conflicts are lost by the low side, whose two
    setup attempts (A21) are then used up: 16#0709 on a clean line, which the invariants
    accept as starvation, and only as that."""
    m = TwoStations()
    m.start(procedure="3964", a_high=True, setup=2, tx=1, baud=9600)
    m.request(payload=b"\x10", side="a")
    m.both_at_once(pa=b"\x10", pb=b"\x10")
    m.settle()
    failed = [e for e in m.link.events_of(m.b) if isinstance(e, SendFailed)]
    assert [e.code for e in failed] == [0x0709] and m.starved(m.b, failed[0])
    assert not m.starved(m.a, failed[0])      # never for the high-priority side
    # one more setup attempt and the same job gets through after the two conflicts
    m = TwoStations()
    m.start(procedure="3964", a_high=True, setup=3, tx=1, baud=9600)
    m.request(payload=b"\x10", side="a")
    m.both_at_once(pa=b"\x10", pb=b"\x10")
    m.settle()
    assert [type(e) for e in m.link.events_of(m.b) if isinstance(e, (SendDone, SendFailed))] == [SendDone]


def test_a_starved_job_is_not_counted_among_the_deliveries_of_its_payload():
    """Found by bench_model (seed 1): the low-priority side's first of two jobs with the
    same payload starves (16#0709 on a clean line), the second gets through. The payload
    is delivered once, for the job that did not fail: the check counts the requested jobs
    of a payload less those reported failed (it counted the failed one too)."""
    m = TwoStations()
    m.start(procedure="3964", a_high=False, setup=2, tx=1, baud=9600)
    m.both_at_once(pa=b"\x10", pb=b"\x10")
    m.both_at_once(pa=b"\x10", pb=b"\x10")
    m.settle()
    outcomes = [type(e) for e in m.link.events_of(m.a) if isinstance(e, (SendDone, SendFailed))]
    assert outcomes == [SendFailed, SendDone] and not m.disturbed()
    assert [e.payload for e in m.link.events_of(m.b, Delivered)] == [b"\x10"]


def test_final_nak_crossing_an_stx_disturbs_the_line():
    """Found by the thorough profile: after the low-priority side is starved (two conflicts
    lost, 16#0709), its final NAK crosses the high-priority side's next STX. 3964 then
    delivers the block with the repeated STX as an extra first byte; 3964R refuses it by
    its BCC. The invariants accept both only because the NAK crossed an STX."""
    for procedure in ("3964", "3964R"):
        m = TwoStations()
        m.start(procedure=procedure, a_high=True, setup=2, tx=1, baud=9600)
        m.both_at_once(pa=b"\x01", pb=b"\x11")
        m.both_at_once(pa=b"\x03", pb=b"\x12")
        m.both_at_once(pa=b"\x02\x10\x9b", pb=b"\x13")
        m.settle()
        assert m.disturbed() and not m.faulted
        delivered = [e.payload for e in m.link.events_of(m.b) if isinstance(e, Delivered)]
        if procedure == "3964":
            assert b"\x02\x02\x10\x9b" in delivered
        else:
            assert b"\x02\x10\x9b" not in delivered and b"\x02\x02\x10\x9b" not in delivered
    # without the third pair of jobs nothing crosses: the line stays clean
    m = TwoStations()
    m.start(procedure="3964", a_high=True, setup=2, tx=1, baud=9600)
    m.both_at_once(pa=b"\x01", pb=b"\x11")
    m.settle()
    assert not m.disturbed()
