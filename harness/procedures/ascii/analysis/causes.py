"""Why an ASCII station sends each character, and what a character it should not send breaks.

The part of :class:`~ptpcert.procedures.ascii.analysis.analyzer.AsciiAnalyzer` that speaks for
the manual (:class:`Causes`, mixed into it): for every character the model sends, the rule,
the manual's reference and the timing window (a :class:`~ptpcert.analysis.interface.Cause`),
from the model station's record of why it sent it (its start-up XON, the XON and XOFF of its
receiver, a frame of a send job, held back by the pause between frames or resumed by the
partner's XON, a character its transmitter still held after the partner's XOFF); for a
character the seat sent where the model sends nothing, or something else, the rule the
station broke (a BREAK, a character error, an XON or XOFF not due, a job the driver refuses,
a character after the partner's XOFF, the echo of what its receiver discarded). The names of
the characters in reports are here too.

Timing windows (on top of the capture's resolution): a character of a frame may come up to
half the shorter CDT late after the one before (see ``AsciiAnalyzer._gap``); so may the
first character after the partner's XON (the partner's CDT runs again from its XON); the
first character of a frame held back by the pause between frames may come one character time
and 5 % of the pause early; XON and XOFF the tolerance late.
"""

from __future__ import annotations

from typing import Any

from ptpcert.analysis import OTHER, WAIT, Cause
from ptpcert.model.codes import Code
from ptpcert.procedures.ascii.analysis.host import AFTER_XOFF_WHY, MAX_AFTER_XOFF, AsciiAnalysisHost
from ptpcert.procedures.ascii.model import events as aev
from ptpcert.procedures.ascii.model.codec import char_name
from ptpcert.procedures.ascii.model.table import RxState, TxState

#: the manual's reference of XON/XOFF flow control
_FC = "§2.2.4 'data flow control / handshaking'; Table 2-9"
_RECEIVE_RULE = {
    "cdt": ("a frame ends when the CDT passes without a character (expiry of the character delay time)",
            "§2.2.4 'expiry of the character delay time'; Fig. 2-21; Table 2-7"),
    "end_chars": ("a frame ends with its end character(s) (with two, end character 1 directly followed by end "
                  "character 2), which belong to the frame", "§2.2.4 'end character(s)'; Fig. 2-22; Table A-7"),
    "fixed_length": ("a frame ends with its N-th character (the fixed length)",
                     "§2.2.4 'fixed message frame length'; Fig. 2-23; Table 2-7"),
}
#: the catalogue's rules (rules.toml) behind them
_RECEIVE_IDS = {"cdt": ("ASCII.RX-CDT.FRAME-END",), "end_chars": ("ASCII.RX-EC.END-INCLUDED", "ASCII.RX-EC.COMPLETES-AT-ONCE"),
                "fixed_length": ("ASCII.RX-FL.FRAME-END",)}
_BUFFER_RULE = ("the receive buffer hands the oldest frame to the CPU first", "§2.2.4 'receive buffer'; Table 2-10")
_BUFFER_IDS = ("ASCII.BUFFER.FIFO",)
_SEND_IDS = {"up_to_end": ("ASCII.TX.VARIANT-UP-TO-END",), "len_with_end": ("ASCII.TX.VARIANT-LEN-WITH-END",),
             "len_append_end": ("ASCII.TX.VARIANT-APPEND-END",), "cdt": ("ASCII.TX.FRAME-AS-GIVEN", "ASCII.TX.CDT-PAUSE"),
             "fixed_length": ("ASCII.TX.FRAME-AS-GIVEN", "ASCII.TX.FL-PAUSE")}
_XOFF_IDS = ("ASCII.FLOW.XOFF-AT-FRAME-COUNT", "ASCII.FLOW.XOFF-AT-974")
_WAIT_IDS = ("ASCII.FLOW.XON-WAIT", "ASCII.STATUS.0708")

