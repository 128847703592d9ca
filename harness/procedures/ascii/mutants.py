"""Deliberately broken variants of the ASCII driver's reference model, each breaking one rule
of the manual (§2.2.4; Figs. 2-20 to 2-23; Tables 2-7 to 2-10).

``ptpcert iut --procedure ASCII --mutant NAME`` runs one in real time, ``sim:?mutant=NAME``
in virtual time. Each is the reference station with one action, decision or table row
changed; ``profile`` names the settings under which its broken rule shows (the end
criterion, the send variant, flow control...), which the kill matrix and the tests use.
"""

from __future__ import annotations

from collections import deque

from ptpcert.model.codes import Code
from ptpcert.model.events import Status
from ptpcert.procedures.ascii.model import AsciiStation
from ptpcert.procedures.ascii.model import events as aev
from ptpcert.procedures.ascii.model import table as T
from ptpcert.procedures.ascii.model.params import BUFFER_BYTES, MAX_FRAME
from ptpcert.procedures.ascii.model.station import AsciiJob, Timer
from ptpcert.procedures.ascii.model.table import FcInput, FcState, Row, RxInput, RxState, TxInput, TxState
from ptpcert.variants import patched

from .mutant_registry import EC, EC2, FL, MUTANTS, XX, mutant


def _patched_rx(rows: dict) -> dict:
    """The receive tables of every end criterion, each with ``rows`` put in."""
    return {crit: patched(table, rows) for crit, table in T.RX_TABLES.items()}


# ---------------------------------------------------------------- receiving: the CDT
@mutant("cdt-half", "§2.2.4, Table 2-7: the receiver takes half the CDT as the end of a frame", end_criterion="cdt")
class _(AsciiStation):
    def __init__(self, params, *a, **kw):
        super().__init__(params, *a, **kw)
        self._cdt_window = 0.5 * self.params.cdt + self.params.char_time


@mutant("cdt-double", "§2.2.4, Table 2-7: the receiver waits twice the CDT before a frame ends", end_criterion="cdt")
class _(AsciiStation):
    def __init__(self, params, *a, **kw):
        super().__init__(params, *a, **kw)
        self._cdt_window = 2.0 * self.params.cdt + self.params.char_time


@mutant("no-watchdog", "§2.2.4 'fixed message frame length'; Fig. 2-23: the CDT does not watch a fixed-length frame; a short frame waits for more",
        **FL)
class _(AsciiStation):
    def _restart_cdt(self):
        if self.params.end_criterion == "cdt":
            super()._restart_cdt()
        else:
            self._stop(Timer.T_CDT)


@mutant("fragment-delivered", "§2.2.4 'fixed message frame length'; Fig. 2-23: a short fixed-length frame is delivered when the CDT expires",
        **FL)
class _(AsciiStation):
    def _rx_fragment_timeout(self, _v):
        frame, self._cur = bytes(self._cur), bytearray()
        self._store_frame(frame)


@mutant("trailing-kept", "§2.2.4 'end character(s)', malformed frames: characters after the end character are delivered as a frame of their own "
        "when the CDT expires", **EC)
class _(AsciiStation):
    def _rx_fragment_timeout(self, v):
        if not self._trailing:
            return super()._rx_fragment_timeout(v)
        frame, self._cur = bytes(self._cur), bytearray()
        self._store_frame(frame)


# ---------------------------------------------------------------- receiving: end characters and length
@mutant("end-char-not-stored", "§2.2.4 'end character(s)': the end character is not delivered with the data", **EC)
class _(AsciiStation):
    def _store_frame(self, frame):
        end = self.params.end_sequence
        if self.params.end_criterion == "end_chars" and frame.endswith(end) and len(frame) > len(end):
            frame = frame[:-len(end)]
        super()._store_frame(frame)


@mutant("end-char-waits-cdt", "§2.2.4 'end character(s)'; Fig. 2-22: a frame ends only when the CDT expires after its end character; "
        "what follows within the CDT is added to it", **EC)
class _(AsciiStation):
    def _classify(self, b):
        if self.params.end_criterion == "end_chars" and self.rx_state is not RxState.OFF:
            return RxInput.CHAR
        return super()._classify(b)

    def _rx_fragment_timeout(self, v):
        if self.params.end_sequence in self._cur:
            frame, self._cur = bytes(self._cur), bytearray()
            self._store_frame(frame)
            return
        super()._rx_fragment_timeout(v)


