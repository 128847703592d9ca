"""3964/3964R's part of line analysis (``ptpcert analyze``, ``ptpcert monitor``).

Which local events the line reveals (what the model cannot predict, so the seat's bytes say
when it happened):

* an STX from a station without a send job starts one: its application handed over a block
  (Fig. 2-10 "send request"). The block is read ahead from the line: the bytes the station
  sends after the partner's DLE, up to DLE ETX, with each doubled DLE taken once. The model
  then sends that block its own way, so a block framed wrongly (DLE not doubled, a wrong
  BCC) differs from the model's;
* a receive buffer becomes free (Fig. 2-11 "buffer free"): the analysis cannot see the
  application's buffer, so it takes it as busy until the station's DLE shows it free. A DLE
  any time before T_NAKTIM is conforming; no DLE and no NAK after T_NAKTIM is not. A buffer
  seen free may be busy again at a later STX: a station that then answers late, or with NAK
  after T_NAKTIM, is an informational finding of kind "buffer" (the alternative with a busy
  buffer follows it), never a failure;
* a restart (Fig. 2-9): a NAK from a station at rest, on a line that was quiet for longer
  than any timer, is its start-up NAK. A case of ``ptpcert run`` against an IUT it restarts
  (exec:, pty:, sim:) switches the IUT on at the case's start: its first character must be
  that NAK.

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
import re
from dataclasses import replace
from typing import Any

from ptpcert.analysis import OTHER, SEATS, WAIT, Cause, Explanation, ProcedureAnalyzer, Variant
from ptpcert.model.app import Host
from ptpcert.model.codes import Code
from ptpcert.model.events import SendFailed
from ptpcert.procedures.p3964.model import codec
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.params import T_BLOCK, T_NAKTIM
from ptpcert.procedures.p3964.model.readings import READINGS
from ptpcert.procedures.p3964.model.station import Station3964

STX, DLE, ETX, NAK = codec.STX, codec.DLE, codec.ETX, codec.NAK
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

_BUFFER_WORDS = ("with its receive buffer not free when the partner's STX came (the application's buffer is "
                 "not on the line: Fig. 2-11 'buffer not free', DLE once one is free or NAK after T_NAKTIM)")

#: the readings of the open points the alternatives take, in words
_READING_WORDS = {
    "A4": "the setup counter is not reset for a new transmission attempt",
    "A6": "a second NAK ends the last transmission attempt",
    "A7": "a quiet wait is not restarted by further characters",
    "A10": "a DLE during the end sequence counts as a character during the block",
    "A11": "DLE followed by another character is answered by NAK at once",
    "A12": "T_ADT at release runs from DLE ETX",
    "A13": "a character error in idle is not answered by NAK",
    "A17": "a zero-length block is refused",
    "A19": "a NAK while waiting for a repetition ends the wait with another code",
    "A21": "the collided STX of an initialization conflict is not counted",
    "A23": "a high-priority station restarts T_ADT at the partner's STX",
}


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


@functools.lru_cache(maxsize=None)
def _sentence(rule: str) -> str:
    """A rule of the table as a sentence (without the section number of our notes)."""
    return re.sub(r"^§[\d.\-]+(?: items? [\d\-]+)?:\s*", "", rule)


class P3964Analyzer(ProcedureAnalyzer):
    """Line analysis of a 3964/3964R link (see the module docstring)."""

    reference = "§2.2.2; Figs. 2-5 to 2-12"

    def __init__(self, procedure: Any, params: dict[str, Any], apps: dict[str, str] | None = None,
                 late_ms: float = 50.0):
        super().__init__(procedure, params, apps)
        self.late_abs = late_ms / 1000.0
        self._longest = max(max(p.cdt, p.adt) for p in self.params.values())
        self._rest = (1.25 * max(self._longest, T_NAKTIM) + self.late_abs
                      + 4 * max(self.char(s) for s in SEATS))
        self._unsendable: dict[tuple[str, int], bytes] = {}
        self._variants: list[Variant] | None = None

    # -- timing ---------------------------------------------------------------------------
    def rest_gap(self) -> float:
        return self._rest

    def _duration(self, p, timer: str) -> float:
        return {T.T_ADT: p.adt, T.T_CDT: p.cdt, T.T_NAKTIM: T_NAKTIM, T.T_BLOCK: T_BLOCK}[timer]

    def early_wait(self, host: Host) -> float:
        st = host.station
        running = st.timer
        c = st.params.char_time
        if running is None:
            return c + 3e-6
        return c + 0.05 * self._duration(st.params, running[0]) + 3e-6

    def late_max(self, seat: str) -> float:
        p, q = self.params[seat], self.params[OTHER[seat]]
        return max(q.adt, q.cdt, self.late_abs + 0.25 * max(p.cdt, p.adt, T_NAKTIM), self._rest)

    # -- stations -------------------------------------------------------------------------
    def _station(self, seat: str, readings: Any = None) -> Station3964:
        return Station3964(self.params[seat], readings or READINGS, name=seat, explain=True)

    def fresh(self, seat: str, t: float, readings: Any = None) -> Host:
        st = self._station(seat, readings)
        c = self.char(seat)
        on = t - 2 * c - 1e-6
        st.set_buffer_free(on, False)   # busy until the station's DLE shows it free (module docstring)
        st.power_on(on)
        st.pop_output()
        st.pop_events()
        st.tx_log.clear()
        return Host(st, self.apps[seat])

    def powered(self, seat: str, t: float) -> Host:
        st = self._station(seat)
        st.set_buffer_free(t, False)
        st.power_on(t)
        return Host(st, self.apps[seat])

    def at_rest(self, host: Host) -> bool:
        return host.station.idle

    # -- local events ---------------------------------------------------------------------
    def explain(self, run, item, index: int):
        if item.kind != "byte":
            return None
        st = run.st
        b = item.value
        seat = run.judge.seat
        if b == STX and st.pending_jobs == 0 and st.state is not T.START_UP:
            payload = self._payload(run, index)
            if payload is WAIT:
                return WAIT
            aborted = run.memo.get("aborted")
            if (aborted is not None and payload in (None, aborted[0])
                    and item.start - aborted[1] < self._rest):
                return None     # the job a BREAK ended, tried again: not a new job
            if payload is None:
                payload = b"\x00"   # its block never went on the line: any data will do
            if not self._sendable(seat, payload):
                self._unsendable[(seat, index)] = payload
                return None
            return Explanation(lambda r, t, p=payload: self._request(r, t, p))
        if (b == NAK and self._quiet(run, index) and st.pending_jobs == 0 and not st.transmitting
                and st.state in (T.IDLE, T.WAIT_REPETITION)):
            return Explanation(lambda r, t: r.replace_host(self.powered(seat, t)),
                               "restarted: its start-up NAK after a quiet line (Fig. 2-9)")
        if b == DLE and st.state is T.WAIT_BUFFER:
            return Explanation(lambda r, t: r.st.set_buffer_free(t, True))
        return None

    @staticmethod
    def _request(run, t: float, payload: bytes) -> None:
        # the jobs the line revealed (the latest few: a job's block follows it at once)
        run.memo["requested"] = run.memo.get("requested", ())[-3:] + (payload,)
        run.st.request_send(t, payload)

    def before(self, item, inputs) -> bool:
        # two STXs that cross: each station decided to send before it heard the other (Fig. 2-8)
        return (item.kind == "byte" and item.value == STX
                and any(i.kind == "byte" and i.value == STX for i in inputs))

    def _quiet(self, run, index: int) -> bool:
        """Before the seat's ``index``-th item the seat was silent, and the partner sent
        nothing a station answers (NAKs only: at its own start-up), for longer than any timer:
        a NAK now is a start-up NAK."""
        j = run.judge
        item = j.obs[index]
        since = item.start - self._rest
        if index > 0 and j.obs[index - 1].t > since:
            return False
        k = run.i_in - 1
        while k >= 0 and j.inputs[k].t > since:
            q = j.inputs[k]
            if q.kind != "byte" or q.value != NAK:
                return False
            k -= 1
        return True

    def begins(self, byte: int) -> bool:
        return byte == STX

    def event(self, run, e) -> None:
        if isinstance(e, SendFailed) and e.code in (Code.LINE_BREAK, READINGS.a15_break_status_on_send, 0x1E0D):
            run.memo["aborted"] = (e.payload, e.time)

    def resync_at(self, line, k: int) -> int | None:
        """An STX right after a block was acknowledged: the end of one seat's block (DLE ETX,
        for 3964R the BCC after it; a run of DLEs before the ETX odd, so not data), the other
        seat's DLE, and nothing else before the STX."""
        first, n = line.chunk_items[k]
        seat = line.chunks[k].seat
        for j, it in enumerate(line.items[seat][first:first + n]):
            if it.kind == "byte" and it.value == STX and self._after_release(line.before(k, 8, j)):
                return j
        return None

    def _after_release(self, prev) -> bool:
        if not prev or prev[-1][1].kind != "byte" or prev[-1][1].value != DLE:
            return False
        acker = prev[-1][0]
        block = []
        for s, x in reversed(prev[:-1]):
            if s == acker:
                break
            block.insert(0, x)
        sender = "b" if acker == "a" else "a"
        tail = 1 if self.params[sender].has_bcc else 0
        data = bytes(x.value for x in block if x.kind == "byte")
        body = data[:len(data) - tail] if tail else data
        if len(body) < 2 or body[-2:] != bytes((DLE, ETX)):
            return False
        run = len(body) - 1 - len(body[:-1].rstrip(bytes((DLE,))))
        return run % 2 == 1

    def startup(self, run, item, index: int):
        if item.kind == "byte" and item.value == NAK:
            seat = run.judge.seat
            return Explanation(lambda r, t: r.replace_host(self.powered(seat, t)))
        return None

    def startup_name(self, seat: str) -> str:
        return "NAK"

    def startup_rule(self, seat: str) -> tuple[str, str, int | None]:
        row = T.TABLE[T.START_UP][T.POWER_ON]
        return _sentence(row.rule), row.ref, None

    def _sendable(self, seat: str, payload: bytes) -> bool:
        p = self.params[seat]
        return 1 <= len(payload) <= codec.MAX_BLOCK and (p.data_bits == 8 or all(x <= 0x7F for x in payload))

    @staticmethod
    def _seen(best: bytes, data: bytearray) -> bytes | None:
        """What the line showed of a block that never ended (None: nothing)."""
        out = bytes(data) if len(data) > len(best) else best
        return out or None

    def _payload(self, run, index: int) -> Any:
        """The data of the block the send job beginning with the STX ``obs[index]`` carries:
        read ahead on the line (see the module docstring). WAIT when the line has not shown it
        yet; None when the job ended without its block on the line.

        The block is read from the station's own characters: after its STX come further STXs
        (new attempts), a NAK (it gave up), or what it answers as a receiver when the partner's
        STX crossed its own, until the partner answers its latest STX with DLE; then the
        block, back to back, up to DLE ETX. A pause in the block longer than the partner waits
        (CDT) means the block was cut off and a new attempt follows."""
        j = run.judge
        a = j.analysis
        obs, inputs = j.obs, j.inputs
        seat = j.seat
        r = a.resolution
        gap_max = self.params[OTHER[seat]].cdt + 2 * self.char(seat) + r
        stx = obs[index]
        state, data, esc, best = "setup", bytearray(), False, b""
        last = last_stx = stx.t
        i = index + 1
        while True:
            if i >= len(obs):
                if not a.complete and a.known_until - last < self._rest:
                    return WAIT
                return self._seen(best, data)
            it = obs[i]
            gap = it.t - last
            if state == "block" and gap > gap_max:
                if len(data) > len(best):
                    best = bytes(data)       # cut off: a new attempt follows
                state = "setup"
            if state == "setup":
                if gap > self._rest:
                    return self._seen(best, data)   # the job is over without a whole block
                first = self._partner_first(inputs, last_stx, r, it.t + r, self.char(OTHER[seat]))
                v = it.value if it.kind == "byte" else None
                if first != DLE:
                    if v == STX:
                        last_stx = it.t                 # another attempt
                    elif v == NAK and first is None:
                        return self._seen(best, data)   # the station gave up
                    last, i = it.t, i + 1               # (or answered the partner's STX)
                    continue
                state, data, esc = "block", bytearray(), False
            v = it.value if it.kind != "break" else 0
            if esc:
                esc = False
                if v == DLE:
                    data.append(DLE)
                elif v == ETX:
                    return bytes(data)
                else:
                    data += bytes((DLE, v))
            elif v == DLE:
                esc = True
            else:
                data.append(v)
            if len(data) > 4 * codec.MAX_BLOCK:
                return bytes(data)
            last, i = it.t, i + 1

    @staticmethod
    def _partner_first(inputs, t0: float, r: float, t1: float, c: float) -> int | None:
        """The partner's answer to the STX the station sent at ``t0``, if it came by ``t1``:
        its first character after it, passing over an STX that crossed ours (after which a
        low-priority partner answers with DLE); failing that, within the resolution ``r``
        before ``t0``, the one closest to it. -1: a line condition; after a crossing STX, a DLE
        doubled (the first data byte of the high-priority partner's own block: the second
        right after it, ``c`` being a character time) is no answer."""
        lo, hi = 0, len(inputs)
        while lo < hi:
            mid = (lo + hi) // 2
            if inputs[mid].t <= t0:         # an STX complete at the same instant crossed it
                lo = mid + 1
            else:
                hi = mid
        crossed = lo < len(inputs) and inputs[lo].kind == "byte" and inputs[lo].value == STX
        if crossed:
            lo += 1
        if lo < len(inputs) and inputs[lo].t <= t1:
            x = inputs[lo]
            if (crossed and x.kind == "byte" and x.value == DLE and lo + 1 < len(inputs)
                    and inputs[lo + 1].kind == "byte" and inputs[lo + 1].value == DLE
                    and inputs[lo + 1].t - x.t <= c + r + 1e-4):
                return -1
        elif lo > 0 and inputs[lo - 1].t > t0 - r:
            x = inputs[lo - 1]
        else:
            return None
        return x.value if x.kind == "byte" else -1

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
            dur = self._duration(p, inp)
            rule = f"{rule} ({inp} = {1000 * dur:g} ms)"
            return Cause("timer", rule, ref, c + 0.05 * dur + 3e-6, self.late_abs + 0.25 * dur, code, name, ids)
        if inp in _LOCAL:
            # revealed by the seat's own byte (exact), or the echo application's job
            late = self._rest if inp == T.SEND_REQUEST else self.late_abs
            return Cause("local", rule, ref, 3e-6, late, code, name, ids)
        if T.Action.SETUP_ACKNOWLEDGED in actions:
            job = st.job
            if (self.apps[seat] == "echo" and job is not None
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
        r = self.procedure.rules().get(rule_id)
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
        if last is not None and last.kind == "break" and item.start - last.t < self._rest:
            return Cause("reply", *_AFTER_BREAK, 0.0, 0.0, Code.LINE_BREAK)
        if item.value == STX and (run.judge.seat, run.i_obs) in self._unsendable:
            return Cause("reply", *_LEN_RULE, 0.0, 0.0, Code.LEN_ILLEGAL, rules=("3964.TX.LEN-ILLEGAL",))
        rule, ref = _STATE_RULES.get(st.state, ("the model's behaviour", "§2.2.2"))
        return Cause("reply", rule, ref, 0.0, 0.0, rules=_STATE_RULE_IDS.get(st.state, ()))

    def name(self, byte: int) -> str:
        return _NAMES.get(byte, f"{byte:02X}")

    def variants(self, seat: str, resolution: float) -> list[Variant]:
        out = []
        if resolution > 0:
            out.append(Variant("resolution", f"with the other seat's characters {1000 * resolution:.3f} ms earlier "
                                             "(within the timing resolution)", shift=-resolution))
            out.append(Variant("resolution", f"with the other seat's characters {1000 * resolution:.3f} ms later "
                                             "(within the timing resolution)", shift=resolution))
            out.append(Variant("resolution", f"with the seat's own send jobs and free buffers up to "
                                             f"{1000 * resolution:.3f} ms before its characters show them "
                                             "(within the timing resolution)", lead=resolution))
        if self._variants is None:
            kit = self.procedure.fuzz_kit()
            # every alternative starts with its receive buffer busy (see fresh): this one with
            # nothing else changed says that a busy buffer explains the seat (Fig. 2-11)
            self._variants = [Variant("buffer", _BUFFER_WORDS, kind="buffer")] + [
                Variant(name, f"with the other reading of the manual's open point {name} "
                              f"({_READING_WORDS.get(name, 'see ptpcert.model.readings')})",
                        readings=replace(READINGS, **change))
                for name, change in (kit.alternatives if kit is not None else ())]
        return out + self._variants

    # -- reports --------------------------------------------------------------------------
    def describe(self, seat: str, its: list) -> str:
        """E.g. "STX", "block 31 10 32 (3 bytes, BCC)" or "DLE BREAK" (see :meth:`label`)."""
        parts = []
        data = bytearray()

        def flush() -> None:
            if data:
                parts.append(self._run_text(bytes(data)))
                data.clear()

        for it in its:
            if it.kind == "break":
                flush()
                parts.append("BREAK")
            elif it.kind == "invalid":
                flush()
                parts.append(f"{it.value:02X}(error)")
            else:
                data.append(it.value)
        flush()
        return " ".join(parts)

    def _run_text(self, data: bytes) -> str:
        if len(data) == 1:
            return self.name(data[0])
        end = data.find(bytes((DLE, ETX)))
        while end > 0:
            # an even number of DLEs before it: a real DLE ETX
            n = 0
            while end - 1 - n >= 0 and data[end - 1 - n] == DLE:
                n += 1
            if n % 2 == 0:
                break
            end = data.find(bytes((DLE, ETX)), end + 1)
        if end >= 0:
            payload = bytes(data[:end]).replace(bytes((DLE, DLE)), bytes((DLE,)))
            shown = payload[:8].hex(" ").upper() + (" ..." if len(payload) > 8 else "")
            tail = len(data) - end - 2
            return f"block {shown} ({len(payload)} bytes{', BCC' if tail == 1 else ''})".replace("block  (", "block (")
        if len(data) <= 6:
            return " ".join(self.name(x) for x in data)
        return data[:6].hex(" ").upper() + f" ... ({len(data)} bytes)"
