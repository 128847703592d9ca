#!/usr/bin/env python3
"""Independent RK 512 station (SIMATIC CP 341 "computer link") over 3964R / 3964.

Written from a description of the manual's rules only (RK 512, 3964(R), STATUS codes);
it shares no code with ptpcert.  Python 3.11, standard library only.

The serial line is stdin (received bytes) / stdout (transmitted bytes), binary,
paced at one character time per byte.  STATUS events go to stderr as
"STATUS 16#XXXX"; the results of the own requests as "RESULT <label> OK",
"RESULT <label> STATUS 16#XXXX" and "FETCHED <label> <hex>".

Roles:
  passive  always: answers the partner's SEND and FETCH from a memory model of
           the local CPU ("pattern" memory, see README.md);
  active   the requests of a script (--requests FILE), one after the other.

References in comments: "Rn.m" = rule of the author's description, "AMB-n" = its
open point, "An" = 3964(R) open point as docs/readings.md numbers it, "§" = section of the manual as quoted there.

Readings of the open points taken here -- also in README.md:
  AMB-01  counters travel as 5Ah ('Z'); a received 43h ('C') is an invalid
          type letter: 16#0604, REATEL 10h.
  AMB-02  T_RES is a parameter (--tres-ms, default 10000 ms = CP 341 prose);
          the same value on both sides.
  AMB-03  SEND to DX is 'O' 'D'; 'O' with any other byte 4 (and 'A' with
          anything but 'D') is 16#0604, REATEL 10h.
  AMB-10  a frame that is too short (16#0610) is not answered at all.
  AMB-13  byte 2 of commands and responses is not checked.
  AMB-14  M/E/A addresses and T/Z numbers are 16-bit big endian in bytes 5/6.
  AMB-17  active T_RES starts at the partner's DLE that acknowledges the
          command block and stops when the response block has been received
          completely; a block that is being received when T_RES runs out is
          awaited (the expiry is acted on only once the link is no longer in
          the middle of a reception).  The same for the passive T_RES.
  AMB-18  passive side, waiting for a continuation: T_RES expiry aborts the
          partner request silently (no STATUS, no frame); a first command
          frame arriving instead aborts the open request and is answered with
          REATEL 36h (16#060E) without being executed.
  AMB-20  DX is served to a partner FETCH ('E' 'X') when --dx-range is not
          empty; T/Z FETCHes are not limited to 32 bytes.
  AMB-21  a partner SEND 'O' writes to DX <byte 5> at DW <byte 6>.
  AMB-22  CPU number nibble: as given (0..4); "CPU=none" gives 0h with a
          flag and Fh without; received nibbles 0..4 and Fh are accepted.
  AMB-23  coordination flags are allowed for every data type; byte 9 = FFh
          means "no flag" whatever the bit nibble; byte 9 != FFh with bit
          nibble 8..Fh is 16#0609, REATEL 0Ch; so is a flag byte outside the
          flag area.  Coordination flags are kept apart from the M data bytes
          (the pattern memory's M area stays as the partner wrote it).
  AMB-25  a request must fit inside the area (start + length <= size);
          otherwise 16#0608, REATEL 34h.
  AMB-33  an error response that carries data: 16#0A03 (FETCH) / 16#0A04 (SEND).
  Further choices:
  - command with byte 1 not 00h/FFh: 16#0601, REATEL 10h, response byte 1 = 00h;
    an open partner request is left alone.
  - first-frame checks in this order: byte 3 (0602), byte 4 (0604), FETCH with
    data (060C), DB/DX number (0606), start address (0607), length (0608),
    flag (0609), CPU (060A), SEND data count (060B), flag locked (060F);
    a CPU in STOP (--cpu-stop) answers every command with 2Ah (060D) first.
  - any command that arrives while a response is still owed to the partner
    (not yet acknowledged by its DLE) is a synchronisation error: 16#060E,
    REATEL 36h, and the open partner request is aborted (R8.6).
  - coordination flag (AMB-07): checked before the first frame is executed;
    set to 1 when the whole request is done; the application resets it after
    the time given with --cf-set B.b@ms for that flag, at once for any other.
  - local FB checks of the own requests (nothing is sent): LEN 0 -> 16#1E41,
    LEN > 1024 -> 16#0517, DB/DX 0 or start address too high -> 16#0514,
    DB/DX number > 255, CF byte > 255 or SEND to a non-DB/DX area -> 16#0301,
    CF bit > 7 -> 16#0515, CPU > 4 -> 16#0516.  CF byte 255 = no flag.
  - a 3964(R) failure of a command block ends the request with 16#051A, of a
    response block with 16#0612 (after the link's own 07xx/080D event).
  - a response frame that matches no waiting request is 16#0A01; if the own
    request has a frame queued but not yet acknowledged, it is aborted.
  3964(R) readings: as in ../iut3964.py (A1 550 ms, A2 figure path, A4 X reset
  per attempt, A6 one NAK, A7 retriggered quiet waits, A10, A11 deferred NAK,
  A12 T_ADT after the last byte, A13, A15 BREAK = idle + 16#080D, A17, A18,
  A19, A21, A23); the receive buffer is always free.
"""

import argparse
import os
import select
import sys
import time
from collections import deque

STX, ETX, DLE, NAK = 0x02, 0x03, 0x10, 0x15
T_BLOCK = 4.0            # 3964(R) block wait time, fixed (§2.2.2)
MAX_BLOCK = 1024         # user bytes per 3964(R) block
CHUNK = 128              # RK 512 data bytes per frame (R4.5)
MAX_REQ = 1024           # bytes per RK 512 request (R3.12)

