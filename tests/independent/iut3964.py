#!/usr/bin/env python3
"""Independent 3964 / 3964R station (SIMATIC CP 341 procedure), written from
a written description of the manual's rules only, by someone who did not see ptpcert.

Serial line = stdin (received bytes) / stdout (transmitted bytes), binary.
STATUS events go to stderr as "STATUS 16#XXXX".
Application: echo -- every block received without error is submitted as a
new send job with the same user data.

Spec references in comments: "§n" = section of the author's description, "Rn"/"Sn" =
rows of its state tables, "An" = the open points as docs/readings.md numbers them.

Readings chosen for ambiguities (see also README.md):
  A1  default ADT for 3964 = 550 ms (table value).
  A2  CDT timeout in the receiver goes through the common NAK path, i.e. the
      receiver then waits T_BLOCK for a repetition (figure reading).
  A4  the setup counter X is reset to 1 for each new transmission attempt.
  A6  after the "other character during send" path the sender has just sent
      a NAK; if that was the last transmission attempt, no second NAK is sent.
  A7  the CDT "quiet" waits (idle garbage, sender abort) are re-triggered by
      every further received character.
  A9  STATUS events are reported as they happen (specific cause, 0701/0801 on
      the first repetition, 0709/070A on final failure).
  A10 a DLE received after DLE ETX has been transmitted but before the BCC
      has gone out is "DLE too early": 16#0706, new attempt without NAK.
      A NAK received then is also counted as 16#0706.
  A11 DLE + other character: error noted (16#0805), reception continues,
      NAK after the end of the block (or CDT timeout).
  A12 the release T_ADT starts when the last byte of the end sequence
      (BCC for 3964R, ETX for 3964) has been completely transmitted.
      Generally every timer started "after sending X" starts at the end of
      X's stop bit (write time + one character time).
  A13 an invalid character in idle is reported at once (16#080C) and then
      handled like garbage: NAK after CDT of quiet, 16#0802.
  A15 BREAK: immediate return to idle from every state, no NAK, no retry,
      pending output is dropped, the current (or deferred) send job is
      dropped; reported as 16#080D.
  A16 not applicable: the receive buffer is always free, DLE answers STX at once.
  A17 1024 user bytes counted before DLE doubling; a longer block is NAKed
      at its end (16#0816).  A zero-length block is NAKed (reported 16#0805).
  A18 the receiver gives up after the NAK for reception number W_r >= N_tx.
  A19 in "wait for repetition": STX starts the repetition, NAK means the
      partner gave up (16#0815, go idle), any other character is handled as
      garbage in idle.  Send jobs are started only from true IDLE, so a
      pending job waits until the repetition wait has ended (table R5/R30).
  A21 after a low-priority initialization conflict the deferred job resumes
      without resetting X (the collided STX was setup attempt X, the next
      STX is attempt X+1) and W unchanged; if the conflict reception fails,
      the job stays pending and resumes once the station is idle again.
  A23 high priority: the partner's STX is ignored and T_ADT keeps running.
"""

import argparse
import os
import select
import sys
import time
from collections import deque

STX = 0x02
ETX = 0x03
DLE = 0x10
NAK = 0x15

T_BLOCK = 4.0          # fixed, §5
MAX_LEN = 1024         # user bytes, §2.2 / A17

BREAKS = {
    "no-startup-nak":
        "start-up: no NAK is sent at start-up (§6)",
    "bcc-include-stx":
        "framing: the transmitted BCC also includes the STX (§4.1)",
    "bcc-not-checked":
        "framing: the receiver does not compare the BCC, any BCC is accepted (§8.4)",
    "no-dle-doubling":
        "DLE: the sender does not double data bytes equal to 10 (§3.1)",
    "dle-other-accepted":
        "DLE: receiver stores DLE + other character as data, no 16#0805 error (§3.4)",
    "cdt-double":
        "timers: receiver monitors the data phase with 2 x CDT instead of CDT (§8.3)",
    "idle-nak-immediate":
        "timers: garbage in idle is NAKed at once, without waiting for CDT of quiet (§8.1)",
    "answer-idle-nak":
        "acknowledgement: a NAK received in idle is treated as garbage and NAKed (§8.1)",
    "setup-attempts-plus-one":
        "attempts: one STX more than the setup-attempts limit before giving up (§7.1.5)",
    "tx-attempts-plus-one":
        "attempts: transmission attempts counted without the first one (§7.4.1)",
    "no-final-setup-nak":
        "acknowledgement: no NAK after the last failed setup attempt (§7.1.6)",
    "high-prio-yields":
        "conflict: a high-priority station answers the partner's STX with DLE (§9.4)",
    "nak-on-break":
        "BREAK: a NAK is sent after a BREAK condition (§10.5)",
    "parity-nak-immediate":
        "char errors: an invalid character inside a block is NAKed at once (§8.3.4)",
    "no-length-limit":
        "receive: blocks longer than 1024 user bytes are accepted (§8.3.6)",
    "no-quiet-before-nak":
        "send: after a foreign character during send, NAK is sent at once, not after CDT quiet (§7.2.4)",
}

