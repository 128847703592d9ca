"""More broken variants of the RK 512 reference: one for each rule of the catalogue
(``ptpcert rules --procedure RK512``) that the variants of :mod:`.mutants` do not break on
purpose, so that the kill matrix (tests/procedures/rk512/test_rk512_kill_matrix.py) shows a
case failing each rule's own defect. Entered into the same registry as :mod:`.mutants`
(which imports this module at its end); both take their registry and kinds of change from
:mod:`.mutant_base`."""

from __future__ import annotations

from dataclasses import replace

from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.model import Rk512Station
from ptpcert.procedures.rk512.model.codec import CHUNK, FIRST, response_head
from ptpcert.procedures.rk512.mutant_base import LinkMutant, RequestChange, Rewrite, mutant

_FETCH, _SEND_DB, _SEND_DX = 0x45, 0x41, 0x4F


# ---------------------------------------------------------------- the responder's checks: a wrong REATEL
def _wrong_reatel(check: str, reatel: int) -> type:
    """A station whose header check ``check`` (Rk512Station._c_<check>) answers ``reatel``."""
    original = getattr(Rk512Station, "_c_" + check)

    def changed(self, frame, op):
        bad = original(self, frame, op)
        return None if bad is None else (bad[0], reatel)

    return type("_WrongReatel", (Rk512Station,), {"_c_" + check: changed})


for _check, _reatel, _table in (
        ("byte3", 0x10, "Table 8-3 (16#0602: 16h): a bad command letter is refused with 10h"),
        ("byte4", 0x16, "Table 8-3 (16#0604: 10h): a bad data type is refused with 16h"),
        ("address", 0x14, "Table 8-3 (16#0607: 0Ch): a start address beyond the area is refused with 14h"),
        ("length", 0x0C, "Table 8-3 (16#0608: 34h): a length not allowed is refused with 0Ch"),
        ("flag", 0x34, "Table 8-3 (16#0609: 0Ch): a flag bit above 7 is refused with 34h"),
        ("cpu", 0x14, "Table 8-3 (16#060A: 0Ch): a CPU number not permitted is refused with 14h"),
        ("short", 0x16, "Table 8-1 16#0610: a command too short is answered with 16h (no reading gives it)")):
    mutant(f"check-{_check}-reatel-{_reatel:02x}", _table)(_wrong_reatel(_check, _reatel))


@mutant("check-byte2-reatel-16", "§2.2.3 Table 2-1 byte 2 (AMB-13): a command byte 2 other than 00h is refused "
        "with 16h (neither reading gives it)")
class _(Rk512Station):
    def _c_byte2(self, frame, op):
        return (Code.CMD_BYTE1_INVALID, 0x16) if frame[1] != 0 else None


@mutant("byte1-reatel-16", "Table 8-3 (16#0601: 10h): a command byte 1 other than 00h/FFh is refused with 16h")
class _(Rk512Station):
    def _p_refuse_bad_id(self, frame):
        self._status(Code.CMD_BYTE1_INVALID, "receive")
        self._queue(response_head(True, 0x16), "P", None, "REATEL 16h for 16#0601")


@mutant("reatel-36-as-37", "§8.4 Table 8-3: the synchronisation error is sent as 37h, a number the table does not list")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and len(frame) == 4 and frame[3] == 0x36:
            return frame[:3] + b"\x37"
        return frame


@mutant("responder-events-not-reported", "§8.3 Table 8-1 class 06: the responder sends its error numbers but "
        "reports no class-06 event")
class _(Rk512Station):
    def _status(self, code, side, final=False):
        if side != "receive" or int(code) >> 8 != 0x06:
            super()._status(code, side, final)


@mutant("response-failure-not-reported", "§8.3 Table 8-1 16#0612: a response the link gave up on is not reported")
class _(Rk512Station):
    def _status(self, code, side, final=False):
        if int(code) != Code.RESPONSE_NOT_SENT:
            super()._status(code, side, final)


# ---------------------------------------------------------------- the responder's responses and areas
@mutant("response-sent-twice", "§2.2.3 'Response message frame': the positive response that ends a partner's "
        "request is sent twice")
class _(Rk512Station):
    def _queue(self, frame, origin, owner, detail=""):
        super()._queue(frame, origin, owner, detail)
        if origin == "P" and frame == response_head(True, 0) and getattr(owner, "final", False) and not self._out:
            super()._queue(frame, origin, owner, detail)


