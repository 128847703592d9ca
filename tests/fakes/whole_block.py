"""A stand-in IUT that writes everything it sends in one write: a whole block, BCC
included, reaches the pipe at once (as a driver that hands its UART a buffer and does not
wait for it to drain, seen over a pipe). Otherwise the reference model driven as ``ptpcert
iut`` drives it, with no pacing: once its block is written it waits for the release DLE.
STATUS lines on stderr, PARMRK marks read.

    whole_block.py [--cdt-ms N] [--adt-ms N] [--ignore-other-in-release] [--lag-ms N] [--trace DIR]

``--ignore-other-in-release`` breaks the release rule (§2.2.2 Send/release: any character
other than DLE is a failed attempt): such a character is ignored while it waits for DLE.

``--lag-ms N``: a slow stand-in, N ms between its model's handing a block over (and
starting its timers) and the block's write, as a process that builds its output late.

``--trace DIR`` writes DIR/<pid>.trace: every look at the input and every write, on the
monotonic clock the harness's transcript is timed by (its ``origin``), with the process's
CPU time and run-queue wait, to tell a late harness from a late stand-in.
"""
import argparse
import os
import sys
import time

from ptpcert.driver import drive_station
from ptpcert.iut import StdioEndpoint
from ptpcert.model.app import Host
from ptpcert.model.events import Status
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964


class OneWrite(StdioEndpoint):
    """stdin/stdout; what the station sends between two looks at the input goes out in
    one write."""

    def __init__(self):
        super().__init__(parmrk=True)
        self.buffer = bytearray()
        self.trace = None      # --trace: the trace file
        self.sched = None      # --trace: /proc/self/schedstat, kept open
        self.lag = 0.0         # --lag-ms, seconds


    def write(self, data):
        self.buffer += data
        return self.now()

    def poll(self, deadline):
        if self.buffer:
            if self.lag:
                time.sleep(self.lag)
            t = self.now()
            os.write(self.fd_out, bytes(self.buffer))
            self._log(f"W {t:.6f} {bytes(self.buffer).hex()}")
            self.buffer.clear()
        if self.trace is None:
            return super().poll(deadline)
        t = self.now()
        got = super().poll(deadline)
        self._log(f"P {t:.6f} {deadline:.6f} {self.now():.6f} " + " ".join(f"{x[0]:.6f}:{x[1]}:{x[2]}" for x in got))
        return got

    def _log(self, line):
        if self.trace is not None:
            run, wait, _ = os.pread(self.sched, 256, 0).split()
            self.trace.write(f"{line} cpu={int(run) / 1e9:.6f} wait={int(wait) / 1e9:.6f}\n")


ap = argparse.ArgumentParser()
ap.add_argument("--cdt-ms", type=int, default=20)
ap.add_argument("--adt-ms", type=int, default=20)
ap.add_argument("--ignore-other-in-release", action="store_true")
ap.add_argument("--lag-ms", type=float, default=0.0)
ap.add_argument("--trace", metavar="DIR")
args = ap.parse_args()


class IgnoresOtherInRelease(Station3964):
    def line_event(self, now, kind, value=0):
        if self.state == "WAIT_RELEASE_ACK" and kind in ("byte", "bytes"):
            data = bytes([value]) if kind == "byte" else value
            value = bytes(b for b in data if b in (0x10, 0x15))
            if not value:
                return
            kind = "bytes"
        super().line_event(now, kind, value)


# no baud rate: the model's bytes take no line time, so its block has ended when written
params = Params3964(procedure="3964R", cdt_ms=args.cdt_ms, adt_ms=args.adt_ms, baud_rate=None)
st = (IgnoresOtherInRelease if args.ignore_other_in_release else Station3964)(params, name="iut")
ep = OneWrite()
ep.lag = args.lag_ms / 1000.0
if args.trace:
    ep.trace = open(os.path.join(args.trace, f"{os.getpid()}.trace"), "w", buffering=1)
    ep.sched = os.open("/proc/self/schedstat", os.O_RDONLY)


def on_event(e):
    if isinstance(e, Status):
        sys.stderr.write(f"STATUS 16#{e.code:04X}\n")
        sys.stderr.flush()
        ep._log(f"S {ep.now():.6f} 16#{e.code:04X}")


st.power_on(ep.now())
try:
    drive_station(Host(st, "echo"), ep, on_event=on_event)
except (EOFError, BrokenPipeError):
    pass
