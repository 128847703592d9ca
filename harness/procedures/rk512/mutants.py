"""Deliberately broken variants of the RK 512 reference, each breaking one rule.

They prove the RK 512 suite's detection power, in both roles: ``ptpcert iut --procedure
RK512 --mutant NAME`` runs one in real time, ``sim:?mutant=NAME`` in virtual time. A
variant is the reference station (:class:`ptpcert.procedures.rk512.model.Rk512Station`) with
one action, check or frame changed; the ``link-`` variants put a broken 3964(R) link (a 3964
variant of :mod:`ptpcert.procedures.p3964.mutants`) under a correct RK 512 layer. They are
entered with the registrar of :mod:`ptpcert.variants`.
"""

from __future__ import annotations

from dataclasses import replace
from math import inf

from ptpcert.model.codes import Code
from ptpcert.procedures.rk512.model import Rk512Station
from ptpcert.procedures.rk512.model.codec import (
    CHUNK,
    CONTINUATION,
    FETCH,
    FIRST,
    HEADER_LEN,
    response_head,
    status_for_reatel,
)
from ptpcert.procedures.rk512.model.events import Served
from ptpcert.procedures.rk512.model.table import PState
from ptpcert.procedures.rk512.mutant_base import MUTANTS, LinkMutant, RequestChange, Rewrite, mutant

# the registry and the variants' common kinds live in mutant_base, shared with mutants_rules
_Rewrite, _RequestChange, _LinkMutant = Rewrite, RequestChange, LinkMutant


# ---------------------------------------------------------------- passive: responses
@mutant("send-response-with-data", "§2.2.3 'SEND message frame'; Table 8-1 16#0A04: the response to a SEND carries a data byte")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and frame in (response_head(True, 0), response_head(False, 0)) \
                and owner is not None and not owner.fetch:
            return frame + b"\x00"
        return frame


@mutant("continuation-response-id-00", "§2.2.3 Table 2-2: a continuation response begins 00h instead of FFh")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and frame[0] == CONTINUATION:
            return bytes([FIRST]) + frame[1:]
        return frame


@mutant("error-response-byte3-01", "§2.2.3 Table 2-2: byte 3 of an error response is 01h, not 00h")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and len(frame) >= 4 and frame[3]:
            return frame[:2] + b"\x01" + frame[3:]
        return frame


@mutant("error-response-with-data", "§2.2.3 'Receiving data': an error response carries two data bytes")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and len(frame) == 4 and frame[3]:
            return frame + b"\x00\x00"
        return frame


@mutant("fetch-word-bytes-swapped", "§6.4.1 Fig. 6-7: FETCH data from a DB/DX are sent low byte first in each word")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "P" and len(frame) > 4 and frame[3] == 0 and owner is not None and owner.fetch \
                and owner.area is not None and owner.area.block:
            d = bytearray(frame[4:])
            d[0::2], d[1::2] = d[1::2], d[0::2]
            return frame[:4] + bytes(d)
        return frame


@mutant("db-missing-reatel-0c", "Table 8-3: a missing DB is answered with REATEL 0Ch instead of 14h")
class _(Rk512Station):
    def _c_block(self, frame, op):
        bad = super()._c_block(frame, op)
        return None if bad is None else (bad[0], 0x0C)


@mutant("response-to-response", "§2.2.3 'Response message frame': an unsolicited response is answered with a response")
class _(Rk512Station):
    def _a_unsolicited_response(self, f):
        super()._a_unsolicited_response(f)
        self._queue(response_head(True, 0), "P", None, "an answer to a response")


# ---------------------------------------------------------------- passive: header checks
@mutant("send-count-not-checked", "Table 8-1 16#060B: a SEND frame's data count is not checked against its header")
class _(Rk512Station):
    def _c_data(self, frame, op):
        return None if not op.fetch else super()._c_data(frame, op)


@mutant("fetch-with-data-served", "Table 8-1 16#060C: a FETCH command with data is served")
class _(Rk512Station):
    def _c_data(self, frame, op):
        return None if op.fetch else super()._c_data(frame, op)


