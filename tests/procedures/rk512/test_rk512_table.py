"""The RK 512 transition tables, exercised for every (state, input) pair of both sides.

For each state a fresh core is driven into it through its public interface; each input the
state can see is then applied through that interface (a frame arrives, the link reports a
frame sent or given up, a timer runs out, a request or a restart comes), and the core must
run the row's action, end in a state the row allows and raise the row's STATUS. Rows marked
impossible must be refused with ModelError."""

import pytest
from rk512_rules import continuation, header, response

from ptpcert.model.errors import ModelError
from ptpcert.model.events import Status
from ptpcert.procedures.rk512.model import Rk512Core, Rk512Params, Rk512Readings
from ptpcert.procedures.rk512.model import table as T

A, P = T.AState, T.PState
AI, PI = T.AInput, T.PInput


class Core(Rk512Core):
    def __init__(self, readings=None):
        super().__init__(Rk512Params(), readings or Rk512Readings(), name="c", trace=True)
        self.out = []
        self.t = 0.0
        self.power_on(0.0)

    def _lower_send(self, now, frame):
        self.out.append(frame)

    def tick(self):
        self.t += 0.01
        return self.t


def SEND(n=200):
    return header("A", "D", 10, 0, n // 2) + bytes(min(n, 128))


#: rows that only a reading other than the default reaches: the reading to drive them with
READING_FOR = {
    # T_RES runs in the sending states only when it starts at the hand-over (AMB-17)
    (A.SEND_COMMAND, AI.T_RES): Rk512Readings(amb17_tres_start="handed_over"),
    (A.SEND_CONTINUATION, AI.T_RES): Rk512Readings(amb17_tres_start="handed_over"),
}


def drive_active(state, readings=None) -> Core:
    c = Core(readings)
    if state is A.IDLE:
        return c
    c.request(c.tick(), "send DB10:DW0:LEN=200")
    if state is A.SEND_COMMAND:
        return c
    c.frame_sent(c.tick())
    if state is A.WAIT_RESPONSE:
        return c
    c.frame_received(c.tick(), response(0))
    if state is A.SEND_CONTINUATION:
        return c
    c.frame_sent(c.tick())
    assert state is A.WAIT_CONTINUATION_RESPONSE
    return c


def test_drive_reaches_the_states():
    for s in A:
        assert drive_active(s).a_state is s
    for s in P:
        assert drive_passive(s).p_state is s


def drive_passive(state) -> Core:
    c = Core()
    if state is P.IDLE:
        return c
    c.frame_received(c.tick(), SEND())
    if state is P.SEND_RESPONSE:
        return c
    c.frame_sent(c.tick())
    assert state is P.WAIT_CONTINUATION
    return c


def apply_active(c: Core, inp) -> bool:
    """Apply ``inp`` through the public interface; False when the state cannot see it."""
    own = c._inflight is not None and c._inflight[1] == "A"
    if inp is AI.CPU_REQUEST:
        c.request(c.tick(), "fetch E:0:LEN=2")
    elif inp is AI.COMMAND_SENT:
        if not own:
            return False
        c.frame_sent(c.tick())
    elif inp is AI.COMMAND_NOT_SENT:
        if not own:
            return False
        c.frame_failed(c.tick(), 0x0709)
    elif inp is AI.RESPONSE:
        c.frame_received(c.tick(), response(0))
    elif inp is AI.CONTINUATION_RESPONSE:
        c.frame_received(c.tick(), response(0, first=False))
    elif inp is AI.BAD_RESPONSE:
        c.frame_received(c.tick(), b"\x01\x00\x00\x00")
    elif inp is AI.SHORT_RESPONSE:
        c.frame_received(c.tick(), b"\x00\x00\x00")
    elif inp is AI.T_RES:
        if c._t_res_a == float("inf"):
            return False
        c.handle_timer(c._t_res_a)
    elif inp is AI.RESTART:
        c.restart(c.tick())
    return True


def apply_passive(c: Core, inp) -> bool:
    own = c._inflight is not None and c._inflight[1] == "P" and c._inflight[2] is c.open and c.open is not None
    if inp is PI.COMMAND:
        c.frame_received(c.tick(), header("A", "D", 11, 0, 1) + b"\x01\x02")
    elif inp is PI.CONTINUATION:
        c.frame_received(c.tick(), continuation("A", "D", bytes(72)))
    elif inp is PI.BAD_COMMAND:
        c.frame_received(c.tick(), header("A", "D", 11, 0, 1, b1=0x01) + b"\x01\x02")
    elif inp is PI.SHORT_COMMAND:
        c.frame_received(c.tick(), b"\x00\x00\x41")
    elif inp is PI.RESPONSE_SENT:
        if not own:
            return False
        c.frame_sent(c.tick())
    elif inp is PI.RESPONSE_NOT_SENT:
        if not own:
            return False
        c.frame_failed(c.tick(), 0x0709)
    elif inp is PI.T_RES:
        if c._t_res_p == float("inf"):
            return False
        c.handle_timer(c._t_res_p)
    elif inp is PI.RESTART:
        c.restart(c.tick())
    return True


def allowed(row, state):
    if row.target == T.SAME:
        return {state}
    if row.target in T.DECISION_TARGETS:
        return set(T.DECISION_TARGETS[row.target])
    return {row.target}


@pytest.mark.parametrize("state,inp", [(s, i) for s in A for i in AI])
def test_active_rows(state, inp):
    c = drive_active(state, READING_FOR.get((state, inp)))
    c.pop_events()
    row = T.ACTIVE[state][inp]
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            c._active(inp)
        assert not apply_active(c, inp)
        return
    n = len(c.trace)
    assert apply_active(c, inp), f"{inp} can occur in {state} by the table but not through the interface"
    mine = [x for x in c.trace[n:] if x[1] == "active"]
    assert mine[0][2:5] == (state, inp, row.action)
    assert mine[0][5] in allowed(row, state)
    if row.code is not None:
        assert row.code in [e.code for e in c.pop_events() if isinstance(e, Status)]


@pytest.mark.parametrize("state,inp", [(s, i) for s in P for i in PI])
def test_passive_rows(state, inp):
    c = drive_passive(state)
    c.pop_events()
    row = T.PASSIVE[state][inp]
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            c._passive(inp)
        assert not apply_passive(c, inp)
        return
    n = len(c.trace)
    assert apply_passive(c, inp), f"{inp} can occur in {state} by the table but not through the interface"
    mine = [x for x in c.trace[n:] if x[1] == "passive"]
    assert mine[0][2:5] == (state, inp, row.action)
    assert mine[0][5] in allowed(row, state)
    if row.code is not None:
        assert row.code in [e.code for e in c.pop_events() if isinstance(e, Status)]


def test_every_row_has_a_reference():
    for side, state, inp, row in T.rows():
        if row.action != T.IMPOSSIBLE:
            assert row.ref, (side, state, inp)
            assert ("Fig." in row.ref or "Table" in row.ref or "§" in row.ref
                    or row.action in ("ignore",) or "restart" in row.ref.lower()), (side, state, inp, row.ref)


def test_states_and_inputs_are_enums_named_as_the_flowcharts():
    import enum
    for e in (T.AState, T.AInput, T.PState, T.PInput, T.Decision):
        assert issubclass(e, enum.StrEnum)