#: why a receiver discards characters (the model's FrameDiscarded reasons), as rules: the
#: sentence, the reference and the catalogue's ids
_DISCARD_RULES = {
    aev.CDT_EXPIRED: ("characters the CDT cut off before their frame was complete (a fragment, or what followed "
                      "a complete frame) are discarded with an error, never delivered",
                      "§2.2.4 malformed frames; Figs. 2-22, 2-23; Table 8-1 (08)06H",
                      ("ASCII.RX-EC.NO-END-DISCARDED", "ASCII.RX-EC.TRAILING-DISCARDED", "ASCII.RX-FL.SHORT-DISCARDED",
                       "ASCII.RX-FL.SURPLUS-DISCARDED", "ASCII.STATUS.0806")),
    aev.CHARACTER_ERROR: ("a frame with a character error (parity, framing, overrun) is received to its end and "
                          "discarded, never delivered", "Figs. 2-21 to 2-23; Table 8-1 (08)0CH",
                          ("ASCII.RX-CDT.CHARACTER-ERROR", "ASCII.RX-EC.CHARACTER-ERROR", "ASCII.RX-FL.CHARACTER-ERROR",
                           "ASCII.STATUS.080C")),
    aev.NO_ROOM: ("a frame that does not fit in the 1024-byte receive buffer is discarded",
                  "§2.2.4 'receive buffer', 'data flow control'; Table 2-10; Table 8-1 (08)0AH",
                ("ASCII.BUFFER.BYTES", "ASCII.FLOW.OVERFLOW", "ASCII.STATUS.080A")),
    aev.TOO_LONG: ("a frame longer than 1024 bytes is discarded", "Table A-7; Table 8-1 (08)16H",
                   ("ASCII.RX.TOO-LONG", "ASCII.STATUS.0816")),
    aev.BUFFER_FULL: ("with 'prevent overwrite' a frame that finds the buffer full is discarded; the frames stored "
                      "stay", "Table 2-10; Table 8-1 (08)0AH", ("ASCII.BUFFER.FULL-PREVENT", "ASCII.STATUS.080A")),
    aev.OVERWRITTEN: ("with 'prevent overwrite = no' a new frame replaces the unread one", "Table 2-10",
                      ("ASCII.BUFFER.OVERWRITE",)),
    aev.LINE_BREAK: ("a BREAK ends the frame coming in, which is discarded",
                     "Figs. 2-21 to 2-23 'BREAK'; Table 8-1 (08)0DH", ("ASCII.LINE.BREAK", "ASCII.STATUS.080D")),
}


