#!/usr/bin/env python3
"""Independent CP 341 ASCII-driver station, written from a digest of the manual
(CP 341 Point-to-Point Communication, edition 03 (04/2000), §2.2.4, Tables 2-7 to
2-10, Table 8-1) without looking at ptpcert's own model or cases.

The serial line is stdin (received bytes) and stdout (transmitted bytes), both
binary, or a serial device given with --device.  Output is paced at one
character time per byte.  STATUS events go to stderr, one line each:
"STATUS 16#XXXX".  The application on top is an echo (see README.md).

Open points of the manual and the reading taken here (numbered as in README.md):

  O1  CDT range: 2..65535 ms in 1 ms steps (Table A-7), never below the baud
      rate's minimum of Table 2-7 (300 -> 130 ms ... 9600 -> 4 ms, 19200 and
      faster -> 2 ms).  A lower value is refused as a parameter error.
  O2  CDT reference point: a receive timer runs from the moment a character
      has been read (end of its stop bit).  Bytes read together count as
      having arrived at that moment.  Input and timers are taken in time
      order; input at the same instant as a deadline goes first.
  O3  Send pause (CDT criterion: "more than CDT"; fixed length: "CDT"):
      the first byte of the next frame starts no earlier than CDT + 1 ms after
      the end of the stop bit of the previous frame's last byte (the 1 ms
      keeps "more than CDT" true despite scheduling jitter).  Flow-control
      characters sent in between do not restart it.  In the CDT criterion
      the pause is always kept (the switch exists only for fixed length).
      No pause with the end-character criterion.
  O4  Send variants: "up_to_end" sends up to and including the first
      complete end sequence (both characters when two are set); if there is
      none within LEN, all LEN bytes are sent.  "len_with_end" sends LEN bytes
      whatever the last one is.  "len_append_end" sends LEN bytes plus the end
      character(s), even when that makes more than 1024 bytes on the line.
  O5  Number of end characters: one or two, given as a list; 00 is a valid
      second end character.  With two, only end character 1 immediately
      followed by end character 2 ends a frame (a lone one is data;
      "41 0D 0D 0A" ends at the final pair).
  O6  Errors for malformed frames: a fragment cut off by CDT expiry (end
      characters, fixed length) -> 16#0806.  A frame spoiled by a character
      error -> 16#080C, reported when the spoiled frame ends (end sequence,
      N-th character or CDT expiry), even if it ends by CDT expiry.  One STATUS
      per spoiled frame: the first cause.
  O7  Characters after an end character, or beyond N, simply start the next
      frame: discarded with 16#0806 if the CDT expires, merged otherwise.
  O8  Frames over 1024 bytes (CDT criterion, end characters): the frame is
      spoiled at the 1025th byte and discarded at its end with 16#0816.
  O9  Receive buffer: 1024 bytes including the frame being received.  With
      prevent overwrite = yes: a frame that would make the buffer hold more
      than 1024 bytes is spoiled at that byte (16#080A at its end); a complete
      frame that finds all frame places taken is discarded with 16#080A.  With
      prevent overwrite = no (one frame place): a new frame replaces the
      unread one, without a STATUS; stored bytes then do not count.
  O10 XOFF: sent once when the buffered frames reach the configured number
      (at N, not N - 1) or when stored plus in-progress bytes reach
      1024 - 50 = 974.  XON: sent once both conditions have cleared again
      (after the application read a frame, or after a fragment was
      discarded), and only if an XOFF had been sent.  Neither is repeated.
  O11 Received XON/XOFF codes (flow control xon_xoff, no character error)
      are consumed as control: not stored, no effect on frame delimiting or
      the CDT, honoured at any time (also while idle).
  O12 On XOFF the station stops after the character being sent.  The XON
      wait time runs from the XOFF (or from the moment a job would start,
      if the XOFF came earlier); on expiry the job is aborted with 16#0708.
      The stop stays in force until XON (a later job waits again).
      Own flow-control characters are sent even while stopped, ahead of data.
  O13 BREAK (16#080D, reported at once) discards the frame being received
      without a further STATUS.  It does not affect sending.
  O14 7 data bits: received characters and sent data are masked to 7 bits;
      end characters and XON/XOFF codes above 7F are refused.
  O15 Echo application: a frame is read only when it is the oldest, its
      echo delay has passed since it was stored, and no own send job is
      running (a job runs until its last stop bit or its abort).
  O16 Parameter errors: "STATUS 16#020F" and a one-line message on stderr,
      exit code 2, nothing on the line.

Broken variants (--break NAME) each break one rule; see BREAKS and README.md.
"""

