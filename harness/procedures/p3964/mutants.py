"""Deliberately broken variants of the reference implementation, each breaking one rule.

They prove the suite's detection power: ``ptpcert iut --mutant NAME`` runs one in real
time, ``sim:?mutant=NAME`` in virtual time; the tests run the suite against each and
check that it fails, naming the cases that caught it. A mutant is the reference station
with one action, decision or table row changed; nothing else differs. A variant overrides the
station's protected hooks (actions, decisions, ``_body``, ``_durations``, the attempt limits) or
patches rows of its table; it never touches the station's private fields.
"""

from __future__ import annotations

from ptpcert.model import events as ev
from ptpcert.model.codes import Code
from ptpcert.procedure import Mutant
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.variants import patched, registrar

from .model import table as T
from .model.codec import DLE, ETX, MAX_BLOCK, NAK, STX, bcc
from .model.params import T_NAKTIM

MUTANTS: dict[str, Mutant] = {}


mutant = registrar(MUTANTS)


# ---------------------------------------------------------------- framing and BCC (send)
@mutant("bcc-without-end-sequence", "§2.2.2 Block check character: the BCC leaves out DLE ETX")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([b[-1] ^ DLE ^ ETX]) if self.params.has_bcc else b


@mutant("bcc-includes-stx", "§2.2.2 Block check character; Fig. 2-4: the BCC includes the STX")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([b[-1] ^ STX]) if self.params.has_bcc else b


@mutant("bcc-dle-counted-once", "§2.2.2 Block check character, Note: the BCC counts a doubled DLE once")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([bcc(payload)]) if self.params.has_bcc else b


@mutant("no-dle-doubling", "§2.2.2 Control characters, Note: data DLEs are not doubled")
class _(Station3964):
    def _body(self, payload):
        b = payload + bytes([DLE, ETX])
        return b + bytes([bcc(payload)]) if self.params.has_bcc else b


@mutant("bcc-doubled-when-dle", "§2.2.2 Block check character; Fig. 2-8: a BCC equal to DLE is doubled")
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b + bytes([DLE]) if self.params.has_bcc and b[-1] == DLE else b


# ---------------------------------------------------------------- receiving
@mutant("no-dle-undoubling", "§2.2.2 Receive/receiving data; Fig. 2-12 'dual DLE': DLE DLE in the data is stored as two bytes")
class _(Station3964):
    def _a_store_doubled_dle(self, v):
        self._store(DLE, in_bcc=False)  # the first DLE is kept as data; the BCC is unchanged
        super()._a_store_doubled_dle(v)


@mutant("bcc-not-checked", "§2.2.2 Receive/release; Table 8-1 16#0808: the received BCC is not compared")
class _(Station3964):
    def _d_bcc_check(self):
        return T.EVALUATE


@mutant("ack-at-etx-in-3964r", "Table 2-3; Fig. 2-12 'wait for BCC': a 3964R receiver answers at DLE ETX, before the BCC")
class _(Station3964):
    def _d_after_etx(self):
        return T.EVALUATE


@mutant("dle-other-accepted", "Fig. 2-12 'characters except ETX, DLE'; Table 8-1 16#0805: DLE followed by another character is taken as data")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_ETX, T.OTHER): T.Row("store", T.RECEIVE)})


@mutant("parity-error-ignored", "§2.2.2 Receive/receiving data; Fig. 2-12 'invalid character': a character with a parity error is taken as valid")
class _(Station3964):
    def receive_invalid(self, now, value=0):
        self.receive(now, value)


@mutant("parity-error-nak-at-once", "§2.2.2 Receive/receiving data; Fig. 2-12 'note NAK': a parity error inside a block is answered by NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.RECEIVE, T.INVALID): T.Row("note_invalid_character", T.NAK_CHECK)})


@mutant("no-cdt-after-dle", "Table 8-1 16#0806: no timeout for the first character after the receiver's DLE")
class _(Station3964):
    def _d_receive_entry(self):
        out = super()._d_receive_entry()
        if out == T.RECEIVE:
            self._stop_timer()
        return out


@mutant("repetition-refused", "Fig. 2-11 'repetition expected'; Fig. 2-12 'STX': a repetition after NAK is not answered")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_REPETITION, T.STX): T.Row("ignore", T.SAME)})


