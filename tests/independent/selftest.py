#!/usr/bin/env python3
"""Self-test for iut3964.py: plays the partner on the serial line (stdin/stdout
of the subprocess) with real timing.

    python3 selftest.py              # all checks against the correct station
    python3 selftest.py --variants   # additionally: every --break variant must
                                     # fail at least one check
"""
import os
import queue
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
IUT = os.path.join(HERE, "iut3964.py")

STX, ETX, DLE, NAK = 0x02, 0x03, 0x10, 0x15
P1 = bytes([0x31, 0x10, 0x32, 0x15, 0x03])
P1_LINE = bytes([0x31, 0x10, 0x10, 0x32, 0x15, 0x03, 0x10, 0x03, 0x06])
P2_LINE = bytes([0x41, 0x42, 0x10, 0x10, 0x10, 0x03, 0x10])   # BCC = 10

CDT = 0.05
ADT = 0.2
BASE = ["--cdt-ms", "50", "--adt-ms", "200", "--parmrk"]


class Fail(Exception):
    pass


def bcc(line):
    x = 0
    for b in line:
        x ^= b
    return x


def block(payload, r=True):
    body = bytearray()
    for b in payload:
        body.append(b)
        if b == DLE:
            body.append(DLE)
    body += bytes([DLE, ETX])
    if r:
        body.append(bcc(body))
    return bytes(body)


class Peer:
    def __init__(self, args, brk=None):
        cmd = [sys.executable, IUT] + list(args)
        if brk:
            cmd += ["--break", brk]
        self.p = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, bufsize=0)
        self.q = queue.Queue()
        self.status = []
        self.t_sent = None
        threading.Thread(target=self._rd, daemon=True).start()
        threading.Thread(target=self._rderr, daemon=True).start()

    def _rd(self):
        fd = self.p.stdout.fileno()
        while True:
            d = os.read(fd, 4096)
            t = time.monotonic()
            if not d:
                self.q.put((t, None))
                return
            for b in d:
                self.q.put((t, b))

    def _rderr(self):
        for line in self.p.stderr:
            self.status.append(line.decode().strip())

    def send(self, data):
        os.write(self.p.stdin.fileno(), bytes(data))
        self.t_sent = time.monotonic()

    def get(self, timeout):
        try:
            t, b = self.q.get(timeout=max(0.0, timeout))
        except queue.Empty:
            return None, None
        if b is None:
            raise Fail("IUT closed its output")
        return t, b

    def expect(self, data, timeout=1.0, what=""):
        """Expect exactly these bytes; returns the arrival time of the first one."""
        t0 = None
        end = time.monotonic() + timeout
        got = bytearray()
        for want in bytes(data):
            t, b = self.get(end - time.monotonic())
            if b is None:
                raise Fail("%s: expected %s, got %s then timeout" % (what, bytes(data).hex(" "), got.hex(" ")))
            got.append(b)
            if b != want:
                raise Fail("%s: expected %s, got %s" % (what, bytes(data).hex(" "), got.hex(" ")))
            if t0 is None:
                t0 = t
            end = max(end, time.monotonic() + 0.3)
        return t0

    def silence(self, dur, what=""):
        t, b = self.get(dur)
        if b is not None:
            raise Fail("%s: expected silence, got %02x" % (what, b))

    def close(self):
        try:
            self.p.stdin.close()
        except OSError:
            pass
        try:
            self.p.wait(2)
        except subprocess.TimeoutExpired:
            self.p.kill()
            raise Fail("IUT did not exit on EOF")

    def has(self, code):
        return ("STATUS " + code) in self.status


# --------------------------------------------------------------------- checks
def start(args=BASE, brk=None):
    p = Peer(args, brk)
    p.expect([NAK], 2.0, "start-up NAK")
    return p


def receive_ok(p, line, what="receive"):
    p.send([STX])
    p.expect([DLE], 0.5, what + " DLE after STX")
    p.send(line)
    p.expect([DLE], 0.5, what + " DLE after block")


def c_startup(brk=None):
    p = start(brk=brk)
    p.silence(0.15, "after start-up NAK")
    p.close()


def c_receive_echo(brk=None):
    p = start(brk=brk)
    receive_ok(p, P1_LINE)
    p.expect([STX], 0.5, "echo STX")
    p.send([DLE])
    p.expect(P1_LINE, 0.5, "echo block")
    p.send([DLE])
    p.silence(0.3, "after echo")
    p.close()


def c_trailing_dle(brk=None):
    # D22: BCC = 10 is not doubled, stored 41 42 10, echoed identically
    p = start(brk=brk)
    receive_ok(p, P2_LINE)
    p.expect([STX], 0.5, "echo STX")
    p.send([DLE])
    p.expect(P2_LINE, 0.5, "echo block")
    p.send([DLE])
    p.close()