# Table 8-3: REATEL -> event at the active side
REATEL_STATUS = {0x0A: 0x0905, 0x0C: 0x0902, 0x10: 0x090B, 0x12: 0x0904,
                 0x14: 0x0903, 0x16: 0x090A, 0x2A: 0x090D, 0x32: 0x0909,
                 0x34: 0x090C, 0x36: 0x0908}
# Table 8-3: passive-side event -> REATEL
EVENT_REATEL = {0x0601: 0x10, 0x0602: 0x16, 0x0603: 0x16, 0x0604: 0x10,
                0x0605: 0x10, 0x0606: 0x14, 0x0607: 0x0C, 0x0608: 0x34,
                0x0609: 0x0C, 0x060A: 0x0C, 0x060B: 0x34, 0x060C: 0x34,
                0x060D: 0x2A, 0x060E: 0x36, 0x060F: 0x32, 0x0611: 0x34}

CMD_SEND_DB, CMD_SEND_DX, CMD_FETCH = 0x41, 0x4F, 0x45          # 'A' 'O' 'E'
TYPE_OF_LETTER = {0x44: "D", 0x58: "X", 0x4D: "M", 0x45: "E", 0x41: "A",
                  0x5A: "Z", 0x54: "T"}
LETTER_OF_TYPE = {v: k for k, v in TYPE_OF_LETTER.items()}
WORD_TYPES = ("D", "X", "T", "Z")          # length field in words (R3.9)

BREAKS = {
    "reatel-db-0c":
        "passive: a non-existent DB/DX (16#0606) is answered with REATEL 0Ch instead of 14h (Table 8-3)",
    "cont-byte3-changed":
        "active: continuation command header byte 3 differs from the first frame's (R4.2, R4.4)",
    "no-tres-active":
        "active: no T_RES; a withheld response is awaited forever, no 16#0A05 (R7.1, R7.6)",
    "tres-too-short":
        "active: T_RES is a fifth of the configured value (R7.4: never below 5 s)",
    "length-in-bytes":
        "active: header length in bytes where words are due (DB, DX, T, Z) (R3.9)",
    "odd-send-no-pad":
        "active: SEND with odd LEN to DB/DX carries no 00h pad byte (R3.13)",
    "counter-letter-c":
        "active: counter FETCH carries 43h ('C') in byte 4 instead of 5Ah (R3.3)",
    "unknown-reatel-0905":
        "active: an unknown REATEL is reported as 16#0905 instead of 16#090E (§11.5)",
    "response-dle-not-doubled":
        "passive: data bytes 10h inside response frames are not doubled (R1.14)",
    "fetch-one-byte-too-many":
        "passive: the last response of a FETCH carries one data byte too many (R5.4)",
    "cont-response-byte1-00":
        "passive: continuation commands are answered with byte 1 = 00h instead of FFh (R5.6)",
    "no-tres-passive":
        "passive: no T_RES while waiting for a continuation; a late continuation is executed (R7.7)",
    "data-count-unchecked":
        "passive: a SEND frame with more/fewer data than announced is accepted, no 34h (R5.4/060B)",
    "flag-ignored":
        "passive: a set coordination flag does not lock the area, no REATEL 32h (R10.19)",
}


def out_status(code):
    sys.stderr.write("STATUS 16#%04X\n" % code)
    sys.stderr.flush()


def out_line(text):
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def stuff(payload, double=True):
    body = bytearray()
    for b in payload:
        body.append(b)
        if b == DLE and double:
            body.append(DLE)
    return body


# ============================================================== 3964(R) link
class LinkJob:
    """One block to send.  on_done(now) / on_fail(now, code) are called once."""

    def __init__(self, payload, on_done, on_fail, double_dle=True):
        self.payload = bytes(payload)
        self.on_done = on_done
        self.on_fail = on_fail
        self.double_dle = double_dle
        self.W = 1
        self.X = 1
        self.cancelled = False


# link states (3964(R) state tables)
IDLE = "IDLE"
JUNK = "R_IDLE_JUNK"
R_DATA = "R_DATA"
R_DLE = "R_DLE"
R_BCC = "R_BCC"
R_REPEAT = "R_REPEAT"
S_SETUP = "S_WAIT_SETUP_ACK"
S_DATA = "S_SEND_DATA"
S_QUIET = "S_ABORT_QUIET"
S_RELEASE = "S_WAIT_RELEASE_ACK"
RX_STATES = (R_DATA, R_DLE, R_BCC)


