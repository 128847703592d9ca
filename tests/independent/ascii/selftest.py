#!/usr/bin/env python3
"""Self-test for iut_ascii.py, in real time.

    python3 selftest.py              # pair checks + partner checks, correct station
    python3 selftest.py --variants   # also: every --break variant fails a partner check
    python3 selftest.py -k NAME      # only the checks whose name contains NAME

Pair checks wire two instances back to back through pipes (with a tap in the
middle that records the line in both directions): station A issues send jobs,
station B receives them and echoes them, A receives the echoes.  Every end
criterion is covered, with and without XON/XOFF, at 8 and 7 data bits.

Partner checks drive one instance, the test playing the partner on the line.
The expected bytes are derived here from the rules, never read back from the
station.
"""
import os
import queue
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
IUT = os.path.join(HERE, "iut_ascii.py")
XON, XOFF = 0x11, 0x13


class Fail(Exception):
    pass


def hx(b):
    return bytes(b).hex(" ")


# ------------------------------------------------------------------ processes
class Proc:
    """One station as a subprocess; stderr lines collected with arrival times."""

    def __init__(self, args, brk=None):
        cmd = [sys.executable, IUT] + list(args) + ["--trace"]
        if brk:
            cmd += ["--break", brk]
        self.cmd = cmd
        self.p = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, bufsize=0)
        self.lines = []
        self._t = threading.Thread(target=self._err, daemon=True)
        self._t.start()

    def wait_ready(self, timeout=5.0):
        """--trace prints READY once the station runs (self-test aid only)."""
        end = time.monotonic() + timeout
        while not any(s == "READY" for _, s in self.lines):
            if time.monotonic() > end:
                raise Fail("station not ready after %.0f s" % timeout)
            time.sleep(0.005)
        time.sleep(0.02)

    def _err(self):
        for line in self.p.stderr:
            self.lines.append((time.monotonic(), line.decode(errors="replace").strip()))

    def statuses(self):
        return [s.split()[1] for _, s in self.lines if s.startswith("STATUS ")]

    def traced(self, kind):
        return [bytes.fromhex(s[len(kind) + 1:]) for _, s in self.lines if s.startswith(kind + " ")]

    def stop(self):
        try:
            self.p.stdin.close()
        except OSError:
            pass
        try:
            self.p.wait(2)
        except subprocess.TimeoutExpired:
            self.p.kill()
            self.p.wait()
            raise Fail("station did not exit on EOF")
        self._t.join(1)


class Partner:
    """The test as the partner of one station: what it sends, what it reads."""

    def __init__(self, args, brk=None):
        self.s = Proc(args, brk)
        self.q = queue.Queue()
        self.rx = []                      # (time, byte) as read from the station
        threading.Thread(target=self._rd, daemon=True).start()

    def _rd(self):
        fd = self.s.p.stdout.fileno()
        while True:
            d = os.read(fd, 4096)
            t = time.monotonic()
            if not d:
                self.q.put((t, None))
                return
            for b in d:
                self.q.put((t, b))

    def send(self, data, pace=None):
        """Write bytes; with pace (seconds) one byte at a time."""
        fd = self.s.p.stdin.fileno()
        if pace is None:
            os.write(fd, bytes(data))
        else:
            for b in bytes(data):
                os.write(fd, bytes([b]))
                time.sleep(pace)
        return time.monotonic()

    def get(self, timeout):
        try:
            t, b = self.q.get(timeout=max(0.0, timeout))
        except queue.Empty:
            return None, None
        if b is None:
            raise Fail("station closed its output")
        self.rx.append((t, b))
        return t, b

    def expect(self, data, timeout=1.0, what=""):
        """Exactly these bytes next; returns the arrival time of each."""
        times, got = [], bytearray()
        end = time.monotonic() + timeout
        for want in bytes(data):
            t, b = self.get(end - time.monotonic())
            if b is None:
                raise Fail("%s: expected %s, got %s, then nothing" % (what, hx(data), hx(got)))
            got.append(b)
            if b != want:
                raise Fail("%s: expected %s, got %s" % (what, hx(data), hx(got)))
            times.append(t)
            end = max(end, time.monotonic() + 0.2)
        return times

    def silence(self, dur, what=""):
        t, b = self.get(dur)
        if b is not None:
            raise Fail("%s: expected silence, got %02x" % (what, b))

    def collect(self, dur):
        out = bytearray()
        end = time.monotonic() + dur
        while True:
            t, b = self.get(end - time.monotonic())
            if b is None:
                return bytes(out)
            out.append(b)

    def status(self, code, wait=0.0):
        end = time.monotonic() + wait
        while True:
            if code in self.s.statuses():
                return True
            if time.monotonic() >= end:
                return False
            time.sleep(0.005)

    def close(self):
        self.s.stop()