import argparse
import os
import queue
import sys
import threading
import time
from collections import deque

BUFFER_BYTES = 1024        # receive buffer, §2.2.4
MAX_FRAME = 1024           # largest frame, Table A-7
XOFF_MARGIN = 50           # "50 characters before the buffer overflows", §2.2.4
PAUSE_MARGIN = 0.001       # O3: "more than CDT" with room for timing jitter
MIN_CDT_MS = {300: 130, 600: 65, 1200: 32, 2400: 16, 4800: 8, 9600: 4,
              19200: 2, 38400: 2, 57600: 2, 76800: 2}          # Table 2-7

ST_XON_TIMEOUT = 0x0708
ST_CDT = 0x0806
ST_NO_BUFFER = 0x080A
ST_CHAR_ERROR = 0x080C
ST_BREAK = 0x080D
ST_TOO_LONG = 0x0816
ST_PARAM = 0x020F

BREAKS = {
    "no-startup-xon":
        "flow control: no XON is sent at start-up (§2.2.4 flow control)",
    "xoff-late":
        "flow control: XOFF only once buffer_frames + 1 frames are buffered (§2.2.4, Table 2-10)",
    "no-xon-after-read":
        "flow control: no XON after the application has read a frame (§2.2.4 flow control)",
    "xoff-ignored":
        "flow control: a received XOFF does not stop the transmission (§2.2.4 flow control)",
    "no-xon-wait-timeout":
        "flow control: a job held by XOFF waits for ever, no 16#0708 (§2.2.4, Table 2-9)",
    "cdt-from-first-char":
        "receive: the CDT runs from the first character of a frame, not from the last (Table 2-7)",
    "keep-fragment-on-cdt":
        "receive: a fragment cut off by CDT expiry is kept and continued, no 16#0806 (§2.2.4, Fig. 2-22)",
    "fragment-delivered":
        "receive: a fragment cut off by CDT expiry is delivered as a frame, no 16#0806 (§2.2.4)",
    "single-end-char-suffices":
        "receive: with two end characters, end character 1 alone ends the frame (§2.2.4)",
    "fixed-length-plus-one":
        "receive: a fixed-length frame ends after N + 1 characters (§2.2.4, Table 2-7)",
    "echo-drops-end-char":
        "receive: the end character(s) are not passed on with the received data (§2.2.4)",
    "parity-frame-stored":
        "receive: a frame with a parity/framing error is stored, no 16#080C (§2.2.4, Figs. 2-21..2-23)",
    "break-ignored":
        "receive: a BREAK is not reported, no 16#080D (Table 8-1)",
    "overwrite-despite-prevent":
        "buffer: a full buffer drops its oldest frame for the new one despite prevent overwrite (Table 2-10)",
    "echo-newest-first":
        "buffer: the newest buffered frame is handed over first, not the oldest (§2.2.4 receive buffer)",
    "no-send-pause":
        "send: no CDT pause between two sent frames (§2.2.4 sending)",
    "variant-c-no-append":
        "send: the variant 'LEN bytes plus end characters' does not append the end character(s) (§2.2.4)",
}


class ParamError(Exception):
    def __init__(self, name, value, rule):
        super().__init__("parameter %s = %r: %s" % (name, value, rule))


def parse_code(text):
    """A character code: '03', '0x03', '16#03' or '3' (hex)."""
    t = text.strip().lower()
    for prefix in ("0x", "16#"):
        if t.startswith(prefix):
            t = t[len(prefix):]
    return int(t, 16)