# states
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


class Job:
    def __init__(self, data):
        self.data = bytes(data)
        self.W = 1
        self.X = 1


class Station:
    def __init__(self, a):
        self.r = a.procedure == "3964R"
        self.high = a.priority == "high"
        self.cdt = a.cdt_ms / 1000.0
        adt = a.adt_ms if a.adt_ms is not None else (2000 if self.r else 550)
        self.adt = adt / 1000.0
        self.n_setup = a.setup_attempts
        self.n_tx = a.transmission_attempts
        self.chartime = 11.0 / a.baud if a.baud > 0 else 0.0
        self.parmrk = a.parmrk
        self.brk = a.brk

        # receiver CDT (possibly broken)
        self.cdt_rx = self.cdt * (2 if self.brk == "cdt-double" else 1)

        self.state = IDLE
        self.gen = 0
        self.deadline = None
        self.txq = deque()          # (byte, callback or None)
        self.next_tx = 0.0
        self.jobs = deque()         # submitted, not yet started
        self.job = None             # current (possibly deferred) job
        # receiver
        self.rbuf = bytearray()
        self.rbcc = 0
        self.cause = None
        self.Wr = 1
        self.first_nak_done = False
        self.rlen = 0
        # sender
        self.etx_sent = False
        # PARMRK parser
        self.pm = 0                 # 0 normal, 1 after FF, 2 after FF 00

    # ------------------------------------------------------------ helpers
    def status(self, code):
        sys.stderr.write("STATUS 16#%04X\n" % code)
        sys.stderr.flush()

    def goto(self, st):
        self.state = st
        self.gen += 1
        self.deadline = None

    def tx(self, data, arm=None, cb=None):
        """Queue bytes.  arm = duration: arm the state timer when the last byte
        has been transmitted (end of its stop bit), unless the state changed
        or something else armed the timer already.  cb(t_end) is called when
        the last byte is written."""
        data = list(data)
        for i, b in enumerate(data):
            f = None
            if i == len(data) - 1 and (arm is not None or cb is not None):
                gen = self.gen

                def f(t_end, gen=gen, arm=arm, cb=cb):
                    if cb is not None:
                        cb(t_end)
                    if arm is not None and self.gen == gen and self.deadline is None:
                        self.deadline = t_end + arm
            self.txq.append((b, f))

    def pump_tx(self):
        while self.txq:
            now = time.monotonic()
            if now < self.next_tx:
                return
            b, f = self.txq.popleft()
            try:
                os.write(1, bytes([b]))
            except (BrokenPipeError, OSError):
                sys.exit(0)
            self.next_tx = now + self.chartime
            if f is not None:
                f(now + self.chartime)

    # ------------------------------------------------------------ input
    def feed(self, data, now):
        for b in data:
            if not self.parmrk:
                self.rx(b, False, now)
                continue
            if self.pm == 0:
                if b == 0xFF:
                    self.pm = 1
                else:
                    self.rx(b, False, now)
            elif self.pm == 1:
                if b == 0xFF:
                    self.pm = 0
                    self.rx(0xFF, False, now)
                elif b == 0x00:
                    self.pm = 2
                else:
                    # not a valid PARMRK sequence; be lenient: plain FF + byte
                    self.pm = 0
                    self.rx(0xFF, False, now)
                    self.rx(b, False, now)
            else:
                self.pm = 0
                if b == 0x00:
                    self.on_break(now)
                else:
                    self.rx(b, True, now)

    def on_break(self, now):
        # §10.5 / R32 / S17: immediate return to idle, no NAK, no retry.
        self.txq.clear()
        self.status(0x080D)
        self.job = None
        self.goto(IDLE)
        if self.brk == "nak-on-break":
            self.tx([NAK])

    def rx(self, c, err, now):
        st = self.state
        if st in (IDLE, R_REPEAT):
            self.rx_idle(c, err, now, st == R_REPEAT)
        elif st == JUNK:
            self.deadline = now + self.cdt          # R6 (A7): retrigger
        elif st == R_DATA:
            self.rbcc ^= c
            if err:
                self.note(0x080C)
                if self.brk == "parity-nak-immediate":
                    self.rx_nak()
                    return
            elif c == DLE:
                self.goto(R_DLE)
            else:
                self.store(c)
            self.deadline = now + self.cdt_rx
        elif st == R_DLE:
            self.rbcc ^= c
            if err:
                self.note(0x080C)
                if self.brk == "parity-nak-immediate":
                    self.rx_nak()
                    return
                self.goto(R_DATA)
            elif c == DLE:                          # dual DLE -> one 10
                self.store(DLE)
                self.goto(R_DATA)
            elif c == ETX:
                if self.r:
                    self.goto(R_BCC)
                else:
                    self.evaluate()
                    return
            else:                                   # DLE + other (A11)
                if self.brk == "dle-other-accepted":
                    self.store(DLE)
                    self.store(c)
                else:
                    self.note(0x0805)
                self.goto(R_DATA)
            self.deadline = now + self.cdt_rx
        elif st == R_BCC:
            if err:
                self.note(0x080C)
            elif c != self.rbcc and self.brk != "bcc-not-checked":
                self.note(0x0808)
            self.evaluate()
        elif st == S_SETUP:
            if err:
                self.setup_fail(0x080C)
            elif c == DLE:
                self.send_block()
            elif c == STX:
                if self.high and self.brk != "high-prio-yields":
                    pass                             # S3: ignore, T_ADT keeps running
                else:
                    # S4: low priority -> defer own job, receive partner's block
                    self.Wr = 1
                    self.first_nak_done = False
                    self.start_reception()
            else:
                self.setup_fail(0x0702)
        elif st == S_DATA:
            if not err and c == NAK:
                self.txq.clear()
                self.status(0x0706 if self.etx_sent else 0x0704)
                self.tx_fail(False)
            elif not err and c == DLE and self.etx_sent:
                self.txq.clear()
                self.status(0x0706)                 # DLE too early (A10)
                self.tx_fail(False)
            else:
                self.txq.clear()
                self.status(0x0704)                 # S9 (invalid char too)
                if self.brk == "no-quiet-before-nak":
                    self.tx([NAK])
                    self.tx_fail(True)
                else:
                    self.goto(S_QUIET)
                    self.deadline = now + self.cdt
        elif st == S_QUIET:
            self.deadline = now + self.cdt          # S10 (A7): retrigger
        elif st == S_RELEASE:
            if not err and c == DLE:
                self.job = None                     # S13: DONE
                self.goto(IDLE)
            else:
                self.status(0x080C if err else 0x0706)
                self.tx_fail(False)

    def rx_idle(self, c, err, now, repeat):
        if err:
            self.status(0x080C)                     # R4: at once
            self.enter_junk(now)
        elif c == STX:
            if repeat:
                self.Wr += 1                        # R29
            else:
                self.Wr = 1                         # R1
                self.first_nak_done = False
            self.start_reception()
        elif c == NAK and self.brk != "answer-idle-nak":
            if repeat:                              # A19: partner gave up
                self.status(0x0815)
                self.goto(IDLE)
            # R2: ignored in idle
        else:
            self.enter_junk(now)

    def enter_junk(self, now):
        if self.brk == "idle-nak-immediate":
            self.goto(IDLE)
            self.tx([NAK])
            self.status(0x0802)
            return
        self.goto(JUNK)
        self.deadline = now + self.cdt

    # ------------------------------------------------------------ receiver
    def start_reception(self):
        self.rbuf = bytearray()
        self.rbcc = 0
        self.cause = None
        self.rlen = 0
        self.goto(R_DATA)
        self.tx([DLE], arm=self.cdt_rx)             # R8: DLE, start T_CDT

    def note(self, code):
        if self.cause is None:
            self.cause = code

    def store(self, c):
        self.rlen += 1
        if self.rlen > MAX_LEN and self.brk != "no-length-limit":
            self.note(0x0816)                       # R17 (A17)
            return
        self.rbuf.append(c)

    def evaluate(self):
        if self.cause is None and len(self.rbuf) == 0:
            self.note(0x0805)                       # zero-length block (A17)
        if self.cause is not None:
            self.rx_nak()
            return
        # R26: positive acknowledgement, deliver, echo job
        self.tx([DLE])
        self.jobs.append(bytes(self.rbuf))
        self.goto(IDLE)

    def rx_nak(self):
        # R28
        self.status(self.cause)
        if not self.first_nak_done:
            self.first_nak_done = True
            self.status(0x0801)
        if self.Wr >= self.n_tx:                    # A18: final abort
            self.goto(IDLE)
            self.tx([NAK])
        else:
            self.goto(R_REPEAT)
            self.tx([NAK], arm=T_BLOCK)

    # ------------------------------------------------------------ sender
    def maybe_start_job(self):
        if self.state != IDLE:
            return
        if self.job is not None:
            # deferred by an initialization conflict (A21): X not reset
            self.job.X += 1
            self.setup_check()
        elif self.jobs:
            self.job = Job(self.jobs.popleft())     # S1
            self.send_stx()

    def send_stx(self):
        self.goto(S_SETUP)
        self.tx([STX], arm=self.adt)

    def setup_fail(self, code):
        self.status(code)
        self.job.X += 1
        self.setup_check()

    def setup_check(self):
        limit = self.n_setup + (1 if self.brk == "setup-attempts-plus-one" else 0)
        if self.job.X <= limit:
            self.send_stx()
        else:
            if self.brk != "no-final-setup-nak":
                self.tx([NAK])
            self.status(0x0709)
            self.job = None
            self.goto(IDLE)

    def send_block(self):
        self.goto(S_DATA)
        self.etx_sent = False
        body = []
        for b in self.job.data:
            body.append(b)
            if b == DLE and self.brk != "no-dle-doubling":
                body.append(DLE)
        bcc = STX if self.brk == "bcc-include-stx" else 0
        for b in body:
            bcc ^= b
        bcc ^= DLE ^ ETX
        gen = self.gen

        def etx_done(t_end):
            if self.gen == gen:
                self.etx_sent = True

        def last_done(t_end):
            if self.gen == gen:
                self.goto(S_RELEASE)                # S12
                self.deadline = t_end + self.adt

        self.tx(body)
        if self.r:
            self.tx([DLE, ETX], cb=etx_done)
            self.tx([bcc], cb=last_done)            # BCC never doubled
        else:
            self.tx([DLE, ETX], cb=last_done)

    def tx_fail(self, nak_sent):
        self.job.W += 1
        limit = self.n_tx + (1 if self.brk == "tx-attempts-plus-one" else 0)
        if self.job.W <= limit:
            if self.job.W == 2:
                self.status(0x0701)
            self.job.X = 1                          # A4
            self.send_stx()
        else:
            if not nak_sent:                        # A6: one NAK only
                self.tx([NAK])
            self.status(0x070A)
            self.job = None
            self.goto(IDLE)

    # ------------------------------------------------------------ timers
    def on_timer(self, now):
        st = self.state
        self.deadline = None
        if st == JUNK:
            self.goto(IDLE)                          # R7
            self.tx([NAK])
            self.status(0x0802)
        elif st in RX_STATES:
            self.note(0x0806)                        # R16/R22/R25
            self.rx_nak()
        elif st == R_REPEAT:
            self.goto(IDLE)                          # R30
        elif st == S_SETUP:
            self.setup_fail(0x0703)                  # S7
        elif st == S_QUIET:
            self.tx([NAK])                           # S11
            self.tx_fail(True)
        elif st == S_RELEASE:
            self.status(0x0707)                      # S16
            self.tx_fail(False)

    # ------------------------------------------------------------ main loop
    def run(self):
        if self.brk != "no-startup-nak":
            self.tx([NAK])                           # §6: one NAK at start-up
        fd = 0
        while True:
            self.pump_tx()
            self.maybe_start_job()
            self.pump_tx()
            now = time.monotonic()
            waits = []
            if self.deadline is not None:
                waits.append(self.deadline - now)
            if self.txq:
                waits.append(self.next_tx - now)
            timeout = max(0.0, min(waits)) if waits else None
            r, _, _ = select.select([fd], [], [], timeout)
            if r:
                data = os.read(fd, 4096)
                if not data:
                    sys.exit(0)
                self.feed(data, time.monotonic())
                continue
            # no input pending: now it is safe to let an expired timer fire
            now = time.monotonic()
            if self.deadline is not None and now >= self.deadline:
                self.on_timer(now)