def c_wrong_bcc(brk=None):
    p = start(brk=brk)
    p.send([STX])
    p.expect([DLE], 0.5)
    p.send(P1_LINE[:-1] + b"\x07")
    p.expect([NAK], 0.5, "NAK for wrong BCC")
    p.silence(0.15, "after NAK")
    if not p.has("16#0808"):
        raise Fail("no STATUS 16#0808: %s" % p.status)
    # repetition accepted
    receive_ok(p, P1_LINE, "repetition")
    p.close()


def c_stray_byte(brk=None):
    p = start(["--cdt-ms", "20", "--adt-ms", "20", "--parmrk"], brk)
    p.silence(0.05)
    p.send([0x41])
    ts = p.t_sent
    t = p.expect([NAK], 0.5, "NAK for stray byte")
    dt = t - ts
    if not (0.018 <= dt <= 0.08):
        raise Fail("stray byte NAK after %.1f ms, expected ~20 ms" % (dt * 1000))
    p.silence(0.1)
    p.close()


def c_idle_nak(brk=None):
    p = start(brk=brk)
    p.send([NAK])
    p.silence(0.25, "NAK in idle must be ignored")
    p.close()


def c_parity_deferred(brk=None):
    p = start(brk=brk)
    p.send([STX])
    p.expect([DLE], 0.5)
    p.send(b"\x31\x10\x10\xff\x00\x32")       # 32 received with parity error
    p.silence(0.02, "NAK must not come before end of block")
    p.send(b"\x15\x03\x10\x03\x06")
    p.expect([NAK], 0.3, "NAK after block with parity error")
    p.close()


def c_dle_other(brk=None):
    # D8
    p = start(brk=brk)
    line = bytes([0x31, 0x10, 0x41, 0x32, 0x10, 0x03])
    p.send([STX])
    p.expect([DLE], 0.5)
    p.send(line + bytes([bcc(line)]))
    p.expect([NAK], 0.3, "NAK for DLE + other")
    p.close()


def c_cdt_gap(brk=None):
    # D7
    p = start(brk=brk)
    p.send([STX])
    p.expect([DLE], 0.5)
    p.send(b"\x31\x32")
    ts = p.t_sent
    t = p.expect([NAK], 0.5, "NAK for CDT gap")
    if not (CDT * 0.9 <= t - ts <= CDT + 0.04):
        raise Fail("CDT NAK after %.1f ms" % ((t - ts) * 1000))
    p.close()


def c_break(brk=None):
    # D21
    p = start(brk=brk)
    p.send([STX])
    p.expect([DLE], 0.5)
    p.send(b"\x31\x32\xff\x00\x00")
    p.silence(0.2, "no NAK after BREAK")
    receive_ok(p, P1_LINE, "after BREAK")
    p.close()


def c_overlong(brk=None):
    p = start(brk=brk)
    p.send([STX])
    p.expect([DLE], 0.5)
    p.send(block(bytes([0x41]) * 1025))
    p.expect([NAK], 0.5, "NAK for 1025-byte block")
    p.close()


def echo_job(p, payload=P1):
    receive_ok(p, block(payload), "trigger echo")


def c_setup_timeout(brk=None):
    # D10 with ADT 30 ms, 4 setup attempts
    p = start(["--cdt-ms", "30", "--adt-ms", "30", "--setup-attempts", "4", "--parmrk"], brk)
    echo_job(p)
    last = None
    for i in range(4):
        t = p.expect([STX], 0.5, "STX #%d" % (i + 1))
        if last is not None and not (0.025 <= t - last <= 0.08):
            raise Fail("STX spacing %.1f ms" % ((t - last) * 1000))
        last = t
    t = p.expect([NAK], 0.5, "final NAK")
    p.silence(0.15, "after final NAK")
    if not p.has("16#0709"):
        raise Fail("no 16#0709")
    p.close()


def c_release_nak(brk=None):
    # D12 with 3 transmission attempts
    p = start(BASE + ["--transmission-attempts", "3"], brk)
    echo_job(p)
    for i in range(3):
        p.expect([STX], 0.5, "STX attempt %d" % (i + 1))
        p.send([DLE])
        p.expect(P1_LINE, 0.5, "block attempt %d" % (i + 1))
        p.send([NAK])
    p.expect([NAK], 0.5, "final NAK")
    p.silence(0.3, "after final NAK")
    if not (p.has("16#0701") and p.has("16#070A")):
        raise Fail("missing 0701/070A: %s" % p.status)
    p.close()