def parse_hex_bytes(text):
    """Bytes in hex: '03', '0D,0A', '0x0D 0x0A', '[0x0D, 0x0A]' or '0d0a'."""
    t = text.strip().strip("[]")
    out = bytearray()
    for part in t.replace(",", " ").replace(":", " ").split():
        low = part.lower()
        if low.startswith("0x") or low.startswith("16#") or len(part) <= 2:
            out.append(parse_code(part))
        else:
            out += bytes.fromhex(part)
    return bytes(out)


class Config:
    """The [iut]/[ascii] settings, validated against Tables 2-7 to 2-10."""

    def __init__(self, a):
        self.brk = a.brk
        self.baud = a.baud
        if self.baud not in MIN_CDT_MS:
            raise ParamError("baud_rate", a.baud, "one of %s (Table 2-8)" % sorted(MIN_CDT_MS))
        self.data_bits = a.data_bits
        self.parity = a.parity
        self.stop_bits = a.stop_bits
        bits = 1 + self.data_bits + (0 if self.parity == "none" else 1) + self.stop_bits
        self.char_time = bits / float(self.baud)
        top = 0x7F if self.data_bits == 7 else 0xFF
        self.mask = top

        if not 2 <= a.cdt_ms <= 65535:
            raise ParamError("character_delay_ms", a.cdt_ms, "2..65535 ms (Table A-7)")
        if a.cdt_ms < MIN_CDT_MS[self.baud]:
            raise ParamError("character_delay_ms", a.cdt_ms,
                             "at least %d ms at %d bit/s (Table 2-7)" % (MIN_CDT_MS[self.baud], self.baud))
        self.cdt = a.cdt_ms / 1000.0

        self.criterion = a.end_criterion
        try:
            self.end_chars = parse_hex_bytes(a.end_chars)
        except ValueError:
            raise ParamError("end_chars", a.end_chars, "one or two character codes in hex")
        if not 1 <= len(self.end_chars) <= 2:
            raise ParamError("end_chars", a.end_chars, "one or two end characters (Table A-7)")
        if any(c > top for c in self.end_chars):
            raise ParamError("end_chars", a.end_chars,
                             "00..%02X with %d data bits (Table 2-7)" % (top, self.data_bits))
        if not 1 <= a.fixed_length <= MAX_FRAME:
            raise ParamError("fixed_length", a.fixed_length, "1..1024 (Table 2-7)")
        self.fixed_length = a.fixed_length
        self.send_variant = a.send_variant
        self.send_pause = a.send_pause

        self.flow = a.flow_control
        if self.flow in ("rts_cts", "auto_v24"):
            raise ParamError("flow_control", self.flow,
                             "not available here: a pipe has no RS 232C secondary signals")
        self.xon = parse_code(a.xon)
        self.xoff = parse_code(a.xoff)
        if self.flow == "xon_xoff":
            for name, v in (("xon", self.xon), ("xoff", self.xoff)):
                if not 0 <= v <= top:
                    raise ParamError(name, "%02X" % v, "00..%02X with %d data bits (Table 2-9)" % (top, self.data_bits))
            if self.xon == self.xoff:
                raise ParamError("xoff", "%02X" % self.xoff, "must differ from XON (Table 2-9)")
            if self.criterion == "end_chars" and (self.xon in self.end_chars or self.xoff in self.end_chars):
                raise ParamError("end_chars", a.end_chars, "must differ from the XON/XOFF codes (§2.2.4)")
        if not 20 <= a.xon_wait_ms <= 655350:
            raise ParamError("xon_wait_ms", a.xon_wait_ms, "20..655350 ms (Table 2-9)")
        self.xon_wait = a.xon_wait_ms / 1000.0

        if not 1 <= a.buffer_frames <= 250:
            raise ParamError("buffer_frames", a.buffer_frames, "1..250 (Table 2-10)")
        self.buffer_frames = a.buffer_frames
        self.prevent_overwrite = a.prevent_overwrite
        if not self.prevent_overwrite and self.buffer_frames != 1:
            raise ParamError("prevent_overwrite", False, "'no' only with buffer_frames = 1 (Table 2-10)")

        if a.echo_delay_ms < 0:
            raise ParamError("echo_delay_ms", a.echo_delay_ms, ">= 0")
        self.echo_delay = a.echo_delay_ms / 1000.0
        self.echo = a.send_trigger == "echo"
        self.parmrk = a.parmrk
        self.trace = a.trace
        self.send_jobs = [parse_hex_bytes(s) for s in (a.send or [])]
        if any(not 1 <= len(j) <= MAX_FRAME for j in self.send_jobs):
            raise ParamError("send", "...", "LEN 1..1024 (Table 6-2)")