@mutant("fetch-response-in-two-blocks", "§2.2.3 Figs. 2-15, 2-16: a FETCH response's header and data go in two "
        "3964(R) blocks")
class _(Rk512Station):
    def _queue(self, frame, origin, owner, detail=""):
        if origin == "P" and len(frame) > 4 and frame[3] == 0:
            super()._queue(frame[:4], origin, owner, detail)
            frame = frame[4:]
        super()._queue(frame, origin, owner, detail)


@mutant("data-bit-7-cleared", "§2.3.2 note (8 data bits): FETCH data leave with bit 7 cleared (a 7-bit data path)")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and len(frame) > 4 and frame[3] == 0:
            return frame[:4] + bytes(b & 0x7F for b in frame[4:])
        return frame


@mutant("send-to-dx-refused", "§6.3.2 'Receiving data', Table 6-9: a SEND to a DX ('O') is refused with 16h")
class _(Rk512Station):
    def _c_byte3(self, frame, op):
        return (Code.CMD_BYTE3_INVALID, 0x16) if op.b3 == _SEND_DX else super()._c_byte3(frame, op)


@mutant("byte-areas-not-served", "§6.3.2 'Providing data', Table 6-10: a FETCH of inputs, outputs or flags is "
        "refused with 10h")
class _(Rk512Station):
    def _c_byte4(self, frame, op):
        if op.fetch and op.b4 in b"EAM":
            return Code.CMD_BYTE4_INVALID, 0x10
        return super()._c_byte4(frame, op)


@mutant("flag-never-cleared", "§6.3.2 'Using interprocessor communication flags': a coordination flag the "
        "user program resets stays set")
class _(Rk512Station):
    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        setter = self.memory.set_flag
        self.memory.set_flag = lambda byte, bit, value=1: setter(byte, bit, 1) if value else None


@mutant("cell-limit-ignored", "§6.3.2 'Providing data' note: timers and counters are served beyond the 32 bytes "
        "the profile declares", cell_fetch_limit_bytes=32)
class _(Rk512Station):
    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self._cell_limit = None


@mutant("length-limit-512", "§6.3.2 Tables 6-9, 6-10 (LEN 1..1024): a request over 512 bytes is refused with 34h")
class _(Rk512Station):
    def _c_length(self, frame, op):
        if self._usable(frame, op) and op.nbytes > 512:
            return Code.LENGTH_NOT_ALLOWED, 0x34
        return super()._c_length(frame, op)


@mutant("passive-tres-quarter", "Fig. 2-19 'T > T_RES': the responder waits a quarter of T_RES for a continuation")
class _(Rk512Station):
    def _d_after_response(self, f):
        state = super()._d_after_response(f)
        if self.open is not None:
            self._t_res_p = self.now + 0.25 * self._t_res
        return state


# ---------------------------------------------------------------- the requester's commands
def _first_command(frame: bytes) -> bool:
    return len(frame) >= 10 and frame[0] == FIRST and frame[2] in (_FETCH, _SEND_DB, _SEND_DX)


@mutant("send-dx-type-x", "§2.2.3 Table 2-1 byte 4 ('only D when sending'): a SEND to a DX is sent 'O' 'X'")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and len(frame) >= 4 and frame[2] == _SEND_DX:
            return frame[:3] + b"X" + frame[4:]
        return frame


@mutant("fetch-command-letter-f", "§2.2.3 Table 2-1 byte 3: a FETCH is sent with 'F' (46h), not 'E'")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and len(frame) >= 4 and frame[2] == _FETCH:
            return frame[:2] + b"F" + frame[3:]
        return frame


@mutant("fetch-dx-as-d", "§6.3.2 Table 6-8: a FETCH from a DX is sent with type 'D', not 'X'")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and len(frame) >= 4 and frame[2] == _FETCH and frame[3] == ord("X"):
            return frame[:3] + b"D" + frame[4:]
        return frame


@mutant("dw-sent-as-byte-offset", "§2.2.3 Table 2-1 footnote 1: byte 6 of a DB/DX command is the byte offset, not "
        "the data word")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and _first_command(frame) and frame[3] in b"DX":
            return frame[:5] + bytes([(2 * frame[5]) & 0xFF]) + frame[6:]
        return frame


