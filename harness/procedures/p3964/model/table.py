"""The 3964 / 3964R transition table (the manual's Figs. 2-9 to 2-12), as data.

This file does only one thing, and is one piece on purpose although long: it says, for
every state and every input, which action the station performs and where it goes, and for
every decision (a diamond of the flowcharts) where each of its outcomes leads. States, inputs and decisions are named as the manual's
flowcharts name them. Each row and each outcome carries, as data:

* ``ref``: where the manual states the rule (section, figure, table);
* ``code``: the STATUS event of Table 8-1 it raises, where one applies. With ``noted`` the
  receiver only notes the error when the row fires (Fig. 2-12 "note NAK") and raises it with
  the NAK at the end of the block;
* ``sends`` and ``rule``: the characters it puts on the line (``"block"``: the data block) and
  the rule they follow, in one sentence. A row that only leads into a decision names the
  characters that decision sends when the row is the more specific rule for them;
* ``rules``: the ids of the manual's rules the row or outcome implements, from the rules
  catalogue (``ptpcert rules``; a test checks that every id exists there).

Actions and decisions are implemented in :mod:`.station` (``_a_<action>``,
``_d_<decision>``); nothing else decides where the station goes.

A row whose action is :data:`IMPOSSIBLE` cannot occur: the input is a timer that is not
running in that state, or a local event that the state cannot see. The station raises
:class:`~ptpcert.model.errors.ModelError` if it is ever fed one.

References name the manual: section 2.2.2 and its paragraph ("Send/setup", "Sending data",
"Send/release", "Receive/setup", "Receive/receiving data", "Receive/release",
"Initialization conflict", "Error handling"), the figures (with the label read in them), the
parameter tables 2-3/2-4 and the STATUS events of Table 8-1. An "A<n>" names the open point of
the manual whose reading (:mod:`.readings`) the row follows.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Iterator, NamedTuple

from ptpcert.model.codes import Code


class State(StrEnum):
    START_UP = "START_UP"                  # Fig. 2-9: read parameters, initialise interface
    IDLE = "IDLE"                          # Fig. 2-11 "wait (idle)"
    IDLE_JUNK = "IDLE_JUNK"                # stray character seen, wait for CDT of quiet, then NAK
    WAIT_SETUP_ACK = "WAIT_SETUP_ACK"      # Fig. 2-10 "send STX, start T_ADT, wait for acknowledgment"
    SEND_DATA = "SEND_DATA"                # Fig. 2-10 "send block, possibly with doubled DLE; DLE ETX; BCC"
    ABORT_QUIET = "ABORT_QUIET"            # character during the block: wait for CDT of quiet, then NAK
    WAIT_RELEASE_ACK = "WAIT_RELEASE_ACK"  # Fig. 2-10 "start T_ADT, wait for acknowledgment" (release)
    WAIT_BUFFER = "WAIT_BUFFER"            # Fig. 2-11 "start T_NAKTIM, wait" (no free receive buffer)
    RECEIVE = "RECEIVE"                    # Fig. 2-12 "wait to receive"
    WAIT_ETX = "WAIT_ETX"                  # Fig. 2-12 "wait for ETX" (a DLE was received)
    WAIT_BCC = "WAIT_BCC"                  # Fig. 2-12 "wait for BCC" (3964R)
    WAIT_REPETITION = "WAIT_REPETITION"    # Fig. 2-12 "note repetition expected, start T_BLOCK, wait for STX"


class Input(StrEnum):
    # characters received without error, by value
    STX = "STX"
    DLE = "DLE"
    ETX = "ETX"
    NAK = "NAK"
    OTHER = "OTHER"                # any other character value
    INVALID = "INVALID"            # Figs. 2-10/2-12 "invalid character": parity/framing/overrun error
    BREAK = "BREAK"                # line break (§2.2.2 Error handling)
    # timer expiries (Figs. 2-10 to 2-12 "T > T_ADT", ...)
    T_ADT = "T_ADT"
    T_CDT = "T_CDT"
    T_NAKTIM = "T_NAKTIM"
    T_BLOCK = "T_BLOCK"
    # local events
    POWER_ON = "POWER_ON"          # Fig. 2-9 "switch-on after CPU restart or power restoration"
    SEND_REQUEST = "SEND_REQUEST"  # Figs. 2-10/2-11 "send request" (P_SND_RK handed over a job)
    BUFFER_FREE = "BUFFER_FREE"    # Fig. 2-11 "buffer free"
    TX_DONE = "TX_DONE"            # the last byte of the end sequence has left the transmitter


class Decision(StrEnum):
    START_CHECK = "START_CHECK"          # Fig. 2-10 "send request": STX, unless a deferred job is spent (A21)
    SETUP_CHECK = "SETUP_CHECK"          # Fig. 2-10 "X <= n / X > n": STX again, or NAK and give up
    TX_CHECK = "TX_CHECK"                # Fig. 2-10 second diamond, on W (A3): STX again, or NAK and give up
    PRIORITY = "PRIORITY"                # Fig. 2-10 "high priority / low priority"
    IN_END_SEQUENCE = "IN_END_SEQUENCE"  # A10: has the end sequence started?
    RECEIVE_ENTRY = "RECEIVE_ENTRY"      # Fig. 2-11 "buffer free / buffer not free"
    ABANDON_SETUP = "ABANDON_SETUP"      # A16: characters before our DLE: give up the setup?
    NAK_AT_ONCE = "NAK_AT_ONCE"          # A11: DLE followed by another character: NAK at once?
    AFTER_ETX = "AFTER_ETX"              # Fig. 2-12 "3964 / 3964R"
    BCC_CHECK = "BCC_CHECK"              # Fig. 2-12 "BCC" vs "BCC incorrect"
    EVALUATE = "EVALUATE"                # Fig. 2-12 "NAK noted?"
    NAK_CHECK = "NAK_CHECK"              # Fig. 2-12 "send NAK; W > 5 / W <= 5"
    IDLE_CHAR_ERROR = "IDLE_CHAR_ERROR"  # A13: NAK after an invalid character in idle?


class Action(StrEnum):
    IMPOSSIBLE = "impossible"
    IGNORE = "ignore"
    QUEUE_JOB = "queue_job"
    SEND_STARTUP_NAK = "send_startup_nak"
    START_QUIET_WAIT = "start_quiet_wait"
    RESTART_QUIET_WAIT = "restart_quiet_wait"
    QUIET_NAK = "quiet_nak"
    REPORT_BREAK = "report_break"
    REPORT_INVALID_IN_IDLE = "report_invalid_in_idle"
    START_JOB = "start_job"
    SETUP_REFUSED = "setup_refused"
    SETUP_INVALID_CHARACTER = "setup_invalid_character"
    SETUP_TIMEOUT = "setup_timeout"
    INITIALIZATION_CONFLICT = "initialization_conflict"
    SETUP_ACKNOWLEDGED = "setup_acknowledged"
    SEND_REFUSED = "send_refused"
    SEND_INTERRUPTED = "send_interrupted"
    DLE_DURING_SEND = "dle_during_send"
    ABORT_NAK = "abort_nak"
    BLOCK_SENT = "block_sent"
    RELEASE_ACKNOWLEDGED = "release_acknowledged"
    RELEASE_REFUSED = "release_refused"
    RELEASE_INVALID_CHARACTER = "release_invalid_character"
    RELEASE_TIMEOUT = "release_timeout"
    ABORT_JOB = "abort_job"
    BEGIN_RECEPTION = "begin_reception"
    BUFFER_FREED = "buffer_freed"
    NO_BUFFER = "no_buffer"
    SETUP_GARBAGE = "setup_garbage"
    STORE = "store"
    DLE_RECEIVED = "dle_received"
    STORE_DOUBLED_DLE = "store_doubled_dle"
    DLE_FOLLOWED_BY_OTHER = "dle_followed_by_other"
    NOTE_INVALID_CHARACTER = "note_invalid_character"
    CHARACTER_TIMEOUT = "character_timeout"
    END_OF_TEXT = "end_of_text"
    BCC_RECEIVED = "bcc_received"
    BCC_INVALID_CHARACTER = "bcc_invalid_character"
    REPETITION_BEGINS = "repetition_begins"
    PARTNER_GAVE_UP = "partner_gave_up"
    REPETITION_TIMEOUT = "repetition_timeout"
    ABANDON_RECEPTION = "abandon_reception"


# The members under their plain names (table.IDLE, table.STX, ...), for the station's hot paths
# and for readers: an enum's class attribute costs a lookup, a module global does not.
(START_UP, IDLE, IDLE_JUNK, WAIT_SETUP_ACK, SEND_DATA, ABORT_QUIET, WAIT_RELEASE_ACK,
 WAIT_BUFFER, RECEIVE, WAIT_ETX, WAIT_BCC, WAIT_REPETITION) = State
(STX, DLE, ETX, NAK, OTHER, INVALID, BREAK, T_ADT, T_CDT, T_NAKTIM, T_BLOCK,
 POWER_ON, SEND_REQUEST, BUFFER_FREE, TX_DONE) = Input
(START_CHECK, SETUP_CHECK, TX_CHECK, PRIORITY, IN_END_SEQUENCE, RECEIVE_ENTRY, ABANDON_SETUP,
 NAK_AT_ONCE, AFTER_ETX, BCC_CHECK, EVALUATE, NAK_CHECK, IDLE_CHAR_ERROR) = Decision
IMPOSSIBLE = Action.IMPOSSIBLE
#: a row's target when the station stays in its state
SAME = "SAME"

STATES = tuple(State)
SENDER_STATES = (WAIT_SETUP_ACK, SEND_DATA, ABORT_QUIET, WAIT_RELEASE_ACK)
CHARACTERS = (STX, DLE, ETX, NAK, OTHER)
INPUTS = tuple(Input)
TIMERS = (T_ADT, T_CDT, T_NAKTIM, T_BLOCK)
DECISIONS = tuple(Decision)

#: what ``sends`` names: a control character, or the data block after the partner's DLE
BLOCK = "block"
SENDABLE = {"STX": 0x02, "DLE": 0x10, "NAK": 0x15, BLOCK: None}


class Row(NamedTuple):
    """What the station does on one input in one state."""

    action: str               # an :class:`Action` (a broken variant may name its own)
    target: str               # a :class:`State`, a :class:`Decision`, or SAME
    ref: str = ""
    code: Code | None = None
    noted: bool = False       # the code is noted now and raised with the NAK (Fig. 2-12 "note NAK")
    sends: tuple[str, ...] = ()
    rule: str = ""
    rules: tuple[str, ...] = ()  # ids of the manual's rules the row implements (ptpcert.rules)


class Branch(NamedTuple):
    """One outcome of a decision: the condition, as the flowchart labels the edge, and where
    it leads; the other fields as in :class:`Row`."""

    when: str
    target: str               # a :class:`State` or a further :class:`Decision`
    ref: str = ""
    code: Code | None = None
    noted: bool = False
    sends: tuple[str, ...] = ()
    rule: str = ""
    rules: tuple[str, ...] = ()


# -- references used by several rows -----------------------------------------------------
_BREAK = "§2.2.2 Error handling; Figs. 2-10 to 2-12 'immediate return to the initial state on BREAK'"
_NAK_RULE = "a block with an error (BCC, character error, DLE sequence, length) is refused with NAK"
_CDT_RULE = "CDT exceeded in a reception: NAK"


def _rows(default: Row | None = None, **by_input: Row) -> dict[Input, Row]:
    """One state's rows: ``default`` for every character (valid or invalid) not named."""
    rows = {}
    for inp in INPUTS:
        if inp.name in by_input:
            rows[inp] = by_input[inp.name]
        elif default is not None and inp in CHARACTERS + (INVALID,):
            rows[inp] = default
        else:
            rows[inp] = Row(IMPOSSIBLE, SAME)
    return rows