class Job:
    def __init__(self, wire, not_before):
        self.wire = wire
        self.idx = 0
        self.not_before = not_before
        self.hold_deadline = None


class Stored:
    def __init__(self, ready, data):
        self.ready = ready
        self.data = data


class Station:
    def __init__(self, cfg, write, errline, clock=time.monotonic):
        self.c = cfg
        self.clock = clock
        self.brk = cfg.brk
        self.write = write            # write(bytes) -> None: puts bytes on the line
        self.errline = errline        # errline(str) -> None: one line on stderr
        # receiver
        self.rx_active = False
        self.rx_data = bytearray()
        self.rx_len = 0               # characters of this frame, bad ones included
        self.rx_cause = None
        self.rx_prev_ok = False       # previous character of the frame was valid
        self.rx_first = 0.0
        self.rx_deadline = None
        self.pm = 0                   # PARMRK decoder state
        # receive buffer
        self.buf = deque()
        self.buf_bytes = 0
        # flow control
        self.xoff_sent = False        # we have stopped the partner
        self.peer_stopped = False     # the partner has stopped us
        self.xoff_time = 0.0
        # sender
        self.ctl = deque()            # own XON/XOFF, sent ahead of data
        self.jobs = deque(cfg.send_jobs)
        self.job = None
        self.busy_until = float("-inf")   # end of the running job's last stop bit
        self.line_free = float("-inf")    # end of the stop bit of the last byte written
        self.frame_end = float("-inf")    # same, for the last data byte of a frame

    # ------------------------------------------------------------ output helpers
    def status(self, code):
        self.errline("STATUS 16#%04X" % code)

    def trace(self, what, data):
        if self.c.trace:
            self.errline("%s %s" % (what, bytes(data).hex(" ")))

    # ------------------------------------------------------------ start-up
    def start(self, now):
        if self.c.flow == "xon_xoff" and self.brk != "no-startup-xon":
            self.ctl.append(self.c.xon)          # once parameterised: XON
        if self.c.trace:
            self.errline("READY")

    # ------------------------------------------------------------ input
    def on_input(self, t, data):
        for b in data:
            if not self.c.parmrk:
                self.on_char(t, b, False)
            elif self.pm == 0:
                if b == 0xFF:
                    self.pm = 1
                else:
                    self.on_char(t, b, False)
            elif self.pm == 1:
                if b == 0xFF:
                    self.pm = 0
                    self.on_char(t, 0xFF, False)
                elif b == 0x00:
                    self.pm = 2
                else:                              # not a mark: take both as data
                    self.pm = 0
                    self.on_char(t, 0xFF, False)
                    self.on_char(t, b, False)
            else:
                self.pm = 0
                if b == 0x00:
                    self.on_break(t)
                else:
                    self.on_char(t, b, True)

    def on_break(self, t):
        if self.brk != "break-ignored":
            self.status(ST_BREAK)
        if self.rx_active:                         # O13: the fragment is lost
            self.rx_active = False
            self.rx_deadline = None
            self.update_flow(t)

    def on_char(self, t, c, bad):
        c &= self.c.mask
        if self.c.flow == "xon_xoff" and not bad:  # O11
            if c == self.c.xoff:
                if not self.peer_stopped:
                    self.peer_stopped = True
                    self.xoff_time = t
                return
            if c == self.c.xon:
                self.peer_stopped = False
                if self.job is not None:
                    self.job.hold_deadline = None
                return
        if not self.rx_active:
            self.rx_active = True
            self.rx_data = bytearray()
            self.rx_len = 0
            self.rx_cause = None
            self.rx_prev_ok = False
            self.rx_first = t
        prev_ok = self.rx_prev_ok
        prev = self.rx_data[-1] if self.rx_data else None
        self.rx_len += 1
        self.rx_data.append(c)
        self.rx_prev_ok = not bad
        if bad:
            self.spoil(ST_CHAR_ERROR)
        if self.rx_len > MAX_FRAME:
            self.spoil(ST_TOO_LONG)                # O8
        elif self.c.prevent_overwrite and self.buf_bytes + self.rx_len > BUFFER_BYTES:
            self.spoil(ST_NO_BUFFER)               # O9
        if self.brk == "cdt-from-first-char":
            self.rx_deadline = self.rx_first + self.c.cdt
        else:
            self.rx_deadline = t + self.c.cdt
        crit = self.c.criterion
        if crit == "end_chars" and not bad:
            ec = self.c.end_chars
            if len(ec) == 1 or self.brk == "single-end-char-suffices":
                done = c == ec[0]
            else:
                done = c == ec[1] and prev_ok and prev == ec[0] and self.rx_len >= 2
            if done:
                self.end_frame(t)
                return
        elif crit == "fixed_length":
            n = self.c.fixed_length + (1 if self.brk == "fixed-length-plus-one" else 0)
            if self.rx_len >= n:
                self.end_frame(t)
                return
        self.update_flow(t)

    def spoil(self, code):
        if self.rx_cause is None:
            self.rx_cause = code

    # ------------------------------------------------------------ frame end
    def end_frame(self, t):
        self.rx_active = False
        self.rx_deadline = None
        cause = self.rx_cause
        if cause == ST_CHAR_ERROR and self.brk == "parity-frame-stored":
            cause = None
        if cause is not None:
            self.status(cause)
        else:
            self.store(t, bytes(self.rx_data))
        self.update_flow(t)

    def cdt_expired(self, t):
        if self.c.criterion == "cdt":
            self.end_frame(t)                      # the CDT ends the frame
            return
        if self.rx_cause is None:
            if self.brk == "keep-fragment-on-cdt":
                self.rx_deadline = None            # the fragment waits for more
                return
            if self.brk == "fragment-delivered":
                self.end_frame(t)
                return
        self.rx_active = False                     # watchdog: discard (O6)
        self.rx_deadline = None
        self.status(self.rx_cause if self.rx_cause is not None else ST_CDT)
        self.update_flow(t)

    def store(self, t, data):
        if self.c.criterion == "end_chars" and self.brk == "echo-drops-end-char":
            n = len(self.c.end_chars)
            if data[-n:] == self.c.end_chars:
                data = data[:-n]
        if len(self.buf) >= self.c.buffer_frames:
            if self.c.prevent_overwrite and self.brk != "overwrite-despite-prevent":
                self.status(ST_NO_BUFFER)          # O9: the new frame is lost
                return
            old = self.buf.popleft()               # overwrite the unread frame
            self.buf_bytes -= len(old.data)
        self.buf.append(Stored(t + self.c.echo_delay, data))
        self.buf_bytes += len(data)
        self.trace("STORED", data)

    # ------------------------------------------------------------ flow control (receive side)
    def update_flow(self, t):
        if self.c.flow != "xon_xoff":
            return
        fill = self.buf_bytes if self.c.prevent_overwrite else 0
        if self.rx_active:
            fill += self.rx_len
        frames = self.c.buffer_frames + (1 if self.brk == "xoff-late" else 0)
        stop = len(self.buf) >= frames or fill >= BUFFER_BYTES - XOFF_MARGIN
        if stop and not self.xoff_sent:
            self.xoff_sent = True
            self.ctl.append(self.c.xoff)
        elif not stop and self.xoff_sent and self.brk != "no-xon-after-read":
            self.xoff_sent = False
            self.ctl.append(self.c.xon)

    # ------------------------------------------------------------ application
    def read_frame(self, t):
        if not self.buf or self.buf[0].ready > t:
            return None
        if self.brk == "echo-newest-first":
            i = 0
            while i + 1 < len(self.buf) and self.buf[i + 1].ready <= t:
                i += 1
            fr = self.buf[i]
            del self.buf[i]
        else:
            fr = self.buf.popleft()
        self.buf_bytes -= len(fr.data)
        self.trace("READ", fr.data)
        self.update_flow(t)
        return fr.data

    def app(self, t):
        idle = self.job is None and t >= self.busy_until
        if self.c.echo:
            if not idle:
                return
            if self.jobs:
                self.start_job(self.jobs.popleft(), t)
                return
            data = self.read_frame(t)
            if data is not None:
                self.start_job(data, t)
        else:
            if idle and self.jobs:
                self.start_job(self.jobs.popleft(), t)
            while self.read_frame(t) is not None:
                pass

    # ------------------------------------------------------------ sender
    def wire_form(self, data):
        """What a send job with these LEN bytes puts on the line (§2.2.4, O4)."""
        if self.c.criterion == "end_chars":
            ec = self.c.end_chars
            v = self.c.send_variant
            if v == "up_to_end":
                i = data.find(ec)
                if i >= 0:
                    data = data[:i + len(ec)]
            elif v == "len_append_end" and self.brk != "variant-c-no-append":
                data = data + ec
        return bytes(b & self.c.mask for b in data)

    def start_job(self, data, t):
        wire = self.wire_form(data)
        nb = t
        pause = self.c.criterion == "cdt" or (self.c.criterion == "fixed_length" and self.c.send_pause)
        if pause and self.brk != "no-send-pause":
            nb = max(nb, self.frame_end + self.c.cdt + PAUSE_MARGIN)      # O3
        self.job = Job(wire, nb)
        self.trace("SEND", wire)

    def held(self):
        return self.peer_stopped and self.brk != "xoff-ignored"

    def arm_hold(self):
        j = self.job
        if j is not None and self.held() and j.hold_deadline is None and self.brk != "no-xon-wait-timeout":
            j.hold_deadline = max(self.xoff_time, j.not_before) + self.c.xon_wait

    def abort_job(self, t):
        self.status(ST_XON_TIMEOUT)
        self.job = None
        self.busy_until = t

    def pump(self, now):
        """Write every byte whose turn has come at real time `now`."""
        ct = self.c.char_time
        while True:
            if now < self.line_free:
                return
            j = self.job
            if self.ctl:
                b = self.ctl.popleft()
                data_byte = False
                earliest = self.line_free
            elif j is not None and now >= j.not_before and not self.held():
                b = j.wire[j.idx]
                data_byte = True
                earliest = max(self.line_free, j.not_before)
            else:
                return
            # a byte written less than a character time late counts as started
            # on time (keeps the average rate exact)
            start = earliest if now - earliest < ct else now
            end = start + ct
            self.write(bytes([b]))
            self.line_free = end
            if data_byte:
                j.idx += 1
                # the pause is measured from the real write, stamped after it
                # (a delay there can only lengthen the pause): the byte cannot
                # have left the line before then + one character time
                self.frame_end = max(end, self.clock() + ct)
                if j.idx >= len(j.wire):
                    self.job = None
                    self.busy_until = end

    # ------------------------------------------------------------ time
    def advance(self, t, strict):
        """Fire every timer due before t (strict) or at/before t."""
        def due(d):
            return d is not None and (d < t if strict else d <= t)
        while True:
            self.arm_hold()
            cands = []
            if self.rx_active and due(self.rx_deadline):
                cands.append((self.rx_deadline, 0))
            if self.job is not None and self.held() and due(self.job.hold_deadline):
                cands.append((self.job.hold_deadline, 1))
            if not cands:
                break
            d, which = min(cands)
            if which == 0:
                self.cdt_expired(d)
            else:
                self.abort_job(d)
            self.app(d)
        self.app(t)

    def next_wakeup(self):
        self.arm_hold()
        w = []
        if self.rx_active and self.rx_deadline is not None:
            w.append(self.rx_deadline)
        j = self.job
        if self.ctl:
            w.append(self.line_free)
        elif j is not None:
            if self.held():
                if j.hold_deadline is not None:
                    w.append(j.hold_deadline)
            else:
                w.append(max(self.line_free, j.not_before))
        if j is None:
            if self.jobs:
                w.append(self.busy_until)
            elif self.buf:
                w.append(max(self.busy_until, self.buf[0].ready) if self.c.echo else self.buf[0].ready)
        return min(w) if w else None


