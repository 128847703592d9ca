"""Why a 3964/3964R station sends each byte, and what a byte it should not send breaks.

The part of :class:`~ptpcert.procedures.p3964.analysis.analyzer.P3964Analyzer` that speaks for
the manual (:class:`Causes`, mixed into it): for every byte the model sends, the rule, the
manual's reference, the STATUS code and the timing window (a
:class:`~ptpcert.analysis.interface.Cause`), read from the state table's row or decision that
sent it; for a byte the seat sent where the model sends nothing, or something else, the rule
the station broke, from the state the model was in.

Timing windows (on top of the capture's resolution): a DLE or NAK that answers the partner's
STX or block may come as late as the partner's ADT allows (its T_ADT waits for it); each
character of a block as late as the partner's CDT allows after the one before (the first
after the partner's DLE); a character a station sends when its own timer runs out may come
one character time and 5 % of the timer early (a station may time from the start of the
character it waits after, and timers have a granularity) and the tolerance plus 25 % of the
timer late; anything else the tolerance late.
"""

from __future__ import annotations

import functools
from typing import Any

from ptpcert.analysis.interface import OTHER, Cause, strip_section
from ptpcert.model.app import Host
from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import DLE, ETX, NAK, STX
from ptpcert.procedures.p3964.model.params import T_BLOCK, T_NAKTIM
from ptpcert.rules import for_procedure

_NAMES = {STX: "STX", DLE: "DLE", ETX: "ETX", NAK: "NAK"}
_TIMERS = (T.T_ADT, T.T_CDT, T.T_NAKTIM, T.T_BLOCK)
_LOCAL = (T.SEND_REQUEST, T.POWER_ON, T.BUFFER_FREE)
#: actions after which the station answers the partner's STX
_ANSWER_STX = (T.Action.BEGIN_RECEPTION, T.Action.REPETITION_BEGINS, T.Action.INITIALIZATION_CONFLICT)
#: actions and decisions after which the station answers the end of the partner's block
_ANSWER_BLOCK = (T.Action.BCC_RECEIVED, T.Action.END_OF_TEXT, T.Action.BCC_INVALID_CHARACTER,
                 T.EVALUATE, T.BCC_CHECK)

#: what a station in each state sends on its own, for a byte the model does not send
_STATE_RULES: dict[str, tuple[str, str]] = {
    T.START_UP: ("a station that is switched on sends one NAK", "§2.2.2 Receive, Note; Fig. 2-9"),
    T.IDLE: ("an idle station sends only STX, to begin a send job (a NAK only at start-up or "
             "to answer characters on the line)",
             "Fig. 2-10 'send request'; Fig. 2-11 'wait (idle)'; §2.2.2 Receive/setup"),
    T.IDLE_JUNK: ("after a character other than STX or NAK in idle the station answers with NAK only "
                  "once the line has been quiet for CDT",
                  "§2.2.2 Receive/setup; Fig. 2-11 'any characters except STX or NAK'; Table 8-1 16#0802"),
    T.WAIT_SETUP_ACK: ("after its STX a sender waits ADT for the partner's DLE before it tries again",
                       "§2.2.2 Send/setup; Fig. 2-10 'start T_ADT', 'T > T_ADT'"),
    T.SEND_DATA: ("a sender sends its block without a break: the data with every DLE doubled, DLE ETX "
                  "and (3964R) the BCC",
                  "§2.2.2 Sending data; Fig. 2-10 'send block, possibly with doubled DLE'"),
    T.ABORT_QUIET: ("after a character from the partner during its block the sender waits for CDT of quiet "
                    "before its NAK",
                    "§2.2.2 Sending data; Table 8-1 16#0704"),
    T.WAIT_RELEASE_ACK: ("after its block a sender waits ADT for the partner's DLE before it tries again",
                         "§2.2.2 Send/release; Fig. 2-10 'start T_ADT', 'T > T_ADT'"),
    T.WAIT_BUFFER: ("a receiver answers STX with DLE once it has a free receive buffer, or with NAK after "
                    "T_NAKTIM (400 ms)",
                    "§2.2.2 Receive/setup; Fig. 2-11 'buffer free', 'T > T_NAKTIM'; Table 8-1 16#080A"),
    T.RECEIVE: ("a receiver answers a block only at its end (DLE, or NAK for an error), or with NAK once CDT "
                "has passed without a character",
                "§2.2.2 Receive/receiving data; Fig. 2-12 'wait to receive', 'T > T_CDT'"),
    T.WAIT_ETX: ("a receiver answers a block only at its end (DLE, or NAK for an error), or with NAK once "
                 "CDT has passed without a character",
                 "§2.2.2 Receive/receiving data; Fig. 2-12 'wait for ETX'"),
    T.WAIT_BCC: ("a 3964R receiver answers the block only after its BCC, or with NAK once CDT has passed "
                 "without it", "Table 2-3; Fig. 2-12 'wait for BCC', 'T > T_CDT'"),
    T.WAIT_REPETITION: ("after its NAK a receiver waits for the partner to repeat the block (STX); it sends "
                        "nothing of its own meanwhile",
                        "§2.2.2 Receive/receiving data; Fig. 2-12 'note repetition expected, start T_BLOCK'"),
}

