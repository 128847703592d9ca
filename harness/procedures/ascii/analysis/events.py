"""The local events an ASCII seat's characters reveal, for line analysis.

The part of :class:`~ptpcert.procedures.ascii.analysis.analyzer.AsciiAnalyzer` that reads the
line (:class:`LocalEvents`, mixed into it). What an ASCII station puts on its line is its own
frames (its send jobs) and, with XON/XOFF flow control, the XON and XOFF of its receiver.
Neither the send jobs nor the application's reads of the receive buffer are on the line, so
the seat's characters reveal them (what the analysis knows of the application is kept with
the model station: :mod:`~ptpcert.procedures.ascii.analysis.host`):

* a send job: the first character of a frame from a station that has none. Its data is
  read ahead on the line: the station's characters back to back (a pause of less than half
  the shorter CDT, or one while the partner held it with XOFF, does not end it), XON/XOFF
  left out, up to the end character(s) (end-character criterion) or the fixed length
  (fixed-length criterion; reading ``a_fixed_length_job_is_one_frame``), at most 1025
  bytes. With variant 3 of the end-character criterion ("LEN bytes plus automatic end
  character(s)") the end character(s) at its end are the driver's, not the job's. The model
  then sends the job its own way: after the pause between frames (CDT criterion; fixed
  length with the pause switched on), with the send variant applied, stopped by the
  partner's XOFF and resumed by its XON, aborted after the wait time for XON (16#0708);
* a station whose application sends back every frame it receives (the echo convention of
  ``ptpcert run``) reads a frame when its first echoed character shows it: the echo must be
  the oldest frame in the model's receive buffer, as the model's receiver delimited it. So a
  receiver that delimits, stores or discards frames otherwise than the manual says is seen in
  what it sends back. Such a station sends a frame of its own only when its model has none
  stored and no frame coming in, and never characters its model's receiver discarded;
* a read by an application that does not echo is not on the line at all: the model reads
  every frame as soon as it is stored (reading ``a_reads_at_once``), and an XOFF from the
  seat shows that the application had not read since the line last showed a read - the
  frames read "at once" since then are put back, and the model sends XOFF if that fills the
  buffer to a threshold (§2.2.4 'data flow control'; reading Q14). An XON from a station
  holding its partner shows a read (one frame at a time until the model sends XON);
* the transmitter's FIFO: after the partner's XOFF a sender may still send the characters
  its UART had been loaded with, back to back, at most
  :data:`~ptpcert.procedures.ascii.analysis.host.MAX_AFTER_XOFF` (the manual gives no number:
  reading Q15 takes none, and the suite's cases allow up to 16);
* a restart: an XON from a station at rest after a quiet line is its start-up XON. A case of
  ``ptpcert run`` against an IUT it restarts switches the IUT on at the case's start: with
  XON/XOFF flow control its first character must be that XON.
"""

from __future__ import annotations

import bisect
from typing import Any

from ptpcert.analysis import OTHER, QUANTUM, SEATS, WAIT, Explanation
from ptpcert.model.codes import Code
from ptpcert.model.events import SendDone, SendFailed
from ptpcert.procedures.ascii.analysis.host import (AFTER_XOFF_WHY, MAX_AFTER_XOFF, AsciiAnalysisHost, advance,
                                                    send_flow, would_be_full)
from ptpcert.procedures.ascii.model.codec import send_bytes
from ptpcert.procedures.ascii.model.events import FrameDiscarded
from ptpcert.procedures.ascii.model.params import MAX_FRAME
from ptpcert.procedures.ascii.model.station import Timer
from ptpcert.procedures.ascii.model.table import FcState, RxState, TxState


