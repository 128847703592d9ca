"""More broken variants of the ASCII driver, made for the rules catalogue's kill matrix
(``tests/procedures/ascii/test_ascii_kill_matrix.py``): each breaks one rule of
``rules.toml`` that the variants of :mod:`.mutants` leave whole. They are entered into the
same :data:`~ptpcert.procedures.ascii.mutant_registry.MUTANTS` (``--mutant NAME``, ``sim:?mutant=NAME``)."""

from __future__ import annotations

from ptpcert.model.codes import Code
from ptpcert.procedures.ascii.model import AsciiStation
from ptpcert.procedures.ascii.model import events as aev
from ptpcert.procedures.ascii.model.station import Timer
from ptpcert.procedures.ascii.model.table import RxInput, RxState

from .mutant_registry import EC, EC2, XX, mutant

# ---------------------------------------------------------------- the character frame
@mutant("nul-dropped", "§2.2.4 'code transparency'; Table 2-8: a received 00 is taken for a filler and dropped, not "
        "stored as data", end_criterion="cdt")
class _(AsciiStation):
    def _char_in(self, b):
        if (b & (0x7F if self.params.data_bits == 7 else 0xFF)) == 0:
            return
        super()._char_in(b)


# ---------------------------------------------------------------- receiving
@mutant("cdt-quarter", "§2.2.4, Table 2-7: the receiver takes a quarter of the CDT for the CDT (frame end and watchdog)",
        **EC)
class _(AsciiStation):
    def __init__(self, params, *a, **kw):
        super().__init__(params, *a, **kw)
        self._cdt_window = 0.25 * self.params.cdt + self.params.char_time


@mutant("trailing-dropped", "§2.2.4 'end character(s)', 'fixed message frame length' (malformed frames): characters that "
        "follow a complete frame within the CDT are dropped, not merged with the next frame", **EC)
class _(AsciiStation):
    def _put_char(self, b):
        if self._trailing:
            self._count += 1
            self._prev = b
            return
        super()._put_char(b)


@mutant("pair-across-cdt", "§2.2.4 'end character(s)' (malformed frames): with two end characters, end character 2 "
        "completes a frame although the CDT expired after end character 1", **EC2)
class _(AsciiStation):
    _held = None

    def _rx_fragment_timeout(self, v):
        self._held = self._prev
        super()._rx_fragment_timeout(v)

    def _classify(self, b):
        held, self._held = self._held, None
        end = self._end
        if (self.params.end_criterion == "end_chars" and len(end) == 2 and self.rx_state is RxState.WAIT_CHAR
                and held == end[0] and b == end[1]):
            return RxInput.END
        return super()._classify(b)


@mutant("fragment-silent", "§2.2.4 (malformed frames); Table 8-1 (08)06H: a fragment the CDT cuts off is discarded "
        "without an error", **EC)
class _(AsciiStation):
    def _rx_fragment_timeout(self, _v):
        self._emit(aev.FrameDiscarded(self.now, bytes(self._cur), aev.CDT_EXPIRED, None))
        self._cur = bytearray()
        self._room_check("discard")


@mutant("frame-limit-1000", "Table A-7; §2.2.4 'receive buffer': a frame over 1000 bytes is discarded as too long "
        "(the limit is 1024)", end_criterion="cdt")
class _(AsciiStation):
    def _put_char(self, b):
        if self._spoil is None and len(self._cur) >= 1000:
            self._spoil_with(Code.FRAME_TOO_LONG, aev.TOO_LONG)
        super()._put_char(b)


# ---------------------------------------------------------------- sending
@mutant("last-byte-not-sent", "§2.2.4 'sending'; Fig. 2-20: the last byte of a send job of two or more bytes is not "
        "sent", end_criterion="cdt")
class _(AsciiStation):
    def _tx_start_job(self, v):
        super()._tx_start_job(v)
        if len(self.job.wire) > 1:
            self.job.wire = self.job.wire[:-1]


@mutant("len-with-end-appends", "§2.2.4 'sending' (variant 2): the end character is appended to the LEN bytes, "
        "which already end with it", send_variant="len_with_end", **EC)
class _(AsciiStation):
    def _tx_start_job(self, v):
        super()._tx_start_job(v)
        if self.params.send_variant == "len_with_end":
            self.job.wire = self.job.payload + self.params.end_sequence


@mutant("send-limit-1000", "Table 6-2 LEN 1..1024; Table 8-2 (1E)41H: a send job over 1000 bytes is refused",
        end_criterion="cdt")
class _(AsciiStation):
    def request_send(self, now, payload):
        if len(payload) > 1000 and self.mode == "RUN":
            self._at(now, strict=True)
            return self._refuse(bytes(payload), Code.LEN_ILLEGAL)
        return super().request_send(now, payload)


# ---------------------------------------------------------------- flow control
@mutant("flow-code-ends-frame", "§2.2.4 'data flow control' note: a received XON or XOFF ends the frame coming in, as "
        "if it were an end character", **XX)
class _(AsciiStation):
    def _char_in(self, b):
        p = self.params
        if self._xonxoff and b in (p.xon, p.xoff) and self.rx_state is RxState.RECEIVE and self._cur:
            frame, self._cur = bytes(self._cur), bytearray()
            self._stop(Timer.T_CDT)
            self.rx_state = RxState.WAIT_CHAR
            self._store_frame(frame)
        super()._char_in(b)


@mutant("overlong-spoils-next", "Table A-7; §2.2.4: after a frame longer than 1024 bytes the next frame is discarded "
        "as well (the error is not cleared)", end_criterion="cdt")
class _(AsciiStation):
    _latched = False

    def _report_spoiled(self, cdt):
        self._latched = self._latched or self._spoil_reason == aev.TOO_LONG
        super()._report_spoiled(cdt)

    def _store_frame(self, frame):
        if self._latched:
            self._latched = False
            self._emit(aev.FrameDiscarded(self.now, frame, aev.TOO_LONG, None))
            return
        super()._store_frame(frame)