def main(argv=None):
    p = argparse.ArgumentParser(description="3964/3964R station on stdin/stdout (echo application)")
    p.add_argument("--procedure", choices=["3964", "3964R"], default="3964R")
    p.add_argument("--priority", choices=["low", "high"], default="low")
    p.add_argument("--cdt-ms", type=int, default=220)
    p.add_argument("--adt-ms", type=int, default=None)
    p.add_argument("--setup-attempts", type=int, default=6)
    p.add_argument("--transmission-attempts", type=int, default=6)
    p.add_argument("--baud", type=int, default=9600)
    p.add_argument("--parmrk", action="store_true")
    p.add_argument("--break", dest="brk", default=None)
    p.add_argument("--list-breaks", action="store_true")
    a = p.parse_args(argv)
    if a.list_breaks:
        for k, v in BREAKS.items():
            print("%-24s %s" % (k, v))
        return 0
    if a.brk is not None and a.brk not in BREAKS:
        p.error("unknown --break variant %r (see --list-breaks)" % a.brk)
    if a.cdt_ms <= 0 or (a.adt_ms is not None and a.adt_ms <= 0) \
            or a.setup_attempts < 1 or a.transmission_attempts < 1 or a.baud < 0:
        p.error("parameter out of range")
    try:
        Station(a).run()
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