@mutant("continuation-bytes-not-checked", "§2.2.3; Table 8-1 16#0603/16#0605: continuation bytes 3/4 are not compared")
class _(Rk512Station):
    def _d_check_continuation(self, frame):
        op = self.open
        return super()._d_check_continuation(frame[:2] + bytes([op.b3, op.b4]) + frame[4:])


@mutant("dw-as-byte-offset", "§2.2.3 Table 2-1 footnote 1: byte 6 of a DB/DX header is taken as a byte offset, not a data word")
class _(Rk512Station):
    def _c_address(self, frame, op):
        if self._usable(frame, op) and op.area.block:
            op.start = frame[5]
        return super()._c_address(frame, op)


# ---------------------------------------------------------------- passive: sequence and chunks
@mutant("fetch-chunks-126", "§2.2.3 Figs. 2-15, 2-16: FETCH data go out in chunks of 126 bytes, not 128")
class _(Rk512Station):
    def _transfer(self, frame, op, head):
        if not op.fetch:
            return super()._transfer(frame, op, head)
        left = op.nbytes - op.done
        k = min(126, left)
        start = op.start + op.done
        data = bytes(op.buf[start:start + k])
        op.done += k
        op.final = op.done >= op.nbytes
        self._events.append(Served(self.now, "read", op.letter, op.number, start, data, op.final, None))
        self._queue(response_head(head == HEADER_LEN, 0) + data, "P", op, "REATEL 00")
        return PState.SEND_RESPONSE


@mutant("fetch-chunks-unprompted", "§2.2.3 Fig. 2-16: the next FETCH chunk is sent without waiting for a continuation FETCH")
class _(Rk512Station):
    def _d_after_response(self, f):
        op = self.open
        if op is not None and op.fetch and not op.final:
            return self._transfer(b"", op, 4)
        return super()._d_after_response(f)


@mutant("sequence-error-answered-ok", "Table 8-1 16#060E: a continuation with no request open is answered FF 00 00 00")
class _(Rk512Station):
    def _p_refuse_sequence(self, frame):
        self._queue(response_head(False, 0), "P", None, "REATEL 00")


@mutant("pipelined-command-served", "§2.2.3 'Quasi-full-duplex'; Table 8-1 16#060E: a command before the response owed is answered 00")
class _(Rk512Station):
    def _p_refuse_pipelined(self, frame):
        self._queue(response_head(frame[0] == FIRST, 0), "P", None, "REATEL 00")


@mutant("continuation-without-request-ignored",
        "Table 8-1 16#060E; Table 8-3 (36h): a continuation with no request open gets no answer at all")
class _(Rk512Station):
    def _p_refuse_sequence(self, frame):
        self._status(Code.PARTNER_SEQUENCE_ERROR, "receive")   # reported, but the partner hears nothing


@mutant("passive-tres-ignored", "Fig. 2-19 'T > T_RES': the responder waits for a continuation for ever")
class _(Rk512Station):
    def _d_after_response(self, f):
        out = super()._d_after_response(f)
        self._t_res_p = inf
        return out


# ---------------------------------------------------------------- passive: the CPU's state
@mutant("flag-lock-ignored", "§6.3.2 'Using interprocessor communication flags'; Table 8-1 16#060F: a set flag does not lock")
class _(Rk512Station):
    def _c_lock(self, frame, op):
        return None


@mutant("cpu-stop-ignored", "§7.3; Table 8-1 16#060D: commands are served while the CPU is in STOP")
class _(Rk512Station):
    def _c_cpu_stop(self, frame, op):
        return None


# ---------------------------------------------------------------- active: commands
@mutant("counter-letter-c", "§2.2.3 Table 2-1: a counter FETCH is sent with 'C' (43h) instead of 'Z' (5Ah)")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and len(frame) >= 4 and frame[2] == FETCH and frame[3] == 0x5A:
            return frame[:3] + b"C" + frame[4:]
        return frame


@mutant("cpu-nibble-0", "§2.2.3 Table 2-1, Fig. 2-13: 'only CPU 1' is sent as 0Fh instead of 1Fh")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and frame[0] == FIRST and len(frame) >= HEADER_LEN and frame[9] == 0x1F:
            return frame[:9] + b"\x0f" + frame[10:]
        return frame


