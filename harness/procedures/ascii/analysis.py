"""The ASCII driver's part of line analysis (``ptpcert analyze``, ``ptpcert monitor``).

Each judged seat is followed by the reference model of the ASCII driver (§2.2.4), fed the
other seat's characters. What an ASCII station puts on its line is its own frames (its send
jobs) and, with XON/XOFF flow control, the XON and XOFF of its receiver. Neither the send
jobs nor the application's reads of the receive buffer are on the line, so the seat's
characters reveal them (the local events of :mod:`ptpcert.analyze`):

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
  its UART had been loaded with, back to back, at most :data:`MAX_AFTER_XOFF` (the manual
  gives no number: reading Q15 takes none, and the suite's cases allow up to 16);
* a restart: an XON from a station at rest after a quiet line is its start-up XON. A case of
  ``ptpcert run`` against an IUT it restarts switches the IUT on at the case's start: with
  XON/XOFF flow control its first character must be that XON.

What a line tap cannot show, and is not judged: the application's reads (only inferred as
above), the contents of the receive buffer (a CP 341 in each seat raises, and each finding
and exchange carries, the STATUS events of its model: 16#0806, 16#080C, 16#080A...), the
modem lines (RTS/CTS and the automatic use of the V.24 signals are not judged), and the
send jobs' data beyond what was sent (a job the driver cut after its end character looks
like two jobs: see the tests' NOT_VISIBLE_ON_THE_WIRE).

Timing windows (on top of the capture's resolution): a character of a frame may come up to
half the shorter CDT late after the one before (see ``AsciiAnalyzer._gap``); so may the
first character after the partner's XON (the partner's CDT runs again from its XON); the
first character of a frame held back by the pause between
frames may come one character time and 5 % of the pause early; XON and XOFF the tolerance
late.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, replace
from typing import Any

from ptpcert.analysis import (OTHER, QUANTUM, SEATS, WAIT, Cause, Explanation, ProcedureAnalyzer, Variant,
                              resolution_variants)
from ptpcert.model.codes import Code
from ptpcert.model.events import SendDone, SendFailed
from ptpcert.procedures.ascii.model import AsciiStation
from ptpcert.procedures.ascii.model import events as aev
from ptpcert.procedures.ascii.model.codec import char_name, send_bytes, split_frames
from ptpcert.procedures.ascii.model.events import FrameDiscarded
from ptpcert.procedures.ascii.model.params import MAX_FRAME
from ptpcert.procedures.ascii.model.readings import READINGS, AsciiReadings
from ptpcert.procedures.ascii.model.records import Why
from ptpcert.procedures.ascii.model.station import Timer
from ptpcert.procedures.ascii.model.table import FcState, RxState, TxState

#: how many characters a sender may still send after the partner's XOFF: what its UART's
#: transmit FIFO holds (a 16550A: 16). The manual gives no number (reading Q15).
MAX_AFTER_XOFF = 16

_FC = "§2.2.4 'data flow control / handshaking'; Table 2-9"
_RECEIVE_RULE = {
    "cdt": ("a frame ends when the CDT passes without a character (expiry of the character delay time)",
            "§2.2.4 'expiry of the character delay time'; Fig. 2-21; Table 2-7"),
    "end_chars": ("a frame ends with its end character(s) (with two, end character 1 directly followed by end "
                  "character 2), which belong to the frame", "§2.2.4 'end character(s)'; Fig. 2-22; Table A-7"),
    "fixed_length": ("a frame ends with its N-th character (the fixed length)",
                     "§2.2.4 'fixed message frame length'; Fig. 2-23; Table 2-7"),
}
_BUFFER_RULE = ("the receive buffer hands the oldest frame to the CPU first", "§2.2.4 'receive buffer'; Table 2-10")

#: why a receiver discards characters (the model's FrameDiscarded reasons), as rules
_DISCARD_RULES = {
    aev.CDT_EXPIRED: ("characters the CDT cut off before their frame was complete (a fragment, or what followed "
                      "a complete frame) are discarded with an error, never delivered",
                      "§2.2.4 malformed frames; Figs. 2-22, 2-23; Table 8-1 (08)06H"),
    aev.CHARACTER_ERROR: ("a frame with a character error (parity, framing, overrun) is received to its end and "
                          "discarded, never delivered", "Figs. 2-21 to 2-23; Table 8-1 (08)0CH"),
    aev.NO_ROOM: ("a frame that does not fit in the 1024-byte receive buffer is discarded",
                  "§2.2.4 'receive buffer', 'data flow control'; Table 2-10; Table 8-1 (08)0AH"),
    aev.TOO_LONG: ("a frame longer than 1024 bytes is discarded", "Table A-7; Table 8-1 (08)16H"),
    aev.BUFFER_FULL: ("with 'prevent overwrite' a frame that finds the buffer full is discarded; the frames stored "
                      "stay", "Table 2-10; Table 8-1 (08)0AH"),
    aev.OVERWRITTEN: ("with 'prevent overwrite = no' a new frame replaces the unread one", "Table 2-10"),
    aev.LINE_BREAK: ("a BREAK ends the frame coming in, which is discarded",
                     "Figs. 2-21 to 2-23 'BREAK'; Table 8-1 (08)0DH"),
}

_READING_WORDS = {
    "Q4": "a gap of exactly the CDT ends a frame (no grace of one character time)",
    "Q5": "the pause between sent frames is exactly the CDT",
    "Q6": "variant 1 without an end character refuses the job, or cuts at end character 1 alone",
    "Q14": "XOFF one frame before the buffered frames reach the parameter",
    "Q15": "XON after every read, or not after a discard",
    "Q16": "a received XON/XOFF restarts the CDT, or an XOFF while idle does not hold the next frame",
    "d_hold": "the CDT of a frame runs on while the station holds its partner",
    "d_break": "a BREAK also ends the running send job",
}


@dataclass(frozen=True)
class AnalysisReadings:
    """What an analysis takes where the line does not say: the model's readings of the
    manual's open points (``model``), and two of its own.

    ``a_reads_at_once``: an echo station's application reads a frame as soon as it is stored
    (True: the echo that follows later was held back by the send side); by default (False) it
    reads when its echo shows it. ``a_fixed_length_job_is_one_frame``: under the fixed-length
    criterion a send job carries one frame of the fixed length (§2.2.4: "the partner's
    configured length must equal LEN"), so N characters back to back begin a new job, held
    back by the pause; the other reading takes any run of characters as one job."""

    model: AsciiReadings = READINGS
    a_reads_at_once: bool = False
    a_fixed_length_job_is_one_frame: bool = True
    #: reading Q15 (no field of the model's: it sends XON and XOFF once): a station holding
    #: its partner repeats its XOFF while the partner keeps sending (True), or not (False)
    a_xoff_repeated: bool = False


DEFAULT = AnalysisReadings()


class AsciiAnalysisHost:
    """A model station and what the analysis knows of its application (see the module
    docstring): ``echo`` - it sends back every frame it reads; the frames read "at once"
    since the line last showed a read (``tentative``), which an XOFF puts back."""

    def __init__(self, station: AsciiStation, echo: bool, readings: AnalysisReadings):
        self.station = station
        self.echo = echo
        self.readings = readings
        #: reads every frame as soon as it is stored (an application that does not echo,
        #: until an XOFF shows it did not)
        self.at_once = not echo or readings.a_reads_at_once
        #: (stored at, frame, read at)
        self.tentative: list[tuple[float, bytes, float]] = []
        #: the frames it read to send back: (time, frame), the latest few
        self.echoes: list[tuple[float, bytes]] = []

    def drain(self, now: float | None = None) -> list:
        st = self.station
        at = st.now if now is None else max(now, st.now)
        out: list = []
        while True:
            events = st.pop_events()
            out.extend(events)
            acted = False
            # never while it holds its partner: the read that lifts an XOFF sends XON, and
            # when that happened the line shows (the XON)
            if self.at_once and st.fc_state is FcState.OPEN:
                while st.frames_stored and st.fc_state is FcState.OPEN and not (self.echo and st.pending_jobs):
                    stored_at = st.oldest_stored_at
                    frame = st.read_frame(at)
                    acted = True
                    if self.echo:
                        self._send_back(at, frame)
                    else:
                        self.tentative.append((stored_at, frame, at))
            if not events and not acted:
                return out

    def read(self, t: float) -> bytes | None:
        """The application reads the oldest frame at ``t`` (and echoes it)."""
        st = self.station
        frame = st.read_frame(t)
        if frame is not None and self.echo:
            self._send_back(t, frame)
        return frame

    def _send_back(self, t: float, frame: bytes) -> None:
        self.echoes = self.echoes[-3:] + [(t, frame)]
        self.station.request_send(t, frame)

    def is_echo(self, payload: bytes) -> bool:
        return any(f == payload for _, f in self.echoes)

    @property
    def echo_at(self) -> float:
        """When it last read a frame to send it back (-1: not since the model began)."""
        return self.echoes[-1][0] if self.echoes else -1.0

    def unread(self, t: float) -> None:
        """The line showed that the application has not read the frames the model read "at
        once" since the last read the line showed: they go back into the receive buffer
        (oldest first), and the model sends XOFF if that reaches a threshold. From here on
        it reads only what the line shows."""
        st = self.station
        _advance(st, t)
        # the model's receive buffer, put back as it was (the station keeps no other record)
        for stored_at, frame, _ in reversed(self.tentative):
            st._stored.appendleft((stored_at, frame))
            st._stored_bytes += len(frame)
        self.tentative = []
        self.at_once = False
        st._full_check()


def _advance(st: AsciiStation, t: float) -> None:
    """Bring the station to ``t`` as an input at ``t`` does (its deadlines before ``t`` run
    out first): no characters received."""
    st.receive(t, b"")


def _send_flow(st: AsciiStation, t: float, code: int) -> None:
    """The station sends the flow-control character ``code`` once more (reading Q15's
    other side: the model itself sends each only once)."""
    _advance(st, t)
    st._send_control(code)


def _would_be_full(host: AsciiAnalysisHost) -> bool:
    """With the frames read "at once" put back, would the buffer reach a threshold (§2.2.4
    'data flow control': the buffered frames reach the parameter, or 50 characters before the
    1024-byte buffer overflows; reading Q14)?"""
    st = host.station
    r = st.readings
    frames = st.frames_stored + len(host.tentative)
    fill = st.buffer_fill + sum(len(f) for _, f, _ in host.tentative)
    return frames >= max(1, st.params.buffer_frames + r.q14_xoff_frame_offset) or fill >= r.q14_xoff_fill_bytes


_AFTER_XOFF_WHY = Why("tx", "STOPPED", "FIFO", "after_xoff",
                      "§2.2.4 'data flow control': the characters the transmitter held when the XOFF came")


class AsciiAnalyzer(ProcedureAnalyzer):
    """Line analysis of a link between two ASCII drivers (see the module docstring)."""

    reference = "§2.2.4; Figs. 2-20 to 2-23; Tables 2-7 to 2-10"

    def __init__(self, procedure: Any, params: dict[str, Any], apps: dict[str, str] | None = None,
                 late_ms: float = 50.0):
        super().__init__(procedure, params, apps)
        self.late_abs = late_ms / 1000.0
        ps = list(self.params.values())
        # the longest timer after which a station that has stopped sending and receiving is at
        # rest: the CDT (a frame ends, or is discarded) and the pause after it. (The wait
        # time for XON is left out: a stopped sender that is followed afresh after a quiet
        # line sends the rest of its frame as a frame of its own, which the model accepts.)
        longest = max(p.cdt + p.char_time for p in ps)
        self._rest = 1.25 * longest + self.late_abs + 4 * max(self.char(s) for s in SEATS)
        self._unsendable: dict[tuple[str, int], str] = {}
        self._variants: list[Variant] | None = None
        flow = [p for p in ps if p.flow_control == "xon_xoff"]
        self._names: dict[int, str] = {}
        for p in flow:
            self._names.setdefault(p.xon, "XON")
            self._names.setdefault(p.xoff, "XOFF")

    # -- timing ---------------------------------------------------------------------------
    def rest_gap(self) -> float:
        return self._rest

    def _pause(self, p, readings: AsciiReadings = READINGS) -> float:
        return p.cdt + readings.q5_send_pause_extra_chars * p.char_time

    @staticmethod
    def _gap(p, q) -> float:
        """The longest pause inside a frame (and before the first character after the
        partner's XON): half the shorter CDT. A driver sends a frame back to back (it sends
        nothing before it has all of the job's data); a pause of half the CDT is where a
        receiver's timer may begin to take it for the end of the frame (the CDT runs again
        from an XON). Of two CDTs the shorter: a CP 341 partner is usually set as the station
        itself, and a tester's CDT may be a mere watchdog. A longer pause ends the job: what
        follows is another one (held back by the pause between frames where one is due)."""
        return 0.5 * min(p.cdt, q.cdt)

    def early_wait(self, host: AsciiAnalysisHost) -> float:
        st = host.station
        c = st.params.char_time
        if st.tx_state is TxState.PAUSE:
            return c + 0.05 * self._pause(st.params, st.readings) + 3e-6
        return c + 3e-6

    def late_max(self, seat: str) -> float:
        p, q = self.params[seat], self.params[OTHER[seat]]
        return max(self._gap(p, q) + 2 * p.char_time, self.late_abs + 0.25 * self._pause(p))

    # -- stations -------------------------------------------------------------------------
    def _readings(self, readings: Any) -> AnalysisReadings:
        if readings is None:
            return DEFAULT
        if isinstance(readings, AsciiReadings):
            return AnalysisReadings(model=readings)
        return readings

    def _host(self, seat: str, readings: Any = None) -> AsciiAnalysisHost:
        r = self._readings(readings)
        st = AsciiStation(self.params[seat], r.model, name=seat, explain=True)
        return AsciiAnalysisHost(st, self.apps[seat] == "echo", r)

    def fresh(self, seat: str, t: float, readings: Any = None) -> AsciiAnalysisHost:
        host = self._host(seat, readings)
        st = host.station
        st.power_on(t - 2 * self.char(seat) - 1e-6)
        st.pop_output()
        st.pop_events()
        st.tx_log.clear()
        return host

    def powered(self, seat: str, t: float) -> AsciiAnalysisHost:
        host = self._host(seat)
        host.station.power_on(t)
        return host

    def at_rest(self, host: AsciiAnalysisHost) -> bool:
        """Where a model afresh would go on as this one: nothing to send, nothing stored,
        nobody held. (The pause after its last frame is kept across a rest point in the run's
        memo: see :meth:`event` and :meth:`_request`.)"""
        st = host.station
        return st.idle and st.fc_state is FcState.OPEN and not st.partner_stopped and not st.frames_stored

    def entry_start(self, entry: Any) -> float:
        return entry.start

    def continues(self, prev: Any, entry: Any) -> bool:
        # the station logs what it sent as it is popped: a frame whose schedule moved comes
        # in several records with one explanation
        return prev.why is entry.why and prev.kind == entry.kind

    # -- local events ---------------------------------------------------------------------
    def announces_startup(self, seat: str) -> bool:
        return self.params[seat].flow_control == "xon_xoff"

    def startup_name(self, seat: str) -> str:
        return "XON"

    def startup_rule(self, seat: str) -> tuple[str, str, int | None]:
        return ("with XON/XOFF flow control the driver sends XON once it has been parameterised", _FC, None)

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
            if st.fc_state is FcState.OPEN and host.tentative and _would_be_full(host):
                return Explanation(lambda r, t: r.host.unread(t),
                                   "its application had not read the frames it received (the XOFF shows it)")
            if st.fc_state is FcState.HELD and host.readings.a_xoff_repeated:
                return Explanation(lambda r, t: _send_flow(r.st, t, p.xoff))
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
        if host.echo and self._discarded(run, frame) is not None:
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
        _advance(st, t)
        while st.fc_state is FcState.HELD and st.frames_stored:
            host.read(t)
        host.at_once = not host.echo or host.readings.a_reads_at_once
        host.drain(t)

    @staticmethod
    def _one_more(run, t: float) -> None:
        """The transmitter sends one more character of the interrupted frame (it held it
        when the XOFF came)."""
        st = run.st
        _advance(st, t)
        job = st.job
        _, end = st._line.schedule(t, job.wire[job.pos:job.pos + 1], "data", _AFTER_XOFF_WHY)
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

    # -- why the model sends what it sends ------------------------------------------------
    def _send_rule(self, p) -> tuple[str, str]:
        if p.end_criterion == "end_chars":
            v = {"up_to_end": "variant 1: the data up to and including the first end character(s); nothing after them",
                 "len_with_end": "variant 2: exactly LEN bytes, the last the end character(s)",
                 "len_append_end": "variant 3: the LEN bytes, then the end character(s) the driver appends"}
            return (f"a send job goes on the line as one frame, {v[p.send_variant]}",
                    "§2.2.4 'sending' (end character criterion); Table 2-7")
        if p.end_criterion == "fixed_length":
            return ("a send job goes on the line as one frame of its LEN bytes, back to back"
                    + (", with a pause of the CDT before the next" if p.send_pause else ""),
                    "§2.2.4 'sending' (fixed message frame length); Table 2-7")
        return ("a send job goes on the line as one frame of its LEN bytes, back to back, and the next frame only "
                "after a pause of more than the CDT", "§2.2.4 'sending' (expiry of the character delay time); Table 2-7")

    def cause(self, run, entry: Any, k: int, byte: int) -> Cause:
        st = run.st
        seat = run.judge.seat
        p, q = self.params[seat], self.params[OTHER[seat]]
        c = p.char_time
        name = self.name(byte)
        if entry is None:
            return Cause("reply", "the model's behaviour", self.reference, 3e-6, self.late_abs, what=name)
        why = entry.why
        if entry.kind == "control":
            if why.input == "START" or why.machine == "station":
                return Cause("local", *self.startup_rule(seat)[:2], 3e-6, self.late_abs, what=name)
            if byte == p.xoff:
                return Cause("reply", "XOFF when the frames in the receive buffer reach 'buffered receive message "
                                      "frames', or 50 characters before the 1024-byte buffer overflows (reading Q14)",
                             _FC + "; Table 2-10", 3e-6, self.late_abs, what=name)
            return Cause("reply", "XON once the receive buffer can take data again after an XOFF: a frame read, or "
                                  "a discarded frame that freed room (reading Q15)",
                         _FC + "; Table 2-10", 3e-6, self.late_abs, what=name)
        rule, ref = self._send_rule(p)
        job = st.job
        if job is not None and run.host.is_echo(job.payload):
            rrule, rref = _RECEIVE_RULE[p.end_criterion]
            rule = (f"with the echo convention the station sends back the oldest frame of its receive buffer, as its "
                    f"receiver delimited it ({rrule}; {_BUFFER_RULE[0]}); {rule}")
            ref = f"{rref}; {_BUFFER_RULE[1]}; {ref}"
        late = self._gap(p, q) + c
        if why is _AFTER_XOFF_WHY:
            return Cause("local", "after XOFF the transmitter still sends what it holds (at most "
                                  f"{MAX_AFTER_XOFF} characters, reading Q15)", _FC, 3e-6, late)
        if why.input == "GO":
            return Cause("reply", "on the partner's XON before the wait time is over the interrupted frame goes on, "
                                  "nothing lost or repeated; " + rule, f"{_FC}; {ref}", 3e-6, late)
        if why.input == "T_PAUSE":
            pause = self._pause(p, st.readings)
            return Cause("timer", f"the next frame waits until the pause after the last one is over "
                                  f"(more than the CDT, {1000 * p.cdt:g} ms: reading Q5); " + rule, ref,
                         c + 0.05 * pause + 3e-6, late)
        return Cause("local", rule, ref, 3e-6, late)

    def what(self, host: AsciiAnalysisHost, entry: Any, k: int, byte: int) -> str:
        if entry is None or entry.kind != "data":
            return ""
        st = host.station
        job = st.job
        p = st.params
        if job is not None and p.end_criterion == "end_chars" and byte in p.end_chars:
            return f"the end character {char_name(byte)}"
        return f"a character of the frame ({char_name(byte)})"

    def name(self, byte: int) -> str:
        return self._names.get(byte) or char_name(byte)

    # -- what a byte the model does not send breaks ----------------------------------------
    def unexpected(self, run, host: AsciiAnalysisHost, item, later) -> Cause:
        st = host.station
        seat = run.judge.seat
        p = st.params
        if item.kind == "break":
            return Cause("reply", "an ASCII driver never sends a BREAK (a CP 341 receiving one discards the frame "
                                  "coming in and raises 16#080D)", "Figs. 2-21 to 2-23 'BREAK'; Table 8-1 (08)0DH",
                         0.0, 0.0, Code.LINE_BREAK)
        if item.kind == "invalid":
            return Cause("reply", "a character with a parity or framing error: the line or the sender's transmitter "
                                  "is at fault (a CP 341 receiving it discards the frame and raises 16#080C)",
                         "Table 2-8; Figs. 2-21 to 2-23; Table 8-1 (08)0CH", 0.0, 0.0, Code.CHARACTER_ERROR)
        b = item.value
        if p.data_bits == 7 and b > 0x7F:
            return Cause("reply", "with 7 data bits no character above 7F goes on the line", "Table 2-8; Table 2-7 "
                                  "footnote 2", 0.0, 0.0)
        if later is not None and later[1] == b:
            return later[2]
        xonxoff = p.flow_control == "xon_xoff"
        if xonxoff and b == p.xoff:
            return Cause("reply", "XOFF only when the frames in the receive buffer reach 'buffered receive message "
                                  "frames', or 50 characters before the 1024-byte buffer overflows (reading Q14): the "
                                  "frames it received do not fill it that far, even unread",
                         _FC + "; Table 2-10", 0.0, 0.0)
        if xonxoff and b == p.xon:
            return Cause("reply", "XON once the driver is parameterised, and after an XOFF once the buffer can take "
                                  "data again; not otherwise (reading Q15)", _FC, 0.0, 0.0)
        if (seat, run.i_obs) in self._unsendable:
            return Cause("reply", "a send job carries 1 to 1024 bytes (LEN): a longer frame is never sent, the job "
                                  "is refused with 16#1E41", "Table 6-2 LEN; Table A-7; Table 8-2 (1E)41H",
                         0.0, 0.0, Code.LEN_ILLEGAL)
        if st.job is None and self._rest_of_aborted(run, self._frame_now(run), item.start):
            return Cause("reply", f"no XON within the wait time ({p.xon_wait_ms} ms): the send job is aborted "
                                  "with 16#0708, and what is left of it is not sent (a late XON does not resume it)",
                         _FC + "; Table 8-1 (07)08H", 0.0, 0.0, Code.XON_CTS_WAIT_EXPIRED)
        if st.tx_state is TxState.STOPPED or st.partner_stopped:
            aborted = run.memo.get("aborted")
            if aborted is not None and st.job is None:
                return Cause("reply", f"no XON within the wait time ({p.xon_wait_ms} ms): the send job is aborted "
                                      "with 16#0708, and what is left of it is not sent", _FC + "; Table 8-1 (07)08H",
                             0.0, 0.0, Code.XON_CTS_WAIT_EXPIRED)
            return Cause("reply", "on the partner's XOFF the driver interrupts its transmission (its transmitter may "
                                  f"finish what it holds, at most {MAX_AFTER_XOFF} characters: reading Q15) and goes on "
                                  "only after XON (an XOFF while idle holds the next frame: reading Q16)",
                         _FC, 0.0, 0.0)
        if host.echo and st.job is None:
            if not st.frames_stored and st.rx_state is not RxState.WAIT_CHAR:
                rule, ref = _RECEIVE_RULE[p.end_criterion]
                return Cause("reply", "with the echo convention a station sends back a frame only once it is "
                                      f"complete: {rule}", ref, 0.0, 0.0)
            d = self._discarded(run, self._frame_now(run))
            if d is not None:
                rule, ref = _DISCARD_RULES.get(d[1], ("a frame the receiver discards is never delivered", "§2.2.4"))
                return Cause("reply", "with the echo convention a station sends back only the frames it stored; "
                                      + rule, ref, 0.0, 0.0, d[2])
        rule, ref = self._send_rule(p)
        return Cause("reply", "an ASCII driver sends only the frames of its send jobs, and (with XON/XOFF) its XON and "
                              "XOFF; " + rule, ref, 0.0, 0.0)

    def _frame_now(self, run) -> bytes:
        fr = self._frame_ahead(run, run.i_obs) if run.i_obs < len(run.judge.obs) else b""
        return b"" if fr is WAIT else fr

    def wrong(self, run, item, byte: int, cause: Cause) -> Cause:
        """Where an echo differs from the frame the model stored, what the model's receiver
        discarded just before it (if anything) is the rule the seat's receiver broke."""
        st = run.st
        if run.host.echo and st.job is not None and run.host.is_echo(st.job.payload):
            t0 = run.host.echo_at
            if t0 >= 0:
                for t, reason, code, data in reversed(run.memo.get("discards", ())):
                    if t < t0 - self._rest:
                        break
                    rule, ref = _DISCARD_RULES.get(reason, ("", ""))
                    if rule:
                        return Cause(cause.kind, f"{rule}; {cause.rule}", f"{ref}; {cause.reference}", cause.early,
                                     cause.late, code, cause.what, cause.rules)
        return cause

    # -- alternatives -----------------------------------------------------------------------
    def variants(self, seat: str, resolution: float) -> list[Variant]:
        out = resolution_variants(resolution, "send jobs and reads")
        if resolution <= 0:
            # the capture formats keep whole microseconds: an XOFF and the character a station
            # would have begun next that met within one came in either order
            out.append(Variant("resolution", "with the other seat's characters 2 µs earlier (the capture's "
                                             "timestamps are whole microseconds)", shift=-2 * QUANTUM))
        if self._variants is None:
            kit = self.procedure.fuzz_kit()
            alts = list(kit.alternatives if kit is not None else ()) + [
                ("Q5", dict(q5_send_pause_extra_chars=0.0)),
                ("Q15", dict(q15_xon_only_after_xoff=False)),
            ]
            self._variants = [
                Variant("buffer", "with an application that reads each frame as soon as it is stored (the echo held "
                                  "back by the send side; the reads are not on the line)",
                        readings=replace(DEFAULT, a_reads_at_once=True), kind="buffer"),
                Variant("a_fixed_length_job_is_one_frame",
                        "with send jobs of any length under the fixed-length criterion",
                        readings=replace(DEFAULT, a_fixed_length_job_is_one_frame=False)),
                Variant("Q15", "with the other reading of the manual's open point Q15 (a station holding its "
                               "partner repeats its XOFF while the partner keeps sending)",
                        readings=replace(DEFAULT, a_xoff_repeated=True)),
            ] + [
                Variant(name, f"with the other reading of the manual's open point {name} "
                              f"({_READING_WORDS.get(name, 'see ptpcert.model.ascii.readings')})",
                        readings=replace(DEFAULT, model=replace(READINGS, **change)))
                for name, change in alts]
        return out + self._variants

    # -- reports --------------------------------------------------------------------------
    def describe(self, seat: str, its: list) -> str:
        """A seat's characters as the other seat's receiver delimits them, e.g. "frame 41 42 <ETX>
        (3 bytes, end character)" (see :meth:`label`)."""
        rx = self.params[OTHER[seat]]
        parts: list[str] = []
        timed: list[tuple[float, int]] = []

        def flush() -> None:
            for piece in split_frames(timed, rx):
                parts.append(self._piece(piece, rx))
            timed.clear()

        for it in its:
            if it.kind == "byte":
                timed.append((it.start, it.value))
            else:
                flush()
                parts.append("BREAK" if it.kind == "break" else f"{it.value:02X}(error)")
        flush()
        return " ".join(parts)

    def _piece(self, piece, rx) -> str:
        if piece.kind in ("xon", "xoff"):
            return piece.kind.upper()
        body = piece.data[:len(piece.data) - piece.end_len]
        shown = " ".join(f"{x:02X}" for x in body[:8]) + (" ..." if len(body) > 8 else "")
        if piece.end_len:
            shown = (shown + " " if shown else "") + " ".join(f"<{char_name(x)}>" for x in piece.data[len(body):])
        n = len(piece.data)
        if piece.kind == "fragment":
            return f"fragment {shown} ({n} bytes, no end)"
        how = {"cdt": "ended by the CDT", "end_chars": "end character",
               "fixed_length": "fixed length"}[rx.end_criterion]
        return f"frame {shown} ({n} bytes, {how})"