class Pair:
    """Two stations back to back through pipes, with a recording tap."""

    def __init__(self, args_a, args_b):
        # B first, so that it is reading before A's first job goes out
        self.b = Proc(args_b)
        self.b.wait_ready()
        self.a = Proc(args_a)
        self.wire = {"AB": [], "BA": []}
        self._th = [threading.Thread(target=self._fwd, args=(self.a, self.b, "AB"), daemon=True),
                    threading.Thread(target=self._fwd, args=(self.b, self.a, "BA"), daemon=True)]
        for t in self._th:
            t.start()

    def _fwd(self, src, dst, key):
        rfd, wfd = src.p.stdout.fileno(), dst.p.stdin.fileno()
        while True:
            d = os.read(rfd, 4096)
            if not d:
                return
            t = time.monotonic()
            self.wire[key].extend((t, b) for b in d)
            try:
                os.write(wfd, d)
            except OSError:
                return

    def wait_for(self, pred, timeout, what):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if pred():
                return
            time.sleep(0.01)
        raise Fail("%s (A: %s | B: %s)" % (what, self.a.lines, self.b.lines))

    def close(self):
        self.a.stop()
        self.b.stop()


def gaps(times_bytes, frames):
    """Idle times between consecutive frames in a recorded direction, given
    the frame lengths in order (flow-control bytes already removed)."""
    out, i = [], 0
    for n in frames[:-1]:
        i += n
        out.append(times_bytes[i][0] - times_bytes[i - 1][0])
    return out


# ------------------------------------------------------------------ pair checks
PAIR_CDT_MS = "50"                # generous: two stations and a tap share the CPU
PAIR_CDT = 0.050
def pair_run(common_a, common_b, jobs, expect_b, expect_a, timeout=3.0):
    args_a = common_a + ["--send-trigger", "none"]
    for j in jobs:
        args_a += ["--send", j.hex()]
    pr = Pair(args_a, common_b)
    try:
        pr.wait_for(lambda: pr.b.traced("READ") == expect_b and pr.a.traced("READ") == expect_a,
                    timeout, "frames did not go through: B read %s, A read %s"
                    % ([hx(x) for x in pr.b.traced("READ")], [hx(x) for x in pr.a.traced("READ")]))
        time.sleep(0.1)
        if pr.a.statuses() or pr.b.statuses():
            raise Fail("unexpected STATUS: A %s, B %s" % (pr.a.statuses(), pr.b.statuses()))
    finally:
        pr.close()
    return pr


def p_cdt():
    # no --parmrk: the tap passes the bytes as they are, so a data FF is a plain FF
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "cdt"]
    jobs = [b"Hello", b"World", bytes(range(0xF0, 0x100))]
    pr = pair_run(c, c, jobs, jobs, jobs)
    for key in ("AB", "BA"):
        g = gaps(pr.wire[key], [len(j) for j in jobs])
        if min(g) <= PAIR_CDT:
            raise Fail("%s: pause between frames %s ms, CDT is %s ms" % (key, [round(x * 1000, 1) for x in g], PAIR_CDT_MS))


def p_end_char_up_to_end():
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "end_chars", "--end-chars", "03", "--send-variant", "up_to_end"]
    jobs = [bytes.fromhex("41 42 03 58 59"), bytes.fromhex("43 03")]
    want = [bytes.fromhex("41 42 03"), bytes.fromhex("43 03")]
    pair_run(c, c, jobs, want, want)


def p_end_char_len_with_end():
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "end_chars", "--end-chars", "0d", "--send-variant", "len_with_end"]
    jobs = [b"ab\r", b"\r", b"xyz\r"]
    pair_run(c, c, jobs, jobs, jobs)


def p_two_end_chars_append():
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "end_chars", "--end-chars", "0D,0A",
         "--send-variant", "len_append_end"]
    jobs = [b"AB", b"C\rD"]
    at_b = [b"AB\r\n", b"C\rD\r\n"]
    # B's echo of "AB\r\n" under the same variant is "AB\r\n\r\n": A sees two frames
    at_a = [b"AB\r\n", b"\r\n", b"C\rD\r\n", b"\r\n"]
    pair_run(c, c, jobs, at_b, at_a)