#: the ids in the rules catalogue (ptpcert rules) of what a station in each state may send
_STATE_RULE_IDS: dict[str, tuple[str, ...]] = {
    T.START_UP: ("3964.START.NAK",),
    T.IDLE: ("3964.TX.SETUP-STX", "3964.IDLE.NAK-IGNORED"),
    T.IDLE_JUNK: ("3964.IDLE.STRAY-NAK", "3964.IDLE.QUIET-RESTARTS"),
    T.WAIT_SETUP_ACK: ("3964.TX.SETUP-WAIT",),
    T.SEND_DATA: ("3964.TX.BLOCK-LAYOUT", "3964.TX.NO-GAPS"),
    T.ABORT_QUIET: ("3964.TX.DATA-OTHER", "3964.TX.QUIET-RESTARTS"),
    T.WAIT_RELEASE_ACK: ("3964.TX.RELEASE-WAIT",),
    T.WAIT_BUFFER: ("3964.RX.NO-BUFFER",),
    T.RECEIVE: ("3964.RX.CDT-WAIT",),
    T.WAIT_ETX: ("3964.RX.CDT-WAIT",),
    T.WAIT_BCC: ("3964.RX.BCC-WAIT",),
    T.WAIT_REPETITION: ("3964.RX.NAK-AWAITS-REPETITION",),
}

_BREAK_RULE = ("a station never sends a BREAK: the line is broken (a CP 341 on the other end returns to "
               "its initial state and raises 16#080D)",
               "§2.2.2 Error handling; Figs. 2-10 to 2-12 'BREAK'; Table 8-1 16#080D")
_INVALID_RULE = ("a character with a parity or framing error: the line or the sender's transmitter is at "
                 "fault (a CP 341 receiving it raises 16#080C)",
                 "§2.2.2 Error handling; Figs. 2-10 to 2-12 'invalid character'; Table 8-1 16#080C")
_AFTER_BREAK = ("after a BREAK a station returns to its initial state at once: it abandons what it was "
                "sending or receiving and sends nothing, no NAK and no new attempt (16#080D)",
                "§2.2.2 Error handling; Figs. 2-10 to 2-12 'BREAK'; Table 8-1 16#080D")
#: the rule a high-priority station breaks when it answers the partner's STX in an initialization
#: conflict (rule, reference); RK 512's analysis cites it too
HIGH_KEEPS = ("initialization conflict: the high-priority station does not answer the partner's STX; it "
               "keeps waiting for the DLE to its own STX",
               "§2.2.2 Initialization conflict; Fig. 2-8; Fig. 2-10 'high priority'")
_LEN_RULE = ("a send job carries 1 to 1024 bytes: a block without data or longer than 1024 bytes is not "
             "sent (the CP 341 refuses the job with 16#1E41)",
             "Tables 6-2/6-3 LEN; Table A-5; Table 8-2 16#1E41")

#: the catalogue's rule behind the error a receiver's NAK reports (Table 8-1)
_NOTED_RULES = {Code.FRAME_TOO_LONG: ("3964.RX.TOO-LONG",), Code.BCC_ERROR: ("3964.RX.BCC-CHECK",),
                Code.CHARACTER_ERROR: ("3964.RX.CHARACTER-ERROR",)}