# ---------------------------------------------------------------- idle and start-up
@mutant("no-startup-nak", "Fig. 2-9 'send NAK': no NAK at start-up")
class _(Station3964):
    def _a_send_startup_nak(self, v):
        pass


@mutant("idle-nak-without-quiet-wait", "§2.2.2 Receive/setup: a stray character is NAKed at once, not after CDT")
class _(Station3964):
    def _a_start_quiet_wait(self, v):
        self._start_timer(T.T_CDT, 0.0)


@mutant("idle-stray-ignored", "§2.2.2 Receive/setup: stray characters in idle are never answered with NAK")
class _(Station3964):
    def _a_quiet_nak(self, v):
        self._emit(ev.Status(self.now, Code.RX_SETUP_ERROR, "receive"))


@mutant("nak-in-idle-answered", "§2.2.2 Receive/setup: a NAK in idle is treated as a stray character")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.IDLE, T.NAK): T.Row("start_quiet_wait", T.IDLE_JUNK)})


# ---------------------------------------------------------------- attempts and acknowledgements (send)
@mutant("setup-attempts-plus-one", "Fig. 2-10 'X <= 6 / X > 6'; Table 2-4: one STX more than the setup attempts")
class _(Station3964):
    def _setup_limit(self):
        return self.params.setup_attempts + 1


@mutant("setup-attempts-minus-one", "Fig. 2-10 'X <= 6 / X > 6'; Table 2-4: one STX fewer than the setup attempts")
class _(Station3964):
    def _setup_limit(self):
        return self.params.setup_attempts - 1


@mutant("tx-attempts-without-first", "Table 2-4: the first attempt is not counted (one block too many)")
class _(Station3964):
    def _tx_limit(self):
        return self.params.transmission_attempts + 1


@mutant("no-final-setup-nak", "§2.2.2 Send/setup; Fig. 2-10 'send NAK': no NAK after the last failed setup attempt")
class _(Station3964):
    def _d_setup_check(self):
        if self.job.x <= self._setup_limit():
            return super()._d_setup_check()
        self._fail_job(Code.SETUP_ATTEMPTS_EXCEEDED)
        return T.IDLE


@mutant("no-final-tx-nak", "Fig. 2-10 'send NAK': no NAK after the last failed transmission attempt")
class _(Station3964):
    def _d_tx_check(self):
        if self.job.w <= self._tx_limit():
            return super()._d_tx_check()
        self._fail_job(Code.TX_ATTEMPTS_EXCEEDED)
        return T.IDLE


@mutant("nak-after-data-nak", "§2.2.2 Sending data: a NAK during the data is answered with a NAK of its own")
class _(Station3964):
    def _a_send_refused(self, v):
        super()._a_send_refused(v)
        self._send(bytes([NAK]))


@mutant("no-quiet-before-nak", "§2.2.2 Sending data: after another character during the data, NAK at once (no CDT wait)")
class _(Station3964):
    def _a_send_interrupted(self, v):
        super()._a_send_interrupted(v)
        self._start_timer(T.T_CDT, 0.0)


@mutant("adt-half", "Table 2-4: the sender waits only half the ADT for DLE")
class _(Station3964):
    def _durations(self):
        cdt, adt = super()._durations()
        return cdt, adt / 2


@mutant("cdt-half", "Table 2-4: the receiver times out after half the CDT")
class _(Station3964):
    def _durations(self):
        cdt, adt = super()._durations()
        return cdt / 2, adt


# ---------------------------------------------------------------- priority
@mutant("high-priority-yields", "§2.2.2 Initialization conflict; Fig. 2-10 'high priority': a high-priority station answers the partner's STX with DLE",
        priority="high")
class _(Station3964):
    def _d_priority(self):
        self._stop_timer()
        self.deferred, self.job = self.job, None
        self._a_begin_reception(0)
        return T.RECEIVE_ENTRY


@mutant("low-priority-insists", "§2.2.2 Initialization conflict; Fig. 2-10 'low priority': a low-priority station ignores the partner's STX", priority="low")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_SETUP_ACK, T.STX): T.Row("ignore", T.SAME)})  # T_ADT keeps running