def p_fixed_pause():
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "fixed_length", "--fixed-length", "5"]
    jobs = [b"12345", b"67890", b"abcde"]
    pr = pair_run(c, c, jobs, jobs, jobs)
    g = gaps(pr.wire["AB"], [5, 5, 5])
    if min(g) <= PAIR_CDT:
        raise Fail("fixed length: pause %s ms, CDT is %s ms" % ([round(x * 1000, 1) for x in g], PAIR_CDT_MS))


def p_fixed_no_pause():
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "fixed_length", "--fixed-length", "3", "--no-send-pause"]
    jobs = [b"abc", b"def", b"ghi"]
    pr = pair_run(c, c, jobs, jobs, jobs)
    g = gaps(pr.wire["AB"], [3, 3, 3])
    if max(g) >= PAIR_CDT:
        raise Fail("fixed length without pause: gaps %s ms" % [round(x * 1000, 1) for x in g])


def p_xon_xoff(bits="8"):
    """B buffers 2 frames and reads slowly: B stops A with XOFF and releases it."""
    fl = ["--flow-control", "xon_xoff", "--data-bits", bits]
    a = ["--cdt-ms", "50", "--end-criterion", "fixed_length", "--fixed-length", "4"] + fl
    b = a + ["--buffer-frames", "2", "--echo-delay-ms", "300"]
    jobs = [b"AAAA", b"BBBB", b"CCCC", b"DDDD"]
    pr = pair_run(a, b, jobs, jobs, jobs, timeout=5.0)
    ab = [b for _, b in pr.wire["AB"]]
    ba = [b for _, b in pr.wire["BA"]]
    if not ab or ab[0] != XON or not ba or ba[0] != XON:
        raise Fail("no XON at start-up: A %s... B %s..." % (hx(ab[:3]), hx(ba[:3])))
    if XOFF not in ba:
        raise Fail("B never sent XOFF: %s" % hx(ba))
    # A must not send its third frame between B's XOFF and B's next XON
    t_xoff = next(t for t, b in pr.wire["BA"] if b == XOFF)
    t_xon = next(t for t, b in pr.wire["BA"] if b == XON and t > t_xoff)
    held = [b for t, b in pr.wire["AB"] if t_xoff + 0.005 < t < t_xon and b not in (XON, XOFF)]
    if held:
        raise Fail("A sent %s while stopped" % hx(held))
    if t_xon - t_xoff < 0.2:
        raise Fail("B released A after %.0f ms, echo delay is 300" % ((t_xon - t_xoff) * 1000))


def p_xon_xoff_7bit():
    p_xon_xoff("7")


def p_cdt_7bit_mask():
    c = ["--cdt-ms", PAIR_CDT_MS, "--end-criterion", "cdt", "--data-bits", "7", "--parity", "odd", "--stop-bits", "2"]
    jobs = [bytes.fromhex("c1 42 ff")]
    want = [bytes.fromhex("41 42 7f")]
    pair_run(c, c, jobs, want, want)


PAIR_CHECKS = [p_cdt, p_end_char_up_to_end, p_end_char_len_with_end, p_two_end_chars_append,
               p_fixed_pause, p_fixed_no_pause, p_xon_xoff, p_xon_xoff_7bit, p_cdt_7bit_mask]


# ------------------------------------------------------------------ partner checks
CDT = 0.030
CT = 11 / 9600.0                  # 8E1 at 9600
BASE = ["--cdt-ms", "30", "--parmrk"]
EC = BASE + ["--end-criterion", "end_chars"]
IDLE = 5 * CDT


def start(args, brk, xon=False):
    p = Partner(args, brk)
    p.s.wait_ready()
    if xon:
        p.expect([XON], 1.5, "start-up XON")
    return p


def c_startup_xon(brk=None):
    p = start(BASE + ["--flow-control", "xon_xoff"], brk, xon=True)
    p.silence(0.1, "after start-up XON")
    p.close()


def c_cdt_frames_and_pause(brk=None):
    """CDT criterion: a long frame, then a short one 2 CDT later.  The short
    one is stored while the long echo is still going out, so its echo must
    wait for the pause (> CDT after the long echo)."""
    p = start(BASE, brk)
    long_frame = bytes(range(0x20, 0x5C))          # 60 bytes, 69 ms at 9600
    p.send(long_frame)
    time.sleep(2 * CDT)
    p.send(b"CD")
    t1 = p.expect(long_frame, 1.0, "echo 1")
    t2 = p.expect(b"CD", 1.0, "echo 2")
    if t2[0] - t1[-1] <= CDT + CT:
        raise Fail("pause between sent frames %.1f ms (start to start), CDT %.0f ms"
                   % ((t2[0] - t1[-1]) * 1000, CDT * 1000))
    p.silence(0.1)
    p.close()


