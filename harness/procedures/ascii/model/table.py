"""The ASCII driver's transition tables, as data.

Three independent machines run side by side in one driver (full duplex, §2.1):

* the **receiver**, one table per end criterion (Fig. 2-21 "expiry of character delay
  time", Fig. 2-22 "end character(s)", Fig. 2-23 "fixed message frame length");
* the **sender** (Fig. 2-20, the send rules of §2.2.4 and, for the automatic use of the
  V.24 signals, Fig. 2-24);
* the **receive-side flow control** (§2.2.4 "data flow control / handshaking"): when the
  driver sends XON/XOFF or switches RTS.

Each row names the action the station performs, where it goes, the manual's reference and,
where the row raises one, the STATUS code (Table 8-1). Actions (``_rx_<action>``,
``_tx_<action>``, ``_fc_<action>``) and decisions (``_d_<decision>``, a diamond of the
flowchart that picks the next state) are implemented in :mod:`.station`. A row whose action
is :data:`IMPOSSIBLE` cannot occur (a timer that is not running in that state); the station
raises :class:`~ptpcert.model.errors.ModelError` if it is ever fed one.

Inputs are classified by the station before the table is consulted: a received character
is END when it completes the end criterion (the end character, the second of two end
characters right after the first, the N-th character of a fixed-length frame), XON/XOFF
codes (with XON/XOFF flow control) go to the sender as STOP/GO and never reach the receiver.
"""

from __future__ import annotations

from enum import StrEnum
from typing import NamedTuple

from ptpcert.model.codes import Code


# ======================================================================= receiver
class RxState(StrEnum):
    WAIT_CHAR = "WAIT_CHAR"    # Figs. 2-21..2-23 "wait for a character"
    RECEIVE = "RECEIVE"        # a frame is coming in; the CDT runs after every character
    DISCARD = "DISCARD"        # a character error (or no room) spoiled the frame: receive it
                               # to its end, discard it, then report (Figs. 2-21..2-23)
    OFF = "OFF"                # automatic V.24 with DSR = OFF: nothing is received (§2.2.4)


class RxInput(StrEnum):
    CHAR = "CHAR"              # a character received intact that does not end the frame
    END = "END"                # a character received intact that completes the end criterion
    INVALID = "INVALID"        # a character with a parity, framing or overrun error
    INVALID_END = "INVALID_END"  # fixed length: such a character is the N-th of its frame
    BREAK = "BREAK"            # the receive line is interrupted
    T_CDT = "T_CDT"            # the character delay time expired
    DSR_OFF = "DSR_OFF"        # automatic V.24: DSR went OFF
    DSR_ON = "DSR_ON"          # automatic V.24: DSR went ON


class RxDecision(StrEnum):
    ROOM = "ROOM"              # after storing a character: did it fit (frame <= 1024 bytes,
                               # room in the buffer)? RECEIVE, or DISCARD (spoiled)


# ======================================================================= sender
class TxState(StrEnum):
    IDLE = "IDLE"                  # Fig. 2-20 "wait for a send request"
    PAUSE = "PAUSE"                # §2.2.4: the next frame waits until the CDT pause is over
    RTS_ON_WAIT = "RTS_ON_WAIT"    # Fig. 2-24: RTS ON, data output waiting time running
    SEND = "SEND"                  # Fig. 2-20 "send user data"
    STOPPED = "STOPPED"            # §2.2.4: XOFF / CTS OFF, wait for XON / CTS ON
    RTS_OFF_WAIT = "RTS_OFF_WAIT"  # Fig. 2-24: all sent, time to RTS OFF running