@mutant("either-end-char", "§2.2.4; Table A-7: with two end characters either one alone ends the frame", **EC2)
class _(AsciiStation):
    def _classify(self, b):
        if self.params.end_criterion == "end_chars" and self.rx_state is not RxState.OFF and b in self._end:
            return RxInput.END
        return super()._classify(b)


@mutant("fixed-length-plus-one", "§2.2.4 'fixed message frame length', Table 2-7: a fixed-length frame ends one character late", **FL)
class _(AsciiStation):
    def _classify(self, b):
        if self.params.end_criterion == "fixed_length" and self.rx_state is not RxState.OFF:
            count = 0 if self.rx_state is RxState.WAIT_CHAR else self._count
            return RxInput.END if count + 1 == self.params.fixed_length + 1 else RxInput.CHAR
        return super()._classify(b)


# ---------------------------------------------------------------- receiving: character errors and BREAK
@mutant("char-error-delivered", "Fig. 2-21; Table 8-1 (08)0CH: a frame with a parity error is delivered, the bad character "
        "left out, and no error is entered", end_criterion="cdt")
class _(AsciiStation):
    RX_TABLES = _patched_rx({
        (RxState.WAIT_CHAR, RxInput.INVALID): Row("ignore", T.SAME, "mutant"),
        (RxState.RECEIVE, RxInput.INVALID): Row("skip_invalid", T.SAME, "mutant"),
    })

    def _rx_skip_invalid(self, _v):
        self._count += 1
        self._restart_cdt()


@mutant("error-ends-frame-at-once", "Fig. 2-22; Table 8-1 (08)0CH: after a character error the frame is discarded at once, not "
        "at its end character; the rest of it is taken as a new frame", **EC)
class _(AsciiStation):
    RX_TABLES = _patched_rx({(RxState.RECEIVE, RxInput.INVALID): Row("drop_now", RxState.WAIT_CHAR, "mutant")})

    def _rx_drop_now(self, _v):
        self._emit(Status(self.now, Code.CHARACTER_ERROR, "receive"))
        self._emit(aev.FrameDiscarded(self.now, bytes(self._cur), aev.CHARACTER_ERROR, Code.CHARACTER_ERROR))
        self._cur = bytearray()


@mutant("break-ignored", "Table 8-1 (08)0DH: a BREAK is neither reported nor ends the frame coming in", end_criterion="cdt")
class _(AsciiStation):
    RX_TABLES = _patched_rx({(s, RxInput.BREAK): Row("ignore", T.SAME, "mutant") for s in RxState})


# ---------------------------------------------------------------- sending
@mutant("no-send-pause", "§2.2.4 'sending' (CDT criterion): no pause of more than the CDT between two frames sent",
        end_criterion="cdt")
class _(AsciiStation):
    def _tx_frame_sent(self, v):
        if self.params.end_criterion != "cdt":
            super()._tx_frame_sent(v)


@mutant("send-pause-half", "§2.2.4 'sending' (CDT criterion): the pause between two frames sent is half the CDT",
        end_criterion="cdt")
class _(AsciiStation):
    def _tx_frame_sent(self, v):
        self._last_frame_end = self.now - 0.5 * self.params.cdt - self._char


@mutant("fixed-length-no-pause", "§2.2.4 'sending' (fixed length): no pause of the CDT between frames although it is "
        "switched on", **FL)
class _(AsciiStation):
    def _tx_frame_sent(self, v):
        if self.params.end_criterion != "fixed_length":
            super()._tx_frame_sent(v)


@mutant("append-end-missing", "§2.2.4 'sending' (variant 3): the end character is not appended",
        send_variant="len_append_end", **EC)
class _(AsciiStation):
    def _tx_start_job(self, v):
        super()._tx_start_job(v)
        self.job.wire = self.job.payload


@mutant("up-to-end-not-cut", "§2.2.4 'sending' (variant 1): the data after the end character is sent as well",
        send_variant="up_to_end", **EC)
class _(AsciiStation):
    def _tx_start_job(self, v):
        super()._tx_start_job(v)
        self.job.wire = self.job.payload


@mutant("len-over-1024-sent", "Table 6-2, Table 8-2 (1E)41H: a send job longer than 1024 bytes is sent, not refused",
        end_criterion="cdt")