def c_cdt_long_frame(brk=None):
    """A frame that takes longer than the CDT but has no gap >= CDT is one
    frame: in the end-character criterion the CDT watchdog must not fire."""
    p = start(EC, brk)
    frame = b"0123456789\x03"
    p.send(frame, pace=0.008)                      # 88 ms in all, gaps 8 ms
    p.expect(frame, 1.0, "one frame")
    p.silence(0.1)
    if p.s.statuses():
        raise Fail("unexpected STATUS %s" % p.s.statuses())
    p.close()


def c_end_char_kept(brk=None):
    p = start(EC + ["--send-variant", "len_with_end"], brk)
    p.send(bytes.fromhex("41 42 03"))
    p.expect(bytes.fromhex("41 42 03"), 1.0, "echo with the end character")
    p.silence(0.1)
    p.close()


def c_two_end_chars(brk=None):
    p = start(BASE + ["--end-criterion", "end_chars", "--end-chars", "0D,0A"], brk)
    p.send(bytes.fromhex("41 0D 42 0D 0A"))
    p.expect(bytes.fromhex("41 0D 42 0D 0A"), 1.0, "lone 0D is data")
    p.silence(0.1)
    p.close()


def c_fragment_discarded(brk=None):
    """End characters: a fragment cut off by the CDT is discarded with 16#0806."""
    p = start(EC, brk)
    p.send(b"AB")
    time.sleep(IDLE)
    if not p.status("16#0806", 1.0):
        raise Fail("no STATUS 16#0806 for the fragment: %s" % p.s.statuses())
    p.send(bytes.fromhex("43 03"))
    p.expect(bytes.fromhex("43 03"), 1.0, "only the second frame")
    p.silence(0.1)
    p.close()


def c_fixed_length(brk=None):
    p = start(BASE + ["--end-criterion", "fixed_length", "--fixed-length", "5"], brk)
    p.send(b"1234567")
    p.expect(b"12345", 1.0, "first 5 characters")
    p.silence(IDLE, "surplus discarded")
    if not p.status("16#0806", 1.0):
        raise Fail("no STATUS 16#0806 for the surplus: %s" % p.s.statuses())
    p.send(b"abcde")
    p.expect(b"abcde", 1.0, "next frame")
    p.close()


def c_variant_c(brk=None):
    p = start(EC + ["--send-variant", "len_append_end"], brk)
    p.send(bytes.fromhex("41 03"))
    p.expect(bytes.fromhex("41 03 03"), 1.0, "LEN bytes plus the end character")
    p.silence(0.1)
    p.close()


def c_parity_error(brk=None):
    p = start(BASE, brk)
    p.send(bytes.fromhex("41 FF 00 42 43"))       # 42 with a parity error
    time.sleep(IDLE)
    p.send(bytes.fromhex("51 52 FF FF"))          # FF FF is data FF
    p.expect(bytes.fromhex("51 52 FF"), 1.0, "only the good frame")
    p.silence(0.1)
    p.status("16#080C", 1.0)
    if p.s.statuses() != ["16#080C"]:
        raise Fail("expected one STATUS 16#080C, got %s" % p.s.statuses())
    p.close()


def c_break(brk=None):
    p = start(EC, brk)
    p.send(bytes.fromhex("41 42 FF 00 00"))
    time.sleep(IDLE)
    p.silence(0.05, "no echo of a broken frame")
    p.status("16#080D", 1.0)
    if p.s.statuses() != ["16#080D"]:
        raise Fail("expected one STATUS 16#080D, got %s" % p.s.statuses())
    p.send(bytes.fromhex("44 03"))
    p.expect(bytes.fromhex("44 03"), 1.0, "after BREAK")
    p.close()


def c_buffer_full(brk=None):
    """Two frame places, prevent overwrite, slow reader: the third frame is
    lost with 16#080A and the first two come back oldest first."""
    p = start(EC + ["--buffer-frames", "2", "--echo-delay-ms", "200"], brk)
    p.send(bytes.fromhex("41 03 42 03 43 03"))
    if not p.status("16#080A", 1.0):
        raise Fail("no STATUS 16#080A: %s" % p.s.statuses())
    p.expect(bytes.fromhex("41 03 42 03"), 1.0, "oldest first, third frame lost")
    p.silence(0.3)
    p.close()


