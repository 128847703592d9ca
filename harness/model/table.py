"""The 3964 / 3964R transition table (3964r.md §12, Figs. 2-9 to 2-12), as data.

This file does only one thing: it says, for every state and every input, which action the
station performs and where it goes. States and inputs are named as the manual's flowcharts
name them. Actions and decisions are implemented in :mod:`ptpcert.model.station`; a
decision is a branch point of the flowchart (a diamond) that picks the next state.

A row whose action is :data:`IMPOSSIBLE` cannot occur: the input is a timer that is not
running in that state, or a local event that the state cannot see. The station raises
:class:`~ptpcert.model.station.ModelError` if it is ever fed one.
"""

from __future__ import annotations

from typing import NamedTuple

# -- states ------------------------------------------------------------------------------
START_UP = "START_UP"                  # Fig. 2-9: read parameters, initialise interface
IDLE = "IDLE"                          # Fig. 2-11 "wait (idle)"
IDLE_JUNK = "IDLE_JUNK"                # §8.1: stray character seen, wait for CDT of quiet
WAIT_SETUP_ACK = "WAIT_SETUP_ACK"      # Fig. 2-10 "send STX, start T_ADT, wait for acknowledgment"
SEND_DATA = "SEND_DATA"                # Fig. 2-10 "send block, possibly with doubled DLE; DLE ETX; BCC"
ABORT_QUIET = "ABORT_QUIET"            # §7.2 item 4: character during send, wait for CDT of quiet
WAIT_RELEASE_ACK = "WAIT_RELEASE_ACK"  # Fig. 2-10 "start T_ADT, wait for acknowledgment" (release)
WAIT_BUFFER = "WAIT_BUFFER"            # Fig. 2-11 "start T_NAKTIM, wait" (no free receive buffer)
RECEIVE = "RECEIVE"                    # Fig. 2-12 "wait to receive"
WAIT_ETX = "WAIT_ETX"                  # Fig. 2-12 "wait for ETX" (a DLE was received)
WAIT_BCC = "WAIT_BCC"                  # Fig. 2-12 "wait for BCC" (3964R)
WAIT_REPETITION = "WAIT_REPETITION"    # Fig. 2-12 "note repetition expected, start T_BLOCK, wait for STX"

STATES = (
    START_UP, IDLE, IDLE_JUNK,
    WAIT_SETUP_ACK, SEND_DATA, ABORT_QUIET, WAIT_RELEASE_ACK,
    WAIT_BUFFER, RECEIVE, WAIT_ETX, WAIT_BCC, WAIT_REPETITION,
)
SENDER_STATES = (WAIT_SETUP_ACK, SEND_DATA, ABORT_QUIET, WAIT_RELEASE_ACK)
RECEIVER_STATES = (WAIT_BUFFER, RECEIVE, WAIT_ETX, WAIT_BCC, WAIT_REPETITION)

# -- inputs ------------------------------------------------------------------------------
# Characters received without error, by value:
STX, DLE, ETX, NAK = "STX", "DLE", "ETX", "NAK"
OTHER = "OTHER"                # any other character value
INVALID = "INVALID"            # Fig. 2-10/2-12 "invalid character": parity/framing/overrun error
BREAK = "BREAK"                # line break (§10 item 5)
# Timer expiries (§5):
T_ADT, T_CDT, T_NAKTIM, T_BLOCK = "T_ADT", "T_CDT", "T_NAKTIM", "T_BLOCK"
# Local events:
POWER_ON = "POWER_ON"          # Fig. 2-9 "switch-on after CPU restart or power restoration"
SEND_REQUEST = "SEND_REQUEST"  # Fig. 2-10/2-11 "send request" (P_SND_RK handed over a job)
BUFFER_FREE = "BUFFER_FREE"    # Fig. 2-11 "buffer free"
TX_DONE = "TX_DONE"            # the last byte of the end sequence has left the transmitter

CHARACTERS = (STX, DLE, ETX, NAK, OTHER)
INPUTS = CHARACTERS + (INVALID, BREAK, T_ADT, T_CDT, T_NAKTIM, T_BLOCK,
                       POWER_ON, SEND_REQUEST, BUFFER_FREE, TX_DONE)

