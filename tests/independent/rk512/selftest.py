#!/usr/bin/env python3
"""Self-test for iut_rk512.py, in real time, standard library only.

    python3 selftest.py              # back-to-back pair + scripted-partner checks
    python3 selftest.py --variants   # also: every --break variant fails >= 1 check

1. Back to back: two stations (one high, one low priority) joined through pipes
   by a relay that records the wire.  Both run a request script at the same time
   (quasi-full-duplex): SEND and FETCH of 200 bytes and more.  Every RESULT must
   come, FETCHED data must equal what was sent or the pattern memory, and the
   recorded frames must carry the headers the rules give.
2. Scripted partner: this file plays the partner on the line (its own small
   3964R sender/receiver) and checks exact frames, REATELs, timers, RESULTs.
   Expected bytes are built here from the rules, not copied from the station.
"""
import os
import queue
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
TMP = tempfile.TemporaryDirectory(prefix="rk512-selftest-")      # request scripts
IUT = os.path.join(HERE, "iut_rk512.py")
STX, ETX, DLE, NAK = 0x02, 0x03, 0x10, 0x15


class Fail(Exception):
    pass


def stuffed_block(payload):
    body = bytearray()
    for b in payload:
        body.append(b)
        if b == DLE:
            body.append(DLE)
    body += bytes([DLE, ETX])
    bcc = 0
    for b in body:
        bcc ^= b
    body.append(bcc)
    return bytes(body)


def pattern_db(n, i):
    return (n + i) & 0xFF


def seed_data(length, seed=0x10):
    return bytes((seed + 7 * i) & 0xFF for i in range(length))


def write_script(tmp, name, lines):
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


class Proc:
    """An IUT process; stderr lines are collected."""

    def __init__(self, args):
        self.p = subprocess.Popen([sys.executable, IUT] + list(args), stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, bufsize=0)
        self.lines = []
        threading.Thread(target=self._err, daemon=True).start()

    def _err(self):
        for line in self.p.stderr:
            self.lines.append(line.decode().strip())

    def results(self):
        return [ln for ln in self.lines if ln.startswith("RESULT ")]

    def close(self):
        for f in (self.p.stdin,):
            try:
                f.close()
            except OSError:
                pass
        try:
            self.p.wait(2)
        except subprocess.TimeoutExpired:
            self.p.kill()
            self.p.wait()


# ============================================================ 1. back to back
def decode_wire(log, with_bcc=True):
    """Split a recorded two-way 3964R exchange (clean line) into blocks:
    [(direction, payload)].  Setup: STX from X, acknowledged by DLE from Y; a
    station that answers DLE while its own STX is out has yielded a conflict."""
    state = {"A": "idle", "B": "idle"}
    buf = {"A": None, "B": None}
    blocks = []
    for d, b in log:
        o = "B" if d == "A" else "A"
        st = state[d]
        if st == "data":
            if b == DLE:
                state[d] = "dle"
            else:
                buf[d].append(b)
        elif st == "dle":
            if b == DLE:
                buf[d].append(DLE)
                state[d] = "data"
            elif b == ETX and with_bcc:
                state[d] = "bcc"
            elif b == ETX:
                blocks.append((d, bytes(buf[d])))
                state[d] = "idle"
            else:
                raise Fail("wire: DLE + %02x inside a block from %s" % (b, d))
        elif st == "bcc":
            blocks.append((d, bytes(buf[d])))
            state[d] = "idle"
        elif b == STX:
            state[d] = "stx"
        elif b == DLE:
            if st == "stx":
                state[d] = "idle"            # yielded (low priority)
            if state[o] == "stx":
                state[o] = "data"
                buf[o] = bytearray()
    return blocks