@mutant("byte-length-in-words", "§2.2.3 Table 2-1 bytes 7/8: a FETCH of inputs, outputs or flags counts its length "
        "in words")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and _first_command(frame) and frame[2] == _FETCH and frame[3] in b"EAM":
            n = -(-((frame[6] << 8) | frame[7]) // 2)
            return frame[:6] + bytes([n >> 8, n & 0xFF]) + frame[8:]
        return frame


@mutant("length-of-first-frame", "§2.2.3 Table 2-1 bytes 7/8: the first frame of a long SEND announces only its own "
        "128 bytes")
class _(Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and _first_command(frame) and frame[2] != _FETCH and len(frame) == 10 + CHUNK:
            return frame[:6] + bytes([0, CHUNK // 2]) + frame[8:]
        return frame


@mutant("odd-offset-rounded-up", "§6.3.2 'Important notes': an odd offset into a partner DB is rounded up, not down")
class _(RequestChange):
    def change(self, req):
        return replace(req, address=req.address + 1) if req.area.block and req.address % 2 else req


@mutant("local-checks-skipped", "§6.3.2 Tables 6-4, 6-6; Table 8-1 class 05: the requester checks nothing before it "
        "sends: a request the FB refuses goes on the line")
class _(Rk512Station):
    def _d_local_check(self, f):
        import ptpcert.procedures.rk512.model.core as core
        check, core.local_check = core.local_check, lambda req, readings=None: None
        try:
            return super()._d_local_check(f)
        finally:
            core.local_check = check


@mutant("odd-fetch-stores-pad", "§6.3.2 'Notes on DB/DX': a FETCH of odd LEN stores the pad byte too (LEN + 1)")
class _(Rk512Station):
    def _end(self, code):
        if code is None and self.job is not None and self.job.fetch:
            self.job.store = len(self.job.data)
        return super()._end(code)


@mutant("fetched-data-reversed", "§6.3.2 Table 6-6 (DB_NO, DBB_NO): FETCH data are stored in reverse order")
class _(Rk512Station):
    def _end(self, code):
        if code is None and self.job is not None and self.job.fetch and len(self.job.data) > 1:
            self.job.data = bytearray(reversed(self.job.data))
        return super()._end(code)


# ---------------------------------------------------------------- the requester's pace and responses
@mutant("responses-held-while-requesting", "§2.2.3 'Quasi-full-duplex': a station waiting for its own response "
        "holds back its answers to the partner until its request is over")
class _(Rk512Station):
    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self._held: list = []

    def _queue(self, frame, origin, owner, detail=""):
        if origin == "P" and self.job is not None:
            self._held.append((frame, origin, owner, detail))
            return
        super()._queue(frame, origin, owner, detail)

    def _end(self, code):
        state = super()._end(code)
        held, self._held = self._held, []
        for item in held:
            super()._queue(*item)
        return state


def _incoming(check):
    """A station that changes each response the partner sends before its requester sees it."""
    class _Incoming(Rk512Station):
        def frame_received(self, now, frame):
            if self.job is not None and len(frame) <= 4 + 2 * CHUNK and (len(frame) < 3 or frame[2] == 0):
                frame = check(self, frame)
            super().frame_received(now, frame)
    return _Incoming


mutant("response-byte1-not-checked", "Table 8-1 16#0A02: a response's byte 1 is not checked (taken as 00h)")(
    _incoming(lambda st, f: bytes([0 if st.job.k == 0 else 0xFF]) + f[1:] if f and f[0] not in (0, 0xFF) else f))
mutant("response-id-not-checked", "Table 8-1 16#0A01: a first response to a continuation (or the reverse) is taken")(
    _incoming(lambda st, f: bytes([0 if st.job.k == 0 else 0xFF]) + f[1:] if f and f[0] in (0, 0xFF) else f))
mutant("send-response-data-ignored", "Table 8-1 16#0A04: the data of a SEND response are ignored")(
    _incoming(lambda st, f: f[:4] if not st.job.fetch and len(f) > 4 and f[3] == 0 else f))
mutant("short-response-taken", "Table 8-1 16#0610: a response of fewer than 4 bytes is taken as 00h")(
    _incoming(lambda st, f: response_head(st.job.k == 0, 0) if len(f) < 4 else f))


# ---------------------------------------------------------------- the link below
@mutant("link-cdt-half", "§2.2.2 'Receiving data' (character delay time): the link waits half the CDT")
class _(LinkMutant):
    LINK = "cdt-half"


@mutant("link-3964-waits-for-bcc", "§2.2.3 Figs. 2-13 to 2-16 ('only with BCC'): over plain 3964 the link waits "
        "for a BCC after DLE ETX", link="3964")
class _(LinkMutant):
    LINK = "3964-waits-for-bcc"