#: the outcomes of "send NAK" that refuse a received block, and "NAK noted?" leading to them
_REFUSALS = (T.branch(T.NAK_CHECK, T.WAIT_REPETITION), T.branch(T.NAK_CHECK, T.IDLE))
_NAK_NOTED = T.branch(T.EVALUATE, T.NAK_CHECK)

#: (action, input) -> the rows of the table with them (several states may share an action)
_ROWS_OF: dict[tuple[str, str], list] = {}
for _state, _inp, _row in T.rows():
    _same = _ROWS_OF.setdefault((_row.action, _inp), [])
    if not any(r is _row for r in _same):
        _same.append(_row)
del _state, _inp, _row, _same

#: a rule of the table as a sentence (without the section number of our notes)
_sentence = functools.lru_cache(maxsize=None)(strip_section)


def timer_duration(params: Any, timer: str) -> float:
    """How long the station's ``timer`` (an input of the state table: T_ADT, T_CDT, T_NAKTIM,
    T_BLOCK) runs with its ``params``, in seconds."""
    return {T.T_ADT: params.adt, T.T_CDT: params.cdt, T.T_NAKTIM: T_NAKTIM, T.T_BLOCK: T_BLOCK}[timer]


def _leading_to(actions: list[str], inp: str, element: Any) -> Any:
    """The row or decision outcome that led to ``element`` (the outcome of a later decision
    that sends the byte) in the chain ``actions`` of the input ``inp``: the outcome of the
    decision before it that leads on, or else the row (when one row of the table has this
    action and input). None when ``element`` is the row itself or nothing is certain."""
    chain = list(actions)
    at = next((i for i, name in enumerate(chain) if name in T.BRANCHES and element in T.BRANCHES[name]), None)
    if at is None or at == 0:
        return None
    if at >= 2:
        prev = chain[at - 1]
        return next((b for b in T.BRANCHES[prev] if b.target == chain[at]), None)
    rows = _ROWS_OF.get((chain[0], inp), [])
    if len(rows) == 1 and not rows[0].sends and rows[0].ref:
        return rows[0]
    return None


def _dles_before(items, k: int) -> int:
    """How many DLE characters come right before ``items[k]``."""
    n = 0
    while k - 1 - n >= 0 and items[k - 1 - n].kind == "byte" and items[k - 1 - n].value == DLE:
        n += 1
    return n


def _joined(first: str, second: str) -> str:
    """Two references as one, each part once."""
    parts = [x.strip() for x in first.split(";") + second.split(";") if x.strip()]
    return "; ".join(dict.fromkeys(parts))


