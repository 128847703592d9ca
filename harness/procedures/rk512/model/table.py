"""The RK 512 transition tables, as data: the active side ("CPU requests", Fig. 2-18) and
the passive side ("partner requests", Fig. 2-19) of §2.2.3.

This file says, for every state and input of each side, which action the station performs
and where it goes, with the manual reference of the row and, where one applies, its STATUS
code. The two sides run side by side in one station (quasi-full-duplex, §2.2.3, Fig. 2-17):
the frame classification of §2.2.3 (byte 3: a command letter or 00h) hands every received
frame to one of them. Actions (``_a_<name>``) and decisions (``_d_<name>``, the flowcharts'
diamonds, which pick the next state) are implemented in :mod:`.core`.

A row whose action is :data:`IMPOSSIBLE` cannot occur (a timer that is not running, an
acknowledgement of a frame that was not sent); the station raises ModelError if fed one.
Acknowledgements of frames that belong to no open request (a refusal, a frame of a request
that was aborted meanwhile) do not reach the tables.
"""

from __future__ import annotations

from enum import StrEnum
from typing import NamedTuple

from ptpcert.model.codes import Code


# == active side: "CPU requests" (Fig. 2-18) ===============================================
class AState(StrEnum):
    IDLE = "A_IDLE"                              # "initial state for CPU request"
    SEND_COMMAND = "A_SEND_COMMAND"              # "CPU command frame" handed to 3964(R)
    WAIT_RESPONSE = "A_WAIT_RESPONSE"            # "waiting for response frame", T_RES running
    SEND_CONTINUATION = "A_SEND_CONTINUATION"    # "send continuation command frame"
    WAIT_CONTINUATION_RESPONSE = "A_WAIT_CONTINUATION_RESPONSE"  # "waiting for continuation response frame"


class AInput(StrEnum):
    CPU_REQUEST = "CPU_REQUEST"                  # "CPU request" (P_SND_RK, REQ)
    COMMAND_SENT = "COMMAND_SENT"                # the 3964(R) block of our command was acknowledged
    COMMAND_NOT_SENT = "COMMAND_NOT_SENT"        # 3964(R) gave up on it
    RESPONSE = "RESPONSE"                        # "response frame received" (byte 1 00h)
    CONTINUATION_RESPONSE = "CONTINUATION_RESPONSE"  # "continuation response frame received" (FFh)
    BAD_RESPONSE = "BAD_RESPONSE"                # byte 3 00h, byte 1 neither 00h nor FFh
    SHORT_RESPONSE = "SHORT_RESPONSE"            # a response of fewer than 4 bytes
    T_RES = "T_RES"                              # "T > T_RES"
    RESTART = "RESTART"                          # CP restart


# == passive side: "partner requests" (Fig. 2-19) ===========================================
class PState(StrEnum):
    IDLE = "P_IDLE"                              # "initial state for partner request"
    SEND_RESPONSE = "P_SEND_RESPONSE"            # "send response frame with(out) error message"
    WAIT_CONTINUATION = "P_WAIT_CONTINUATION"    # "waiting for continuation command frame", T_RES running


class PInput(StrEnum):
    COMMAND = "COMMAND"                          # "partner command frame received" (byte 1 00h)
    CONTINUATION = "CONTINUATION"                # continuation command frame (byte 1 FFh)
    BAD_COMMAND = "BAD_COMMAND"                  # byte 3 a letter, byte 1 neither 00h nor FFh
    SHORT_COMMAND = "SHORT_COMMAND"              # a command of fewer than 4 bytes
    RESPONSE_SENT = "RESPONSE_SENT"              # our response block was acknowledged
    RESPONSE_NOT_SENT = "RESPONSE_NOT_SENT"      # 3964(R) gave up on it
    T_RES = "T_RES"                              # "T > T_RES"
    RESTART = "RESTART"                          # CP restart


class Decision(StrEnum):
    LOCAL_CHECK = "LOCAL_CHECK"                  # Fig. 2-18: the request's parameters (classes 03, 05, 1E)
    CHECK_RESPONSE = "CHECK_RESPONSE"            # Fig. 2-18: REATEL, length; "all data transferred" / "continuation blocks"
    CHECK_COMMAND = "CHECK_COMMAND"              # Fig. 2-19: header checks, "transfer data to (from) AS" / "error"
    CHECK_CONTINUATION = "CHECK_CONTINUATION"    # Fig. 2-19: bytes 3/4 as in the first frame, data count
    AFTER_RESPONSE = "AFTER_RESPONSE"            # Fig. 2-19: "all data transferred" / "continuation blocks"
    FIRST_WHILE_WAITING = "FIRST_WHILE_WAITING"  # Fig. 2-19 "1st command frame received" (AMB-18)
    AFTER_SHORT_RESPONSE = "AFTER_SHORT_RESPONSE"  # AMB-10: a short response ends the request, or not
    AFTER_EARLY_RESPONSE = "AFTER_EARLY_RESPONSE"  # AMB-32: a response before our command was sent


