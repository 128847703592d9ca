"""Data flow control (§2.2.4 'data flow control / handshaking'; Table 2-9): XON/XOFF in both
directions, the thresholds and the wait time. RTS/CTS and the automatic use of the V.24
signals need the modem lines, which no transport carries: those cases are unsupported."""

from __future__ import annotations

import math
from dataclasses import replace

from ptpcert.procedures.ascii.model import send_bytes
from ptpcert.procedures.ascii.model.params import BUFFER_BYTES, XOFF_MARGIN

from ._build import (
    FILL_TIME,
    IDLE,
    OVER,
    RX_ERRORS,
    SLOW,
    SLOW_SETUP,
    case,
    echo_steps,
    expect,
    frame_of,
    hold,
    modem_case,
    unbuilt_case,
    quiet_flow,
    receive_case,
    send,
    sending_time,
    silence,
    wait,
    xon_in_time,
)

REF = "§2.2.4 'data flow control / handshaking'; Table 2-9"
#: the fill level at which XOFF is due: 50 characters before the 1024-byte buffer overflows
FILL = BUFFER_BYTES - XOFF_MARGIN


def cases(p):
    if p.flow_control in ("rts_cts", "auto_v24"):
        return _modem(p)
    if p.flow_control != "xon_xoff":
        return []
    xon, xoff = bytes((p.xon,)), bytes((p.xoff,))
    out = [case(p, "FC.XON-AT-START-UP", "One XON once the driver is parameterised", REF,
                "With XON/XOFF flow control the driver sends XON once it has been parameterised (start-up).",
                "start-up", "idle", [expect(xon, within="STARTUP", note="XON")], start="power-on", requires=())]
    out += _sender_side(p, xon, xoff)
    out += _receiver_side(p, xon, xoff)
    return out


def _long_echo(p):
    """A frame whose echo is long enough to be interrupted, and that echo on the line."""
    if p.end_criterion == "fixed_length":
        if p.fixed_length < 60:
            return None, None
        f = frame_of(p, 0)
    else:
        f = frame_of(p, 300)
    return f, send_bytes(f, p)


def _no_room(p, share: float) -> str:
    """Why a case that holds the IUT with XOFF cannot be built: seeing the IUT stop takes
    longer than ``share`` of the wait time for XON leaves."""
    seen = (p.cdt + 4 * p.char_time) * 1000
    return (f"the tester needs {seen:.0f} ms (a CDT and 4 characters) to see the IUT stop after XOFF; with "
            f"xon_wait_ms = {p.xon_wait * 1000:.0f} that leaves no room to lift or let the wait run out "
            f"in time ({share:.0%} of the wait time at most)")


