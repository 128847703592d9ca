"""Our readings of the open points of the ASCII driver's description.

The manual leaves many details of the ASCII driver open (the figures of §2.2.4 survive only
as fragments, error codes for malformed frames are not named, thresholds are given in
words). Every place where the model had to choose between defensible readings, and the
choice changes what is on the line or which STATUS event is raised, is one field here. The
fields carry the number Q1..Q28 of the open point as we count them, and each comment says
what the point is and which manual text leaves it open; details that needed a choice but are
not among those points start with ``d_``. :data:`READINGS`
holds the readings the model uses by default; a station built with other readings shows
what an implementation that took the other reading does, so that cases and the fuzzer can
accept it instead of failing it.

Points whose reading is fixed in the parameters rather than here: Q1 and Q2 (the ranges of
CDT and wait times, see ``params.MAX_CDT_MS``), Q3 (a default CDT below the baud rate's
minimum is raised to it, ``params.default_cdt_ms``), Q7 (the number of end characters is
the length of ``end_chars``, so 00 can be a second end character), Q8 (the fixed-length
pause is on unless switched off, ``send_pause``), Q9 (the data output waiting time starts
at RTS ON, Fig. 2-24).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ptpcert.model.codes import Code


@dataclass(frozen=True)
class AsciiReadings:
    # Q4: the CDT is the idle time between the stop bit of one character and the start bit
    # of the next (Fig. 2-2). A receiver sees a character only once its stop bit is in, so it
    # gives the next character CDT plus one character time after the last one completed;
    # a character completing exactly then is still in time (a gap of exactly CDT does not
    # end a frame).
    q4_cdt_grace_one_character: bool = True

    # Q5: the pause between two sent frames (CDT criterion: "more than the CDT"; fixed
    # length: "equal to the CDT") is, for both, the CDT plus this many character times of
    # idle line between the last stop bit of one frame and the first start bit of the next.
    # One character more than the CDT is the smallest pause a receiver that measures as in
    # Q4 recognises as a frame end; a pause of exactly CDT would merge the frames there.
    q5_send_pause_extra_chars: float = 1.0

    # Q6: send variants of the end-character criterion (§2.2.4).
    # "Up to and including the end character" with no end character within LEN: the LEN
    # bytes are sent as they are (True), or the job is refused with 16#1E41 (False).
    q6_up_to_end_without_end_sends_all: bool = True
    # ... with two end characters, the data is cut after the first complete end sequence
    # (True), not after the first end character 1 alone (False).
    q6_up_to_end_finds_sequence: bool = True
    # "LEN bytes, the last being the end character(s)" with other last bytes, and "LEN
    # bytes plus automatic end character(s)" with end characters inside the data: the data
    # is sent as given; the driver does not check it. LEN + 1 or LEN + 2 may exceed 1024
    # in the append variant (the length rule applies to LEN). (No field: fixed.)

    # Q10: characters discarded because the CDT expired after them: a fragment without an
    # end character, a short fixed-length frame ("an error message is issued", §2.2.4)
    # always raise 16#0806. Characters that followed a complete frame without a CDT gap
    # (after the end character, beyond the fixed length) and then timed out are the same
    # situation for the receiver: this code (None: discarded silently).
    q10_trailing_discard_code: int | None = Code.CDT_EXCEEDED

    # Q11: "merged with the next frame": the leftover characters become the first bytes of
    # the next frame (no field: fixed).

    # Q12: recovery after a character error (Figs. 2-21 to 2-23): the damaged frame is
    # received to its end (CDT expiry; a valid end character or CDT expiry; the configured
    # number of characters or CDT expiry) and discarded, and its first error is reported
    # then (16#080C). When the CDT ends a damaged frame in the end-character or fixed-length
    # criterion, 16#0806 is reported as well (True) or not (False).
    q12_cdt_also_reports_0806: bool = False

    # Q13: a frame longer than 1024 bytes (CDT criterion, or no end character in time) is
    # received to its end and discarded with this code (16#0816, "received frame longer
    # than agreed"); the alternative reading is 16#080A (no room in the receive buffer).
    q13_overlong_frame_code: int = Code.FRAME_TOO_LONG

    # Q14: XOFF (RTS OFF) is sent when the number of frames in the receive buffer reaches
    # buffer_frames + this offset (0: at N; -1: at N - 1), ...
    q14_xoff_frame_offset: int = 0
    # ... or when the buffer holds this many bytes, the frame being received included
    # ("50 characters before the 1024-byte buffer overflows": 1024 - 50).
    q14_xoff_fill_bytes: int = 1024 - 50

    # Q15: XON (RTS ON) is sent only to lift an XOFF (RTS OFF) sent before (True), not after
    # every read (False); ...
    q15_xon_only_after_xoff: bool = True
    # ... it is sent as soon as the buffer is below both thresholds again, after a read by
    # the CPU or after a discarded frame freed the room (True), or only after a read (False);
    # ...
    q15_xon_after_discard: bool = True
    # ... XON and XOFF are sent once, not repeated while the partner keeps sending; and
    # after an XOFF (CTS OFF) the driver finishes the character on the line and sends this
    # many characters more.
    q15_chars_after_xoff: int = 0

    # d_hold: while the driver holds its partner (XOFF sent, RTS OFF), the CDT of an intact
    # frame coming in is suspended, so the pause the driver asked for does not cut off the
    # frame its XOFF interrupted; the CDT starts again once the XON is out (RTS ON). §2.2.4
    # gives handshaking the purpose that no data is lost. The other reading (False) lets the
    # CDT run: the interrupted frame is then discarded with 16#0806 (end-character and
    # fixed-length criteria) or ends at the pause (CDT criterion). A frame already spoiled
    # (no room, character error) is received to its end as usual.
    d_cdt_suspended_while_holding: bool = True

    # Q16: received XON/XOFF codes are flow control, never data: they are not stored, ...
    # (no field: fixed, §2.2.4 "the user data must not contain XON or XOFF") ...
    # ... they do not restart the receiver's CDT (False) ...
    q16_flow_char_restarts_cdt: bool = False
    # ... and an XOFF received while nothing is being sent holds the next frame until XON
    # (True), rather than being ignored (False).
    q16_xoff_while_idle_holds: bool = True

    # Q17: when the buffer overflows (the partner ignored XOFF, or no flow control), the
    # frame being received is discarded (only it; the frames before stay intact) with this
    # code.
    q17_overflow_code: int = Code.NO_RECEIVE_BUFFER

    # Q18: a complete frame that finds the buffer full (buffer_frames frames stored,
    # prevent overwrite = yes) is discarded with this code when it ends. With prevent
    # overwrite = no (one frame) the frame coming in may use the room of the unread frame
    # it is going to replace, and the replaced frame goes without a STATUS (no field).
    q18_full_buffer_code: int = Code.NO_RECEIVE_BUFFER

    # Q19: automatic use of the V.24 signals (§2.2.4, Fig. 2-24):
    # the code when CTS is not ON at the end of the data output waiting time, or drops
    # while sending, and when DSR drops during a send or a reception ("DSR = OFF or
    # CTS = OFF", Table 8-1); ...
    q19_v24_code: int = Code.DSR_CTS_DROPPED
    # ... DSR need not be ON to send (only its ON->OFF edge aborts); ...
    q19_send_needs_dsr: bool = False
    # ... a send job ends (DONE) when RTS goes OFF after the time to RTS OFF (True: the
    # note of §2.2.4 drops "RTS and the send request" together), not at the last stop
    # bit (False); after an abort RTS goes OFF at once.
    q19_done_at_rts_off: bool = True

    # Q20: no arbitration in the half-duplex automatic V.24 mode: the model receives while
    # it sends; keeping to one direction is the user program's business (no field).
    # Not modelled: flow control in CPU STOP (Q21), EN_R/R of the FBs (Q24), the RS 485
    # switch-over time, the CPU->CP transfer time (a job's frame starts when it is handed
    # over, Table A-8 is not modelled).

    # d_break: a BREAK on the receive line reports 16#080D at once and discards the frame
    # being received; it does not touch a running send job (full duplex).
    d_break_aborts_send: bool = False

    # d_start_up: before its parameters are in, and in STOP after 16#020F, the driver drives
    # no output; with XON/XOFF the start-up XON goes out at once, with RTS/CTS RTS goes ON;
    # DTR is set (ON) only with automatic use of V.24 signals. The modem inputs (CTS, DSR)
    # are taken as ON until the line reports otherwise (a port without modem lines).
    d_dtr_on_outside_auto_v24: bool = False


READINGS = AsciiReadings()

#: the readings of the station in the tester's seat, where the harness plays a conforming
#: partner: its application reads each frame at once and it has room for any frame the IUT
#: sends, so it never holds the IUT on its own (with a fixed length near 1024 bytes a
#: receiver at the Q14 threshold would stop the frame it can only read once complete); a
#: case that wants the IUT held sends XOFF itself
TESTER_READINGS = replace(READINGS, q14_xoff_fill_bytes=1024 + 1)


def frame_reaches_xoff(params) -> bool:
    """One frame of the profile's fixed length reaches the fill at which a receiver sends
    XOFF (Q14: 50 bytes before the 1024-byte buffer overflows; the exact byte is open, so
    from 50 bytes earlier)."""
    return params.end_criterion == "fixed_length" and params.fixed_length > READINGS.q14_xoff_fill_bytes - 50