class TxInput(StrEnum):
    SEND_REQUEST = "SEND_REQUEST"  # P_SND_RK handed over a job (Fig. 2-20)
    TX_DONE = "TX_DONE"            # the last stop bit of the frame is out
    T_PAUSE = "T_PAUSE"            # the pause between frames is over
    T_DOW = "T_DOW"                # the data output waiting time is over (Fig. 2-24)
    T_RTS_OFF = "T_RTS_OFF"        # the time to RTS OFF is over (Fig. 2-24)
    T_XON_WAIT = "T_XON_WAIT"      # the wait time for XON / CTS = ON is over (Table 2-9)
    STOP = "STOP"                  # XOFF received (XON/XOFF) or CTS OFF (RTS/CTS)
    GO = "GO"                      # XON received (XON/XOFF) or CTS ON (RTS/CTS)
    CTS_OFF = "CTS_OFF"            # automatic V.24: CTS went OFF
    CTS_ON = "CTS_ON"              # automatic V.24: CTS went ON
    DSR_OFF = "DSR_OFF"            # automatic V.24: DSR went OFF
    DSR_ON = "DSR_ON"              # automatic V.24: DSR went ON


class TxDecision(StrEnum):
    START = "START"          # may the frame go out now? pause over, RTS/data output waiting
                             # time (automatic V.24), the partner not stopped
    CTS_CHECK = "CTS_CHECK"  # Fig. 2-24: at the end of the data output waiting time, CTS ON?
    AFTER_SEND = "AFTER_SEND"  # Fig. 2-24: automatic V.24 holds RTS for the time to RTS OFF


# ======================================================================= receive flow control
class FcState(StrEnum):
    OPEN = "OPEN"      # XON sent / RTS ON: the partner may send
    HELD = "HELD"      # XOFF sent / RTS OFF


class FcInput(StrEnum):
    START = "START"    # the driver has been parameterised (start-up)
    FULL = "FULL"      # the buffer reached a threshold (frame count or 50 bytes left)
    ROOM = "ROOM"      # the buffer is below both thresholds after a read or a discard


IMPOSSIBLE = "impossible"
SAME = "SAME"


class Row(NamedTuple):
    action: str
    target: str          # a state, a decision, or SAME
    ref: str             # the manual's reference
    #: the STATUS code the row raises, where one applies; a row that reports a spoiled
    #: frame raises the error noted first in it, usually this one (16#080C), else 16#080A
    #: (no room) or 16#0816 (longer than 1024 bytes)
    code: int | None = None


def _fill(states, inputs, rows: dict) -> dict:
    out = {}
    for s in states:
        out[s] = {}
        for i in inputs:
            out[s][i] = rows.get((s, i), Row(IMPOSSIBLE, SAME, ""))
    return out


# ----------------------------------------------------------------------- receiver rows
_S, _I = RxState, RxInput
_REF_DSR = "§2.2.4 automatic use of the V.24 signals"


