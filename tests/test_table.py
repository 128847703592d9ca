"""The transition table, exercised for every (state, input) pair.

For each state we drive a fresh station into it by a path through the protocol, then feed
each of the table's inputs and check that the station ran the row's action and ended in a
state the row allows. Rows marked impossible must be refused with ModelError."""

import pytest

from ptpcert.model import ModelError, Params3964, Station3964, table as T
from ptpcert.model.codec import DLE, ETX, NAK, STX

P = Params3964(cdt_ms=20, adt_ms=20)
CHAR = {T.STX: STX, T.DLE: DLE, T.ETX: ETX, T.NAK: NAK, T.OTHER: 0x41}


def drive(state: str) -> Station3964:
    s = Station3964(P, name="s", trace=True)
    t = 0.0
    if state == T.START_UP:
        return s
    s.power_on(t)
    paths = {
        T.IDLE: [],
        T.IDLE_JUNK: [("rx", 0x41)],
        T.WAIT_SETUP_ACK: [("req", b"ABCDEFGH")],
        T.SEND_DATA: [("req", b"ABCDEFGH"), ("rx", DLE)],
        T.ABORT_QUIET: [("req", b"ABCDEFGH"), ("rx", DLE), ("rx", 0x41)],
        T.WAIT_RELEASE_ACK: [("req", b"AB"), ("rx", DLE), ("until", T.WAIT_RELEASE_ACK)],
        T.WAIT_BUFFER: [("full",), ("rx", STX)],
        T.RECEIVE: [("rx", STX)],
        T.WAIT_ETX: [("rx", STX), ("rx", 0x31), ("rx", DLE)],
        T.WAIT_BCC: [("rx", STX), ("rx", 0x31), ("rx", DLE), ("rx", ETX)],
        T.WAIT_REPETITION: [("rx", STX), ("rx", 0x31), ("rx", DLE), ("rx", ETX), ("rx", 0x99)],
    }
    for step in paths[state]:
        t += 0.001
        if step[0] == "rx":
            s.receive(t, step[1])
        elif step[0] == "req":
            s.request_send(t, step[1])
        elif step[0] == "full":
            s.set_buffer_free(t, False)
        elif step[0] == "until":
            while s.state != step[1]:
                t = max(s.now, s.next_deadline())
                s.handle_timer(t)
                s.pop_output(t)
    s.pop_output()
    s.pop_events()
    assert s.state == state, (state, s.state)
    return s


def reachable(target: str, current: str) -> set[str]:
    if target == T.SAME:
        return {current, T.WAIT_SETUP_ACK}
    out, todo = set(), [target]
    while todo:
        x = todo.pop()
        if x in T.DECISION_TARGETS:
            todo.extend(T.DECISION_TARGETS[x])
        else:
            out.add(x)
    if T.IDLE in out:
        out.add(T.WAIT_SETUP_ACK)  # a pending job starts as soon as the station is idle
    return out


def feed(s: Station3964, inp: str) -> None:
    t = s.now + 0.0005
    if inp in CHAR:
        s.receive(t, CHAR[inp])
    elif inp == T.INVALID:
        s.receive_invalid(t, 0x41)
    elif inp == T.BREAK:
        s.line_break(t)
    elif inp == T.POWER_ON:
        s.power_on(t)
    elif inp == T.SEND_REQUEST:
        s.request_send(t, b"XYZ")
    elif inp == T.BUFFER_FREE:
        s.set_buffer_free(t, True)
    elif inp == T.TX_DONE:
        if s._tx_done_at == float("inf"):
            s._input(T.TX_DONE)
        s.handle_timer(s._tx_done_at)
    else:  # a timer
        if s._timer != inp:
            s._input(inp)  # not armed here: the station must refuse it
        s.handle_timer(s._timer_at)


@pytest.mark.parametrize("state,inp", [(s, i) for s in T.STATES for i in T.INPUTS])
def test_every_state_input_pair(state, inp):
    s = drive(state)
    row = T.TABLE[state][inp]
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            feed(s, inp)
        return
    if inp == T.BUFFER_FREE and state != T.WAIT_BUFFER:
        feed(s, inp)  # only a state waiting for a buffer reacts
        assert s.state == state
        return
    n = len(s.trace)
    feed(s, inp)
    steps = [x for x in s.trace[n:] if x[1] != "timer"]
    assert steps, "the input reached the table"
    first = steps[0]
    assert first[1:4] == (state, inp, row.action)
    assert first[4] in reachable(row.target, state), (first, row)


def test_table_is_complete_and_targets_are_known():
    assert len(list(T.rows())) == len(T.STATES) * len(T.INPUTS)
    for d, targets in T.DECISION_TARGETS.items():
        assert d in T.DECISIONS
        for x in targets:
            assert x in T.STATES or x in T.DECISIONS
    # every action named in the table exists on the station
    for _, _, row in T.rows():
        if row.action != T.IMPOSSIBLE:
            assert hasattr(Station3964, "_a_" + row.action), row.action
    for d in T.DECISIONS:
        assert hasattr(Station3964, "_d_" + d.lower()), d


def test_every_state_reachable_and_every_action_used():
    used = {row.action for _, _, row in T.rows()}
    defined = {n[3:] for n in dir(Station3964) if n.startswith("_a_")}
    assert used - {T.IMPOSSIBLE} == defined
