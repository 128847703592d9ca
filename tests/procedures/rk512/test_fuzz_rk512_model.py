"""Fuzzer level 1 for RK 512: two model RK 512 stations over the 3964(R) link model in
virtual time, driven by a hypothesis state machine - requests on either side or both at once
(SEND and FETCH of every type and size, valid or refused by the partner), time steps around
T_RES, bytes dropped, corrupted or duplicated on the line - with the invariants of the RK 512
layer checked after every step (§2.2.3, Figs. 2-17 to 2-19):

* every command is answered exactly once: each side's acknowledged responses never outnumber
  the partner's acknowledged commands, and on a clean line they are equal once all is quiet;
* no data are written for a refused frame: a station's memory is exactly its start contents
  plus the writes it reported (Served), and every write belongs to a command it answered
  with REATEL 00;
* depth 1 per direction: a station never has two commands of its own unanswered;
* every request ends exactly once (a result per request), and on a clean line only with
  the outcomes the request itself decides (it is refused by the rules, not by the line).

Settings: the "ptpcert-quick" profile unless --hypothesis-profile says otherwise.
"""

from hypothesis import note
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule

from ptpcert.model.link import CORRUPT, DELIVER, DROP, DUPLICATE, Link
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.rk512.model import Rk512Host, Rk512Params, Rk512Station
from ptpcert.procedures.rk512.model.events import FrameNotSent, FrameReceived, FrameSent, RequestResult, Served

AREAS = st.sampled_from(["DB5", "DB9", "DX3", "M", "E", "A", "T", "Z", "DB0", "DB250"])
LENGTHS = st.sampled_from([1, 2, 6, 127, 128, 129, 130, 256, 300, 600, 1024, 1025])


@st.composite
def request_line(draw):
    op = draw(st.sampled_from(["send", "fetch"]))
    area = draw(AREAS if op == "fetch" else st.sampled_from(["DB5", "DB9", "DX3", "DB0", "M"]))
    n = draw(LENGTHS)
    if area.startswith(("DB", "DX")):
        where = draw(st.sampled_from(["DW0", "DW3", "OFF=7", "DW250"]))
    else:
        where = str(draw(st.sampled_from([0, 5, 200])))
    extra = draw(st.sampled_from(["", "", ":CPU=none", ":CF=3.5:CPU=2", ":CF=3.9", ":CPU=6"]))
    return f"{op} {area}:{where}:LEN={n}{extra}"