def _rx_common() -> dict:
    """The rows every end criterion shares."""
    r = {}
    for s in (_S.WAIT_CHAR, _S.RECEIVE, _S.DISCARD):
        r[(s, _I.DSR_ON)] = Row("ignore", SAME, _REF_DSR)
    r[(_S.WAIT_CHAR, _I.CHAR)] = Row("begin_frame", RxDecision.ROOM, "§2.2.4; Figs. 2-21..2-23")
    r[(_S.WAIT_CHAR, _I.INVALID)] = Row("begin_spoiled", _S.DISCARD, "§2.2.4; Figs. 2-21..2-23",
                                        Code.CHARACTER_ERROR)
    r[(_S.WAIT_CHAR, _I.BREAK)] = Row("report_break", _S.WAIT_CHAR, "Table 8-1 (08)0DH", Code.LINE_BREAK)
    r[(_S.WAIT_CHAR, _I.DSR_OFF)] = Row("receiver_off", _S.OFF, _REF_DSR)
    r[(_S.RECEIVE, _I.CHAR)] = Row("store", RxDecision.ROOM, "§2.2.4; Figs. 2-21..2-23")
    r[(_S.RECEIVE, _I.INVALID)] = Row("spoil", _S.DISCARD, "Figs. 2-21..2-23; Table 8-1 (08)0CH",
                                      Code.CHARACTER_ERROR)
    r[(_S.RECEIVE, _I.BREAK)] = Row("abandon_frame", _S.WAIT_CHAR, "Table 8-1 (08)0DH", Code.LINE_BREAK)
    r[(_S.RECEIVE, _I.DSR_OFF)] = Row("abort_reception", _S.OFF, _REF_DSR + "; Table 8-1 (08)18H",
                                      Code.DSR_CTS_DROPPED)
    r[(_S.DISCARD, _I.CHAR)] = Row("discard", SAME, "Figs. 2-21..2-23")
    r[(_S.DISCARD, _I.INVALID)] = Row("discard_invalid", SAME, "Figs. 2-21..2-23")
    r[(_S.DISCARD, _I.BREAK)] = Row("abandon_frame", _S.WAIT_CHAR, "Table 8-1 (08)0DH", Code.LINE_BREAK)
    r[(_S.DISCARD, _I.DSR_OFF)] = Row("abort_reception", _S.OFF, _REF_DSR + "; Table 8-1 (08)18H",
                                      Code.DSR_CTS_DROPPED)
    for i in (_I.CHAR, _I.END, _I.INVALID, _I.INVALID_END):
        r[(_S.OFF, i)] = Row("ignore", SAME, _REF_DSR + ": data is received only while DSR = ON")
    r[(_S.OFF, _I.BREAK)] = Row("report_break", SAME, "Table 8-1 (08)0DH", Code.LINE_BREAK)
    r[(_S.OFF, _I.DSR_ON)] = Row("receiver_on", _S.WAIT_CHAR, _REF_DSR)
    r[(_S.OFF, _I.DSR_OFF)] = Row("ignore", SAME, _REF_DSR)
    return r


def _rx_cdt() -> dict:
    """Fig. 2-21: the end of a frame is a pause of at least the CDT."""
    r = _rx_common()
    r[(_S.RECEIVE, _I.T_CDT)] = Row("frame_complete", _S.WAIT_CHAR,
                                    "§2.2.4 expiry of the character delay time; Fig. 2-21")
    r[(_S.DISCARD, _I.T_CDT)] = Row("report_spoiled", _S.WAIT_CHAR,
                                    "Fig. 2-21: after an error, wait for the CDT to expire, then report",
                                    Code.CHARACTER_ERROR)
    return r


def _rx_end_chars() -> dict:
    """Fig. 2-22: the end character(s) end a frame; the CDT watches for fragments."""
    r = _rx_common()
    ref = "§2.2.4 end character; Fig. 2-22"
    r[(_S.WAIT_CHAR, _I.END)] = Row("complete_frame", _S.WAIT_CHAR, ref)
    r[(_S.RECEIVE, _I.END)] = Row("complete_frame", _S.WAIT_CHAR, ref)
    r[(_S.RECEIVE, _I.T_CDT)] = Row("fragment_timeout", _S.WAIT_CHAR,
                                    "§2.2.4: the CDT expired before the end character: error, "
                                    "fragment discarded", Code.CDT_EXCEEDED)
    r[(_S.DISCARD, _I.END)] = Row("end_spoiled", _S.WAIT_CHAR,
                                  "Fig. 2-22: after an error, wait for a valid end character",
                                  Code.CHARACTER_ERROR)
    r[(_S.DISCARD, _I.T_CDT)] = Row("report_spoiled", _S.WAIT_CHAR,
                                    "Fig. 2-22: ... or for the CDT to expire", Code.CHARACTER_ERROR)
    return r