class Link:
    def __init__(self, cfg, tx, deliver):
        self.bcc_on = cfg.link == "3964R"
        self.high = cfg.priority == "high"
        self.cdt = cfg.cdt_ms / 1000.0
        adt = cfg.adt_ms if cfg.adt_ms is not None else (2000 if self.bcc_on else 550)   # A1
        self.adt = adt / 1000.0
        self.n_setup = cfg.setup_attempts
        self.n_tx = cfg.transmission_attempts
        self.tx = tx                  # tx(bytes, cb(t_end) or None)
        self.clear_tx = None          # set by the station
        self.deliver = deliver        # deliver(payload, now)
        self.state = IDLE
        self.gen = 0
        self.deadline = None
        self.queue = deque()
        self.job = None
        self.rbuf = bytearray()
        self.rbcc = 0
        self.cause = None
        self.Wr = 1
        self.first_nak_done = False
        self.rlen = 0
        self.etx_sent = False

    @property
    def receiving(self):
        return self.state in RX_STATES

    def goto(self, st):
        self.state = st
        self.gen += 1
        self.deadline = None

    def arm_after(self, data, delay):
        """Send data; arm the state timer `delay` after the last byte's stop bit."""
        gen = self.gen

        def cb(t_end):
            if self.gen == gen and self.deadline is None:
                self.deadline = t_end + delay
        self.tx(bytes(data), cb)

    # ---------------------------------------------------------------- jobs
    def submit(self, job):
        self.queue.append(job)

    def cancel(self, job):
        """Forget a job that has not started; a block on the line is finished."""
        job.cancelled = True
        try:
            self.queue.remove(job)
        except ValueError:
            pass

    def maybe_start(self, now):
        if self.state != IDLE:
            return
        if self.job is not None and self.job.cancelled:
            self.job = None                                 # given up while deferred
        if self.job is not None:
            # deferred by an initialization conflict (A21): X not reset
            self.job.X += 1
            self.setup_check(now)
            return
        while self.queue:
            job = self.queue.popleft()
            if job.cancelled:
                continue
            self.job = job
            self.send_stx()
            return

    def finish_job(self, now, code=None):
        job, self.job = self.job, None
        if job is None:
            return
        if code is None:
            job.on_done(now)
        else:
            job.on_fail(now, code)

    # ---------------------------------------------------------------- input
    def on_break(self, now):
        # A15: immediate return to idle, no NAK, no retry, output dropped
        self.clear_tx()
        out_status(0x080D)
        self.goto(IDLE)
        self.finish_job(now, 0x080D)

    def rx(self, c, err, now):
        st = self.state
        if st in (IDLE, R_REPEAT):
            self.rx_idle(c, err, now, st == R_REPEAT)
        elif st == JUNK:
            self.deadline = now + self.cdt                  # A7: retrigger
        elif st == R_DATA:
            self.rbcc ^= c
            if err:
                self.note(0x080C)                           # deferred NAK
            elif c == DLE:
                self.state = R_DLE
            else:
                self.store(c)
            self.deadline = now + self.cdt
        elif st == R_DLE:
            self.rbcc ^= c
            if err:
                self.note(0x080C)
                self.state = R_DATA
            elif c == DLE:
                self.store(DLE)                             # dual DLE
                self.state = R_DATA
            elif c == ETX:
                if self.bcc_on:
                    self.state = R_BCC
                else:
                    self.evaluate(now)
                    return
            else:
                self.note(0x0805)                           # A11
                self.state = R_DATA
            self.deadline = now + self.cdt
        elif st == R_BCC:
            if err:
                self.note(0x080C)
            elif c != self.rbcc:
                self.note(0x0808)
            self.evaluate(now)
        elif st == S_SETUP:
            if err:
                self.setup_fail(0x080C, now)
            elif c == DLE:
                self.send_block()
            elif c == STX:
                if not self.high:
                    # low priority: defer the job, receive the partner's block
                    self.Wr = 1
                    self.first_nak_done = False
                    self.start_reception()
                # high priority: ignore, T_ADT keeps running (A23)
            else:
                self.setup_fail(0x0702, now)
        elif st == S_DATA:
            self.clear_tx()
            if not err and c == NAK:
                out_status(0x0706 if self.etx_sent else 0x0704)
                self.tx_fail(now, False)
            elif not err and c == DLE and self.etx_sent:
                out_status(0x0706)                          # DLE too early (A10)
                self.tx_fail(now, False)
            else:
                out_status(0x0704)
                self.goto(S_QUIET)
                self.deadline = now + self.cdt
        elif st == S_QUIET:
            self.deadline = now + self.cdt                  # A7
        elif st == S_RELEASE:
            if not err and c == DLE:
                self.goto(IDLE)
                self.finish_job(now)
            else:
                out_status(0x080C if err else 0x0706)
                self.tx_fail(now, False)

    def rx_idle(self, c, err, now, repeat):
        if err:
            out_status(0x080C)                              # at once (A13)
            self.goto(JUNK)
            self.deadline = now + self.cdt
        elif c == STX:
            if repeat:
                self.Wr += 1
            else:
                self.Wr = 1
                self.first_nak_done = False
            self.start_reception()
        elif c == NAK:
            if repeat:                                      # A19
                out_status(0x0815)
                self.goto(IDLE)
        else:
            self.goto(JUNK)
            self.deadline = now + self.cdt

    # ---------------------------------------------------------------- receiver
    def start_reception(self):
        self.rbuf = bytearray()
        self.rbcc = 0
        self.cause = None
        self.rlen = 0
        self.goto(R_DATA)
        self.arm_after([DLE], self.cdt)

    def note(self, code):
        if self.cause is None:
            self.cause = code

    def store(self, c):
        self.rlen += 1
        if self.rlen > MAX_BLOCK:
            self.note(0x0816)
            return
        self.rbuf.append(c)

    def evaluate(self, now):
        if self.cause is None and not self.rbuf:
            self.note(0x0805)                               # A17: empty block
        if self.cause is not None:
            self.rx_nak()
            return
        self.goto(IDLE)
        self.tx(bytes([DLE]), None)
        self.deliver(bytes(self.rbuf), now)

    def rx_nak(self):
        out_status(self.cause)
        if not self.first_nak_done:
            self.first_nak_done = True
            out_status(0x0801)
        if self.Wr >= self.n_tx:                            # A18
            self.goto(IDLE)
            self.tx(bytes([NAK]), None)
        else:
            self.goto(R_REPEAT)
            self.arm_after([NAK], T_BLOCK)

    # ---------------------------------------------------------------- sender
    def send_stx(self):
        if self.job.cancelled:
            # the request above gave the frame up (e.g. 16#0A01) before it went
            # out: no new setup attempt for it (a deferred or repeated block)
            self.job = None
            self.goto(IDLE)
            return
        self.goto(S_SETUP)
        self.arm_after([STX], self.adt)

    def setup_fail(self, code, now):
        out_status(code)
        self.job.X += 1
        self.setup_check(now)

    def setup_check(self, now):
        if self.job.X <= self.n_setup:
            self.send_stx()
        else:
            self.tx(bytes([NAK]), None)
            out_status(0x0709)
            self.goto(IDLE)
            self.finish_job(now, 0x0709)

    def send_block(self):
        self.goto(S_DATA)
        self.etx_sent = False
        body = stuff(self.job.payload, self.job.double_dle)
        body += bytes([DLE, ETX])
        bcc = 0
        for b in body:
            bcc ^= b
        gen = self.gen

        def etx_done(t_end):
            if self.gen == gen:
                self.etx_sent = True

        def last_done(t_end):
            if self.gen == gen:
                self.goto(S_RELEASE)
                self.deadline = t_end + self.adt            # A12

        if self.bcc_on:
            self.tx(bytes(body), etx_done)
            self.tx(bytes([bcc]), last_done)                # BCC never doubled
        else:
            self.tx(bytes(body), last_done)

    def tx_fail(self, now, nak_sent):
        self.job.W += 1
        if self.job.W <= self.n_tx:
            if self.job.W == 2:
                out_status(0x0701)
            self.job.X = 1                                  # A4
            self.send_stx()
        else:
            if not nak_sent:                                # A6
                self.tx(bytes([NAK]), None)
            out_status(0x070A)
            self.goto(IDLE)
            self.finish_job(now, 0x070A)

    # ---------------------------------------------------------------- timers
    def on_timer(self, now):
        st = self.state
        self.deadline = None
        if st == JUNK:
            self.goto(IDLE)
            self.tx(bytes([NAK]), None)
            out_status(0x0802)
        elif st in RX_STATES:
            self.note(0x0806)
            self.rx_nak()
        elif st == R_REPEAT:
            self.goto(IDLE)
        elif st == S_SETUP:
            self.setup_fail(0x0703, now)
        elif st == S_QUIET:
            self.tx(bytes([NAK]), None)
            self.tx_fail(now, True)
        elif st == S_RELEASE:
            out_status(0x0707)
            self.tx_fail(now, False)