def run(st, in_fd, out_fd):
    q = queue.Queue()

    def reader():
        while True:
            try:
                d = os.read(in_fd, 4096)
            except OSError:
                d = b""
            q.put((time.monotonic(), d))
            if not d:
                return

    threading.Thread(target=reader, daemon=True).start()
    st.start(time.monotonic())
    while True:
        st.advance(time.monotonic(), strict=False)
        st.pump(time.monotonic())
        wake = st.next_wakeup()
        try:
            if wake is None:
                item = q.get()
            else:
                timeout = wake - time.monotonic()
                item = q.get(timeout=timeout) if timeout > 0 else q.get_nowait()
        except queue.Empty:
            continue
        items = [item]
        while True:
            try:
                items.append(q.get_nowait())
            except queue.Empty:
                break
        for t, d in items:
            if not d:
                return 0
            st.advance(t, strict=True)             # O2: timers before t first
            st.on_input(t, d)


def build_parser():
    p = argparse.ArgumentParser(
        description="CP 341 ASCII-driver station on stdin/stdout (echo application)")
    a = p.add_argument
    a("--cdt-ms", type=int, default=4, help="character delay time (Table 2-7), default 4")
    a("--baud", type=int, default=9600)
    a("--data-bits", type=int, choices=[7, 8], default=8)
    a("--parity", choices=["none", "odd", "even"], default="even")
    a("--stop-bits", type=int, choices=[1, 2], default=1)
    a("--end-criterion", choices=["cdt", "end_chars", "fixed_length"], default="cdt")
    a("--end-chars", default="03", help="one or two codes in hex, e.g. 03 or 0D,0A")
    a("--fixed-length", type=int, default=240)
    a("--send-variant", choices=["up_to_end", "len_with_end", "len_append_end"], default="up_to_end")
    a("--send-pause", action=argparse.BooleanOptionalAction, default=True,
      help="CDT pause between sent frames with the fixed-length criterion (default on)")
    a("--flow-control", choices=["none", "xon_xoff", "rts_cts", "auto_v24"], default="none")
    a("--xon", default="11")
    a("--xoff", default="13")
    a("--xon-wait-ms", type=int, default=20000)
    a("--buffer-frames", type=int, default=250)
    a("--prevent-overwrite", action=argparse.BooleanOptionalAction, default=True)
    a("--echo-delay-ms", type=int, default=0,
      help="the application reads a stored frame only this long after it was stored")
    a("--send-trigger", choices=["echo", "none"], default="echo",
      help="echo: read frames are sent back; none: read frames are dropped")
    a("--send", action="append", metavar="HEX",
      help="a send job issued at start-up (repeatable; self-test aid)")
    a("--parmrk", action="store_true", help="read PARMRK marks (FF 00 00, FF 00 xx, FF FF)")
    a("--device", default=None, help="use this serial device (e.g. a pty) instead of stdin/stdout")
    a("--trace", action="store_true", help="also print READY/STORED/READ/SEND lines on stderr")
    a("--break", dest="brk", default=None, metavar="NAME")
    a("--list-breaks", action="store_true")
    return p


def main(argv=None):
    p = build_parser()
    a = p.parse_args(argv)
    if a.list_breaks:
        for k, v in BREAKS.items():
            print("%-26s %s" % (k, v))
        return 0
    if a.brk is not None and a.brk not in BREAKS:
        p.error("unknown --break variant %r (see --list-breaks)" % a.brk)

    def errline(s):
        try:
            sys.stderr.write(s + "\n")
            sys.stderr.flush()
        except (OSError, ValueError):
            pass

    try:
        cfg = Config(a)
    except (ParamError, ValueError) as e:
        errline("STATUS 16#%04X" % ST_PARAM)
        errline("iut_ascii: %s" % e)
        return 2

    if a.device:
        import tty
        fd = os.open(a.device, os.O_RDWR | os.O_NOCTTY)
        try:
            tty.setraw(fd)
        except Exception:
            pass
        in_fd = out_fd = fd
    else:
        in_fd, out_fd = 0, 1

    def write(b):
        try:
            os.write(out_fd, b)
        except OSError:
            os._exit(0)

    sys.setswitchinterval(0.0005)
    st = Station(cfg, write, errline)
    try:
        return run(st, in_fd, out_fd)
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