class LocalEvents:
    """What an ASCII seat's characters reveal, for
    :class:`~ptpcert.procedures.ascii.analysis.analyzer.AsciiAnalyzer` (it brings ``params``,
    ``_rest``, ``_unsendable``, ``_names``, :meth:`char`, :meth:`_gap`, :meth:`powered` and
    :meth:`at_rest`)."""

    def announces_startup(self, seat: str) -> bool:
        return self.params[seat].flow_control == "xon_xoff"

    def startup(self, run, item, index: int):
        p = self.params[run.judge.seat]
        if item.kind == "byte" and p.flow_control == "xon_xoff" and item.value == p.xon:
            seat = run.judge.seat
            return Explanation(lambda r, t: r.replace_host(self.powered(seat, t)))
        return None

    def interjects(self, run, item) -> bool:
        # XON and XOFF go out at the next character boundary, between two characters of the
        # station's own frame if need be (full duplex)
        p = self.params[run.judge.seat]
        return item.kind == "byte" and p.flow_control == "xon_xoff" and item.value in (p.xon, p.xoff)

    def explain(self, run, item, index: int):
        if item.kind != "byte":
            return None
        host: AsciiAnalysisHost = run.host
        st = host.station
        p = st.params
        b = item.value
        seat = run.judge.seat
        if p.flow_control == "xon_xoff" and b == p.xoff:
            self._forget_before_quiet(run, item.start)
            if st.fc_state is FcState.OPEN and host.tentative and would_be_full(host):
                return Explanation(lambda r, t: r.host.unread(t),
                                   "its application had not read the frames it received (the XOFF shows it)")
            if st.fc_state is FcState.HELD and host.readings.a_xoff_repeated:
                return Explanation(lambda r, t: send_flow(r.st, t, p.xoff))
            return None
        if p.flow_control == "xon_xoff" and b == p.xon:
            if st.fc_state is FcState.HELD and st.frames_stored:
                return Explanation(self._read_until_xon)
            if st.frames_stored and not st.readings.q15_xon_only_after_xoff:
                return Explanation(lambda r, t: r.host.read(t))
            if self.at_rest(host) and self._quiet(run, index):
                return Explanation(lambda r, t: self._restart(r, t),
                                   "restarted: its start-up XON after a quiet line (§2.2.4 'data flow control')")
            return None
        # a data character
        if p.data_bits == 7 and b > 0x7F:
            return None
        if st.tx_state is TxState.STOPPED and st.job is not None:
            if self._fifo(run, item, index):
                return Explanation(self._one_more)
            return None
        if st.pending_jobs:
            return None     # the model sends a frame of its own: compare
        if host.echo:
            if st.frames_stored:
                return Explanation(self._echo)
            if st.rx_state is not RxState.WAIT_CHAR:
                return None     # the frame coming in is not complete: nothing to echo yet
        frame = self._frame_ahead(run, index)
        if frame is WAIT:
            return WAIT
        payload = self._payload(seat, frame)
        if not 1 <= len(payload) <= MAX_FRAME:
            self._unsendable[(seat, index)] = "len"
            return None
        if host.echo and (self._discarded(run, frame) is not None or not (host.own_jobs or host.is_echo(payload))):
            # an echo station sends back the frames its application read, and nothing of its
            # own: another frame is not a send job it may have had
            return None
        if self._rest_of_aborted(run, frame, item.start):
            return None
        return Explanation(lambda r, t, d=payload: self._request(r, t, d))

    @staticmethod
    def _request(run, t: float, payload: bytes) -> None:
        st = run.st
        # a model begun at a rest point (an alternative) knows the end of the station's last
        # frame from the run's memo: the pause after it holds this job back as well
        end = run.memo.get("frame_end")
        if end is not None and end > st._last_frame_end:
            st._last_frame_end = end
        st.request_send(t, payload)

    @staticmethod
    def _echo(run, t: float) -> None:
        run.host.read(t)

    @staticmethod
    def _read_until_xon(run, t: float) -> None:
        host: AsciiAnalysisHost = run.host
        st = host.station
        advance(st, t)
        while st.fc_state is FcState.HELD and st.frames_stored:
            host.read(t)
        host.at_once = not host.echo or host.readings.a_reads_at_once
        host.drain(t)

    @staticmethod
    def _one_more(run, t: float) -> None:
        """The transmitter sends one more character of the interrupted frame (it held it
        when the XOFF came)."""
        st = run.st
        advance(st, t)
        job = st.job
        _, end = st._line.schedule(t, job.wire[job.pos:job.pos + 1], "data", AFTER_XOFF_WHY)
        job.pos += 1
        if job.pos >= len(job.wire):
            # the whole frame went out after all: as if the XOFF had come too late to stop it
            st._stop(Timer.T_XON_WAIT)
            st.tx_state = TxState.SEND
            st._start(Timer.TX_DONE, end)

    def _fifo(self, run, item, index: int) -> bool:
        """Is ``item`` a character the seat's transmitter still held when the partner's XOFF
        came: the next of the interrupted frame, back to back with the seat's character
        before, at most MAX_AFTER_XOFF of them since the partner's last XOFF?"""
        st = run.st
        job = st.job
        if job.pos >= len(job.wire) or item.value != job.wire[job.pos]:
            return False
        j = run.judge
        xoff = self.params[OTHER[j.seat]].xoff
        k = run.i_in - 1
        while k >= 0 and not (j.inputs[k].kind == "byte" and j.inputs[k].value == xoff):
            k -= 1
        if k < 0:
            return False
        t_x = j.inputs[k].t
        c = self.char(j.seat)
        r = j.analysis.resolution
        if index == 0 or item.start - j.obs[index - 1].t > 0.5 * c + r + QUANTUM:
            return False
        n = sum(1 for x in j.obs[max(0, index - MAX_AFTER_XOFF - 1):index] if x.start >= t_x - c - r)
        return n < MAX_AFTER_XOFF

    def _forget_before_quiet(self, run, t: float) -> None:
        """Frames read "at once" before the line was last quiet for the rest gap stay read: a
        model followed afresh from there (a recording that begins there, or one resumed
        after a difference) knows nothing of them either. (A frame the model read "at once"
        only after the quiet line - when an XON showed an earlier one read - counts.)"""
        host: AsciiAnalysisHost = run.host
        if not host.tentative:
            return
        j = run.judge
        t0 = min(f[2] for f in host.tentative) - self._rest
        times = sorted([x.t for x in j.obs if t0 <= x.t <= t] + [x.t for x in j.inputs if t0 <= x.t <= t] + [t])
        quiet = None
        for a, b in zip(times, times[1:]):
            if b - a >= self._rest:
                quiet = b
        if quiet is not None:
            host.tentative = [f for f in host.tentative if f[2] >= quiet - QUANTUM]

    def _restart(self, run, t: float) -> None:
        run.replace_host(self.powered(run.judge.seat, t))
        run.memo.pop("discards", None)      # what the receiver discarded before is gone with it

    def _quiet(self, run, index: int) -> bool:
        """Before the seat's ``index``-th item the seat was silent, and the partner sent
        nothing but XON/XOFF, for longer than both CDTs and two characters: an XON from a
        station at rest (nothing to send, nothing stored, nobody held) is then its start-up
        XON (any other XON from it breaks a rule, reading Q15, so nothing else can explain it)."""
        j = run.judge
        item = j.obs[index]
        since = item.start - max(p.cdt for p in self.params.values()) - 2 * max(self.char(s) for s in SEATS)
        if index > 0 and j.obs[index - 1].t > since:
            return False
        q = self.params[OTHER[j.seat]]
        flow = (q.xon, q.xoff) if q.flow_control == "xon_xoff" else ()
        k = run.i_in - 1
        while k >= 0 and j.inputs[k].t > since:
            x = j.inputs[k]
            if x.kind != "byte" or x.value not in flow:
                return False
            k -= 1
        return True

    def _payload(self, seat: str, frame: bytes) -> bytes:
        """The send job's data behind a frame on the line (variant 3 of the end-character
        criterion appends the end character(s): they are not the job's)."""
        p = self.params[seat]
        if p.end_criterion == "end_chars" and p.send_variant == "len_append_end":
            end = p.end_sequence
            if len(frame) > len(end) and frame.endswith(end):
                return frame[:-len(end)]
        return frame

    def _frame_ahead(self, run, index: int) -> Any:
        """The frame that begins with the seat's ``obs[index]``, read ahead on the line (see
        the module docstring); WAIT when the line has not shown its end yet."""
        j = run.judge
        a = j.analysis
        obs, inputs = j.obs, j.inputs
        seat = j.seat
        p, q = self.params[seat], self.params[OTHER[seat]]
        host: AsciiAnalysisHost = run.host
        r = a.resolution
        gap_max = self._gap(p, q) + r + QUANTUM     # as late as a character of a frame may come (see cause)
        flow = (p.xon, p.xoff) if p.flow_control == "xon_xoff" else ()
        partner_flow = (q.xon, q.xoff) if q.flow_control == "xon_xoff" else None
        end = p.end_sequence if p.end_criterion == "end_chars" else b""
        n_fixed = (p.fixed_length if p.end_criterion == "fixed_length"
                   and host.readings.a_fixed_length_job_is_one_frame else 0)
        data = bytearray()
        last = None
        i = index
        while True:
            if i >= len(obs):
                if not a.complete and (last is None or a.known_until - last < self._rest):
                    return WAIT
                return bytes(data)
            it = obs[i]
            if it.kind != "byte":
                return bytes(data)
            if it.value in flow:
                i += 1
                continue
            if (last is not None and it.start - last > gap_max
                    and not self._held(inputs, partner_flow, last, self.char(seat), r)):
                return bytes(data)
            data.append(it.value & (0x7F if p.data_bits == 7 else 0xFF))
            last = it.t
            i += 1
            if end and data.endswith(end):
                return bytes(data)
            if n_fixed and len(data) == n_fixed:
                return bytes(data)
            if len(data) > MAX_FRAME:
                return bytes(data)

    @staticmethod
    def _held(inputs, flow: tuple[int, int] | None, last: float, c: float, r: float) -> bool:
        """Did the partner's XOFF stop the seat after its character complete at ``last``: is
        the partner's last XON or XOFF by then (or while that character was the last on the
        line) an XOFF, come at most MAX_AFTER_XOFF characters before it (``c`` a character
        time, ``r`` the resolution)?"""
        if flow is None:
            return False
        xon, xoff = flow
        lo, hi = last - (MAX_AFTER_XOFF + 1) * c - r, last + c + r
        i = bisect.bisect_right(inputs, hi, key=lambda x: x.t) - 1
        while i >= 0 and inputs[i].t >= lo:
            x = inputs[i]
            if x.kind == "byte" and x.value in (xon, xoff):
                return x.value == xoff
            i -= 1
        return False

    def _discarded(self, run, frame: bytes) -> tuple | None:
        """The discard (one of the last few the model's receiver made since the model was
        followed afresh or restarted) whose characters the seat sends as a frame of its own,
        if any: the frame begins with the discarded characters, or is a part of them at least
        two long."""
        for d in reversed(run.memo.get("discards", ())):
            t, reason, code, data = d
            if frame and data and (frame.startswith(data) or (len(frame) >= 2 and frame in data)):
                return d
        return None

    def _rest_of_aborted(self, run, frame: bytes, t: float) -> bool:
        """Is ``frame`` the rest of the send job the model aborted after the wait time for
        XON (16#0708), sent all the same?"""
        aborted = run.memo.get("aborted")
        if aborted is None or not frame:
            return False
        at, wire = aborted
        p = self.params[run.judge.seat]
        return t - at <= max(self._rest, p.xon_wait) and len(frame) < len(wire) and frame in wire

    def event(self, run, e) -> None:
        if isinstance(e, SendDone):
            run.memo["frame_end"] = e.time      # the last stop bit of the frame (the pause runs from it)
        elif isinstance(e, FrameDiscarded):
            run.memo["discards"] = run.memo.get("discards", ())[-7:] + ((e.time, e.reason, e.code, e.data),)
        elif isinstance(e, SendFailed) and e.code == Code.XON_CTS_WAIT_EXPIRED:
            run.memo["aborted"] = (e.time, send_bytes(e.payload, run.st.params, run.st.readings) or e.payload)

    def begins(self, byte: int) -> bool:
        return byte not in self._names