# -- decisions (flowchart diamonds); each picks the next state ---------------------------
SETUP_CHECK = "SETUP_CHECK"        # Fig. 2-10 "X <= n / X > n": STX again, or NAK and give up
TX_CHECK = "TX_CHECK"              # Fig. 2-10 second diamond, on W (A3): STX again, or NAK and give up
PRIORITY = "PRIORITY"              # Fig. 2-10 "high priority / low priority" (§9)
RECEIVE_ENTRY = "RECEIVE_ENTRY"    # Fig. 2-11 "buffer free / buffer not free"
AFTER_ETX = "AFTER_ETX"            # Fig. 2-12 "3964 / 3964R"
BCC_CHECK = "BCC_CHECK"            # Fig. 2-12 "BCC" vs "BCC incorrect"
EVALUATE = "EVALUATE"              # Fig. 2-12 "NAK noted?"
NAK_CHECK = "NAK_CHECK"            # Fig. 2-12 "send NAK; W > n / W <= n"
IN_END_SEQUENCE = "IN_END_SEQUENCE"  # A10: has the end sequence started?
IDLE_CHAR_ERROR = "IDLE_CHAR_ERROR"  # A13: NAK after an invalid character in idle?

DECISIONS = (SETUP_CHECK, TX_CHECK, PRIORITY, RECEIVE_ENTRY, AFTER_ETX, BCC_CHECK,
             EVALUATE, NAK_CHECK, IN_END_SEQUENCE, IDLE_CHAR_ERROR)

#: A decision's possible outcomes (states or further decisions), for drawing and tests.
DECISION_TARGETS = {
    SETUP_CHECK: (WAIT_SETUP_ACK, IDLE),
    TX_CHECK: (WAIT_SETUP_ACK, IDLE),
    PRIORITY: (WAIT_SETUP_ACK, RECEIVE_ENTRY),
    RECEIVE_ENTRY: (RECEIVE, WAIT_BUFFER),
    AFTER_ETX: (EVALUATE, WAIT_BCC),
    BCC_CHECK: (EVALUATE, NAK_CHECK),
    EVALUATE: (IDLE, NAK_CHECK),
    NAK_CHECK: (WAIT_REPETITION, IDLE),
    IN_END_SEQUENCE: (TX_CHECK, ABORT_QUIET),
    IDLE_CHAR_ERROR: (IDLE_JUNK, IDLE),
}

IMPOSSIBLE = "impossible"
SAME = "SAME"   # stay in the current state


class Row(NamedTuple):
    action: str
    target: str  # a state, a decision, or SAME


def _rows(default: Row | None = None, **by_input: Row) -> dict[str, Row]:
    rows = {}
    for inp in INPUTS:
        if inp in by_input:
            rows[inp] = by_input[inp]
        elif default is not None and inp in CHARACTERS + (INVALID,):
            rows[inp] = default
        else:
            rows[inp] = Row(IMPOSSIBLE, SAME)
    return rows


_IGNORE = Row("ignore", SAME)
_QUEUE = Row("queue_job", SAME)            # §8.1 item 6: a job waits until the station is idle
_RX_BREAK = Row("abandon_reception", IDLE)  # §10 item 5: back to idle, no NAK, 16#080D