# ============================================================== memory model
class Memory:
    """The local CPU as the partner sees it ("pattern" memory of the profile)."""

    def __init__(self, cfg):
        self.db = {n: bytearray((n + i) & 0xFF for i in range(cfg.db_bytes)) for n in cfg.db_range}
        self.dx = {n: bytearray((n + i + 0x80) & 0xFF for i in range(cfg.db_bytes)) for n in cfg.dx_range}
        nb = cfg.byte_area_bytes
        nc = 2 * cfg.cell_area_cells
        self.areas = {
            "E": bytearray((0x40 + i) & 0xFF for i in range(nb)),
            "A": bytearray((0xC0 + i) & 0xFF for i in range(nb)),
            "M": bytearray(nb),
            "T": bytearray((0x20 + i) & 0xFF for i in range(nc)),
            "Z": bytearray((0x60 + i) & 0xFF for i in range(nc)),
        }
        self.flag_bytes = nb
        self.flags = set()          # coordination flags that are 1: (byte, bit)

    def resolve(self, typ, b5, b6, lenfield):
        """Area, byte offset and byte count of a header, or the class-06 event."""
        if typ in ("D", "X"):
            area = (self.db if typ == "D" else self.dx).get(b5)
            if area is None:
                return 0x0606
            start = 2 * b6                                  # R3.4: DW number
            nbytes = 2 * lenfield
        elif typ in ("T", "Z"):
            area = self.areas[typ]
            start = 2 * ((b5 << 8) | b6)                    # AMB-14: cell number
            nbytes = 2 * lenfield
        else:
            area = self.areas[typ]
            start = (b5 << 8) | b6                          # AMB-14: byte address
            nbytes = lenfield
        if start >= len(area):
            return 0x0607
        if lenfield == 0 or nbytes > MAX_REQ or start + nbytes > len(area):
            return 0x0608                                   # AMB-25
        return area, start, nbytes


# ============================================================== request script
class ScriptError(Exception):
    pass


class Request:
    def __init__(self, verb, spec):
        self.verb = verb.lower()
        self.label = "%s:%s" % (verb, spec)
        self.cf = None
        self.cpu = 1                # FB default R_CPU_NO = 1
        self.data = None
        self.seed = 0x10
        self.length = None
        parts = spec.split(":")
        if len(parts) < 3:
            raise ScriptError("bad request spec %r" % spec)
        area = parts[0].upper()
        if area[:2] in ("DB", "DX") and area[2:].isdigit():
            self.area = "D" if area[:2] == "DB" else "X"
            self.no = int(area[2:])
        elif area in ("M", "E", "A", "T", "Z"):
            self.area = area
            self.no = None
        else:
            raise ScriptError("bad area %r" % parts[0])
        addr = parts[1].upper()
        try:
            if self.area in ("D", "X"):
                if addr.startswith("DW"):
                    self.offset = 2 * int(addr[2:])
                elif addr.startswith("OFF="):
                    self.offset = int(addr[4:]) & ~1        # R3.5: rounded down to even
                else:
                    raise ValueError
            else:
                self.offset = int(addr[4:] if addr.startswith("OFF=") else addr)
        except ValueError:
            raise ScriptError("bad address %r" % parts[1])
        for kv in parts[2:]:
            if "=" not in kv:
                raise ScriptError("bad field %r" % kv)
            k, v = kv.split("=", 1)
            k = k.upper()
            try:
                if k == "LEN":
                    self.length = int(v)
                elif k == "CF":
                    b, bit = v.split(".")
                    self.cf = (int(b), int(bit))
                elif k == "CPU":
                    self.cpu = None if v.lower() == "none" else int(v)
                elif k == "DATA":
                    self.data = bytes.fromhex(v)
                elif k == "SEED":
                    try:
                        self.seed = int(v, 0)
                    except ValueError:
                        self.seed = int(v, 10)
                else:
                    raise ScriptError("unknown field %r" % k)
            except ValueError:
                raise ScriptError("bad value in %r" % kv)
        if self.length is None:
            raise ScriptError("LEN missing in %r" % spec)
        if self.verb == "send" and self.data is not None and len(self.data) != self.length:
            raise ScriptError("DATA has %d bytes, LEN=%d in %r" % (len(self.data), self.length, spec))

    def local_check(self):
        """The checks the CP does before anything goes on the wire (R3.8, R3.12, R3.18)."""
        if self.verb == "send" and self.area not in ("D", "X"):
            return 0x0301                                   # SEND goes to DB/DX only
        if self.length < 1:
            return 0x1E41
        if self.length > MAX_REQ:
            return 0x0517
        if self.area in ("D", "X"):
            if self.no == 0:
                return 0x0514
            if self.no > 255:
                return 0x0301
            if self.offset > 510:
                return 0x0514
        elif self.offset > 255:
            return 0x0514
        if self.cf is not None:
            if self.cf[0] > 255:
                return 0x0301
            if self.cf[1] > 7 or self.cf[1] < 0:
                return 0x0515
        if self.cpu is not None and self.cpu > 4:
            return 0x0516
        return None


