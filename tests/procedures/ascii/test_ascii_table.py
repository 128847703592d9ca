"""The ASCII driver's tables (receiver per end criterion, sender, receive-side flow control),
exercised row by row: a station is driven into each state through the protocol, then fed
each input of the table; it must run the row's action and end in a state the row allows.
Rows marked impossible must be refused with ModelError."""

import pytest

from ptpcert.model.errors import ModelError
from ptpcert.procedures.ascii.model import AsciiJob, AsciiParams, AsciiStation
from ptpcert.procedures.ascii.model import table as T
from ptpcert.procedures.ascii.model.table import FcInput, FcState, RxInput, RxState, TxInput, TxState

BASE = dict(flow_control="auto_v24")   # the only mode with DSR inputs to the receiver
RX_PARAMS = {
    "cdt": AsciiParams(**BASE),
    "end_chars": AsciiParams(end_criterion="end_chars", end_chars=(0x03,), **BASE),
    "fixed_length": AsciiParams(end_criterion="fixed_length", fixed_length=3, **BASE),
}


def rx_station(crit: str, state: RxState) -> AsciiStation:
    st = AsciiStation(RX_PARAMS[crit], name="s", trace=True)
    st.power_on(0.0)
    if state is RxState.RECEIVE:
        st.receive(0.001, 0x41)
    elif state is RxState.DISCARD:
        st.receive_invalid(0.001, 0x41)
    elif state is RxState.OFF:
        st.set_line(0.001, "dsr", 0)
    assert st.rx_state is state
    return st


def resolve(target, decisions, state):
    if target == T.SAME:
        return {state}
    out, todo = set(), [target]
    while todo:
        x = todo.pop()
        if x in decisions:
            todo.extend(decisions[x])
        else:
            out.add(x)
    return out


RX_CASES = [(c, s, i) for c, table in T.RX_TABLES.items() for s in RxState for i in RxInput]


@pytest.mark.parametrize("crit, state, inp", RX_CASES, ids=[f"{c}-{s}-{i}" for c, s, i in RX_CASES])
def test_receiver_row(crit, state, inp):
    st = rx_station(crit, state)
    row = T.RX_TABLES[crit][state][inp]
    value = 0x03 if inp is RxInput.END else 0x42
    st.now = 0.002
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            st._rx(inp, value)
        return
    st._rx(inp, value)
    (now, machine, old, got_inp, action, new) = [x for x in st.trace if x[1] == "rx"][-1]
    assert (machine, old, got_inp, action) == ("rx", state, inp, row.action)
    assert new in resolve(row.target, T.RX_DECISION_TARGETS, state)
    assert st.rx_state is new


def tx_station(state: TxState) -> AsciiStation:
    v24 = state in (TxState.RTS_ON_WAIT, TxState.RTS_OFF_WAIT)
    p = AsciiParams(flow_control="auto_v24" if v24 else "xon_xoff")
    st = AsciiStation(p, name="s", trace=True)
    st.power_on(0.0)
    st.pop_output()
    if state is TxState.PAUSE:
        st.request_send(0.001, b"A")          # goes out after the start-up XON
        st.handle_timer(0.003)                # done at 2 character times
        st.request_send(0.003, b"B")          # within the pause after it
    elif state in (TxState.SEND, TxState.RTS_ON_WAIT):
        st.request_send(0.001, b"ABCDEFGH")
    elif state is TxState.STOPPED:
        st.request_send(0.001, b"ABCDEFGH")
        st.receive(0.002, p.xoff)
    elif state is TxState.RTS_OFF_WAIT:
        st.request_send(0.001, b"A")
        st.handle_timer(0.001 + p.data_output_wait + p.char_time)
    assert st.tx_state is state, (state, st.tx_state)
    return st


TX_CASES = [(s, i) for s in TxState for i in TxInput]


@pytest.mark.parametrize("state, inp", TX_CASES, ids=[f"{s}-{i}" for s, i in TX_CASES])
def test_sender_row(state, inp):
    st = tx_station(state)
    row = T.TX_TABLE[state][inp]
    if inp is TxInput.SEND_REQUEST:
        st._jobs.append(AsciiJob(b"Z", b"Z"))
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            st._tx(inp)
        return
    st._tx(inp)
    rows = [x for x in st.trace if x[1] == "tx" and x[2] == state and x[3] == inp]
    assert rows and rows[-1][4] == row.action
    allowed = resolve(row.target, T.TX_DECISION_TARGETS, state)
    if TxState.IDLE in allowed:
        allowed |= {TxState.PAUSE, TxState.SEND, TxState.RTS_ON_WAIT, TxState.STOPPED}  # a queued job starts
    assert rows[-1][5] in allowed


FC_CASES = [(s, i) for s in FcState for i in FcInput]


@pytest.mark.parametrize("state, inp", FC_CASES, ids=[f"{s}-{i}" for s, i in FC_CASES])
def test_flow_control_row(state, inp):
    p = AsciiParams(flow_control="xon_xoff", end_criterion="end_chars", buffer_frames=1)
    st = AsciiStation(p, name="s", trace=True)
    st.power_on(0.0)
    if state is FcState.HELD:
        st.receive(0.001, b"A\x03")
    assert st.fc_state is state
    row = T.FC_TABLE[state][inp]
    if row.action == T.IMPOSSIBLE:
        with pytest.raises(ModelError):
            st._fc(inp)
        return
    st._fc(inp, "read")
    last = [x for x in st.trace if x[1] == "fc"][-1]
    assert last[2:5] == (state, inp, row.action)
    assert st.fc_state in resolve(row.target, {}, state)


def test_every_row_cites_the_manual():
    for machine, state, inp, row in T.rows():
        if row.action != T.IMPOSSIBLE:
            assert row.ref and ("§" in row.ref or "Fig" in row.ref or "Table" in row.ref), (machine, state, inp)


def test_rows_that_report_carry_their_status_code():
    # every row whose action reports an error names a STATUS code of Table 8-1
    reporting = ("report", "abort", "spoil", "fragment", "expired", "abandon")
    for machine, state, inp, row in T.rows():
        if any(w in row.action for w in reporting) or row.action == "wait_expired":
            assert row.code is not None, (machine, state, inp, row.action)


def test_timer_rows_exist_only_where_the_timer_runs():
    for crit, table in T.RX_TABLES.items():
        assert table[RxState.WAIT_CHAR][RxInput.T_CDT].action == T.IMPOSSIBLE
        assert table[RxState.RECEIVE][RxInput.T_CDT].action != T.IMPOSSIBLE
    assert T.RX_TABLES["cdt"][RxState.RECEIVE][RxInput.END].action == T.IMPOSSIBLE
    for s in TxState:
        assert (T.TX_TABLE[s][TxInput.T_XON_WAIT].action != T.IMPOSSIBLE) == (s is TxState.STOPPED)
        assert (T.TX_TABLE[s][TxInput.TX_DONE].action != T.IMPOSSIBLE) == (s is TxState.SEND)