def c_xoff_at_frame_count(brk=None):
    p = start(EC + ["--flow-control", "xon_xoff", "--buffer-frames", "2", "--echo-delay-ms", "300"],
              brk, xon=True)
    p.send(bytes.fromhex("41 03"))
    p.silence(0.05, "one frame buffered")
    ts = p.send(bytes.fromhex("42 03"))
    t = p.expect([XOFF], 0.1, "XOFF after the second frame")[0]
    if t - ts > 0.05:
        raise Fail("XOFF %.0f ms late" % ((t - ts) * 1000))
    p.expect([XON], 0.6, "XON after the first read")
    p.expect(bytes.fromhex("41 03 42 03"), 1.0, "echoes")
    p.silence(0.2)
    p.close()


def c_xoff_obeyed(brk=None):
    p = start(BASE + ["--flow-control", "xon_xoff"], brk, xon=True)
    frame = bytes(range(0x20, 0x48))               # 40 bytes, no XON/XOFF inside
    p.send(frame)
    p.expect(frame[:5], 1.0, "start of the echo")
    p.send([XOFF])
    rest = p.collect(0.3)
    if len(rest) > 3:
        raise Fail("%d bytes sent after XOFF" % len(rest))
    p.send([XON])
    p.expect(frame[5 + len(rest):], 1.0, "rest of the echo after XON")
    p.silence(0.1)
    if p.s.statuses():
        raise Fail("unexpected STATUS %s" % p.s.statuses())
    p.close()


def c_xon_wait(brk=None):
    p = start(BASE + ["--flow-control", "xon_xoff", "--xon-wait-ms", "200"], brk, xon=True)
    p.send([XOFF])
    ts = p.send(b"abc")
    p.silence(CDT + 0.1, "held by XOFF")
    if not p.status("16#0708", 1.0):
        raise Fail("no STATUS 16#0708: %s" % p.s.statuses())
    t = next(t for t, s in p.s.lines if s == "STATUS 16#0708")
    dt = t - ts - CDT
    if not 0.15 <= dt <= 0.35:
        raise Fail("16#0708 after %.0f ms, wait time 200 ms" % (dt * 1000))
    p.send([XON])
    p.send(b"xy")
    p.expect(b"xy", 1.0, "next job after XON")
    p.close()


def c_eof(brk=None):
    p = start(BASE, brk)
    p.close()


PARTNER_CHECKS = [c_startup_xon, c_cdt_frames_and_pause, c_cdt_long_frame, c_end_char_kept, c_two_end_chars,
                  c_fragment_discarded, c_fixed_length, c_variant_c, c_parity_error, c_break, c_buffer_full,
                  c_xoff_at_frame_count, c_xoff_obeyed, c_xon_wait, c_eof]


def run_check(fn, brk=None):
    t0 = time.monotonic()
    try:
        fn(brk) if brk is not None else fn()
        return True, "", time.monotonic() - t0
    except Fail as e:
        return False, str(e), time.monotonic() - t0


def list_breaks():
    out = subprocess.run([sys.executable, IUT, "--list-breaks"], capture_output=True, text=True).stdout
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def main(argv):
    sel = None
    if "-k" in argv:
        sel = argv[argv.index("-k") + 1]
    t_all = time.monotonic()
    bad = 0
    n = 0
    for fn in PAIR_CHECKS + PARTNER_CHECKS:
        if sel and sel not in fn.__name__:
            continue
        n += 1
        ok, msg, dt = run_check(fn, None) if fn in PAIR_CHECKS else run_check(fn, "")
        print("%-4s %-28s %5.2f s %s" % ("ok" if ok else "FAIL", fn.__name__, dt, msg))
        bad += not ok
    print("%d checks, %d failed, %.1f s" % (n, bad, time.monotonic() - t_all))
    if "--variants" in argv:
        for v in list_breaks():
            caught = None
            for fn in PARTNER_CHECKS:
                ok, msg, _ = run_check(fn, v)
                if not ok:
                    caught = (fn.__name__, msg)
                    break
            if caught:
                print("killed   %-26s by %s: %s" % (v, caught[0], caught[1][:90]))
            else:
                print("SURVIVED %-26s" % v)
                bad += 1
        print("variants done, %.1f s in all" % (time.monotonic() - t_all))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