@mutant("continuation-full-header", "§2.2.3 Table 2-1: continuation frames repeat the 10-byte header instead of 4 bytes")
class _(_Rewrite):
    def rewrite(self, frame, origin, owner):
        if origin == "A" and frame[0] == CONTINUATION and self.job is not None:
            return bytes([CONTINUATION]) + self.job.header.encode()[1:] + frame[4:]
        return frame


@mutant("odd-send-not-padded", "§6.3.2 'Important notes': a SEND of odd LEN to a DB drops its last byte (no pad word)")
class _(_RequestChange):
    def change(self, req):
        if req.op == "send" and req.area.block and req.length % 2:
            req = replace(req, length=req.length - 1, data=None if req.data is None else req.data[:-1])
        return req


# ---------------------------------------------------------------- active: responses and T_RES
@mutant("error-reatel-taken-as-success", "Table 8-3: a response's error number is ignored (taken as 00h)")
class _(Rk512Station):
    def _d_check_response(self, frame):
        if frame[3]:
            frame = frame[:3] + b"\x00" + frame[4:]
        return super()._d_check_response(frame)


@mutant("error-response-goes-on", "§2.2.3 Fig. 2-19 ('send response with error message': 'partner request "
        "finished'): after an error number on a response that is not the last, the requester reports it and goes on "
        "with its next continuation")
class _(Rk512Station):
    def _d_check_response(self, frame):
        job = self.job
        if job is not None and len(frame) == 4 and frame[3] and job.remaining > CHUNK:
            self._status(status_for_reatel(frame[3]), "send")
            frame = frame[:3] + b"\x00" + (bytes(CHUNK) if job.fetch else b"")
        return super()._d_check_response(frame)


@mutant("unknown-reatel-0905", "Table 8-3: an unknown error number is reported as 16#0905 instead of 16#090E")
class _(Rk512Station):
    def _end(self, code):
        if code == Code.PARTNER_UNKNOWN_ERROR:
            code = Code.PARTNER_TYPE_OR_PLC_FAULT
        return super()._end(code)


@mutant("fetch-length-not-checked", "Table 8-1 16#0A03: a FETCH response with too few or too many data is taken")
class _(Rk512Station):
    def _d_check_response(self, frame):
        job = self.job
        if job is not None and job.fetch and frame[3] == 0:
            want = min(128, job.remaining)
            frame = frame[:4] + (bytes(frame[4:]) + bytes(want))[:want]
        return super()._d_check_response(frame)


@mutant("no-tres-active", "Fig. 2-18 'T > T_RES'; Table 8-1 16#0A05: the requester waits for a response for ever")
class _(Rk512Station):
    def _a_command_sent(self, f):
        super()._a_command_sent(f)
        self._t_res_a = inf


@mutant("tres-half", "Figs. 2-18, 2-19: T_RES is half the response monitoring time set")
class _(Rk512Station):
    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self._t_res /= 2


@mutant("retry-after-link-failure", "Table 8-1 16#051A: after the link gave up on a command the request is started again")
class _(Rk512Station):
    _retried = False

    def _a_fail_request(self, f):
        if self._row.code == Code.COMMAND_NOT_SENT and not self._retried and self.job is not None:
            self._retried = True
            self._requests.appendleft(self.job.req)
        return super()._a_fail_request(f)


# ---------------------------------------------------------------- the link below
@mutant("link-no-dle-doubling", "§2.2.2 note (DLE doubling): the link does not double data DLEs in RK 512 frames")
class _(_LinkMutant):
    LINK = "no-dle-doubling"


@mutant("link-bcc-not-checked", "§2.2.2 'Receive release', Fig. 2-12: the link takes frames whatever their BCC")
class _(_LinkMutant):
    LINK = "bcc-not-checked"


@mutant("link-high-priority-yields", "§2.2.2 'Initialization conflict': the high-priority station answers the partner's STX",
        priority="high")
class _(_LinkMutant):
    LINK = "high-priority-yields"


# the variants made for the rules catalogue's kill matrix, entered into MUTANTS as they load
from ptpcert.procedures.rk512 import mutants_rules  # noqa: E402,F401

__all__ = ["MUTANTS", "mutant"]