class TwoRkStations(RuleBasedStateMachine):
    @initialize(link=st.sampled_from(["3964R", "3964"]), a_high=st.booleans(), baud=st.sampled_from([9600, None]),
                t_res=st.sampled_from([500, 3000]))
    def start(self, link, a_high, baud, t_res):
        def params(prio):
            return Rk512Params(link=link, line=Params3964(procedure=link, priority=prio, baud_rate=baud, cdt_ms=60,
                                                          adt_ms=200), response_time_ms=t_res, db_bytes=1024)
        self.a = Rk512Station(params("high" if a_high else "low"), name="a")
        self.b = Rk512Station(params("low" if a_high else "high"), name="b")
        self.hosts = {"a": Rk512Host(self.a), "b": Rk512Host(self.b)}
        self.start_mem = {"a": self.a.memory.snapshot(), "b": self.b.memory.snapshot()}
        self.noise = 0.0
        self.faulted = False
        self.asked = {"a": 0, "b": 0}
        self.seed = 0
        self.link = Link(self.a, self.b, hook=self._hook, hosts=self.hosts)
        self.link.power_on(0.0)
        self.link.run_until_quiet(1.0)

    def _hook(self, w):
        self.seed = (self.seed * 1103515245 + 12345) & 0x7FFFFFFF
        if self.noise and (self.seed % 10_000) / 10_000 < self.noise:
            self.faulted = True
            return (DROP, CORRUPT, DUPLICATE)[self.seed % 3]
        return DELIVER

    def station(self, name):
        return self.a if name == "a" else self.b

    @rule(side=st.sampled_from(["a", "b"]), line=request_line())
    def request(self, side, line):
        note(f"{side}: {line}")
        self.station(side).request(self.link.now, line)
        self.link._collect(self.link.now)
        self.asked[side] += 1

    @rule(side=st.sampled_from(["a", "b"]), lines=st.lists(request_line(), min_size=2, max_size=3))
    def requests_in_a_row(self, side, lines):
        for line in lines:
            self.request(side, line)

    @rule(step=st.sampled_from([0.0, 0.001, 0.05, 0.3, 0.7, 1.5]))
    def advance(self, step):
        # steps relative to T_RES: just under and just over it, and small ones
        t_res = self.a.params.t_res
        self.link.run_until(self.link.now + (step * t_res if step >= 0.3 else step))

    @precondition(lambda self: not self.noise)
    @rule(p=st.sampled_from([0.002, 0.01]))
    def noisy_line(self, p):
        self.noise = p

    # -- invariants after every step ------------------------------------------------------------
    def _events(self, name, cls):
        return [e for n, e in self.link.events if n == name and isinstance(e, cls)]

    @invariant()
    def depth_one_per_direction(self):
        for name in ("a", "b"):
            waiting = False
            for n, e in self.link.events:
                if n != name:
                    continue
                if isinstance(e, FrameSent) and len(e.frame) >= 3 and e.frame[2] != 0:
                    assert not waiting, f"{name} sent a second command before the answer to the first"
                    waiting = True
                elif isinstance(e, RequestResult) or (isinstance(e, FrameReceived) and len(e.frame) >= 3
                                                      and e.frame[2] == 0):
                    waiting = False

    @invariant()
    def answers_never_outnumber_commands(self):
        for name, other in (("a", "b"), ("b", "a")):
            sent = self._events(name, FrameSent)
            answers = [e for e in sent if len(e.frame) >= 3 and e.frame[2] == 0]
            got = self._events(name, FrameReceived)
            commands = [e for e in got if len(e.frame) >= 3 and e.frame[2] != 0]
            shorts = [e for e in got if len(e.frame) < 3]
            assert len(answers) <= len(commands) + len(shorts), f"{name} answered a frame that was no command"

    @invariant()
    def memory_moves_only_with_reported_writes(self):
        for name in ("a", "b"):
            st_ = self.station(name)
            shadow = {"db": {n: bytearray(b) for n, b in self.start_mem[name]["db"].items()},
                      "dx": {n: bytearray(b) for n, b in self.start_mem[name]["dx"].items()}}
            for e in self._events(name, Served):
                if e.op == "write":
                    buf = shadow["db" if e.area == "D" else "dx"][e.number]
                    buf[e.start:e.start + len(e.data)] = e.data
            for kind in ("db", "dx"):
                for n, buf in shadow[kind].items():
                    have = getattr(st_.memory, kind)[n]
                    assert bytes(have) == bytes(buf), f"{name}: {kind.upper()}{n} changed without a reported write"
            # every write belongs to a frame answered 00 (the answer may still be on its way)
            writes = [e for e in self._events(name, Served) if e.op == "write"]
            handed = self._events(name, FrameSent) + self._events(name, FrameNotSent)
            ok = [e for e in handed if len(e.frame) >= 4 and e.frame[2] == 0 and e.frame[3] == 0]
            assert len(writes) <= len(ok) + 1, f"{name} wrote data for a frame it did not answer 00"

    def teardown(self):
        if not hasattr(self, "link"):
            return
        t_res = self.a.params.t_res
        assert self.link.run_until_quiet(self.link.now + 200 * t_res + 600), "no rest: a deadlock"
        for name in ("a", "b"):
            assert self.station(name).idle
            results = self._events(name, RequestResult)
            assert len(results) == self.asked[name], f"{name}: {len(results)} results for {self.asked[name]} requests"
        if not self.faulted:
            for name, other in (("a", "b"), ("b", "a")):
                answers = [e for e in self._events(name, FrameSent) if len(e.frame) >= 3 and e.frame[2] == 0]
                commands = [e for e in self._events(other, FrameSent) if len(e.frame) >= 3 and e.frame[2] != 0]
                assert len(answers) == len(commands), f"{name} answered {len(answers)} of {len(commands)} commands"
                # a clean line refuses nothing: no sequence error, no monitoring time, no lost frame
                codes = {e.code for n, e in self.link.events if n == name and hasattr(e, "code") and e.code}
                assert not codes & {0x060E, 0x0A01, 0x0A05, 0x0612, 0x051A}, sorted(codes)


TestTwoRkStations = TwoRkStations.TestCase