# ---------------------------------------------------------------- BREAK
@mutant("break-as-data", "§2.2.2 Error handling; Table 8-1 16#080D: a BREAK is read as a 00 character")
class _(Station3964):
    def line_break(self, now):
        self.receive(now, 0x00)


@mutant("nak-after-break", "§2.2.2 Error handling; Figs. 2-10 to 2-12 legend: a NAK is sent after a BREAK")
class _(Station3964):
    def _a_abandon_reception(self, v):
        super()._a_abandon_reception(v)
        self._send(bytes([NAK]))

    def _a_report_break(self, v):
        super()._a_report_break(v)
        self._send(bytes([NAK]))


@mutant("retry-after-break", "Fig. 2-10 legend: a BREAK during sending is followed by a new attempt")
class _(Station3964):
    TABLE = patched(T.TABLE, {(s, T.BREAK): T.Row("abort_job", T.TX_CHECK) for s in T.SENDER_STATES})

    def _a_abort_job(self, v):
        self._cancel_tx()
        self._emit(ev.Status(self.now, Code.LINE_BREAK, "send"))
        self.job.w += 1


# ---------------------------------------------------------------- made for the cases of the rules catalogue
# Each breaks the one rule a case of the suite checks (its name in the comment); the kill
# matrix test (tests/test_kill_matrix.py) runs that case against the variant and the reference.

# SUITE.RECEIVE.DATA-DLE-THEN-ETX/-STX/-NAK
@mutant("dle-pair-rescanned", "Fig. 2-12 'dual DLE': after a doubled data DLE the next character is read as if a DLE preceded it")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_ETX, T.DLE): T.Row("store_doubled_dle", T.WAIT_ETX)})


# SUITE.RECEIVE.BCC-CHARACTER-ERROR
@mutant("bcc-character-error-ignored", "Fig. 2-12 'invalid character': a BCC with a parity error is taken for its value")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_BCC, T.INVALID): T.Row("bcc_received", T.BCC_CHECK)})


# SUITE.RECEIVE.CHARACTER-ERROR-AFTER-DATA-DLE
@mutant("character-error-after-dle-nak-at-once",
        "Fig. 2-12 'wait for ETX', 'note NAK': a character error right after a data DLE is answered by NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_ETX, T.INVALID): T.Row("note_invalid_character", T.NAK_CHECK)})


# SUITE.RECEIVE.CHARACTER-ERROR-ON-ETX
@mutant("corrupted-etx-ends-block", "Fig. 2-12 'invalid character': an ETX with a parity error ends the block as an intact one")
class _(Station3964):
    def receive_invalid(self, now, value=0):
        if self.state is T.WAIT_ETX and value == ETX:
            self.receive(now, value)
        else:
            super().receive_invalid(now, value)


# SUITE.IDLE.CORRUPTED-STX
@mutant("corrupted-stx-accepted", "Fig. 2-11 'STX received'; Table 8-1 16#080C: a STX with a parity error in idle is answered with DLE")
class _(Station3964):
    def receive_invalid(self, now, value=0):
        if self.state is T.IDLE and value == STX:
            self.receive(now, value)
        else:
            super().receive_invalid(now, value)


# SUITE.SEND.DLE-DURING-DATA
@mutant("dle-during-data-is-acknowledgement", "§2.2.2 Sending data: a DLE in the middle of the block is taken for the acknowledgement")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.SEND_DATA, T.DLE): T.Row("dle_taken_as_acknowledgement", T.IDLE)})

    def _a_dle_taken_as_acknowledgement(self, v):
        self._cancel_tx()
        self._a_release_acknowledged(v)


# SUITE.SEND.STX-DURING-DATA
@mutant("stx-during-data-is-conflict", "§2.2.2 Sending data; §2.2.2 Initialization conflict: a STX during the block is taken for a conflict",
        priority="low")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.SEND_DATA, T.STX): T.Row("conflict_during_data", T.RECEIVE_ENTRY)})

    def _a_conflict_during_data(self, v):
        self._cancel_tx()
        self._a_initialization_conflict(v)