#: A decision's possible outcomes, for drawing and tests.
DECISION_TARGETS: dict[Decision, tuple[str, ...]] = {
    Decision.LOCAL_CHECK: (AState.SEND_COMMAND, AState.IDLE),
    Decision.CHECK_RESPONSE: (AState.SEND_CONTINUATION, AState.IDLE),
    Decision.CHECK_COMMAND: (PState.SEND_RESPONSE,),
    Decision.CHECK_CONTINUATION: (PState.SEND_RESPONSE,),
    Decision.AFTER_RESPONSE: (PState.WAIT_CONTINUATION, PState.IDLE),
    Decision.FIRST_WHILE_WAITING: (PState.IDLE, PState.SEND_RESPONSE),
    Decision.AFTER_SHORT_RESPONSE: (AState.IDLE, AState.WAIT_RESPONSE, AState.WAIT_CONTINUATION_RESPONSE),
    Decision.AFTER_EARLY_RESPONSE: (AState.IDLE, AState.SEND_COMMAND, AState.SEND_CONTINUATION),
}

IMPOSSIBLE = "impossible"
SAME = "SAME"


class Row(NamedTuple):
    action: str
    target: str              # a state, a Decision, or SAME
    ref: str = ""            # the manual's reference for the row
    code: int | None = None  # the STATUS the row raises, where one applies


def _rows(inputs, default: Row | None = None, **by_input: Row) -> dict[str, Row]:
    out = {}
    for inp in inputs:
        out[inp] = by_input.get(inp.name, default if default is not None else Row(IMPOSSIBLE, SAME))
    unknown = set(by_input) - {i.name for i in inputs}
    assert not unknown, unknown
    return out


# -- active rows ------------------------------------------------------------------------------
_QUEUE = Row("queue_request", SAME, "§6.3.2: one P_SND_RK request at a time; the next waits")
_UNSOLICITED = Row("unsolicited_response", SAME, "Table 8-1 16#0A01: response without request",
                   Code.RESPONSE_OUT_OF_SEQUENCE)
_EARLY = Row("early_response", Decision.AFTER_EARLY_RESPONSE,
             "Table 8-1 16#0A01: response received before the (continuation) frame was sent (AMB-32)",
             Code.RESPONSE_OUT_OF_SEQUENCE)
_NOT_SENT = Row("fail_request", AState.IDLE, "Table 8-1 16#051A: error sending the command frame",
                Code.COMMAND_NOT_SENT)
_TIMEOUT = Row("fail_request", AState.IDLE, "Fig. 2-18 'T > T_RES'; Table 8-1 16#0A05",
               Code.RESPONSE_TIMEOUT)
_BAD = Row("fail_request", AState.IDLE, "Table 8-1 16#0A02: response byte 1 not 00h/FFh",
           Code.RESPONSE_STRUCTURE)
_SHORT = Row("short_response", Decision.AFTER_SHORT_RESPONSE,
             "Table 8-1 16#0610: response frame shorter than 4 bytes (AMB-10/19)", Code.FRAME_TOO_SHORT)
_A_RESTART = Row("abort_for_restart", AState.IDLE, "Table 8-1 16#0501: request aborted by CP restart",
                 Code.ABORTED_BY_CP_RESTART)
_A_SENDING = dict(
    CPU_REQUEST=_QUEUE,
    RESPONSE=_EARLY, CONTINUATION_RESPONSE=_EARLY, BAD_RESPONSE=_EARLY, SHORT_RESPONSE=_EARLY,
    COMMAND_NOT_SENT=_NOT_SENT,
    T_RES=_TIMEOUT,   # only with T_RES started at hand-over (AMB-17)
    RESTART=_A_RESTART,
)