def parse_script(path):
    items = []
    with open(path, "r", encoding="utf-8") as f:
        for n, raw in enumerate(f, 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            words = line.split()
            verb = words[0]
            try:
                if verb.lower() == "wait" and len(words) == 2:
                    items.append(("wait", int(words[1])))
                elif verb.lower() in ("send", "fetch") and len(words) == 2:
                    items.append(("req", Request(verb, words[1])))
                else:
                    raise ScriptError("cannot read %r" % line)
            except (ScriptError, ValueError) as e:
                raise ScriptError("%s line %d: %s" % (path, n, e))
    return items


# ============================================================== RK 512 station
class ActiveReq:
    def __init__(self, req, brk):
        self.req = req
        r = req
        t = r.area
        if r.verb == "send":
            b3 = CMD_SEND_DB if t == "D" else CMD_SEND_DX
            b4 = LETTER_OF_TYPE["D"]
        else:
            b3 = CMD_FETCH
            b4 = LETTER_OF_TYPE[t]
            if t == "Z" and brk == "counter-letter-c":
                b4 = 0x43
        if t in ("D", "X"):
            b5, b6 = r.no, r.offset // 2
        else:
            b5, b6 = (r.offset >> 8) & 0xFF, r.offset & 0xFF
        if t in WORD_TYPES:
            words = (r.length + 1) // 2                     # R3.13
            lenfield = words
            self.nbytes = 2 * words
            if brk == "length-in-bytes":
                lenfield = 2 * words
        else:
            lenfield = r.length
            self.nbytes = r.length
        # bytes 9/10 (R3.17)
        if r.cf is not None and r.cf[0] != 255:
            b9 = r.cf[0]
            b10 = ((r.cpu if r.cpu is not None else 0) << 4) | r.cf[1]
        else:
            b9 = 0xFF
            b10 = ((r.cpu if r.cpu is not None else 0xF) << 4) | 0xF
        self.header = bytes([0x00, 0x00, b3, b4, b5, b6, (lenfield >> 8) & 0xFF, lenfield & 0xFF, b9, b10])
        cb3 = b3
        if brk == "cont-byte3-changed":
            cb3 = {CMD_SEND_DB: CMD_SEND_DX, CMD_SEND_DX: CMD_SEND_DB, CMD_FETCH: 0x41}[b3]
        self.cont_header = bytes([0xFF, 0x00, cb3, b4])
        if r.verb == "send":
            if r.data is not None:
                data = bytes(r.data)
            else:
                data = bytes((r.seed + 7 * i) & 0xFF for i in range(r.length))
            if len(data) < self.nbytes and brk != "odd-send-no-pad":
                data += bytes(self.nbytes - len(data))      # R3.13: 00h pad
            self.data = data
            self.total = len(data)
        else:
            self.data = bytearray()
            self.total = self.nbytes
        self.sent = 0             # data bytes covered by the frames answered so far
        self.frame = 0            # index of the frame in flight
        self.state = "SEND"       # SEND (queued / on the line) | WAIT (T_RES running)
        self.job = None

    def chunk_len(self):
        return min(CHUNK, self.total - self.sent)


class PassiveReq:
    def __init__(self, b3, b4, typ, area, start, nbytes, flag):
        self.b3, self.b4 = b3, b4
        self.typ = typ
        self.area, self.start, self.nbytes = area, start, nbytes
        self.done = 0             # bytes transferred so far
        self.flag = flag
        self.state = "RESP"       # RESP (response owed) | WAITC (T_RES running)


class Station:
    def __init__(self, cfg):
        self.cfg = cfg
        self.brk = cfg.brk
        self.chartime = cfg.frame_bits / cfg.baud if cfg.baud > 0 else 0.0
        self.parmrk = cfg.parmrk
        self.txq = deque()        # (byte, cb or None)
        self.next_tx = 0.0
        self.pm = 0               # PARMRK parser state
        self.link = Link(cfg, self.tx, self.on_block)
        self.link.clear_tx = self.txq.clear
        self.mem = Memory(cfg)
        tres = cfg.tres_ms / 1000.0
        self.tres_passive = tres
        self.tres_active = tres / 5 if self.brk == "tres-too-short" else tres
        self.timers = {}          # key -> (deadline, callback, defer_while_receiving)
        self.active = None
        self.passive = None
        self.owed = 0             # responses queued and not yet acknowledged
        self.script = deque(cfg.script)
        self.script_at = 0.0
        self.cf_reset = {}        # (byte, bit) -> seconds
        for (byte, bit, ms) in cfg.cf_set:
            self.mem.flags.add((byte, bit))
            self.cf_reset[(byte, bit)] = ms / 1000.0

    # ---------------------------------------------------------------- output
    def tx(self, data, cb):
        data = bytes(data)
        for i, b in enumerate(data):
            self.txq.append((b, cb if i == len(data) - 1 else None))

    def pump_tx(self):
        while self.txq:
            now = time.monotonic()
            if now < self.next_tx:
                return
            if self.chartime == 0.0:
                items = list(self.txq)
                self.txq.clear()
                self.write(bytes(b for b, _ in items))
                for _, cb in items:
                    if cb is not None:
                        cb(now)
                continue
            b, cb = self.txq.popleft()
            self.write(bytes([b]))
            self.next_tx = now + self.chartime              # end of this byte's stop bit
            if cb is not None:
                cb(self.next_tx)

    def write(self, data):
        try:
            os.write(1, data)
        except OSError:
            sys.exit(0)

    # ---------------------------------------------------------------- timers
    def set_timer(self, key, when, cb, defer_rx=False):
        self.timers[key] = (when, cb, defer_rx)

    def cancel_timer(self, key):
        self.timers.pop(key, None)

    def next_deadline(self):
        ds = [w for (w, _, d) in self.timers.values() if not (d and self.link.receiving)]
        if self.link.deadline is not None:
            ds.append(self.link.deadline)
        return min(ds) if ds else None

    def fire_timers(self, now):
        if self.link.deadline is not None and now >= self.link.deadline:
            self.link.on_timer(now)
        for key, entry in sorted(self.timers.items(), key=lambda kv: kv[1][0]):
            when, cb, defer_rx = entry
            if when <= now and not (defer_rx and self.link.receiving) and self.timers.get(key) is entry:
                del self.timers[key]
                cb(now)

    # ---------------------------------------------------------------- input
    def feed(self, data, now):
        for b in data:
            if not self.parmrk:
                self.link.rx(b, False, now)
            elif self.pm == 0:
                if b == 0xFF:
                    self.pm = 1
                else:
                    self.link.rx(b, False, now)
            elif self.pm == 1:
                self.pm = 0
                if b == 0xFF:
                    self.link.rx(0xFF, False, now)
                elif b == 0x00:
                    self.pm = 2
                else:                                       # not a mark: take both
                    self.link.rx(0xFF, False, now)
                    self.link.rx(b, False, now)
            else:
                self.pm = 0
                if b == 0x00:
                    self.link.on_break(now)
                else:
                    self.link.rx(b, True, now)

    # ---------------------------------------------------------------- frames in
    def on_block(self, p, now):
        if len(p) < 4:
            out_status(0x0610)                              # AMB-10: no answer
            return
        if p[2] == 0x00:                                    # R2.4: a response
            self.on_response(p, now)
        else:
            self.on_command(p, now)

    # ---------------------------------------------------------------- passive role
    def respond(self, b1, reatel, data=b"", final=True):
        if b1 == 0xFF and self.brk == "cont-response-byte1-00":
            b1 = 0x00
        payload = bytes([b1, 0x00, 0x00, reatel]) + bytes(data)
        pr = self.passive
        self.owed += 1

        def done(now):
            self.owed -= 1
            if pr is not None and self.passive is pr:
                if final:
                    self.passive = None
                else:
                    pr.state = "WAITC"                      # Fig. 2-19: start T_RES
                    if self.brk != "no-tres-passive":
                        self.set_timer("tres-p", now + self.tres_passive, self.passive_timeout, True)

        def fail(now, code):
            self.owed -= 1
            out_status(0x0612)
            if pr is not None and self.passive is pr:
                self.passive = None

        self.link.submit(LinkJob(payload, done, fail,
                                 double_dle=self.brk != "response-dle-not-doubled"))

    def reject(self, b1, event):
        """Error response (R5.5: no data); the partner request is finished."""
        out_status(event)
        reatel = EVENT_REATEL[event]
        if event == 0x0606 and self.brk == "reatel-db-0c":
            reatel = 0x0C
        self.respond(b1, reatel, final=True)

    def abort_passive(self):
        self.passive = None
        self.cancel_timer("tres-p")

    def passive_timeout(self, now):
        self.passive = None                                 # AMB-18: silent abort

    def on_command(self, p, now):
        b1 = p[0]
        mirror = 0xFF if b1 == 0xFF else 0x00
        if self.cfg.cpu_stop:                               # R10.14
            self.abort_passive()
            self.reject(mirror, 0x060D)
            return
        if b1 not in (0x00, 0xFF):
            out_status(0x0601)                              # the open request is left alone
            self.respond_detached(0x00, EVENT_REATEL[0x0601])
            return
        if b1 == 0x00 and len(p) < 10:
            out_status(0x0610)                              # AMB-10: no answer
            return
        if self.owed > 0:                                   # R8.6: response still owed
            self.abort_passive()
            self.reject(mirror, 0x060E)
            return
        if b1 == 0xFF:
            self.on_continuation(p, now)
        else:
            if self.passive is not None:                    # AMB-18
                self.abort_passive()
                self.reject(0x00, 0x060E)
                return
            self.on_first(p, now)

    def respond_detached(self, b1, reatel):
        """A response that does not belong to the open partner request."""
        keep, self.passive = self.passive, None
        self.respond(b1, reatel, final=True)
        self.passive = keep

    def on_first(self, p, now):
        b3, b4 = p[2], p[3]
        if b3 not in (CMD_SEND_DB, CMD_SEND_DX, CMD_FETCH):
            return self.reject(0x00, 0x0602)
        typ = TYPE_OF_LETTER.get(b4)
        if typ is None or (b3 != CMD_FETCH and typ != "D"):
            return self.reject(0x00, 0x0604)                # AMB-01, AMB-03
        if b3 == CMD_FETCH and len(p) > 10:
            return self.reject(0x00, 0x060C)
        if b3 == CMD_SEND_DX:
            typ = "X"                                       # AMB-21
        lenfield = (p[6] << 8) | p[7]
        r = self.mem.resolve(typ, p[4], p[5], lenfield)
        if isinstance(r, int):
            return self.reject(0x00, r)
        area, start, nbytes = r
        b9, b10 = p[8], p[9]
        flag = None
        if b9 != 0xFF:
            if (b10 & 0x0F) > 7 or b9 >= self.mem.flag_bytes:
                return self.reject(0x00, 0x0609)            # AMB-23
            flag = (b9, b10 & 0x0F)
        if (b10 >> 4) not in (0, 1, 2, 3, 4, 0xF):
            return self.reject(0x00, 0x060A)                # AMB-22
        data = p[10:]
        first = min(CHUNK, nbytes)
        if b3 != CMD_FETCH and len(data) != first and self.brk != "data-count-unchecked":
            return self.reject(0x00, 0x060B)
        if flag is not None and flag in self.mem.flags and self.brk != "flag-ignored":
            return self.reject(0x00, 0x060F)                # R10.19
        self.passive = PassiveReq(b3, b4, typ, area, start, nbytes, flag)
        self.transfer(0x00, data)

    def on_continuation(self, p, now):
        pr = self.passive
        if pr is None or pr.state != "WAITC":
            self.abort_passive()
            return self.reject(0xFF, 0x060E)                # R8.6, P-09a
        self.cancel_timer("tres-p")
        if p[2] != pr.b3:
            self.abort_passive()
            return self.reject(0xFF, 0x0603)
        if p[3] != pr.b4:
            self.abort_passive()
            return self.reject(0xFF, 0x0605)
        data = p[4:]
        if pr.b3 == CMD_FETCH:
            if data:
                self.abort_passive()
                return self.reject(0xFF, 0x060C)
        elif len(data) != min(CHUNK, pr.nbytes - pr.done) and self.brk != "data-count-unchecked":
            self.abort_passive()
            return self.reject(0xFF, 0x060B)
        pr.state = "RESP"
        self.transfer(0xFF, data)

    def transfer(self, b1, data):
        """Execute one frame of the open partner request and answer it (R5.8, R5.9)."""
        pr = self.passive
        n = min(CHUNK, pr.nbytes - pr.done)
        pos = pr.start + pr.done
        if pr.b3 == CMD_FETCH:
            chunk = bytes(pr.area[pos:pos + n])
        else:
            chunk = bytes(data[:n])
            pr.area[pos:pos + len(chunk)] = chunk
        pr.done += n
        final = pr.done >= pr.nbytes
        if final:
            self.request_done(pr)
        if pr.b3 == CMD_FETCH:
            if final and self.brk == "fetch-one-byte-too-many":
                end = pr.start + pr.done
                chunk += bytes(pr.area[end:end + 1]) or b"\x00"
            self.respond(b1, 0x00, chunk, final=final)
        else:
            self.respond(b1, 0x00, final=final)

    def request_done(self, pr):
        if pr.flag is None:
            return
        self.mem.flags.add(pr.flag)                         # R10.19: flag := 1
        delay = self.cf_reset.get(pr.flag, 0.0)
        key = "cf:%d.%d" % pr.flag
        self.set_timer(key, time.monotonic() + delay, lambda now, f=pr.flag: self.mem.flags.discard(f))

    # ---------------------------------------------------------------- active role
    def poll_script(self, now):
        while self.active is None and self.script and now >= self.script_at:
            kind, item = self.script.popleft()
            if kind == "wait":
                self.script_at = now + item / 1000.0
                continue
            code = item.local_check()
            if code is not None:
                out_status(code)
                out_line("RESULT %s STATUS 16#%04X" % (item.label, code))
                continue
            self.active = ActiveReq(item, self.brk)
            self.send_frame(now)

    def next_wakeup_script(self):
        if self.active is None and self.script:
            return self.script_at
        return None

    def send_frame(self, now):
        a = self.active
        if a.frame == 0:
            payload = a.header + (a.data[:a.chunk_len()] if a.req.verb == "send" else b"")
        else:
            payload = a.cont_header + (a.data[a.sent:a.sent + a.chunk_len()] if a.req.verb == "send" else b"")
        a.state = "SEND"

        def done(t):
            if self.active is a and a.job is job:
                a.state = "WAIT"
                if self.brk != "no-tres-active":
                    self.set_timer("tres-a", t + self.tres_active, self.active_timeout, True)

        def fail(t, code):
            if self.active is a and a.job is job:
                self.active_end(0x051A)

        job = LinkJob(payload, done, fail)
        a.job = job
        self.link.submit(job)

    def active_timeout(self, now):
        if self.active is not None and self.active.state == "WAIT":
            self.active_end(0x0A05)

    def active_end(self, code):
        a = self.active
        self.active = None
        self.cancel_timer("tres-a")
        if a.job is not None:
            self.link.cancel(a.job)
        self.script_at = time.monotonic()
        if code is None:
            if a.req.verb == "fetch":
                out_line("FETCHED %s %s" % (a.req.label, bytes(a.data[:a.req.length]).hex()))
            out_line("RESULT %s OK" % a.req.label)
        else:
            out_status(code)
            out_line("RESULT %s STATUS 16#%04X" % (a.req.label, code))

    def on_response(self, p, now):
        a = self.active
        if a is None or a.state != "WAIT":
            if a is not None:                               # before our frame went out
                return self.active_end(0x0A01)
            out_status(0x0A01)                              # unsolicited (R8.7)
            return
        self.cancel_timer("tres-a")
        b1, reatel, data = p[0], p[3], p[4:]
        if b1 not in (0x00, 0xFF):
            return self.active_end(0x0A02)
        if b1 != (0x00 if a.frame == 0 else 0xFF):
            return self.active_end(0x0A01)                  # R5.6
        if reatel != 0:
            if data:                                        # AMB-33
                return self.active_end(0x0A04 if a.req.verb == "send" else 0x0A03)
            code = REATEL_STATUS.get(reatel)
            if code is None:
                code = 0x0905 if self.brk == "unknown-reatel-0905" else 0x090E
            return self.active_end(code)
        n = a.chunk_len()
        if a.req.verb == "send":
            if data:
                return self.active_end(0x0A04)
        else:
            if len(data) != n:
                return self.active_end(0x0A03)
            a.data += data
        a.sent += n
        if a.sent >= a.total:
            return self.active_end(None)
        a.frame += 1
        self.send_frame(now)

    # ---------------------------------------------------------------- main loop
    def run(self):
        self.tx(bytes([NAK]), None)                         # start-up NAK (§2.2.2)
        start = time.monotonic()
        for flag, delay in self.cf_reset.items():           # --cf-set: the application
            self.set_timer("cf:%d.%d" % flag, start + delay,  # resets the flag after ms
                           lambda now, f=flag: self.mem.flags.discard(f))
        while True:
            now = time.monotonic()
            self.poll_script(now)
            self.link.maybe_start(now)
            self.pump_tx()
            now = time.monotonic()
            waits = []
            d = self.next_deadline()
            if d is not None:
                waits.append(d - now)
            s = self.next_wakeup_script()
            if s is not None:
                waits.append(s - now)
            if self.txq:
                waits.append(self.next_tx - now)
            timeout = max(0.0, min(waits)) if waits else None
            r, _, _ = select.select([0], [], [], timeout)
            if r:
                data = os.read(0, 4096)
                if not data:
                    return
                self.feed(data, time.monotonic())
                continue
            # inputs of an instant before its deadlines
            self.fire_timers(time.monotonic())


# ============================================================== command line
def parse_range(text):
    text = text.strip()
    if text.lower() in ("", "none", "[]"):
        return []
    out = []
    for part in text.strip("[]").split(","):
        part = part.strip()
        if not part:
            continue
        if "-" in part:
            lo, hi = part.split("-", 1)
            out.extend(range(int(lo), int(hi) + 1))
        else:
            out.append(int(part))
    return out


def parse_cf_set(text):
    flag, ms = text.split("@", 1)
    byte, bit = flag.split(".", 1)
    return int(byte), int(bit), int(ms)


def main(argv=None):
    p = argparse.ArgumentParser(description="RK 512 station over 3964R/3964 on stdin/stdout")
    p.add_argument("--link", choices=["3964", "3964R"], default="3964R")
    p.add_argument("--priority", choices=["low", "high"], default="low")
    p.add_argument("--cdt-ms", type=int, default=220)
    p.add_argument("--adt-ms", type=int, default=None)
    p.add_argument("--setup-attempts", type=int, default=6)
    p.add_argument("--transmission-attempts", type=int, default=6)
    p.add_argument("--baud", type=int, default=9600)
    p.add_argument("--data-bits", type=int, choices=[8], default=8)     # R1.7: fixed 8
    p.add_argument("--parity", choices=["none", "odd", "even"], default="even")
    p.add_argument("--stop-bits", type=int, choices=[1, 2], default=1)
    p.add_argument("--parmrk", action="store_true")
    p.add_argument("--tres-ms", type=int, default=10000)
    p.add_argument("--db-range", default="1-199")
    p.add_argument("--dx-range", default="1-199")
    p.add_argument("--db-bytes", type=int, default=512)
    p.add_argument("--byte-area-bytes", type=int, default=256)
    p.add_argument("--cell-area-cells", type=int, default=256)
    p.add_argument("--requests", default=None)
    p.add_argument("--cpu-stop", action="store_true")
    p.add_argument("--cf-set", action="append", default=[])
    p.add_argument("--break", dest="brk", default=None)
    p.add_argument("--list-breaks", action="store_true")
    a = p.parse_args(argv)
    if a.list_breaks:
        for k, v in BREAKS.items():
            print("%-26s %s" % (k, v))
        return 0
    if a.brk is not None and a.brk not in BREAKS:
        p.error("unknown --break variant %r (see --list-breaks)" % a.brk)
    if a.cdt_ms <= 0 or (a.adt_ms is not None and a.adt_ms <= 0) or a.tres_ms <= 0 \
            or not 1 <= a.setup_attempts <= 255 or not 1 <= a.transmission_attempts <= 255 \
            or a.baud < 0 or a.db_bytes < 2 or a.byte_area_bytes < 1 or a.cell_area_cells < 1:
        p.error("parameter out of range")
    try:
        a.db_range = parse_range(a.db_range)
        a.dx_range = parse_range(a.dx_range)
        a.cf_set = [parse_cf_set(x) for x in a.cf_set]
    except ValueError:
        p.error("bad --db-range, --dx-range or --cf-set")
    a.frame_bits = 1 + a.data_bits + (0 if a.parity == "none" else 1) + a.stop_bits
    try:
        a.script = parse_script(a.requests) if a.requests else []
    except (OSError, ScriptError) as e:
        p.error(str(e))
    try:
        Station(a).run()
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