# SUITE.SEND.CHARACTER-ERROR-DURING-DATA
@mutant("character-error-during-data-ignored", "§2.2.2 Sending data: a corrupted character during the block is ignored")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.SEND_DATA, T.INVALID): T.Row("ignore", T.SAME)})


# SUITE.SEND.QUIET-RESTARTS
@mutant("sender-nak-per-character", "§2.2.2 Sending data: every further character during the quiet wait gets a NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.ABORT_QUIET, T.OTHER): T.Row("nak_now_and_wait_again", T.SAME)})

    def _a_nak_now_and_wait_again(self, v):
        self._send(bytes([NAK]))
        self._start_timer(T.T_CDT, self._durations()[0])


# SUITE.IDLE.QUIET-RESTARTS
@mutant("stray-nak-per-character", "§2.2.2 Receive/setup: every further stray character gets a NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.IDLE_JUNK, T.OTHER): T.Row("nak_now_and_wait_again", T.SAME)})

    def _a_nak_now_and_wait_again(self, v):
        self._a_quiet_nak(v)
        self._start_timer(T.T_CDT, self._durations()[0])


# SUITE.SEND.SETUP-ATTEMPTS-MIXED
class _PerCause(Station3964):
    """A job's attempt counter (``counter``: the job's ``x`` or ``w``) kept per kind of failure."""
    counter = "x"

    def _a_start_job(self, v):
        super()._a_start_job(v)
        self.causes = {}

    def count_cause(self, cause):
        self.causes[cause] = self.causes.get(cause, 0) + 1
        setattr(self.job, self.counter, 1 + max(self.causes.values()))


@mutant("setup-counter-per-cause", "Fig. 2-10 'X+1': each kind of failed setup (NAK, timeout, character error) has a counter of its own")
class _(_PerCause):
    counter = "x"

    def _a_setup_refused(self, v):
        super()._a_setup_refused(v)
        self.count_cause("refused")

    def _a_setup_invalid_character(self, v):
        super()._a_setup_invalid_character(v)
        self.count_cause("invalid")

    def _a_setup_timeout(self, v):
        super()._a_setup_timeout(v)
        self.count_cause("timeout")


# SUITE.RELEASE.ATTEMPTS-MIXED
@mutant("transmission-counter-per-cause",
        "Table 2-4 transmission attempts; Fig. 2-10 'W+1': each kind of failed attempt has a counter of its own")
class _(_PerCause):
    counter = "w"

    def _a_send_refused(self, v):
        super()._a_send_refused(v)
        self.count_cause("data NAK")

    def _a_release_refused(self, v):
        super()._a_release_refused(v)
        self.count_cause("refused")

    def _a_release_invalid_character(self, v):
        super()._a_release_invalid_character(v)
        self.count_cause("invalid")

    def _a_release_timeout(self, v):
        super()._a_release_timeout(v)
        self.count_cause("timeout")

    def _a_abort_nak(self, v):
        super()._a_abort_nak(v)
        self.count_cause("other")


# SUITE.SEND.SETUP-EXHAUSTED-ENDS-JOB
@mutant("setup-exhaustion-retries-block",
        "Fig. 2-10 'X > 6', 'send NAK': used-up setup attempts start a new transmission attempt instead of ending the job")
class _(Station3964):
    def _d_setup_check(self):
        job = self.job
        if job.x > self._setup_limit() and job.w < self._tx_limit():
            job.w += 1
            job.x = 1
            self._send_stx()
            return T.WAIT_SETUP_ACK
        return super()._d_setup_check()


# SUITE.COUNTERS.SETUP-PER-JOB
@mutant("setup-counter-never-reset", "Fig. 2-10 'send request', 'X := 1': a new job goes on with the setup counter of the last one")
class _(Station3964):
    def _a_start_job(self, v):
        carried = self.deferred is None and getattr(self, "last_x", None)
        super()._a_start_job(v)
        if carried:
            self.job.x = carried

    def _a_release_acknowledged(self, v):
        self.last_x = self.job.x
        super()._a_release_acknowledged(v)


# SUITE.COUNTERS.TRANSMISSION-PER-JOB
@mutant("transmission-counter-never-reset",
        "Fig. 2-10 'send request', 'W := 1': a new job goes on with the transmission counter of the last one")
class _(Station3964):
    def _a_start_job(self, v):
        carried = self.deferred is None and getattr(self, "last_w", None)
        super()._a_start_job(v)
        if carried:
            self.job.w = carried

    def _a_release_acknowledged(self, v):
        self.last_w = self.job.w
        super()._a_release_acknowledged(v)


# SUITE.COUNTERS.SETUP-PER-ATTEMPT
@mutant("setup-counter-spent-per-attempt",
        "Fig. 2-10 'X := 1': a repeated block gets a single setup attempt (the counter is set to its limit)")
class _(Station3964):
    def _d_tx_check(self):
        out = super()._d_tx_check()
        if out is T.WAIT_SETUP_ACK:
            self.job.x = self._setup_limit()
        return out


# SUITE.COUNTERS.RECEIVE-PER-BLOCK
@mutant("receive-counter-never-reset",
        "Fig. 2-11 'STX received'; Fig. 2-12 'W > 5': a new block goes on with the reception count of the last one",
        priority="low")
class _(Station3964):
    def _a_begin_reception(self, v):
        super()._a_begin_reception(v)
        self.receptions = getattr(self, "receptions", 0) + 1

    def _a_repetition_begins(self, v):
        super()._a_repetition_begins(v)
        self.receptions += 1

    def _d_nak_check(self):
        out = super()._d_nak_check()
        if out is T.WAIT_REPETITION and self.receptions >= self.params.transmission_attempts:
            self._stop_timer()   # it gives up as if this block had used up the receptions
            return T.IDLE
        return out


# SUITE.RECEIVE.REPETITION-LIMIT
@mutant("receiver-locked-after-limit",
        "Fig. 2-12 'W > 5': after giving up a block the receiver answers no further STX with DLE (its buffer stays taken)")
class _(Station3964):
    def _d_nak_check(self):
        out = super()._d_nak_check()
        if out is T.IDLE:
            self.buffer_free = False
        return out


# SUITE.RECEIVE.AFTER-T-BLOCK
@mutant("receiver-locked-after-t-block",
        "Fig. 2-12 'T > T_BLOCK': after T_BLOCK the receiver answers no further STX with DLE (its buffer stays taken)")
class _(Station3964):
    def _a_repetition_timeout(self, v):
        super()._a_repetition_timeout(v)
        self.buffer_free = False


# SUITE.RECEIVE.PARTNER-GAVE-UP
@mutant("receiver-locked-after-partner-nak",
        "Fig. 2-12 'wait for STX': after the partner's NAK the receiver answers no further STX with DLE")
class _(Station3964):
    def _a_partner_gave_up(self, v):
        super()._a_partner_gave_up(v)
        self.buffer_free = False


# SUITE.RECEIVE.NO-FREE-BUFFER
@mutant("buffer-wait-too-short", "Fig. 2-11 'T_NAKTIM = 400 ms': with no free buffer the STX is answered with NAK after 200 ms")
class _(Station3964):
    def _d_receive_entry(self):
        out = super()._d_receive_entry()
        if out is T.WAIT_BUFFER:
            self._start_timer(T.T_NAKTIM, T_NAKTIM / 2)
        return out


# SUITE.RECEIVE.GARBAGE-DURING-BUFFER-WAIT
@mutant("buffer-wait-garbage-accepted", "Table 8-1 16#0802: a character before the receiver's DLE makes it answer DLE")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_BUFFER, T.OTHER): T.Row("buffer_freed", T.RECEIVE)})