TABLE: dict[str, dict[str, Row]] = {
    START_UP: _rows(
        _IGNORE,  # the interface is not initialised yet: nothing is received
        POWER_ON=Row("send_startup_nak", IDLE),      # Fig. 2-9, §6
        BREAK=_IGNORE,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    IDLE: _rows(
        Row("start_quiet_wait", IDLE_JUNK),          # §8.1 item 3: stray character
        STX=Row("begin_reception", RECEIVE_ENTRY),   # §8.2 item 1
        NAK=_IGNORE,                                 # §8.1 item 2
        INVALID=Row("report_invalid_in_idle", IDLE_CHAR_ERROR),  # §8.1 item 4, A13
        BREAK=Row("report_break", IDLE),             # §10 item 5
        SEND_REQUEST=Row("start_job", WAIT_SETUP_ACK),  # Fig. 2-10 "send request; W:=1; X:=1; send STX"
        BUFFER_FREE=_IGNORE,
    ),
    IDLE_JUNK: _rows(
        Row("restart_quiet_wait", SAME),             # A7: every character restarts the wait
        T_CDT=Row("quiet_nak", IDLE),                # §8.1 item 3: NAK, 16#0802
        BREAK=Row("report_break", IDLE),
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    WAIT_SETUP_ACK: _rows(
        Row("setup_refused", SETUP_CHECK),           # §7.1 item 3: NAK or other character, 16#0702
        DLE=Row("setup_acknowledged", SEND_DATA),    # §7.1 item 2
        STX=Row("initialization_conflict", PRIORITY),  # §9
        INVALID=Row("setup_invalid_character", SETUP_CHECK),  # §7.1 item 3, 16#080C
        T_ADT=Row("setup_timeout", SETUP_CHECK),     # §7.1 item 3, 16#0703
        BREAK=Row("abort_job", IDLE),                # §7.6
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    SEND_DATA: _rows(
        Row("send_interrupted", ABORT_QUIET),        # §7.2 item 4: other character, 16#0704
        NAK=Row("send_refused", TX_CHECK),           # §7.2 item 3: stop, no NAK, new STX
        DLE=Row("dle_during_send", IN_END_SEQUENCE),  # A10
        TX_DONE=Row("block_sent", WAIT_RELEASE_ACK),  # Fig. 2-10 "send BCC, start T_ADT"
        BREAK=Row("abort_job", IDLE),
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    ABORT_QUIET: _rows(
        Row("restart_quiet_wait", SAME),             # A7
        T_CDT=Row("abort_nak", TX_CHECK),            # §7.2 item 4: NAK, then a new attempt
        BREAK=Row("abort_job", IDLE),
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    WAIT_RELEASE_ACK: _rows(
        Row("release_refused", TX_CHECK),            # §7.3 item 4: NAK or any character but DLE, 16#0706
        DLE=Row("release_acknowledged", IDLE),       # §7.3 item 3: job done
        INVALID=Row("release_invalid_character", TX_CHECK),  # §7.3 item 4, 16#080C
        T_ADT=Row("release_timeout", TX_CHECK),      # §7.3 item 4, 16#0707
        BREAK=Row("abort_job", IDLE),
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    WAIT_BUFFER: _rows(
        Row("setup_garbage", IDLE_JUNK),             # §8.2 item 4, A16: 16#0802
        BUFFER_FREE=Row("buffer_freed", RECEIVE),    # Fig. 2-11 "buffer free: send DLE"
        T_NAKTIM=Row("no_buffer", IDLE),             # §8.2 item 2: NAK, 16#080A
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
    ),
    RECEIVE: _rows(
        Row("store", SAME),                          # §8.3 item 1: STX, ETX, NAK are data here
        DLE=Row("dle_received", WAIT_ETX),           # Fig. 2-12 "DLE"
        INVALID=Row("note_invalid_character", SAME),  # §8.3 item 4: keep receiving, 16#080C
        T_CDT=Row("character_timeout", NAK_CHECK),   # §8.3 item 5, A2: 16#0806
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    WAIT_ETX: _rows(
        Row("dle_followed_by_other", RECEIVE),       # §8.3 item 3, A11: 16#0805
        DLE=Row("store_doubled_dle", RECEIVE),       # Fig. 2-12 "dual DLE"
        ETX=Row("end_of_text", AFTER_ETX),           # Fig. 2-12 "ETX"
        INVALID=Row("note_invalid_character", RECEIVE),
        T_CDT=Row("character_timeout", NAK_CHECK),
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    WAIT_BCC: _rows(
        Row("bcc_received", BCC_CHECK),              # §8.4 item 2: any value is the BCC
        INVALID=Row("bcc_invalid_character", NAK_CHECK),
        T_CDT=Row("character_timeout", NAK_CHECK),   # Fig. 2-12 "T > T_CDT"
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
    WAIT_REPETITION: _rows(
        Row("start_quiet_wait", IDLE_JUNK),          # A19: treated as in idle
        STX=Row("repetition_begins", RECEIVE_ENTRY),  # §8.5 item 2: W+1
        NAK=Row("partner_gave_up", IDLE),            # A19: 16#0815
        INVALID=Row("report_invalid_in_idle", IDLE_CHAR_ERROR),  # A19: as in idle
        T_BLOCK=Row("repetition_timeout", IDLE),     # §8.5 item 3
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_IGNORE,
    ),
}


def rows():
    """Every (state, input, row) triple, in table order."""
    for state in STATES:
        for inp in INPUTS:
            yield state, inp, TABLE[state][inp]


def _check() -> None:
    assert set(TABLE) == set(STATES), "every state has rows"
    for state, inp, row in rows():
        t = row.target
        assert t in STATES or t in DECISIONS or t == SAME, (state, inp, t)


_check()