def c_back_to_back(brk=None, link="3964R"):
    tmp = TMP.name
    a_script = write_script(tmp, "a.txt", [
        # both stations send their start-up NAK; a STX that crosses the
        # partner's start-up NAK is a failed setup (0702) and, over plain 3964
        # without BCC, can corrupt the first block: start after the NAKs
        "wait 300",
        "send DB10:DW0:LEN=200",
        "fetch DB10:DW0:LEN=200",
        "fetch DB20:DW0:LEN=200",
        "fetch Z:5:LEN=20",
        "send DB11:OFF=7:LEN=11:DATA=0102030405060708090A0B",
        "fetch DB11:DW3:LEN=12",
        "fetch DB250:DW0:LEN=4        # no such DB: 14h",
        "send DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004",
        "fetch DX7:DW3:LEN=5",
        "fetch E:0:LEN=10",
    ])
    b_script = write_script(tmp, "b.txt", [
        "wait 400",
        "send DB30:DW0:LEN=300",
        "fetch M:0:LEN=8",
        "fetch DB30:DW0:LEN=300",
    ])
    common = ["--tres-ms", "5000", "--link", link]  # 9600 bit/s, 11-bit characters
    extra = ["--break", brk] if brk else []
    A = Proc(common + ["--priority", "high", "--requests", a_script] + extra)
    B = Proc(common + ["--priority", "low", "--requests", b_script] + extra)
    log = []
    lock = threading.Lock()

    def relay(src, dst, d):
        fd = src.p.stdout.fileno()
        while True:
            try:
                data = os.read(fd, 4096)
            except OSError:
                return
            if not data:
                return
            with lock:
                log.extend((d, b) for b in data)
            try:
                os.write(dst.p.stdin.fileno(), data)
            except OSError:
                return

    threading.Thread(target=relay, args=(A, B, "A"), daemon=True).start()
    threading.Thread(target=relay, args=(B, A, "B"), daemon=True).start()
    t0 = time.monotonic()
    while time.monotonic() - t0 < 30:
        if len(A.results()) >= 10 and len(B.results()) >= 3:
            break
        time.sleep(0.05)
    elapsed = time.monotonic() - t0
    time.sleep(0.2)
    A.close()
    B.close()
    ra, rb = A.results(), B.results()
    want_a = [
        "RESULT send:DB10:DW0:LEN=200 OK",
        "RESULT fetch:DB10:DW0:LEN=200 OK",
        "RESULT fetch:DB20:DW0:LEN=200 OK",
        "RESULT fetch:Z:5:LEN=20 OK",
        "RESULT send:DB11:OFF=7:LEN=11:DATA=0102030405060708090A0B OK",
        "RESULT fetch:DB11:DW3:LEN=12 OK",
        "RESULT fetch:DB250:DW0:LEN=4 STATUS 16#0903",
        "RESULT send:DX7:OFF=6:LEN=5:CF=12.3:CPU=2:DATA=0102031004 OK",
        "RESULT fetch:DX7:DW3:LEN=5 OK",
        "RESULT fetch:E:0:LEN=10 OK",
    ]
    want_b = [
        "RESULT send:DB30:DW0:LEN=300 OK",
        "RESULT fetch:M:0:LEN=8 OK",
        "RESULT fetch:DB30:DW0:LEN=300 OK",
    ]
    if ra != want_a:
        raise Fail("A results %s\n  want %s\n  A stderr: %s" % (ra, want_a, A.lines))
    if rb != want_b:
        raise Fail("B results %s\n  want %s\n  B stderr: %s" % (rb, want_b, B.lines))

    def fetched(lines, label):
        for ln in lines:
            if ln.startswith("FETCHED %s " % label):
                return bytes.fromhex(ln.split()[-1])
        raise Fail("no FETCHED line for %s" % label)

    checks = [
        (A.lines, "fetch:DB10:DW0:LEN=200", seed_data(200)),            # what A sent before
        (A.lines, "fetch:DB20:DW0:LEN=200", bytes(pattern_db(20, i) for i in range(200))),
        (A.lines, "fetch:Z:5:LEN=20", bytes((0x60 + 10 + i) & 0xFF for i in range(20))),
        (A.lines, "fetch:DB11:DW3:LEN=12", bytes(range(1, 12)) + b"\x00"),  # pad byte (R3.13)
        (A.lines, "fetch:DX7:DW3:LEN=5", bytes([1, 2, 3, 0x10, 4])),
        (A.lines, "fetch:E:0:LEN=10", bytes(0x40 + i for i in range(10))),
        (B.lines, "fetch:M:0:LEN=8", bytes(8)),
        (B.lines, "fetch:DB30:DW0:LEN=300", seed_data(300)),
    ]
    for lines, label, want in checks:
        got = fetched(lines, label)
        if got != want:
            raise Fail("%s fetched %s, want %s" % (label, got.hex(), want.hex()))
    blocks = decode_wire(log, link == "3964R")
    a_blocks = [p for d, p in blocks if d == "A"]
    b_blocks = [p for d, p in blocks if d == "B"]
    d200 = seed_data(200)
    need = [
        ("A", bytes([0, 0, 0x41, 0x44, 10, 0, 0, 100, 0xFF, 0x1F]) + d200[:128]),   # R3.x, Fig. 2-13
        ("A", bytes([0xFF, 0, 0x41, 0x44]) + d200[128:]),                             # R4.2
        ("A", bytes([0, 0, 0x45, 0x5A, 0, 5, 0, 10, 0xFF, 0x1F])),                    # R3.3, R3.10
        ("A", bytes([0, 0, 0x41, 0x44, 11, 3, 0, 6, 0xFF, 0x1F]) + bytes(range(1, 12)) + b"\x00"),
        ("A", bytes([0, 0, 0x4F, 0x44, 7, 3, 0, 3, 12, 0x23, 1, 2, 3, 0x10, 4, 0])),  # R3.17
        ("B", bytes([0, 0, 0, 0x14])),                                                # REATEL 14h
        ("B", bytes([0xFF, 0, 0, 0])),
        ("A", bytes([0xFF, 0, 0x45, 0x44])),
    ]
    for d, payload in need:
        if payload not in (a_blocks if d == "A" else b_blocks):
            raise Fail("frame %s from %s not on the wire" % (payload.hex(" "), d))
    return "%d blocks A->B, %d blocks B->A, all 13 requests in %.2f s" % (
        len(a_blocks), len(b_blocks), elapsed)