# SUITE.TIMING.GAP-AT-80-CDT-IN-DLE-PAIR
@mutant("cdt-half-after-data-dle", "Fig. 2-12 'wait for ETX', 'start T_CDT': after a DLE in the data the receiver waits only half the CDT")
class _(Station3964):
    def _a_dle_received(self, v):
        super()._a_dle_received(v)
        self._start_timer(T.T_CDT, self._durations()[0] / 2)


# SUITE.RECEIVE.FROM-3964R-PARTNER
@mutant("3964-waits-for-bcc", "Table 2-3: a 3964 receiver waits for a BCC after DLE ETX", procedure="3964")
class _(Station3964):
    def _d_after_etx(self):
        return T.WAIT_BCC

    def _a_end_of_text(self, v):
        super()._a_end_of_text(v)
        self._start_timer(T.T_CDT, self._durations()[0])


# SUITE.CONFLICT.HIGH-NO-DLE
@mutant("partner-stx-refuses-setup", "Fig. 2-10 'high priority'; Table 8-1 16#0702: a high-priority station takes the partner's STX for a refused setup",
        priority="high")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_SETUP_ACK, T.STX): T.Row("setup_refused", T.SETUP_CHECK)})


# SUITE.BREAK.* in the states not covered before
def _break_ignored(name: str, state: str, rule: str, **profile) -> None:
    class BreakIgnored(Station3964):
        TABLE = patched(T.TABLE, {(state, T.BREAK): T.Row("ignore", T.SAME)})
    mutant(name, rule, **profile)(BreakIgnored)


