"""3964(R) variants that break the receiver: the block's characters, its end, its repetitions, its length.

Part of :mod:`ptpcert.procedures.p3964.mutants`. These variants read DLE pairs, the end
sequence or the BCC wrongly (Fig. 2-12, §2.2.2 'Receive'), refuse or miscount repetitions,
stay locked after giving a block up, or leave a block of the wrong length unanswered.
:class:`Counting` counts the block's bytes for the last of them (and for stand-ins in the
tests). Character errors and BREAK are in :mod:`.line`, the timers in :mod:`.timers`. A
``# SUITE...`` comment above a variant names the case of the rules catalogue it was made for.
"""

from __future__ import annotations

from ptpcert.procedures.p3964.model import table as T
from ptpcert.procedures.p3964.model.codec import DLE, MAX_BLOCK
from ptpcert.procedures.p3964.model.station import Station3964
from ptpcert.variants import patched

from .registry import mutant


# ---------------------------------------------------------------- the characters of the block
@mutant("no-dle-undoubling", "§2.2.2 Receive/receiving data; Fig. 2-12 'dual DLE': DLE DLE in the data is stored as two bytes")
class _(Station3964):
    def _a_store_doubled_dle(self, v):
        self._store(DLE, in_bcc=False)  # the first DLE is kept as data; the BCC is unchanged
        super()._a_store_doubled_dle(v)


@mutant("dle-other-accepted", "Fig. 2-12 'characters except ETX, DLE'; Table 8-1 16#0805: DLE followed by another character is taken as data")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_ETX, T.OTHER): T.Row("store", T.RECEIVE)})


# SUITE.RECEIVE.DATA-DLE-THEN-ETX/-STX/-NAK
@mutant("dle-pair-rescanned", "Fig. 2-12 'dual DLE': after a doubled data DLE the next character is read as if a DLE preceded it")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_ETX, T.DLE): T.Row("store_doubled_dle", T.WAIT_ETX)})


@mutant("bcc-not-checked", "§2.2.2 Receive/release; Table 8-1 16#0808: the received BCC is not compared")
class _(Station3964):
    def _d_bcc_check(self):
        return T.EVALUATE


@mutant("ack-at-etx-in-3964r", "Table 2-3; Fig. 2-12 'wait for BCC': a 3964R receiver answers at DLE ETX, before the BCC")
class _(Station3964):
    def _d_after_etx(self):
        return T.EVALUATE


# SUITE.RECEIVE.FROM-3964R-PARTNER
@mutant("3964-waits-for-bcc", "Table 2-3: a 3964 receiver waits for a BCC after DLE ETX", procedure="3964")
class _(Station3964):
    def _d_after_etx(self):
        return T.WAIT_BCC

    def _a_end_of_text(self, v):
        super()._a_end_of_text(v)
        self._start_timer(T.T_CDT, self._durations()[0])


# ---------------------------------------------------------------- repetitions and the free buffer
@mutant("repetition-refused", "Fig. 2-11 'repetition expected'; Fig. 2-12 'STX': a repetition after NAK is not answered")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_REPETITION, T.STX): T.Row("ignore", T.SAME)})


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


# SUITE.RECEIVE.GARBAGE-DURING-BUFFER-WAIT
@mutant("buffer-wait-garbage-accepted", "Table 8-1 16#0802: a character before the receiver's DLE makes it answer DLE")
class _(Station3964):
    TABLE = patched(T.TABLE, {(T.WAIT_BUFFER, T.OTHER): T.Row("buffer_freed", T.RECEIVE)})


# ---------------------------------------------------------------- the length of the block
class Counting(Station3964):
    """A station that counts the block it is receiving itself: its data bytes (``count``) and
    its doubled DLEs (``pairs``), for the variants here, and the stand-ins of the tests, that
    judge a block by its length. The counts start again with each block and repetition."""

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
class _(Counting):
    def _d_evaluate(self):
        if getattr(self, "count", 0) == 0:
            self._clear_reception()
            return T.IDLE
        return super()._d_evaluate()


# SUITE.RECEIVE.TOO-LONG-1025
@mutant("overlong-block-unanswered", "Table 8-1 16#0816: a block longer than 1024 bytes is answered with nothing")
class _(Counting):
    def _d_nak_check(self):
        if getattr(self, "count", 0) > MAX_BLOCK:
            self._clear_reception()
            self.count = 0
            return T.IDLE
        return super()._d_nak_check()


# SUITE.RECEIVE.MAX-STUFFING
@mutant("line-length-overflow-unanswered",
        "Table A-5; §2.2.2 Control characters, Note: a block of more than 1024 bytes on the line (doubled DLEs) is answered with nothing")
class _(Counting):
    def _d_evaluate(self):
        if getattr(self, "count", 0) + getattr(self, "pairs", 0) > MAX_BLOCK:
            self._clear_reception()
            return T.IDLE
        return super()._d_evaluate()