def _rx_fixed_length() -> dict:
    """Fig. 2-23: the N-th character ends a frame; the CDT watches for fragments."""
    r = _rx_common()
    ref = "§2.2.4 fixed message frame length; Fig. 2-23"
    r[(_S.WAIT_CHAR, _I.END)] = Row("complete_frame", _S.WAIT_CHAR, ref)
    r[(_S.WAIT_CHAR, _I.INVALID_END)] = Row("report_spoiled_at_once", _S.WAIT_CHAR,
                                            "Fig. 2-23; Table 8-1 (08)0CH", Code.CHARACTER_ERROR)
    r[(_S.RECEIVE, _I.END)] = Row("complete_frame", _S.WAIT_CHAR, ref)
    r[(_S.RECEIVE, _I.INVALID_END)] = Row("report_spoiled_at_once", _S.WAIT_CHAR,
                                          "Fig. 2-23; Table 8-1 (08)0CH", Code.CHARACTER_ERROR)
    r[(_S.RECEIVE, _I.T_CDT)] = Row("fragment_timeout", _S.WAIT_CHAR,
                                    "§2.2.4: the CDT expired before N characters: error, "
                                    "fragment discarded", Code.CDT_EXCEEDED)
    r[(_S.DISCARD, _I.END)] = Row("end_spoiled", _S.WAIT_CHAR,
                                  "Fig. 2-23: after an error, wait for the configured number of characters",
                                  Code.CHARACTER_ERROR)
    r[(_S.DISCARD, _I.INVALID_END)] = Row("end_spoiled_invalid", _S.WAIT_CHAR, "Fig. 2-23",
                                          Code.CHARACTER_ERROR)
    r[(_S.DISCARD, _I.T_CDT)] = Row("report_spoiled", _S.WAIT_CHAR,
                                    "Fig. 2-23: ... or for the CDT to expire", Code.CHARACTER_ERROR)
    return r


RX_TABLES: dict[str, dict[RxState, dict[RxInput, Row]]] = {
    "cdt": _fill(RxState, RxInput, _rx_cdt()),
    "end_chars": _fill(RxState, RxInput, _rx_end_chars()),
    "fixed_length": _fill(RxState, RxInput, _rx_fixed_length()),
}
RX_DECISION_TARGETS = {RxDecision.ROOM: (RxState.RECEIVE, RxState.DISCARD)}


# ----------------------------------------------------------------------- sender rows
_T, _J = TxState, TxInput
_REF_FC = "§2.2.4 data flow control"
_REF_V24 = "§2.2.4 automatic use of the V.24 signals; Fig. 2-24"


def _tx() -> dict:
    r = {}
    busy = (_T.PAUSE, _T.RTS_ON_WAIT, _T.SEND, _T.STOPPED, _T.RTS_OFF_WAIT)
    for s in busy:
        r[(s, _J.SEND_REQUEST)] = Row("queue_job", SAME, "§6.3.1: one P_SND_RK; the next job waits")
        r[(s, _J.DSR_OFF)] = Row("abort_on_dsr", _T.IDLE, _REF_V24 + "; Table 8-1 (08)18H",
                                 Code.DSR_CTS_DROPPED)
    for s in _T:
        r[(s, _J.DSR_ON)] = Row("ignore", SAME, _REF_V24)
        if s not in (_T.SEND,):
            r[(s, _J.CTS_ON)] = Row("ignore", SAME, _REF_V24)
        if s not in (_T.SEND, _T.RTS_ON_WAIT):
            r[(s, _J.CTS_OFF)] = Row("ignore", SAME, _REF_V24 + ": the CP does not wait for CTS OFF")
        if s not in (_T.SEND, _T.STOPPED):
            r[(s, _J.STOP)] = Row("partner_stopped", SAME, _REF_FC)
            r[(s, _J.GO)] = Row("partner_ready", SAME, _REF_FC)
    r[(_T.IDLE, _J.SEND_REQUEST)] = Row("start_job", TxDecision.START, "Fig. 2-20; §2.2.4")
    r[(_T.IDLE, _J.DSR_OFF)] = Row("ignore", SAME, _REF_V24)
    r[(_T.PAUSE, _J.T_PAUSE)] = Row("pause_over", TxDecision.START,
                                    "§2.2.4: the next frame waits for more than the CDT")
    r[(_T.RTS_ON_WAIT, _J.T_DOW)] = Row("output_wait_over", TxDecision.CTS_CHECK, _REF_V24)
    r[(_T.RTS_ON_WAIT, _J.CTS_OFF)] = Row("ignore", SAME, _REF_V24 + ": CTS is checked when the time is over")
    r[(_T.SEND, _J.TX_DONE)] = Row("frame_sent", TxDecision.AFTER_SEND, "Fig. 2-20; §6.3: DONE")
    r[(_T.SEND, _J.STOP)] = Row("interrupt", _T.STOPPED, _REF_FC + ": the CP interrupts the transmission")
    r[(_T.SEND, _J.GO)] = Row("ignore", SAME, _REF_FC)
    r[(_T.SEND, _J.CTS_OFF)] = Row("abort_on_cts", _T.IDLE,
                                   _REF_V24 + ": CTS OFF while sending; Table 8-1 (08)18H",
                                   Code.DSR_CTS_DROPPED)
    r[(_T.SEND, _J.CTS_ON)] = Row("ignore", SAME, _REF_V24)
    r[(_T.STOPPED, _J.GO)] = Row("resume", _T.SEND, _REF_FC)
    r[(_T.STOPPED, _J.STOP)] = Row("ignore", SAME, _REF_FC)
    r[(_T.STOPPED, _J.T_XON_WAIT)] = Row("wait_expired", _T.IDLE,
                                         _REF_FC + "; Table 2-9; Table 8-1 (07)08H",
                                         Code.XON_CTS_WAIT_EXPIRED)
    r[(_T.RTS_OFF_WAIT, _J.T_RTS_OFF)] = Row("rts_off", _T.IDLE, _REF_V24)
    return r