def _sender_side(p, xon, xoff):
    f, w = _long_echo(p)
    if f is None or not quiet_flow(p):
        return []
    first = "2*CDT + 10*CHAR" if p.end_criterion == "cdt" else "CDT + 10*CHAR"
    out = []
    # an XOFF the tester cannot lift in time would end the job with 16#0708: unsupported
    spots = ((1, "AFTER-FIRST", "after the first character"), (len(w) // 2, "MIDDLE", "in the middle"),
             (len(w) - 20, "NEAR-END", "near the end"))
    if not xon_in_time(p):
        for _k, name, where in spots:
            out.append(unbuilt_case(p, f"FC.XOFF-{name}", f"XOFF {where} of a frame stops it; XON resumes it",
                                    REF, "On XOFF the driver interrupts its transmission; on XON it goes on.",
                                    "flow-control", _no_room(p, 0.75), role="both"))
        spots = ()
    for k, name, where in spots:
        out.append(receive_case(
            p, f"FC.XOFF-{name}", f"XOFF {where} of a frame stops it; XON resumes it", REF,
            "On XOFF the driver interrupts its transmission; on XON before the wait time is over it goes on, with "
            "no character lost or repeated (how many characters may still follow the XOFF is open, reading Q15).",
            [send(f, note="a long frame: the IUT sends it back"),
             expect(w[:k], within=first, note=f"the first {k} character(s) of the echo"),
             send(xoff, note="XOFF"),
             expect(w[k:], within="16*CHAR", partial=True, note="the IUT stops (a few characters may be under way)"),
             silence(hold(p), note="nothing while stopped"),
             send(xon, note="XON"),
             expect(w[k:], within="CDT + 10*CHAR", resume=True, note="the rest of the echo")],
            [f], group="flow-control", role="both", echo=False, readings=["Q15"]))
    out += [unbuilt_case(p, "FC.XON-WITHIN-WAIT", "An XON at 0.7 of the wait time resumes the frame", REF,
                         "An XON that comes before the wait time for XON is over resumes the transmission.",
                         "flow-control", _no_room(p, 0.2), role="both")] if not xon_in_time(p, at=0.7) else [receive_case(
        p, "FC.XON-WITHIN-WAIT", "An XON at 0.7 of the wait time resumes the frame", REF,
        "An XON that comes before the wait time for XON is over resumes the interrupted transmission; no 16#0708.",
        [send(f), expect(w[:10], within=first), send(xoff, note="XOFF"),
         expect(w[10:], within="16*CHAR", partial=True), silence("0.7*XONWAIT", note="no XON yet"),
         send(xon, note="XON at 0.7 of the wait time"), expect(w[10:], within="CDT + 10*CHAR", resume=True)],
        [f], group="flow-control", role="both", echo=False, timing_sensitive=True)]
    # the tester sees that the IUT has stopped (a CDT of quiet) well before the wait time is over
    out += [unbuilt_case(p, "FC.XON-WAIT-EXPIRES", "No XON within the wait time: the job is aborted with 16#0708",
                         REF + "; Table 8-1 (07)08H", "If no XON comes within the wait time the job is aborted.",
                         "flow-control", _no_room(p, 0.5), role="both")] if not xon_in_time(p, at=0.4) else [receive_case(
        p, "FC.XON-WAIT-EXPIRES", "No XON within the wait time: the job is aborted with 16#0708",
        REF + "; Table 8-1 (07)08H",
        "If no XON comes within the wait time after XOFF the send job is aborted with 16#0708; a late XON does "
        "not resume it.",
        [send(f), expect(w[:10], within=first), send(xoff, note="XOFF"),
         expect(w[10:], within="16*CHAR", partial=True), silence("1.3*XONWAIT", note="no XON: the wait time runs out"),
         send(xon, note="a late XON"), silence("5*CDT", note="the job is gone")],
        [f], group="flow-control", role="both", echo=False, status=["16#0708"])]
    short = frame_of(p, 4, 3)
    if 4 * p.cdt + 0.2 < p.xon_wait:
        early = "2*CDT + 10*CHAR" if p.end_criterion == "cdt" else "CDT + 10*CHAR"
        out.append(receive_case(
            p, "FC.XOFF-WHILE-IDLE", "An XOFF received while idle holds the next frame until XON", REF,
            "An XOFF received while the driver sends nothing holds its next frame until XON (reading Q16; a driver "
            "that ignores it is graded informational).",
            [send(xoff, note="XOFF while the IUT is idle"), send(short, at="CDT"),
             expect(send_bytes(short, p), within=early, optional=True,
                    note="an IUT that ignores an XOFF while idle sends the echo now"),
             send(xon, note="XON"),
             expect(send_bytes(short, p), within="CDT + 10*CHAR", optional=True, absent_grade="informational",
                    note="the held echo goes out now")],
            [short], group="flow-control", role="both", echo=False, readings=["Q16"]))
    plain = frame_of(p, 6, 5)
    if p.end_criterion != "fixed_length" or p.fixed_length >= 3:
        k = 2
        withx = plain[:k] + xon + plain[k:]
        if p.end_criterion == "fixed_length":
            withx = withx[:p.fixed_length + 1]
        out.append(receive_case(
            p, "FC.CODES-NOT-DATA", "An XON among received data is flow control, not data", REF + "; §2.2.4 'code transparency'",
            "With XON/XOFF the XON and XOFF codes are control characters: an XON among the data is not stored "
            "(a driver that stores it is graded informational, reading Q16).",
            [send(withx, note="an XON among the data"),
             expect(send_bytes(plain, p), within="2*CDT + 10*CHAR", alternatives=[send_bytes(withx[:len(plain)], p)]
                    if p.end_criterion == "fixed_length" else [send_bytes(withx, p)], alt_grade="informational")],
            [plain], group="flow-control", role="receiver", echo=False, readings=["Q16"]))
    return out


def _frames_to_fill(p):
    """Frames the tester sends to reach the XOFF threshold of 974 bytes and how: (size of a
    frame, how many, the gap before each) or None where the profile cannot be filled that way
    without overflowing or reaching the frame count first."""
    if p.end_criterion == "fixed_length":
        size = p.fixed_length
    else:
        size = 100
    k = math.ceil(FILL / size)
    if k * size > 1000 or p.buffer_frames < k + 1:
        return None
    gap = IDLE if p.end_criterion == "cdt" else "0"
    if sending_time(p, [b"x" * size] * k, 3.0 if gap != "0" else 0.0) > FILL_TIME:
        return None
    return size, k, gap


def _sends(frames, gap: str, watch: int, settle: str = ""):
    """Steps sending ``frames`` (``gap`` before each but the first), with a mark before the
    last ``watch`` of them (at the start where there are no more), and the window from that
    mark to the end of the last (four characters more, and ``settle``: what completes the
    last frame after its last character, the CDT under the CDT criterion)."""
    steps = [send(fr, at=gap if i else "0") for i, fr in enumerate(frames)]
    split = max(0, len(frames) - watch)
    if split:
        steps[split - 1] = replace(steps[split - 1], mark=True)
    else:
        steps.insert(0, wait("0ms", note="the first frame starts here", mark=True))
    tail = frames[split:]
    chars = sum(len(fr) for fr in tail) + 4
    gaps = len(tail) - (0 if split else 1)
    window = f"{chars}*CHAR" + (f" + {gaps}*{gap}" if gap != "0" and gaps else "") + (f" + {settle}" if settle else "")
    return steps, window


def _receiver_side(p, xon, xoff):
    out = []
    # XOFF at the frame count (reading Q14: at N, or at N - 1)
    n = p.buffer_frames
    size = 2 if p.end_criterion != "fixed_length" else p.fixed_length
    gap = OVER if p.end_criterion == "cdt" else "0"
    frames = [frame_of(p, size, i) for i in range(n)]
    if n * size <= FILL - 100 and sending_time(p, frames, 1.4 if gap != "0" else 0.0) <= FILL_TIME:
        steps, window = _sends(frames, gap, watch=2, settle="CDT" if p.end_criterion == "cdt" else "")
        steps += [expect(xoff, within=window, since="mark", note="XOFF at the last frame (reading Q14: or the one before)"),
                  expect(xon + send_bytes(frames[0], p), within=SLOW, alternatives=[send_bytes(frames[0], p) + xon],
                         alt_grade="informational",
                         note="XON once the slow application has read a frame, and the frame sent back (reading Q14: "
                              "XOFF at N - 1 lifts only after a second read)")]
        steps += echo_steps(p, frames[1:], first="3*CDT + 20*CHAR")
        out.append(case(
            p, "FC.XOFF-AT-FRAME-COUNT", "XOFF when the buffered frames reach the parameter; XON after a read",
            REF + "; Table 2-10",
            "The driver sends XOFF when the number of frames in its receive buffer reaches 'buffered receive message "
            "frames' (at N or N - 1: reading Q14), and XON as soon as the CPU has read a frame.",
            "flow-control", "receiver", steps, delivered=frames, setup=SLOW_SETUP, readings=["Q14", "Q15"]))
    fill = _frames_to_fill(p)
    if fill is not None:
        size, k, gap = fill
        frames = [frame_of(p, size, i) for i in range(k)]
        steps = [send(fr, at=gap if i else "0", note=f"frame {i + 1} of {size} bytes") for i, fr in enumerate(frames)]
        if k > 1:
            steps[-2] = replace(steps[-2], mark=True)
        else:  # one frame reaches the threshold: the window opens where it starts
            steps.insert(0, wait("0ms", note="the frame starts here", mark=True))
        before = (k - 1) * size
        lo = max(0, FILL - before - XOFF_MARGIN)
        pre = f"{gap} + " if gap != "0" else ""
        xoff_step = expect(xoff, after=f"{pre}{lo}*CHAR", within=f"{pre}{size + 4}*CHAR", since="mark",
                           note=f"XOFF around the {FILL}th byte (the exact byte is open: reading Q14)")
        out.append(case(
            p, "FC.XOFF-AT-974-BYTES", "XOFF when 50 bytes are left in the 1024-byte buffer; XON after a read", REF,
            "The driver sends XOFF when only 50 characters remain before its 1024-byte receive buffer overflows, and "
            "XON once a read has made room.", "flow-control", "receiver",
            steps + [xoff_step, expect(xon, within=SLOW, note="XON once the slow application has read a frame")]
            + echo_steps(p, frames, first="CDT + 10*CHAR", late_last=p.end_criterion == "cdt"),
            delivered=frames, setup=SLOW_SETUP, readings=["Q14", "Q15", "d_hold"]))
        if p.end_criterion != "fixed_length":
            over = frame_of(p, 200, 50)
            steps = steps[:-1] + [send(over, at=gap, note="a frame of 200 bytes: the tester ignores the XOFF")]
            kept = frames[:-1]
        elif (k + 1) * size > BUFFER_BYTES:
            # every frame has the fixed length: one frame more than the XOFF asked for
            steps = steps + [send(frame_of(p, 0, 50), note="one frame more: the tester ignores the XOFF")]
            kept = frames
        else:
            kept = None
        if kept is not None:
            out.append(case(
                p, "FC.OVERFLOW", "A partner that ignores XOFF overflows the buffer: its last frame is discarded", REF,
                "If the partner keeps sending after XOFF the buffer overflows, an error is generated and the data of the "
                "last frame is discarded; the frames before it stay intact (the code is open: reading Q17).",
                "flow-control", "receiver",
                steps + [xoff_step, expect(xon, within=SLOW, note="XON once there is room again")]
                + echo_steps(p, kept),
                delivered=kept, status=[RX_ERRORS], soft=["16#080A"], setup=SLOW_SETUP,
                readings=["Q15", "Q17"]))
    return out


def _modem(p):
    ref = "§2.2.4 'data flow control / handshaking'; Table 2-9"
    if p.flow_control == "rts_cts":
        return [
            modem_case(p, "RTS.ON-AT-START-UP", "RTS/CTS: RTS goes ON once the driver is parameterised", ref,
                       "With RTS/CTS flow control the driver sets RTS ON once it has been parameterised."),
            modem_case(p, "RTS.OFF-WHEN-FULL", "RTS/CTS: RTS OFF when the buffer is full, ON after a read", ref,
                       "The driver sets RTS OFF at the frame count or 50 bytes before overflow, and ON after a read.",
                       readings=["Q14"]),
            modem_case(p, "RTS.CTS-OFF-STOPS", "RTS/CTS: CTS OFF stops sending; no CTS ON within the wait time: 16#0708",
                       ref + "; Table 8-1 (07)08H",
                       "When CTS goes OFF the driver interrupts its transmission and aborts the job with 16#0708 if CTS "
                       "does not come back within the wait time."),
        ]
    ref = "§2.2.4 'automatic use of the V.24 signals'; Fig. 2-24"
    return [
        modem_case(p, "V24.START-UP", "Automatic V.24: DTR ON and RTS OFF at start-up", ref,
                   "Once parameterised for the automatic use of the V.24 signals the driver sets DTR ON and RTS OFF."),
        modem_case(p, "V24.SEND-TIMING", "Automatic V.24: RTS ON, the data output waiting time, data, RTS OFF", ref,
                   "On a send request RTS goes ON, the data follows when the data output waiting time is over and CTS "
                   "is ON, and RTS goes OFF the time to RTS OFF after the last character.", readings=["Q19"]),
        modem_case(p, "V24.CTS-ABSENT", "Automatic V.24: no CTS within the data output waiting time aborts the job",
                   ref + "; Table 8-1 (08)18H",
                   "If CTS is not ON when the data output waiting time is over the send job is aborted with an error.",
                   readings=["Q19"]),
        modem_case(p, "V24.DSR-OFF", "Automatic V.24: nothing is received while DSR is OFF", ref,
                   "Data is received only while DSR is ON; DSR going OFF aborts a reception with an error.",
                   readings=["Q19"]),
    ]