class Causes:
    """The rules behind the characters of an ASCII seat, for
    :class:`~ptpcert.procedures.ascii.analysis.analyzer.AsciiAnalyzer` (it brings ``params``,
    ``reference``, ``late_abs``, ``_rest``, ``_unsendable``, ``_names``, :meth:`_gap`,
    :meth:`_pause`, and from its local events :meth:`_frame_ahead`, :meth:`_discarded` and
    :meth:`_rest_of_aborted`)."""

    def startup_name(self, seat: str) -> str:
        return "XON"

    def startup_rule(self, seat: str) -> tuple[str, str, int | None]:
        return ("with XON/XOFF flow control the driver sends XON once it has been parameterised", _FC, None)

    # -- why the model sends what it sends ------------------------------------------------
    def _send_ids(self, p) -> tuple[str, ...]:
        """The catalogue's rules of what a send job puts on the line."""
        if p.end_criterion == "end_chars":
            return _SEND_IDS[p.send_variant]
        return _SEND_IDS[p.end_criterion]

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
            return Cause("reply", "the model's behaviour", self.reference, 3e-6, self.late_abs, what=name,
                         rules=self._send_ids(p))
        why = entry.why
        if entry.kind == "control":
            if why.input == "START" or why.machine == "station":
                return Cause("local", *self.startup_rule(seat)[:2], 3e-6, self.late_abs, what=name,
                             rules=("ASCII.FLOW.XON-AT-START-UP",))
            if byte == p.xoff:
                return Cause("reply", "XOFF when the frames in the receive buffer reach 'buffered receive message "
                                      "frames', or 50 characters before the 1024-byte buffer overflows (reading Q14)",
                             _FC + "; Table 2-10", 3e-6, self.late_abs, what=name, rules=_XOFF_IDS)
            return Cause("reply", "XON once the receive buffer can take data again after an XOFF: a frame read, or "
                                  "a discarded frame that freed room (reading Q15)",
                         _FC + "; Table 2-10", 3e-6, self.late_abs, what=name, rules=("ASCII.FLOW.XON-AFTER-READ",))
        rule, ref = self._send_rule(p)
        ids = self._send_ids(p)
        job = st.job
        if job is not None and run.host.is_echo(job.payload):
            rrule, rref = _RECEIVE_RULE[p.end_criterion]
            rule = (f"with the echo convention the station sends back the oldest frame of its receive buffer, as its "
                    f"receiver delimited it ({rrule}; {_BUFFER_RULE[0]}); {rule}")
            ref = f"{rref}; {_BUFFER_RULE[1]}; {ref}"
            ids = _RECEIVE_IDS[p.end_criterion] + _BUFFER_IDS + ids
        late = self._gap(p, q) + c
        if why is AFTER_XOFF_WHY:
            return Cause("local", "after XOFF the transmitter still sends what it holds (at most "
                                  f"{MAX_AFTER_XOFF} characters, reading Q15)", _FC, 3e-6, late,
                         rules=("ASCII.FLOW.XOFF-STOPS",))
        if why.input == "GO":
            return Cause("reply", "on the partner's XON before the wait time is over the interrupted frame goes on, "
                                  "nothing lost or repeated; " + rule, f"{_FC}; {ref}", 3e-6, late,
                         rules=("ASCII.FLOW.XON-RESUMES",) + ids)
        if why.input == "T_PAUSE":
            pause = self._pause(p, st.readings)
            return Cause("timer", f"the next frame waits until the pause after the last one is over "
                                  f"(more than the CDT, {1000 * p.cdt:g} ms: reading Q5); " + rule, ref,
                         c + 0.05 * pause + 3e-6, late, rules=ids)
        return Cause("local", rule, ref, 3e-6, late, rules=ids)

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
                         0.0, 0.0, Code.LINE_BREAK, rules=("ASCII.LINE.BREAK",))
        if item.kind == "invalid":
            return Cause("reply", "a character with a parity or framing error: the line or the sender's transmitter "
                                  "is at fault (a CP 341 receiving it discards the frame and raises 16#080C)",
                         "Table 2-8; Figs. 2-21 to 2-23; Table 8-1 (08)0CH", 0.0, 0.0, Code.CHARACTER_ERROR,
                         rules=("ASCII.FRAME.SETTINGS",))
        b = item.value
        if p.data_bits == 7 and b > 0x7F:
            return Cause("reply", "with 7 data bits no character above 7F goes on the line", "Table 2-8; Table 2-7 "
                                  "footnote 2", 0.0, 0.0, rules=("ASCII.FRAME.SEVEN-BIT",))
        if later is not None and later[1] == b:
            return later[2]
        xonxoff = p.flow_control == "xon_xoff"
        if xonxoff and b == p.xoff:
            return Cause("reply", "XOFF only when the frames in the receive buffer reach 'buffered receive message "
                                  "frames', or 50 characters before the 1024-byte buffer overflows (reading Q14): the "
                                  "frames it received do not fill it that far, even unread",
                         _FC + "; Table 2-10", 0.0, 0.0, rules=_XOFF_IDS)
        if xonxoff and b == p.xon:
            return Cause("reply", "XON once the driver is parameterised, and after an XOFF once the buffer can take "
                                  "data again; not otherwise (reading Q15)", _FC, 0.0, 0.0,
                         rules=("ASCII.FLOW.XON-AT-START-UP", "ASCII.FLOW.XON-AFTER-READ"))
        if (seat, run.i_obs) in self._unsendable:
            return Cause("reply", "a send job carries 1 to 1024 bytes (LEN): a longer frame is never sent, the job "
                                  "is refused with 16#1E41", "Table 6-2 LEN; Table A-7; Table 8-2 (1E)41H",
                         0.0, 0.0, Code.LEN_ILLEGAL, rules=("ASCII.TX.LEN-ILLEGAL", "ASCII.STATUS.1E41"))
        if st.job is None and self._rest_of_aborted(run, self._frame_now(run), item.start):
            return Cause("reply", f"no XON within the wait time ({p.xon_wait_ms} ms): the send job is aborted "
                                  "with 16#0708, and what is left of it is not sent (a late XON does not resume it)",
                         _FC + "; Table 8-1 (07)08H", 0.0, 0.0, Code.XON_CTS_WAIT_EXPIRED, rules=_WAIT_IDS)
        if st.tx_state is TxState.STOPPED or st.partner_stopped:
            aborted = run.memo.get("aborted")
            if aborted is not None and st.job is None:
                return Cause("reply", f"no XON within the wait time ({p.xon_wait_ms} ms): the send job is aborted "
                                      "with 16#0708, and what is left of it is not sent", _FC + "; Table 8-1 (07)08H",
                             0.0, 0.0, Code.XON_CTS_WAIT_EXPIRED, rules=_WAIT_IDS)
            return Cause("reply", "on the partner's XOFF the driver interrupts its transmission (its transmitter may "
                                  f"finish what it holds, at most {MAX_AFTER_XOFF} characters: reading Q15) and goes on "
                                  "only after XON (an XOFF while idle holds the next frame: reading Q16)",
                         _FC, 0.0, 0.0, rules=("ASCII.FLOW.XOFF-STOPS", "ASCII.FLOW.XOFF-WHILE-IDLE"))
        if host.echo and st.job is None:
            if not st.frames_stored and st.rx_state is not RxState.WAIT_CHAR:
                rule, ref = _RECEIVE_RULE[p.end_criterion]
                return Cause("reply", "with the echo convention a station sends back a frame only once it is "
                                      f"complete: {rule}", ref, 0.0, 0.0, rules=_RECEIVE_IDS[p.end_criterion])
            d = self._discarded(run, self._frame_now(run))
            if d is not None:
                rule, ref, ids = _DISCARD_RULES.get(d[1], ("a frame the receiver discards is never delivered", "§2.2.4",
                                                           ()))
                return Cause("reply", "with the echo convention a station sends back only the frames it stored; "
                                      + rule, ref, 0.0, 0.0, d[2], rules=ids)
            if not host.own_jobs:
                rule, ref = _RECEIVE_RULE[p.end_criterion]
                return Cause("reply", "with the echo convention a station sends back the frames it received, and no "
                                      f"frame of its own: {rule}", ref, 0.0, 0.0, rules=_RECEIVE_IDS[p.end_criterion])
        rule, ref = self._send_rule(p)
        return Cause("reply", "an ASCII driver sends only the frames of its send jobs, and (with XON/XOFF) its XON and "
                              "XOFF; " + rule, ref, 0.0, 0.0, rules=self._send_ids(p))

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
                    rule, ref, ids = _DISCARD_RULES.get(reason, ("", "", ()))
                    if rule:
                        return Cause(cause.kind, f"{rule}; {cause.rule}", f"{ref}; {cause.reference}", cause.early,
                                     cause.late, code, cause.what, ids + cause.rules)
        return cause