TX_TABLE: dict[TxState, dict[TxInput, Row]] = _fill(TxState, TxInput, _tx())
TX_DECISION_TARGETS = {
    TxDecision.START: (TxState.PAUSE, TxState.RTS_ON_WAIT, TxState.STOPPED, TxState.SEND),
    TxDecision.CTS_CHECK: (TxState.SEND, TxState.IDLE),
    TxDecision.AFTER_SEND: (TxState.RTS_OFF_WAIT, TxState.IDLE),
}


# ----------------------------------------------------------------------- receive flow control
FC_TABLE: dict[FcState, dict[FcInput, Row]] = _fill(FcState, FcInput, {
    (FcState.OPEN, FcInput.START): Row("let_partner_send", FcState.OPEN,
                                       _REF_FC + ": XON / RTS ON once parameterised"),
    (FcState.OPEN, FcInput.FULL): Row("hold_partner", FcState.HELD,
                                      _REF_FC + ": XOFF / RTS OFF at the frame count or 50 bytes left"),
    (FcState.OPEN, FcInput.ROOM): Row("room_while_open", FcState.OPEN, _REF_FC),
    (FcState.HELD, FcInput.FULL): Row("ignore", SAME, _REF_FC),
    (FcState.HELD, FcInput.ROOM): Row("let_partner_send", FcState.OPEN,
                                      _REF_FC + ": XON / RTS ON once a frame has been read"),
})


def rows():
    """Every (machine, state, input, row), in table order (the receiver once per criterion)."""
    for crit, table in RX_TABLES.items():
        for s, by_input in table.items():
            for i, row in by_input.items():
                yield f"rx.{crit}", s, i, row
    for s, by_input in TX_TABLE.items():
        for i, row in by_input.items():
            yield "tx", s, i, row
    for s, by_input in FC_TABLE.items():
        for i, row in by_input.items():
            yield "fc", s, i, row


def _check() -> None:
    targets = {"rx": set(RxState) | set(RxDecision), "tx": set(TxState) | set(TxDecision),
               "fc": set(FcState)}
    for machine, s, i, row in rows():
        allowed = targets[machine.split(".")[0]]
        assert row.target == SAME or row.target in allowed, (machine, s, i, row)


_check()
