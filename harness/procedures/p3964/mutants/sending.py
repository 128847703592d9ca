"""3964(R) variants that break the sender: the block it frames, the data phase, the initialization conflict.

Part of :mod:`ptpcert.procedures.p3964.mutants`. These variants get the frame wrong (the
BCC, DLE doubling, the eighth bit with 7 data bits), mishandle what the partner sends while
the block goes out (Fig. 2-10, §2.2.2 'Sending data'), or get the initialization conflict
wrong: the priority that yields, a partner's STX taken for something else (§2.2.2
'Initialization conflict'). The attempt counters of a send job are in :mod:`.attempts`,
the timers in :mod:`.timers`. A ``# SUITE...`` comment above a variant names the case of
the rules catalogue it was made for.
"""

from __future__ import annotations

from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import DLE, ETX, NAK, STX, bcc
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.variants import patched

from .registry import mutant


# ---------------------------------------------------------------- framing and BCC of the block sent
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


# SUITE.FRAME.SEVEN-BIT
@mutant("bcc-eighth-bit-set", "Table 2-5 (7 data bits): the BCC is sent with its eighth bit set", data_bits=7)
class _(Station3964):
    def _body(self, payload):
        b = super()._body(payload)
        return b[:-1] + bytes([b[-1] | 0x80]) if self.params.has_bcc else b


# ---------------------------------------------------------------- the data phase
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


# SUITE.SEND.DLE-DURING-DATA
@mutant("dle-during-data-is-acknowledgement", "§2.2.2 Sending data: a DLE in the middle of the block is taken for the acknowledgement")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.SEND_DATA, T.DLE): T.Row("dle_taken_as_acknowledgement", T.IDLE)})

    def _a_dle_taken_as_acknowledgement(self, v):
        self._cancel_tx()
        self._a_release_acknowledged(v)


# SUITE.SEND.QUIET-RESTARTS
@mutant("sender-nak-per-character", "§2.2.2 Sending data: every further character during the quiet wait gets a NAK at once")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.ABORT_QUIET, T.OTHER): T.Row("nak_now_and_wait_again", T.SAME)})

    def _a_nak_now_and_wait_again(self, v):
        self._send(bytes([NAK]))
        self._start_timer(T.T_CDT, self._durations()[0])


# ---------------------------------------------------------------- initialization conflict and priority
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


# SUITE.SEND.STX-DURING-DATA
@mutant("stx-during-data-is-conflict", "§2.2.2 Sending data; §2.2.2 Initialization conflict: a STX during the block is taken for a conflict",
        priority="low")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.SEND_DATA, T.STX): T.Row("conflict_during_data", T.RECEIVE_ENTRY)})

    def _a_conflict_during_data(self, v):
        self._cancel_tx()
        self._a_initialization_conflict(v)


# SUITE.CONFLICT.HIGH-NO-DLE
@mutant("partner-stx-refuses-setup", "Fig. 2-10 'high priority'; Table 8-1 16#0702: a high-priority station takes the partner's STX for a refused setup",
        priority="high")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_SETUP_ACK, T.STX): T.Row("setup_refused", T.SETUP_CHECK)})