ACTIVE: dict[AState, dict[AInput, Row]] = {
    AState.IDLE: _rows(
        AInput,
        CPU_REQUEST=Row("take_request", Decision.LOCAL_CHECK, "Fig. 2-18 'CPU request'"),
        RESPONSE=_UNSOLICITED, CONTINUATION_RESPONSE=_UNSOLICITED,
        BAD_RESPONSE=_UNSOLICITED, SHORT_RESPONSE=_UNSOLICITED,
        RESTART=Row("ignore", SAME, "no request to abort"),
    ),
    AState.SEND_COMMAND: _rows(
        AInput,
        COMMAND_SENT=Row("command_sent", AState.WAIT_RESPONSE, "Fig. 2-18 'CPU command frame; start T_RES'"),
        **_A_SENDING,
    ),
    AState.WAIT_RESPONSE: _rows(
        AInput,
        CPU_REQUEST=_QUEUE,
        RESPONSE=Row("response_received", Decision.CHECK_RESPONSE, "Fig. 2-18 'response frame received'"),
        CONTINUATION_RESPONSE=Row("fail_request", AState.IDLE,
                                  "Table 8-1 16#0A01: continuation response after a first command",
                                  Code.RESPONSE_OUT_OF_SEQUENCE),
        BAD_RESPONSE=_BAD,
        SHORT_RESPONSE=_SHORT,
        T_RES=_TIMEOUT,
        RESTART=_A_RESTART,
    ),
    AState.SEND_CONTINUATION: _rows(
        AInput,
        COMMAND_SENT=Row("command_sent", AState.WAIT_CONTINUATION_RESPONSE,
                         "Fig. 2-18 'send continuation command frame; start T_RES'"),
        **_A_SENDING,
    ),
    AState.WAIT_CONTINUATION_RESPONSE: _rows(
        AInput,
        CPU_REQUEST=_QUEUE,
        CONTINUATION_RESPONSE=Row("response_received", Decision.CHECK_RESPONSE,
                                  "Fig. 2-18 'continuation response frame received'"),
        RESPONSE=Row("fail_request", AState.IDLE,
                     "Fig. 2-18 '1st response frame received'; Table 8-1 16#0A01",
                     Code.RESPONSE_OUT_OF_SEQUENCE),
        BAD_RESPONSE=_BAD,
        SHORT_RESPONSE=_SHORT,
        T_RES=_TIMEOUT,
        RESTART=_A_RESTART,
    ),
}

# -- passive rows -----------------------------------------------------------------------------
_BAD_ID = Row("refuse_bad_id", SAME, "Table 8-1 16#0601: command byte 1 not 00h/FFh; Table 8-3 10h",
              Code.CMD_BYTE1_INVALID)
_SHORT_CMD = Row("refuse_short", SAME, "Table 8-1 16#0610: command frame too short (AMB-10)",
                 Code.FRAME_TOO_SHORT)
_P_RESTART = Row("drop_partner_request", PState.IDLE, "CP restart: the partner request is lost")

PASSIVE: dict[PState, dict[PInput, Row]] = {
    PState.IDLE: _rows(
        PInput,
        COMMAND=Row("take_command", Decision.CHECK_COMMAND, "Fig. 2-19 'partner command frame received'"),
        CONTINUATION=Row("refuse_sequence", SAME,
                         "Table 8-1 16#060E: 1st frame expected, continuation came; Table 8-3 36h",
                         Code.PARTNER_SEQUENCE_ERROR),
        BAD_COMMAND=_BAD_ID,
        SHORT_COMMAND=_SHORT_CMD,
        RESTART=Row("ignore", SAME, "no partner request open"),
    ),
    PState.SEND_RESPONSE: _rows(
        PInput,
        COMMAND=Row("refuse_pipelined", SAME,
                    "Table 8-1 16#060E: new command before the response was sent; Table 8-3 36h",
                    Code.PARTNER_SEQUENCE_ERROR),
        CONTINUATION=Row("refuse_pipelined", SAME,
                         "Table 8-1 16#060E: continuation before the response was sent; Table 8-3 36h",
                         Code.PARTNER_SEQUENCE_ERROR),
        BAD_COMMAND=_BAD_ID,
        SHORT_COMMAND=_SHORT_CMD,
        RESPONSE_SENT=Row("response_sent", Decision.AFTER_RESPONSE, "Fig. 2-19 'send response frame'"),
        RESPONSE_NOT_SENT=Row("response_not_sent", PState.IDLE,
                              "Table 8-1 16#0612: error sending the (continuation) response",
                              Code.RESPONSE_NOT_SENT),
        RESTART=_P_RESTART,
    ),
    PState.WAIT_CONTINUATION: _rows(
        PInput,
        CONTINUATION=Row("take_continuation", Decision.CHECK_CONTINUATION,
                         "Fig. 2-19 'continuation (command) frame received' (AMB-30)"),
        COMMAND=Row("first_while_waiting", Decision.FIRST_WHILE_WAITING,
                    "Fig. 2-19 '1st command frame received: abort with error'; Table 8-1 16#060E (AMB-18)",
                    Code.PARTNER_SEQUENCE_ERROR),
        BAD_COMMAND=_BAD_ID,
        SHORT_COMMAND=_SHORT_CMD,
        T_RES=Row("continuation_timeout", PState.IDLE, "Fig. 2-19 'T > T_RES: abort with error' (AMB-18)"),
        RESTART=_P_RESTART,
    ),
}


def rows():
    """Every (side, state, input, row), in table order."""
    for side, table in (("active", ACTIVE), ("passive", PASSIVE)):
        for state, by_input in table.items():
            for inp, row in by_input.items():
                yield side, state, inp, row


def _check() -> None:
    assert set(ACTIVE) == set(AState) and set(PASSIVE) == set(PState)
    for side, state, inp, row in rows():
        states = AState if side == "active" else PState
        t = row.target
        assert t == SAME or t in set(states) or t in set(Decision), (side, state, inp, t)


_check()