def _ignore(ref: str) -> Row:
    return Row(Action.IGNORE, SAME, ref)


# §2.2.2 Receive/setup: a send job raised while the station is busy waits until it is idle
# a send job handed over while the station is busy waits until it is idle (Fig. 2-11 takes the
# "send request" in idle only); a freed buffer matters only to a station waiting for one
_QUEUE = Row(Action.QUEUE_JOB, SAME, "§2.2.2 Receive/setup; Fig. 2-11 'send request'", rules=("3964.TX.SETUP-STX",))
_NO_BUFFER_EVENT = _ignore("Fig. 2-11 'buffer free'")
_SEND_BREAK = Row(Action.ABORT_JOB, IDLE, _BREAK + "; A15", Code.LINE_BREAK, rules=("3964.BREAK.SEND",))
_RX_BREAK = Row(Action.ABANDON_RECEPTION, IDLE, _BREAK + "; no NAK", Code.LINE_BREAK, rules=("3964.BREAK.RECEIVE",))

TABLE: dict[State, dict[Input, Row]] = {
    START_UP: _rows(
        _ignore("Fig. 2-9"),  # the interface is not initialised yet: nothing is received
        POWER_ON=Row(Action.SEND_STARTUP_NAK, IDLE, "§2.2.2 Receive, Note; Fig. 2-9 'send NAK'",
                     sends=("NAK",), rule="one NAK at start-up", rules=("3964.START.NAK",)),
        BREAK=_ignore("Fig. 2-9"),
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    IDLE: _rows(
        Row(Action.START_QUIET_WAIT, IDLE_JUNK,
            "§2.2.2 Receive/setup; Fig. 2-11 'any characters except STX or NAK'", rules=("3964.IDLE.STRAY-NAK",)),
        STX=Row(Action.BEGIN_RECEPTION, RECEIVE_ENTRY, "§2.2.2 Receive/setup; Fig. 2-11 'STX received'",
                rules=("3964.RX.SETUP-DLE", "3964.START.IDLE")),
        NAK=Row(Action.IGNORE, SAME, "§2.2.2 Receive/setup",  # NAK is not a stray character
                rules=("3964.IDLE.NAK-IGNORED",)),
        INVALID=Row(Action.REPORT_INVALID_IN_IDLE, IDLE_CHAR_ERROR,  # reported at once in idle
                    "Table 8-1 16#080C", Code.CHARACTER_ERROR,
                    rules=("3964.IDLE.CHARACTER-ERROR", "3964.IDLE.CORRUPTED-STX")),
        BREAK=Row(Action.REPORT_BREAK, IDLE, _BREAK, Code.LINE_BREAK, rules=("3964.BREAK.IDLE",)),
        SEND_REQUEST=Row(Action.START_JOB, START_CHECK,
                         "Fig. 2-10 'send request', 'W := 1', 'X := 1'; Fig. 2-11 'send request'",
                         rules=("3964.TX.SETUP-STX", "3964.TX.COUNTERS-PER-JOB")),
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    IDLE_JUNK: _rows(
        Row(Action.RESTART_QUIET_WAIT, SAME, "§2.2.2 Receive/setup; A7",  # every character restarts the wait
            rules=("3964.IDLE.QUIET-RESTARTS",)),
        T_CDT=Row(Action.QUIET_NAK, IDLE, "§2.2.2 Receive/setup; Fig. 2-11 'send NAK'",
                  Code.RX_SETUP_ERROR, sends=("NAK",),
                  rule="a stray character is answered with NAK once the line is quiet for CDT",
                  rules=("3964.IDLE.STRAY-NAK", "3964.RX.STRAY-AFTER-ANSWER")),
        BREAK=Row(Action.REPORT_BREAK, IDLE, _BREAK, Code.LINE_BREAK, rules=("3964.BREAK.IDLE",)),
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    WAIT_SETUP_ACK: _rows(
        Row(Action.SETUP_REFUSED, SETUP_CHECK,
            "§2.2.2 Send/setup; Fig. 2-10 'any character except DLE, STX'", Code.SETUP_REFUSED,
            rules=("3964.TX.SETUP-REFUSED",)),
        DLE=Row(Action.SETUP_ACKNOWLEDGED, SEND_DATA,
                "§2.2.2 Sending data; Fig. 2-10 'send block, possibly with doubled DLE', "
                "'send DLE, ETX', 'send BCC'", sends=(BLOCK,),
                rule="after the partner's DLE the block: data with each DLE doubled, DLE ETX [BCC]",
                rules=("3964.TX.BLOCK-LAYOUT", "3964.TX.DLE-DOUBLING", "3964.TX.BCC", "3964.TX.NO-BCC",
                       "3964.TX.NO-GAPS")),
        STX=Row(Action.INITIALIZATION_CONFLICT, PRIORITY,
                "§2.2.2 Initialization conflict; Fig. 2-10 'STX'",
                rules=("3964.CONFLICT.LOW-DEFERS", "3964.CONFLICT.HIGH-WAITS")),
        INVALID=Row(Action.SETUP_INVALID_CHARACTER, SETUP_CHECK,
                    "§2.2.2 Send/setup; Fig. 2-10 'invalid character'", Code.CHARACTER_ERROR,
                    rules=("3964.TX.SETUP-CHARACTER-ERROR",)),
        T_ADT=Row(Action.SETUP_TIMEOUT, SETUP_CHECK, "§2.2.2 Send/setup; Fig. 2-10 'T > T_ADT'",
                  Code.SETUP_TIMEOUT, rules=("3964.TX.SETUP-TIMEOUT", "3964.CONFLICT.HIGH-NO-DLE")),
        BREAK=_SEND_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    SEND_DATA: _rows(
        Row(Action.SEND_INTERRUPTED, ABORT_QUIET, "§2.2.2 Sending data", Code.SEND_INTERRUPTED,
            rules=("3964.TX.DATA-OTHER",)),
        # NAK: stop, no NAK of our own, a new setup
        NAK=Row(Action.SEND_REFUSED, TX_CHECK, "§2.2.2 Sending data", Code.SEND_INTERRUPTED,
                rules=("3964.TX.DATA-NAK",)),
        DLE=Row(Action.DLE_DURING_SEND, IN_END_SEQUENCE, "§2.2.2 Sending data; §2.2.2 Send/release; A10",
                rules=("3964.TX.DATA-OTHER", "3964.TX.DLE-TOO-EARLY")),
        TX_DONE=Row(Action.BLOCK_SENT, WAIT_RELEASE_ACK, "Fig. 2-10 'send BCC', 'start T_ADT'; A12",
                    rules=("3964.TX.RELEASE-WAIT",)),
        BREAK=_SEND_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    ABORT_QUIET: _rows(
        Row(Action.RESTART_QUIET_WAIT, SAME, "§2.2.2 Sending data; A7",  # every character restarts the wait
            rules=("3964.TX.QUIET-RESTARTS",)),
        T_CDT=Row(Action.ABORT_NAK, TX_CHECK, "§2.2.2 Sending data",
                  sends=("NAK",),
                  rule="after a character during its block the sender waits for CDT of quiet, then NAK",
                  rules=("3964.TX.DATA-OTHER",)),
        BREAK=_SEND_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    WAIT_RELEASE_ACK: _rows(
        Row(Action.RELEASE_REFUSED, TX_CHECK,
            "§2.2.2 Send/release; Fig. 2-10 'any character except DLE'", Code.RELEASE_REFUSED,
            rules=("3964.TX.RELEASE-REFUSED",)),
        DLE=Row(Action.RELEASE_ACKNOWLEDGED, IDLE, "§2.2.2 Send/release; Fig. 2-10 'transmission completed'",
                rules=("3964.TX.RELEASE-DLE",)),
        INVALID=Row(Action.RELEASE_INVALID_CHARACTER, TX_CHECK,
                    "§2.2.2 Send/release; Fig. 2-10 'invalid character'", Code.CHARACTER_ERROR,
                    rules=("3964.TX.RELEASE-CHARACTER-ERROR",)),
        T_ADT=Row(Action.RELEASE_TIMEOUT, TX_CHECK, "§2.2.2 Send/release; Fig. 2-10 'T > T_ADT'",
                  Code.RELEASE_TIMEOUT, rules=("3964.TX.RELEASE-TIMEOUT",)),
        BREAK=_SEND_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    WAIT_BUFFER: _rows(
        # characters after STX before the station could send its DLE
        Row(Action.SETUP_GARBAGE, ABANDON_SETUP, "Table 8-1 16#0802; A16", rules=("3964.RX.SETUP-GARBAGE",)),
        BUFFER_FREE=Row(Action.BUFFER_FREED, RECEIVE, "§2.2.2 Receive/setup; Fig. 2-11 'buffer free', 'send DLE'",
                        sends=("DLE",), rule="DLE as soon as a receive buffer is free",
                        rules=("3964.RX.BUFFER-FREED",)),
        T_NAKTIM=Row(Action.NO_BUFFER, IDLE, "§2.2.2 Receive/setup; Fig. 2-11 'T > T_NAKTIM', 'send NAK'",
                     Code.NO_RECEIVE_BUFFER, sends=("NAK",),
                     rule="with no free buffer the STX is answered with NAK after 400 ms",
                     rules=("3964.RX.NO-BUFFER",)),
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
    ),
    RECEIVE: _rows(
        # STX, ETX and NAK are data here; beyond 1024 bytes 16#0816 is noted (A17)
        Row(Action.STORE, SAME, "§2.2.2 Receive/receiving data; Fig. 2-12 'correct characters except DLE'",
            rules=("3964.RX.DLE-PAIRS-ONLY", "3964.RX.LENGTH", "3964.RX.TOO-LONG", "3964.RX.CDT-WAIT")),
        DLE=Row(Action.DLE_RECEIVED, WAIT_ETX, "Fig. 2-12 'DLE', 'wait for ETX'", rules=("3964.RX.DLE-PAIRS-ONLY",)),
        INVALID=Row(Action.NOTE_INVALID_CHARACTER, SAME,
                    "§2.2.2 Receive/receiving data; Fig. 2-12 'invalid character', 'note NAK'",
                    Code.CHARACTER_ERROR, noted=True, rules=("3964.RX.CHARACTER-ERROR",)),
        T_CDT=Row(Action.CHARACTER_TIMEOUT, NAK_CHECK, "§2.2.2 Receive/receiving data; Fig. 2-12 'T > T_CDT'; A2",
                  Code.CDT_EXCEEDED, noted=True, sends=("NAK",), rule=_CDT_RULE,
                  rules=("3964.RX.CDT-TIMEOUT", "3964.RX.FIRST-CHARACTER-TIMEOUT")),
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    WAIT_ETX: _rows(
        Row(Action.DLE_FOLLOWED_BY_OTHER, NAK_AT_ONCE,
            "§2.2.2 Control characters; Fig. 2-12 'characters except ETX, DLE', 'note NAK'",
            Code.RX_LOGICAL_ERROR, noted=True, rules=("3964.RX.DLE-OTHER",)),
        DLE=Row(Action.STORE_DOUBLED_DLE, RECEIVE, "§2.2.2 Control characters; Fig. 2-12 'dual DLE'",
                rules=("3964.RX.DLE-UNDOUBLING",)),
        ETX=Row(Action.END_OF_TEXT, AFTER_ETX, "§2.2.2 Receive/release; Fig. 2-12 'ETX'",
                rules=("3964.RX.ANSWER-AT-ETX", "3964.RX.WAIT-FOR-BCC")),
        INVALID=Row(Action.NOTE_INVALID_CHARACTER, RECEIVE, "Fig. 2-12 'invalid character', 'note NAK'",
                    Code.CHARACTER_ERROR, noted=True, rules=("3964.RX.CHARACTER-ERROR-IN-END",)),
        T_CDT=Row(Action.CHARACTER_TIMEOUT, NAK_CHECK, "§2.2.2 Receive/receiving data; Fig. 2-12 'T > T_CDT'",
                  Code.CDT_EXCEEDED, noted=True, sends=("NAK",), rule=_CDT_RULE, rules=("3964.RX.CDT-AFTER-DLE",)),
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    WAIT_BCC: _rows(
        Row(Action.BCC_RECEIVED, BCC_CHECK, "§2.2.2 Receive/release; Fig. 2-12 'BCC'",  # any value is the BCC
            rules=("3964.RX.BCC-ANY-VALUE", "3964.RX.BCC-WAIT")),
        INVALID=Row(Action.BCC_INVALID_CHARACTER, NAK_CHECK, "Fig. 2-12 'invalid character', 'note NAK'",
                    Code.CHARACTER_ERROR, noted=True, rules=("3964.RX.BCC-CHARACTER-ERROR",)),
        T_CDT=Row(Action.CHARACTER_TIMEOUT, NAK_CHECK, "Fig. 2-12 'T > T_CDT or BCC incorrect'",
                  Code.CDT_EXCEEDED, noted=True, sends=("NAK",), rule=_CDT_RULE, rules=("3964.RX.BCC-TIMEOUT",)),
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
    WAIT_REPETITION: _rows(
        Row(Action.START_QUIET_WAIT, IDLE_JUNK, "Fig. 2-12 'wait for STX'; A19",  # as in idle
            rules=("3964.RX.WAIT-REPETITION-OTHER",)),
        STX=Row(Action.REPETITION_BEGINS, RECEIVE_ENTRY,
                "§2.2.2 Receive/receiving data; Fig. 2-11 'repetition expected', 'W+1'; Fig. 2-12 'STX'",
                rules=("3964.RX.REPETITION",)),
        # A19: the partner's NAK says it gave up; other characters are handled as in idle
        NAK=Row(Action.PARTNER_GAVE_UP, IDLE, "Table 8-1 16#0815; A19", Code.ATTEMPTS_MISMATCH,
                rules=("3964.RX.WAIT-REPETITION-OTHER",)),
        INVALID=Row(Action.REPORT_INVALID_IN_IDLE, IDLE_CHAR_ERROR, "Table 8-1 16#080C; A19",
                    Code.CHARACTER_ERROR, rules=("3964.RX.WAIT-REPETITION-OTHER",)),
        T_BLOCK=Row(Action.REPETITION_TIMEOUT, IDLE,
                    "§2.2.2 Receive/receiving data; Fig. 2-12 'T > T_BLOCK'; A19", Code.ATTEMPTS_MISMATCH,
                    rules=("3964.RX.T-BLOCK",)),
        BREAK=_RX_BREAK,
        SEND_REQUEST=_QUEUE,
        BUFFER_FREE=_NO_BUFFER_EVENT,
    ),
}

#: Every decision's outcomes. The station's ``_d_<decision>`` returns the target of one of them.
BRANCHES: dict[Decision, tuple[Branch, ...]] = {
    START_CHECK: (
        Branch("X <= N_setup", WAIT_SETUP_ACK, "§2.2.2 Send/setup; Fig. 2-10 'send STX', 'start T_ADT'",
               sends=("STX",), rule="a send job starts with STX",
               rules=("3964.TX.SETUP-STX", "3964.CONFLICT.LOW-RESUMES")),
        Branch("deferred job, X > N_setup", SETUP_CHECK,
               "§2.2.2 Initialization conflict; Fig. 2-8 '2nd connection setup attempt'; A21",
               rules=("3964.CONFLICT.LOW-RESUMES",)),
    ),
    SETUP_CHECK: (
        Branch("X <= N_setup", WAIT_SETUP_ACK, "§2.2.2 Send/setup; Fig. 2-10 'X+1', 'X <= 6'",
               sends=("STX",), rule="a failed setup attempt is repeated with STX",
               rules=("3964.TX.SETUP-ATTEMPTS", "3964.TX.SETUP-REFUSED")),
        Branch("X > N_setup", IDLE, "§2.2.2 Send/setup; Fig. 2-10 'X > 6', 'send NAK'",
               Code.SETUP_ATTEMPTS_EXCEEDED, sends=("NAK",),
               rule="after the last setup attempt the sender sends NAK and gives up",
               rules=("3964.TX.SETUP-FINAL-NAK",)),
    ),
    TX_CHECK: (
        # 16#0701 at the first repetition only (W = 2)
        Branch("W <= N_tx", WAIT_SETUP_ACK,
               "§2.2.2 Send/release; Fig. 2-10 'W+1'; Table 2-4 transmission attempts; A3, A4",
               Code.FIRST_REPETITION, sends=("STX",),
               rule="a failed transmission attempt starts again with STX",
               rules=("3964.TX.ATTEMPTS", "3964.TX.SETUP-COUNT-PER-ATTEMPT")),
        Branch("W > N_tx", IDLE, "Fig. 2-10 'W+1', 'send NAK'; Table 2-4 transmission attempts; A3, A5, A6",
               Code.TX_ATTEMPTS_EXCEEDED, sends=("NAK",),
               rule="after the last transmission attempt the sender sends NAK and gives up",
               rules=("3964.TX.FINAL-NAK",)),
    ),
    PRIORITY: (
        Branch("high priority", WAIT_SETUP_ACK, "§2.2.2 Initialization conflict; Fig. 2-10 'high priority'; A23",
               rules=("3964.CONFLICT.HIGH-WAITS",)),
        Branch("low priority", RECEIVE_ENTRY,
               "§2.2.2 Initialization conflict; Fig. 2-10 'low priority'; "
               "Fig. 2-11 'initialization conflict, low priority'",
               sends=("DLE",),
               rule="a low-priority station defers and answers the partner's STX with DLE",
               rules=("3964.CONFLICT.LOW-DEFERS",)),
    ),
    IN_END_SEQUENCE: (
        Branch("DLE within the data", ABORT_QUIET, "§2.2.2 Sending data", Code.SEND_INTERRUPTED,
               rules=("3964.TX.DATA-OTHER",)),
        Branch("DLE within the end sequence", TX_CHECK,
               "§2.2.2 Send/release; Table 8-1 16#0706 'DLE too early'; A10", Code.RELEASE_REFUSED,
               rules=("3964.TX.DLE-TOO-EARLY",)),
    ),
    RECEIVE_ENTRY: (
        Branch("buffer free", RECEIVE, "§2.2.2 Receive/setup; Fig. 2-11 'buffer free', 'send DLE'",
               sends=("DLE",), rule="STX is answered with DLE", rules=("3964.RX.SETUP-DLE",)),
        Branch("buffer not free", WAIT_BUFFER, "§2.2.2 Receive/setup; Fig. 2-11 'buffer not free', 'start T_NAKTIM'",
               rules=("3964.RX.NO-BUFFER",)),
    ),
    ABANDON_SETUP: (
        # the default: NAK once the line is quiet for CDT (16#0802 with it)
        Branch("abandon the setup", IDLE_JUNK, "Table 8-1 16#0802; A16", rules=("3964.RX.SETUP-GARBAGE",)),
        Branch("keep waiting for a buffer", WAIT_BUFFER, "Table 8-1 16#0802; Fig. 2-11 'wait'; A16",
               Code.RX_SETUP_ERROR, rules=("3964.RX.SETUP-GARBAGE",)),
    ),
    NAK_AT_ONCE: (
        Branch("NAK at the end of the block", RECEIVE, "Fig. 2-12 'note NAK'; A11", rules=("3964.RX.DLE-OTHER",)),
        Branch("NAK at once", NAK_CHECK, "Table 8-1 16#0805; A11", rules=("3964.RX.DLE-OTHER",)),
    ),
    AFTER_ETX: (
        Branch("3964", EVALUATE, "Table 2-3; Fig. 2-12 '3964'", rules=("3964.RX.ANSWER-AT-ETX",)),
        Branch("3964R", WAIT_BCC, "Table 2-3; Fig. 2-12 '3964R', 'wait for BCC'", rules=("3964.RX.WAIT-FOR-BCC",)),
    ),
    BCC_CHECK: (
        Branch("BCC correct", EVALUATE, "§2.2.2 Receive/release; Fig. 2-12 'BCC'", rules=("3964.RX.BCC-CHECK",)),
        Branch("BCC incorrect", NAK_CHECK, "§2.2.2 Receive/release; Fig. 2-12 'BCC incorrect'",
               Code.BCC_ERROR, noted=True, rules=("3964.RX.BCC-CHECK",)),
    ),
    EVALUATE: (
        Branch("no NAK noted", IDLE,
               "§2.2.2 Receive/release; Table 2-3; Fig. 2-12 'NAK noted?', 'send DLE', 'receipt completed'",
               sends=("DLE",), rule="a block received without error is acknowledged with DLE",
               rules=("3964.RX.ACK", "3964.RX.ZERO-LENGTH")),
        # A17: an empty block counts as noted (16#0805) only in the alternative reading
        Branch("NAK noted", NAK_CHECK, "Fig. 2-12 'NAK noted?'; A17",
               rules=("3964.RX.NAK-AWAITS-REPETITION", "3964.RX.ZERO-LENGTH")),
    ),
    # NAK_CHECK raises the error noted first and, at the first NAK of a block, 16#0801; when it
    # gives up, it reports the first error again as the final one.
    NAK_CHECK: (
        Branch("W_r < N_tx", WAIT_REPETITION,
               "§2.2.2 Receive/receiving data; Fig. 2-12 'send NAK', 'W <= 5', "
               "'note repetition expected, start T_BLOCK'; Table 8-1 16#0801; A2",
               sends=("NAK",), rule=_NAK_RULE, rules=("3964.RX.NAK-AWAITS-REPETITION",)),
        Branch("W_r >= N_tx", IDLE, "§2.2.2 Receive/receiving data; Fig. 2-12 'send NAK', 'W > 5'; A18",
               sends=("NAK",), rule=_NAK_RULE, rules=("3964.RX.REPETITION-LIMIT", "3964.RX.COUNT-PER-BLOCK")),
    ),
    IDLE_CHAR_ERROR: (
        Branch("NAK once the line is quiet", IDLE_JUNK, "Table 8-1 16#080C; §2.2.2 Receive/setup; A13",
               rules=("3964.IDLE.CHARACTER-ERROR",)),
        Branch("no NAK", IDLE, "Table 8-1 16#080C; A13", rules=("3964.IDLE.CHARACTER-ERROR",)),
    ),
}

#: A decision's possible outcomes (states or further decisions).
DECISION_TARGETS: dict[Decision, tuple[str, ...]] = {
    d: tuple(b.target for b in branches) for d, branches in BRANCHES.items()}


def rows() -> Iterator[tuple[State, Input, Row]]:
    """Every (state, input, row) triple, in table order."""
    for state in STATES:
        for inp in INPUTS:
            yield state, inp, TABLE[state][inp]


def branches() -> Iterator[tuple[Decision, Branch]]:
    """Every (decision, branch) pair, in table order."""
    for d in DECISIONS:
        for b in BRANCHES[d]:
            yield d, b


def branch(decision: str, target: str) -> Branch:
    """The outcome of ``decision`` that leads to ``target``."""
    for b in BRANCHES[decision]:
        if b.target == target:
            return b
    raise KeyError(f"{decision} has no outcome leading to {target}")


def rule_text(element: Row | Branch) -> str:
    """The rule an element's characters follow, with its rule id and reference: what a
    transcript says about them."""
    rid = f"{element.rules[0]}: " if element.rules else ""
    return f"{rid}{element.rule} ({element.ref})"


def rule_for(chain: list[str], byte: int) -> Row | Branch | None:
    """The row or outcome whose rule makes a station send ``byte`` after the steps ``chain``
    (the row's action, then the decisions taken, as the station's ``explain`` log records
    them). The outermost element that names the byte is the most specific rule."""
    for name in chain:
        if name in BRANCHES:
            candidates = BRANCHES[name]
        else:
            candidates = _ROWS_BY_ACTION.get(name, ())
        for e in candidates:
            for s in e.sends:
                if s == BLOCK or SENDABLE[s] == byte:
                    return e
    return None


_ROWS_BY_ACTION: dict[str, list[Row]] = {}
for _s, _i, _r in rows():
    _ROWS_BY_ACTION.setdefault(_r.action, []).append(_r)
del _s, _i, _r


def _check() -> None:
    assert set(TABLE) == set(STATES), "every state has rows"
    assert set(BRANCHES) == set(DECISIONS), "every decision has outcomes"
    names = globals()
    for enum in (State, Input, Decision):
        for m in enum:
            assert names[m.name] is m, m
    actions = set(Action)
    for state, inp, row in rows():
        t = row.target
        assert t in STATES or t in DECISIONS or t == SAME, (state, inp, t)
        assert row.action in actions, row.action
    for d, b in branches():
        assert b.target in STATES or b.target in DECISIONS, (d, b.target)
    for e in [r for _, _, r in rows()] + [b for _, b in branches()]:
        assert all(s in SENDABLE for s in e.sends), e
        assert bool(e.sends) == bool(e.rule), e


_check()