# ============================================================ 2. scripted partner
class Peer(Proc):
    """The IUT with this script playing the partner on its line."""

    def __init__(self, args):
        super().__init__(args)
        self.q = queue.Queue()
        threading.Thread(target=self._rd, daemon=True).start()

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

    def send(self, data):
        # the IUT reads PARMRK marks (FAST has --parmrk): a data FF goes as FF FF
        os.write(self.p.stdin.fileno(), bytes(data).replace(b"\xff", b"\xff\xff"))

    def get(self, timeout, what):
        try:
            t, b = self.q.get(timeout=max(0.0, timeout))
        except queue.Empty:
            raise Fail("%s: timeout" % what)
        if b is None:
            raise Fail("%s: IUT closed its output" % what)
        return t, b

    def expect(self, data, timeout, what):
        t0 = None
        for want in bytes(data):
            t, b = self.get(timeout, what)
            if b != want:
                raise Fail("%s: expected %02x, got %02x" % (what, want, b))
            t0 = t if t0 is None else t0
        return t0

    def silence(self, dur, what):
        try:
            t, b = self.q.get(timeout=dur)
        except queue.Empty:
            return
        raise Fail("%s: expected silence, got %s" % (what, "EOF" if b is None else "%02x" % b))

    def send_block(self, payload, what):
        self.send([STX])
        self.expect([DLE], 1.0, what + " (DLE after STX)")
        self.send(stuffed_block(payload))
        self.expect([DLE], 1.0, what + " (DLE after block)")

    def recv_block(self, timeout, what):
        """Receive one block as a correct 3964R receiver would; any error fails."""
        self.expect([STX], timeout, what + " (STX)")
        self.send([DLE])
        body = bytearray()
        payload = bytearray()
        while True:
            _, b = self.get(0.5, what + " (data)")
            body.append(b)
            if b != DLE:
                payload.append(b)
                continue
            _, c = self.get(0.5, what + " (after DLE)")
            body.append(c)
            if c == DLE:
                payload.append(DLE)
            elif c == ETX:
                break
            else:
                raise Fail("%s: DLE + %02x inside the block" % (what, c))
        _, bcc = self.get(0.5, what + " (BCC)")
        x = 0
        for b in body:
            x ^= b
        if x != bcc:
            raise Fail("%s: BCC %02x, computed %02x" % (what, bcc, x))
        self.send([DLE])
        return bytes(payload)

    def expect_block(self, want, timeout, what):
        got = self.recv_block(timeout, what)
        if got != bytes(want):
            raise Fail("%s:\n   got  %s\n   want %s" % (what, got.hex(" "), bytes(want).hex(" ")))

    def wait_result(self, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            r = self.results()
            if r:
                return r[0], time.monotonic()
            time.sleep(0.01)
        raise Fail("no RESULT line within %.1f s (stderr: %s)" % (timeout, self.lines))


FAST = ["--cdt-ms", "50", "--adt-ms", "300", "--baud", "38400", "--parmrk", "--tres-ms", "1000"]


def peer(extra, brk, script=None):
    args = list(FAST) + list(extra)
    if script is not None:
        args += ["--requests", write_script(TMP.name, "s.txt", script)]
    if brk:
        args += ["--break", brk]
    p = Peer(args)
    p.expect([NAK], 2.0, "start-up NAK")
    return p


def cmd(b3, b4, b5, b6, length, b9=0xFF, b10=0x1F):
    return bytes([0, 0, b3, b4, b5, b6, length >> 8, length & 0xFF, b9, b10])


def c_back_to_back_3964(brk=None):
    """The same pair with plain 3964 (no BCC) as the link (R1.6, AMB-27)."""
    return c_back_to_back(brk, "3964")


def c_p_fetch_300(brk=None):
    """Passive FETCH 300 bytes from DB 10 (Example 4 layout; DB10 byte 6 = 10h is doubled)."""
    p = peer([], brk)
    data = bytes(pattern_db(10, i) for i in range(300))
    p.send_block(cmd(0x45, 0x44, 10, 0, 150), "FETCH command")
    p.expect_block(bytes(4) + data[:128], 1.0, "first response")
    p.send_block(bytes([0xFF, 0, 0x45, 0x44]), "1st continuation")
    p.expect_block(bytes([0xFF, 0, 0, 0]) + data[128:256], 1.0, "1st continuation response")
    p.send_block(bytes([0xFF, 0, 0x45, 0x44]), "2nd continuation")
    p.expect_block(bytes([0xFF, 0, 0, 0]) + data[256:], 1.0, "2nd continuation response")
    p.silence(0.2, "after the last response")
    p.close()


def c_p_no_db(brk=None):
    """Passive FETCH from a DB that does not exist -> REATEL 14h, no data (Table 8-3)."""
    p = peer([], brk)
    p.send_block(cmd(0x45, 0x44, 250, 0, 2), "FETCH DB 250")
    p.expect_block(bytes([0, 0, 0, 0x14]), 1.0, "error response")
    p.close()
    if "STATUS 16#0606" not in p.lines:
        raise Fail("no STATUS 16#0606: %s" % p.lines)


def c_p_short_send(brk=None):
    """Passive SEND announcing 6 words with 10 data bytes -> REATEL 34h; nothing written."""
    p = peer([], brk)
    p.send_block(cmd(0x41, 0x44, 10, 0, 6) + bytes(range(0x50, 0x5A)), "short SEND")
    p.expect_block(bytes([0, 0, 0, 0x34]), 1.0, "error response")
    p.send_block(cmd(0x45, 0x44, 10, 0, 5), "FETCH back")
    p.expect_block(bytes(4) + bytes(pattern_db(10, i) for i in range(10)), 1.0, "DB 10 unchanged")
    p.close()


def c_p_cont_timeout(brk=None):
    """Passive: continuation after T_RES (1 s) -> aborted, REATEL 36h; one in time is served."""
    p = peer([], brk)
    data = bytes(pattern_db(12, i) for i in range(200))
    p.send_block(cmd(0x45, 0x44, 12, 0, 100), "FETCH 200")
    p.expect_block(bytes(4) + data[:128], 1.0, "first response")
    time.sleep(0.6)
    p.send_block(bytes([0xFF, 0, 0x45, 0x44]), "continuation in time")
    p.expect_block(bytes([0xFF, 0, 0, 0]) + data[128:], 1.0, "continuation response")
    p.send_block(cmd(0x45, 0x44, 12, 0, 100), "FETCH 200 again")
    p.expect_block(bytes(4) + data[:128], 1.0, "first response")
    time.sleep(1.5)
    p.send_block(bytes([0xFF, 0, 0x45, 0x44]), "late continuation")
    p.expect_block(bytes([0xFF, 0, 0, 0x36]), 1.0, "sync error response")
    p.close()


def c_p_flag(brk=None):
    """Passive coordination flag 3.5, set at start, reset by the application after 1 s."""
    p = peer(["--cf-set", "3.5@1000"], brk)
    send = cmd(0x41, 0x44, 10, 0, 1, 3, 0x15) + b"\xAB\xCD"
    p.send_block(send, "SEND with flag 3.5")
    p.expect_block(bytes([0, 0, 0, 0x32]), 1.0, "locked")
    time.sleep(1.1)
    p.send_block(send, "SEND after the reset")
    p.expect_block(bytes(4), 1.0, "accepted")
    p.send_block(send, "SEND again at once")
    p.expect_block(bytes([0, 0, 0, 0x32]), 1.0, "locked by the transfer")
    p.close()


def c_p_unsolicited(brk=None):
    """Passive: a response without a request gets no RK 512 answer; a continuation
    without a request gets 36h with byte 1 = FFh."""
    p = peer([], brk)
    p.send_block(bytes(4), "unsolicited response")
    p.silence(0.3, "after the unsolicited response")
    p.send_block(bytes([0xFF, 0, 0x41, 0x44, 1, 2]), "stray continuation")
    p.expect_block(bytes([0xFF, 0, 0, 0x36]), 1.0, "sync error response")
    p.close()
    if "STATUS 16#0A01" not in p.lines or "STATUS 16#060E" not in p.lines:
        raise Fail("STATUS lines %s" % p.lines)


def c_a_send_200(brk=None):
    """Active SEND 200 bytes to DB 10: header in words, 128-byte chunks, FF 00 41 44."""
    p = peer([], brk, ["send DB10:DW0:LEN=200"])
    d = seed_data(200)
    p.expect_block(bytes([0, 0, 0x41, 0x44, 10, 0, 0, 100, 0xFF, 0x1F]) + d[:128], 1.0, "first frame")
    p.send_block(bytes(4), "response")
    p.expect_block(bytes([0xFF, 0, 0x41, 0x44]) + d[128:], 1.0, "continuation")
    p.send_block(bytes([0xFF, 0, 0, 0]), "continuation response")
    r, _ = p.wait_result(1.0)
    p.close()
    if r != "RESULT send:DB10:DW0:LEN=200 OK":
        raise Fail(r)


def c_a_fetch_counters(brk=None):
    """Active FETCH of 10 counters from C 5: 45 5A, cell number, 10 words."""
    p = peer([], brk, ["fetch Z:5:LEN=20"])
    p.expect_block(bytes([0, 0, 0x45, 0x5A, 0, 5, 0, 10, 0xFF, 0x1F]), 1.0, "FETCH command")
    data = bytes(range(0x0A, 0x1E))                 # contains 10h
    p.send_block(bytes(4) + data, "response")
    r, _ = p.wait_result(1.0)
    p.close()
    if r != "RESULT fetch:Z:5:LEN=20 OK" or ("FETCHED fetch:Z:5:LEN=20 " + data.hex()) not in p.lines:
        raise Fail("%s / %s" % (r, p.lines))


def c_a_odd_send(brk=None):
    """Active SEND LEN=11 at OFF=7: DW 3, 6 words, data padded with 00h (R3.5, R3.13)."""
    p = peer([], brk, ["send DB10:OFF=7:LEN=11:DATA=0102030405060708090A0B"])
    p.expect_block(bytes([0, 0, 0x41, 0x44, 10, 3, 0, 6, 0xFF, 0x1F]) + bytes(range(1, 12)) + b"\x00",
                   1.0, "SEND frame")
    p.send_block(bytes(4), "response")
    p.wait_result(1.0)
    p.close()


def c_a_reatels(brk=None):
    """Active: REATEL 14h -> 16#0903, unknown REATEL 01h -> 16#090E (Table 8-3)."""
    p = peer([], brk, ["fetch DB10:DW0:LEN=4", "fetch DB10:DW0:LEN=4"])
    p.expect_block(cmd(0x45, 0x44, 10, 0, 2), 1.0, "1st FETCH")
    p.send_block(bytes([0, 0, 0, 0x14]), "REATEL 14h")
    p.expect_block(cmd(0x45, 0x44, 10, 0, 2), 1.0, "2nd FETCH")
    p.send_block(bytes([0, 0, 0, 0x01]), "REATEL 01h")
    end = time.monotonic() + 1.0
    while len(p.results()) < 2 and time.monotonic() < end:
        time.sleep(0.01)
    p.close()
    want = ["RESULT fetch:DB10:DW0:LEN=4 STATUS 16#0903", "RESULT fetch:DB10:DW0:LEN=4 STATUS 16#090E"]
    if p.results() != want:
        raise Fail("%s" % p.results())


def c_a_tres(brk=None):
    """Active: a withheld response ends the request with 16#0A05 after T_RES (1 s)."""
    p = peer([], brk, ["send DB10:DW0:LEN=2"])
    p.expect_block(cmd(0x41, 0x44, 10, 0, 1) + seed_data(2), 1.0, "SEND frame")
    t0 = time.monotonic()
    r, t = p.wait_result(2.0)
    p.silence(0.2, "after T_RES")
    p.close()
    if r != "RESULT send:DB10:DW0:LEN=2 STATUS 16#0A05" or not 0.9 <= t - t0 <= 1.3:
        raise Fail("%s after %.2f s" % (r, t - t0))


def c_a_quasi_duplex(brk=None):
    """Active SEND 200 waiting for its response; the partner first sends its own
    FETCH (answered), then the response: the request goes on (R8.4, A-08)."""
    p = peer([], brk, ["send DB10:DW0:LEN=200"])
    d = seed_data(200)
    p.expect_block(bytes([0, 0, 0x41, 0x44, 10, 0, 0, 100, 0xFF, 0x1F]) + d[:128], 1.0, "first frame")
    p.send_block(cmd(0x45, 0x44, 20, 0, 2), "partner's own FETCH")
    p.expect_block(bytes(4) + bytes(pattern_db(20, i) for i in range(4)), 1.0, "answer to the FETCH")
    p.send_block(bytes(4), "response to the first frame")
    p.expect_block(bytes([0xFF, 0, 0x41, 0x44]) + d[128:], 1.0, "continuation")
    p.send_block(bytes([0xFF, 0, 0, 0]), "continuation response")
    r, _ = p.wait_result(1.0)
    p.close()
    if r != "RESULT send:DB10:DW0:LEN=200 OK":
        raise Fail(r)


def win_line(p, what):
    """Send STX at once (crossing the IUT's STX, if any) and wait for its DLE:
    the IUT has low priority and must yield (3964R initialization conflict)."""
    p.send([STX])
    end = time.monotonic() + 1.0
    while True:
        _, b = p.get(end - time.monotonic(), what)
        if b == DLE:
            return
        if b != STX:
            raise Fail("%s: got %02x" % (what, b))


def c_a_response_before_cont(brk=None):
    """Active SEND 200: a second response arrives before the continuation went
    out -> 16#0A01, request ended, no continuation afterwards (A-07)."""
    p = peer([], brk, ["send DB10:DW0:LEN=200"])
    d = seed_data(200)
    p.expect_block(bytes([0, 0, 0x41, 0x44, 10, 0, 0, 100, 0xFF, 0x1F]) + d[:128], 1.0, "first frame")
    p.send_block(bytes(4), "response")
    win_line(p, "extra response setup")
    p.send(stuffed_block(bytes(4)))
    p.expect([DLE], 1.0, "extra response acknowledged")
    r, _ = p.wait_result(1.0)
    p.silence(0.6, "no continuation after the abort")
    p.close()
    if r != "RESULT send:DB10:DW0:LEN=200 STATUS 16#0A01":
        raise Fail(r)


def c_p_pipelined(brk=None):
    """Passive: a second command before the response to the first -> the first is
    answered, the second gets 36h (R8.6, P-09c)."""
    p = peer([], brk)
    p.send_block(cmd(0x41, 0x44, 10, 0, 1) + b"\xAB\xCD", "SEND")
    win_line(p, "second command setup")
    p.send(stuffed_block(cmd(0x45, 0x44, 10, 0, 1)))
    p.expect([DLE], 1.0, "second command acknowledged")
    p.expect_block(bytes(4), 1.0, "response to the SEND")
    p.expect_block(bytes([0, 0, 0, 0x36]), 1.0, "sync error for the second command")
    p.close()
    if "STATUS 16#060E" not in p.lines:
        raise Fail("STATUS lines %s" % p.lines)


CHECKS = [c_back_to_back, c_back_to_back_3964, c_p_fetch_300, c_p_no_db, c_p_short_send, c_p_cont_timeout, c_p_flag,
          c_p_unsolicited, c_p_pipelined, c_a_send_200, c_a_fetch_counters, c_a_odd_send, c_a_reatels,
          c_a_tres, c_a_quasi_duplex, c_a_response_before_cont]


def run(brk=None, stop_at_first_fail=False):
    failed = []
    for c in CHECKS:
        t0 = time.monotonic()
        try:
            info = c(brk)
            ok = True
        except Fail as e:
            ok = False
            info = str(e)
        dt = time.monotonic() - t0
        if brk is None:
            print("%-20s %s %5.2f s  %s" % (c.__name__, "ok  " if ok else "FAIL", dt,
                                           (c.__doc__ or "").strip().splitlines()[0] if ok and not info else info))
        if not ok:
            failed.append((c.__name__, info))
            if stop_at_first_fail:
                break
    return failed


def main():
    failed = run()
    print("correct station: %d/%d checks passed" % (len(CHECKS) - len(failed), len(CHECKS)))
    rc = 1 if failed else 0
    if "--variants" in sys.argv:
        names = subprocess.run([sys.executable, IUT, "--list-breaks"], capture_output=True,
                               text=True, check=True).stdout.split("\n")
        names = [n.split()[0] for n in names if n.strip()]
        for n in names:
            f = run(n, stop_at_first_fail=True)
            if f:
                print("variant %-26s caught by %s: %s" % (n, f[0][0], f[0][1].splitlines()[0][:100]))
            else:
                print("variant %-26s NOT CAUGHT" % n)
                rc = 1
    return rc


if __name__ == "__main__":
    sys.exit(main())