class Causes:
    """The rules behind the bytes of a 3964/3964R seat, for
    :class:`~ptpcert.procedures.p3964.analysis.analyzer.P3964Analyzer` (it brings ``params``,
    ``apps``, ``procedure``, ``late_abs``, ``unsendable`` and :meth:`rest_gap`)."""

    # -- why the model sends what it sends ------------------------------------------------
    def cause(self, run, entry: Any, k: int, byte: int) -> Cause:
        st = run.st
        seat = st.name
        p, q = self.params[seat], self.params[OTHER[seat]]
        c = p.char_time
        name = self.name(byte)
        if entry is None:
            return Cause("reply", "the model's behaviour", "§2.2.2; Figs. 2-9 to 2-12", 3e-6, self.late_abs,
                         what=name)
        _start, _end, inp, actions = entry
        element = T.rule_for(actions, byte)
        if element is not None and inp == T.T_CDT and actions[0] == T.Action.CHARACTER_TIMEOUT:
            # three states share the action: the partner's last characters say which one ran out
            element = T.TABLE[self._receiving_state(run)][inp]
        if element is not None:
            rule, ref, code = _sentence(element.rule), element.ref, element.code
            ids = tuple(element.rules)
            before = _leading_to(actions, inp, element)
            if element in _REFUSALS:
                noted = self._noted_code(run, _start)
                if noted is not None:
                    # the error the NAK refuses the block for (Fig. 2-12 'note NAK')
                    ref = _joined(f"Table 8-1 16#{noted:04X}", ref)
                    ids = tuple(dict.fromkeys(_NOTED_RULES.get(noted, ()) + ids))
                    code = noted
                    if before is _NAK_NOTED:
                        before = None       # the error says more than "NAK noted?"
            if before is not None:
                # the rule that led there names why this byte: e.g. the BCC with a character
                # error (its row) before "send NAK" (the decision that sends it)
                # (its first rule: the others of a row may concern other situations, e.g. T_ADT
                # of the setup also ends a high-priority station's wait in a conflict)
                ref, ids = _joined(before.ref, ref), tuple(dict.fromkeys(before.rules[:1] + ids))
                code = code or before.code
        else:
            rule, ref, code = "the model's behaviour", "§2.2.2; Figs. 2-9 to 2-12", None
            ids = ()
        if inp in _TIMERS:
            dur = timer_duration(p, inp)
            rule = f"{rule} ({inp} = {1000 * dur:g} ms)"
            return Cause("timer", rule, ref, c + 0.05 * dur + 3e-6, self.late_abs + 0.25 * dur, code, name, ids)
        if inp in _LOCAL:
            # revealed by the seat's own byte (exact), or the echo application's job
            late = self.rest_gap() if inp == T.SEND_REQUEST else self.late_abs
            return Cause("local", rule, ref, 3e-6, late, code, name, ids)
        if T.Action.SETUP_ACKNOWLEDGED in actions:
            job = st.job
            if (self.apps[seat] in ("echo", "echo-only") and job is not None
                    and job.payload not in run.memo.get("requested", ())):
                # a block the echo application sends back: the data the station delivered
                rule = ("with the echo convention a station sends back the data it received, each doubled "
                        "DLE taken once; " + rule)
                ref = "§2.2.2 Receive/receiving data; Fig. 2-12 'dual DLE'; " + ref
            # the partner waits CDT for the first character after its DLE and between two
            return Cause("reply", rule, ref, 3e-6, q.cdt, code, rules=ids)
        if byte in (DLE, NAK) and any(x in actions for x in _ANSWER_STX + _ANSWER_BLOCK):
            return Cause("reply", rule, ref, 3e-6, q.adt, code, name, ids)   # the partner's T_ADT waits for it
        return Cause("reply", rule, ref, 3e-6, self.late_abs, code, name, ids)

    def _receiving_state(self, run) -> str:
        """Where a receiver is in the partner's block, from the partner's characters so far:
        after a data DLE (an odd run of DLEs) waiting for ETX, after DLE ETX (3964R) waiting
        for the BCC, else receiving data."""
        inputs, i = run.judge.inputs, run.i_in
        if i and _dles_before(inputs, i) % 2:
            return T.WAIT_ETX
        last = inputs[i - 1] if i else None
        if (last is not None and last.kind == "byte" and last.value == ETX and _dles_before(inputs, i - 1) % 2
                and self.params[run.judge.seat].has_bcc):
            return T.WAIT_BCC
        return T.RECEIVE

    @staticmethod
    def _noted_code(run, start: float) -> int | None:
        """The error a receiver's NAK begun at ``start`` reports: the first STATUS event it
        raised as it decided to send it (before 16#0801 'repetition expected')."""
        out = None
        for t, code in reversed(run.events):
            if t < start - 1e-9:
                break
            if t <= start + 1e-9 and code != Code.EXPECT_REPETITION:
                out = code
        return out

    def what(self, host: Host, entry: Any, k: int, byte: int) -> str:
        """A byte of the block the station sends, in words."""
        if entry is None or T.Action.SETUP_ACKNOWLEDGED not in entry[3]:
            return ""
        st = host.station
        job = st.job
        if job is None:
            return f"byte {k + 1} of the block ({byte:02X})"
        n = len(st.block_body(job.payload))
        n_end = 3 if st.params.has_bcc else 2
        if n - n_end <= k < n:
            return ("DLE of DLE ETX", "ETX of DLE ETX", f"the BCC {byte:02X}")[k - (n - n_end)]
        return f"byte {k + 1} of the block ({byte:02X})"

    def _catalogued(self, rule_id: str, code: int | None = None, cause: Cause | None = None) -> Cause:
        """The rule ``rule_id`` of the catalogue as the rule broken (before ``cause``'s, if given)."""
        r = for_procedure(self.procedure).get(rule_id)
        if cause is None:
            return Cause("reply", r.text.rstrip("."), r.ref, 0.0, 0.0, code, rules=(rule_id,))
        return Cause(cause.kind, r.text.rstrip("."), _joined(r.ref, cause.reference), cause.early, cause.late,
                     code or cause.code, cause.what, tuple(dict.fromkeys((rule_id,) + cause.rules)))

    def _outside_frame(self, seat: str, item) -> bool:
        """A value no character of the seat's frame carries (above 7F with 7 data bits)."""
        return item.kind == "byte" and item.value > 0x7F and self.params[seat].data_bits == 7

    def wrong(self, run, item, byte: int, cause: Cause) -> Cause:
        if self._outside_frame(run.judge.seat, item):
            return self._catalogued("3964.FRAME.SEVEN-BIT", cause=cause)
        return cause

    @staticmethod
    def _character_error_in_block(inputs, i_in: int) -> str | None:
        """The rule a receiver's answer breaks when the block it is receiving has a character
        with a transmission error (the partner's characters back to its STX): the one for an
        error right after a data DLE (an odd run of DLEs before it), or the general one. None
        when the block has no such character."""
        k = i_in - 1
        while k >= 0:
            x = inputs[k]
            if x.kind == "byte" and x.value == STX:
                return None
            if x.kind == "break":
                return None
            if x.kind == "invalid":
                return "3964.RX.CHARACTER-ERROR-IN-END" if _dles_before(inputs, k) % 2 else "3964.RX.CHARACTER-ERROR"
            k -= 1
        return None

    def unexpected(self, run, host: Host, item, later) -> Cause:
        st = host.station
        if item.kind == "break":
            return Cause("reply", *_BREAK_RULE, 0.0, 0.0, Code.LINE_BREAK)
        if item.kind == "invalid":
            return Cause("reply", *_INVALID_RULE, 0.0, 0.0, Code.CHARACTER_ERROR)
        if self._outside_frame(run.judge.seat, item):
            return self._catalogued("3964.FRAME.SEVEN-BIT")
        inputs = run.judge.inputs
        last = inputs[run.i_in - 1] if run.i_in else None
        if item.kind == "byte" and item.value in (DLE, NAK) and st.state in (T.RECEIVE, T.WAIT_ETX, T.WAIT_BCC):
            # an answer in the middle of a block with a corrupted character: NAK only at its end
            rid = self._character_error_in_block(inputs, run.i_in)
            if rid is not None:
                return self._catalogued(rid, Code.CHARACTER_ERROR)
        if (last is not None and last.kind == "invalid" and item.kind == "byte" and item.value == DLE
                and st.state in (T.IDLE, T.IDLE_JUNK)):
            # a corrupted character in idle, an STX too, begins no block
            return self._catalogued("3964.IDLE.CORRUPTED-STX", Code.CHARACTER_ERROR)
        if (st.state is T.WAIT_SETUP_ACK and st.params.priority == "high" and item.kind == "byte"
                and item.value in (DLE, STX) and last is not None and last.kind == "byte" and last.value == STX):
            # it answered the partner's STX, or took it for a refusal and tried again at once
            return Cause("reply", *HIGH_KEEPS, 0.0, 0.0, rules=("3964.CONFLICT.HIGH-WAITS",))
        if later is not None and later[1] == item.value:
            return later[2]
        if last is not None and last.kind == "break" and item.start - last.t < self.rest_gap():
            return Cause("reply", *_AFTER_BREAK, 0.0, 0.0, Code.LINE_BREAK)
        if item.value == STX and (run.judge.seat, run.i_obs) in self.unsendable:
            return Cause("reply", *_LEN_RULE, 0.0, 0.0, Code.LEN_ILLEGAL, rules=("3964.TX.LEN-ILLEGAL",))
        rule, ref = _STATE_RULES.get(st.state, ("the model's behaviour", "§2.2.2"))
        return Cause("reply", rule, ref, 0.0, 0.0, rules=_STATE_RULE_IDS.get(st.state, ()))

    def name(self, byte: int) -> str:
        return _NAMES.get(byte, f"{byte:02X}")