class _(AsciiStation):
    def request_send(self, now, payload):
        payload = bytes(payload)
        if len(payload) <= MAX_FRAME or self.mode == "STOP":
            return super().request_send(now, payload)
        self._at(now, strict=True)
        self._jobs.append(AsciiJob(payload, payload))
        if self.mode == "RUN":
            self._tx(TxInput.SEND_REQUEST)
        return True


# ---------------------------------------------------------------- flow control
@mutant("no-start-up-xon", "§2.2.4 'data flow control': no XON once parameterised", **XX)
class _(AsciiStation):
    def _fc_let_partner_send(self, v):
        if self.fc_state is FcState.OPEN:
            return  # the start-up XON
        super()._fc_let_partner_send(v)


@mutant("xoff-ignored", "§2.2.4 'data flow control': a received XOFF does not stop the transmission", **XX)
class _(AsciiStation):
    TX_TABLE = patched(T.TX_TABLE, {(s, TxInput.STOP): Row("ignore", T.SAME, "mutant") for s in TxState})


@mutant("xon-wait-endless", "§2.2.4, Table 2-9, Table 8-1 (07)08H: the wait time for XON never runs out", **XX)
class _(AsciiStation):
    def _start(self, timer, at):
        if timer is not Timer.T_XON_WAIT:
            super()._start(timer, at)


@mutant("xon-wait-half", "Table 2-9: the wait time for XON is half the configured one", **XX)
class _(AsciiStation):
    def _start(self, timer, at):
        if timer is Timer.T_XON_WAIT:
            at = self.now + 0.5 * self.params.xon_wait
        super()._start(timer, at)


@mutant("no-xoff-when-full", "§2.2.4 'data flow control': no XOFF when the buffer reaches its threshold", **XX)
class _(AsciiStation):
    FC_TABLE = patched(T.FC_TABLE, {(FcState.OPEN, FcInput.FULL): Row("ignore", T.SAME, "mutant")})


@mutant("no-xon-after-read", "§2.2.4 'data flow control': no XON once a read has made room after an XOFF", **XX)
class _(AsciiStation):
    FC_TABLE = patched(T.FC_TABLE, {(FcState.HELD, FcInput.ROOM): Row("ignore", T.SAME, "mutant")})


# ---------------------------------------------------------------- the receive buffer
@mutant("overwrite-when-prevented", "Table 2-10: with 'prevent overwrite' a full buffer drops its oldest frame for "
        "a new one", buffer_frames=2, **EC)
class _(AsciiStation):
    def _store_frame(self, frame):
        if self.params.prevent_overwrite and len(self._stored) >= self.params.buffer_frames:
            _, old = self._stored.popleft()
            self._stored_bytes -= len(old)
        super()._store_frame(frame)


@mutant("no-overwrite", "Table 2-10: with 'prevent overwrite = no' a new frame is discarded instead of replacing the "
        "unread one", buffer_frames=1, prevent_overwrite=False, **EC)
class _(AsciiStation):
    def _store_frame(self, frame):
        if not self.params.prevent_overwrite and len(self._stored) >= self.params.buffer_frames:
            self._emit(aev.FrameDiscarded(self.now, frame, aev.BUFFER_FULL, None))
            return
        super()._store_frame(frame)


@mutant("newest-first", "§2.2.4 'receive buffer': the newest frame is handed to the CPU first, not the oldest", **EC)
class _(AsciiStation):
    def read_frame(self, now):
        if len(self._stored) > 1:
            self._stored = deque([self._stored[-1], *list(self._stored)[:-1]])
        return super().read_frame(now)


@mutant("buffer-2048", "Table 2-10: the receive buffer takes 2048 bytes, not 1024", **EC)
class _(AsciiStation):
    def _put_char(self, b):
        self._count += 1
        self._prev = b
        if self._spoil is None and len(self._cur) >= MAX_FRAME:
            self._spoil_with(self.readings.q13_overlong_frame_code, aev.TOO_LONG)
        elif self._spoil is None:
            room = 2 * BUFFER_BYTES - len(self._cur) - (self._stored_bytes if self.params.prevent_overwrite else 0)
            if room <= 0:
                self._spoil_with(self.readings.q17_overflow_code, aev.NO_ROOM)
        self._cur.append(b)
        if self._spoil is None:
            self._full_check()


# the variants made for the rules catalogue's kill matrix register themselves (after these,
# so that the list keeps its order)
from . import mutants_rules  # noqa: E402,F401