_break_ignored("break-ignored-waiting-for-etx", T.WAIT_ETX,
               "Fig. 2-12 legend 'BREAK': a BREAK after a DLE in the data is ignored (the CDT timeout then NAKs)")
_break_ignored("break-ignored-waiting-for-bcc", T.WAIT_BCC,
               "Fig. 2-12 legend 'BREAK': a BREAK while waiting for the BCC is ignored (the CDT timeout then NAKs)")
_break_ignored("break-ignored-in-idle-quiet-wait", T.IDLE_JUNK,
               "Fig. 2-11 legend 'BREAK': a BREAK during the wait before the NAK for a stray character is ignored")
_break_ignored("break-ignored-in-sender-quiet-wait", T.ABORT_QUIET,
               "Fig. 2-10 legend 'BREAK': a BREAK during the sender's wait before its NAK is ignored")
_break_ignored("break-ignored-waiting-for-buffer", T.WAIT_BUFFER,
               "Fig. 2-11 legend 'BREAK': a BREAK during the wait for a free buffer is ignored (the NAK of T_NAKTIM follows)")


class _Counting(Station3964):
    """The bytes of the block being received, counted by the variant itself."""

    def _a_begin_reception(self, v):
        super()._a_begin_reception(v)
        self.count = self.pairs = 0

    def _a_repetition_begins(self, v):
        super()._a_repetition_begins(v)
        self.count = self.pairs = 0

    def _store(self, b, in_bcc=True):
        super()._store(b, in_bcc)
        self.count = getattr(self, "count", 0) + 1

    def _store_run(self, run):
        super()._store_run(run)
        self.count = getattr(self, "count", 0) + len(run)

    def _a_store_doubled_dle(self, v):
        super()._a_store_doubled_dle(v)
        self.pairs = getattr(self, "pairs", 0) + 1


# SUITE.RECEIVE.ZERO-LENGTH
@mutant("zero-length-unanswered", "Table 6-3 LEN; §2.2.2 Receive/release: a block without data is answered with nothing")
class _(_Counting):
    def _d_evaluate(self):
        if getattr(self, "count", 0) == 0:
            self._clear_reception()
            return T.IDLE
        return super()._d_evaluate()


# SUITE.RECEIVE.TOO-LONG-1025
@mutant("overlong-block-unanswered", "Table 8-1 16#0816: a block longer than 1024 bytes is answered with nothing")
class _(_Counting):
    def _d_nak_check(self):
        if getattr(self, "count", 0) > MAX_BLOCK:
            self._clear_reception()
            self.count = 0
            return T.IDLE
        return super()._d_nak_check()


# SUITE.RECEIVE.MAX-STUFFING
@mutant("line-length-overflow-unanswered",
        "Table A-5; §2.2.2 Control characters, Note: a block of more than 1024 bytes on the line (doubled DLEs) is answered with nothing")
class _(_Counting):
    def _d_evaluate(self):
        if getattr(self, "count", 0) + getattr(self, "pairs", 0) > MAX_BLOCK:
            self._clear_reception()
            return T.IDLE
        return super()._d_evaluate()


# SUITE.FRAME.SEVEN-BIT
@mutant("bcc-eighth-bit-set", "Table 2-5 (7 data bits): the BCC is sent with its eighth bit set", data_bits=7)
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([b[-1] | 0x80]) if self.params.has_bcc else b
