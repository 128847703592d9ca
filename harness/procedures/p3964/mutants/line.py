"""3964(R) variants that mishandle start-up, stray characters in idle, character errors and BREAK.

Part of :mod:`ptpcert.procedures.p3964.mutants`. These variants leave out the NAK at
start-up (Fig. 2-9), answer stray characters in idle wrongly (§2.2.2 'Receive/setup'),
take characters with a parity error for good ones or NAK them too soon (Fig. 2-12
'invalid character'), or mishandle a BREAK (§2.2.2 'Error handling', the legends of
Figs. 2-10 to 2-12), one variant per state where a BREAK may come. A ``# SUITE...`` comment
above a variant names the case of the rules catalogue it was made for.
"""

from __future__ import annotations

from ptpcert.model import events as ev
from ptpcert.model.codes import Code
from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import ETX, NAK, STX
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.variants import patched

from .registry import mutant


# ---------------------------------------------------------------- start-up and stray characters in idle
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


# SUITE.IDLE.QUIET-RESTARTS
@mutant("stray-nak-per-character", "§2.2.2 Receive/setup: every further stray character gets a NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.IDLE_JUNK, T.OTHER): T.Row("nak_now_and_wait_again", T.SAME)})

    def _a_nak_now_and_wait_again(self, v):
        self._a_quiet_nak(v)
        self._start_timer(T.T_CDT, self._durations()[0])


# ---------------------------------------------------------------- character errors
@mutant("parity-error-ignored", "§2.2.2 Receive/receiving data; Fig. 2-12 'invalid character': a character with a parity error is taken as valid")
class _(Station3964):
    def receive_invalid(self, now, value=0):
        self.receive(now, value)


@mutant("parity-error-nak-at-once", "§2.2.2 Receive/receiving data; Fig. 2-12 'note NAK': a parity error inside a block is answered by NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.RECEIVE, T.INVALID): T.Row("note_invalid_character", T.NAK_CHECK)})


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


# SUITE.SEND.CHARACTER-ERROR-DURING-DATA
@mutant("character-error-during-data-ignored", "§2.2.2 Sending data: a corrupted character during the block is ignored")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.SEND_DATA, T.INVALID): T.Row("ignore", T.SAME)})


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