def c_other_during_data(brk=None):
    # D15
    payload = bytes(range(0x40, 0x80))
    p = start(brk=brk)
    echo_job(p, payload)
    p.expect([STX], 0.5)
    p.send([DLE])
    p.expect(payload[:10], 0.5, "first data bytes")
    p.send([0x41])
    ts = p.t_sent
    # IUT stops (a few bytes may already be in flight), stays quiet for CDT,
    # then sends NAK and a new STX
    while True:
        t, b = p.get(0.5)
        if b is None:
            raise Fail("no NAK after foreign character during send")
        if t - ts > 0.02:
            break
        if b == NAK:
            raise Fail("NAK %.1f ms after foreign character, expected after CDT of quiet" % ((t - ts) * 1000))
    if b != NAK:
        raise Fail("expected NAK after CDT of quiet, got %02x" % b)
    if not (CDT * 0.9 <= t - ts <= CDT + 0.04):
        raise Fail("NAK after %.1f ms, expected ~CDT" % ((t - ts) * 1000))
    p.expect([STX], 0.3, "new attempt STX")
    p.send([DLE])
    p.expect(block(payload), 0.5, "repeated block")
    p.send([DLE])
    p.close()


def c_conflict_low(brk=None):
    # D17 / Fig. 2-8 with the IUT low priority
    p = start(brk=brk)
    echo_job(p, P1)
    p.expect([STX], 0.5, "IUT STX")
    p.send([STX])
    p.expect([DLE], 0.15, "low priority IUT answers STX")
    p.send(P2_LINE)
    p.expect([DLE], 0.3, "DLE for partner block")
    p.expect([STX], 0.3, "deferred job STX")
    p.send([DLE])
    p.expect(P1_LINE, 0.5, "deferred block")
    p.send([DLE])
    p.expect([STX], 0.3, "echo of partner block")
    p.send([DLE])
    p.expect(P2_LINE, 0.5, "echo block P2")
    p.send([DLE])
    p.close()


def c_conflict_high(brk=None):
    # D16 with the IUT high priority
    p = start(BASE + ["--priority", "high"], brk)
    echo_job(p, P1)
    p.expect([STX], 0.5, "IUT STX")
    p.send([STX])
    p.silence(0.08, "high priority IUT must not answer STX")
    p.send([DLE])
    p.expect(P1_LINE, 0.5, "IUT block")
    p.send([DLE])
    p.close()


def c_3964(brk=None):
    p = start(["--procedure", "3964", "--cdt-ms", "50", "--adt-ms", "200", "--parmrk"], brk)
    receive_ok(p, P1_LINE[:-1])
    p.expect([STX], 0.5, "echo STX")
    p.send([DLE])
    p.expect(P1_LINE[:-1], 0.5, "echo block 3964")
    p.send([DLE])
    p.silence(0.15)
    p.close()


def c_eof(brk=None):
    p = Peer(BASE, brk)
    p.close()


CHECKS = [
    c_startup, c_receive_echo, c_trailing_dle, c_wrong_bcc, c_stray_byte, c_idle_nak,
    c_parity_deferred, c_dle_other, c_cdt_gap, c_break, c_overlong, c_setup_timeout,
    c_release_nak, c_other_during_data, c_conflict_low, c_conflict_high, c_3964, c_eof,
]

# checks expected to catch each variant (a check a variant must fail)
CATCH = {
    "no-startup-nak": c_startup,
    "bcc-include-stx": c_receive_echo,
    "bcc-not-checked": c_wrong_bcc,
    "no-dle-doubling": c_receive_echo,
    "dle-other-accepted": c_dle_other,
    "cdt-double": c_cdt_gap,
    "idle-nak-immediate": c_stray_byte,
    "answer-idle-nak": c_idle_nak,
    "setup-attempts-plus-one": c_setup_timeout,
    "tx-attempts-plus-one": c_release_nak,
    "no-final-setup-nak": c_setup_timeout,
    "high-prio-yields": c_conflict_high,
    "nak-on-break": c_break,
    "parity-nak-immediate": c_parity_deferred,
    "no-length-limit": c_overlong,
    "no-quiet-before-nak": c_other_during_data,
}


def run(check, brk=None):
    try:
        check(brk)
        return None
    except Fail as e:
        return str(e)


def main():
    t0 = time.monotonic()
    bad = 0
    for c in CHECKS:
        err = run(c)
        print("%-22s %s" % (c.__name__, "ok" if err is None else "FAIL: " + err))
        bad += err is not None
    if "--variants" in sys.argv:
        out = subprocess.run([sys.executable, IUT, "--list-breaks"], capture_output=True, text=True)
        names = [l.split()[0] for l in out.stdout.splitlines() if l.strip()]
        for n in names:
            c = CATCH.get(n)
            err = run(c, n) if c else None
            caught = err is not None
            print("variant %-24s %s" % (n, ("caught by %s: %s" % (c.__name__, err)) if caught else "NOT CAUGHT"))
            bad += not caught
    print("%s in %.1f s" % ("PASS" if bad == 0 else "FAIL (%d)" % bad, time.monotonic() - t0))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
