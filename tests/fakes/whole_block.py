"""A stand-in IUT that writes everything it sends in one write: a whole block, BCC
included, reaches the pipe at once (as a driver that hands its UART a buffer and does not
wait for it to drain, seen over a pipe). Otherwise the reference model driven as ``ptpcert
iut`` drives it, with no pacing: once its block is written it waits for the release DLE.
STATUS lines on stderr, PARMRK marks read.

    whole_block.py [--cdt-ms N] [--adt-ms N] [--ignore-other-in-release]

``--ignore-other-in-release`` breaks the release rule (§2.2.2 Send/release: any character
other than DLE is a failed attempt): such a character is ignored while it waits for DLE.
"""
import argparse
import os
import sys

from ptpcert.driver import drive_station
from ptpcert.iut import StdioEndpoint
from ptpcert.model import Host, Params3964, Station3964
from ptpcert.model.events import Status


class OneWrite(StdioEndpoint):
    """stdin/stdout; what the station sends between two looks at the input goes out in
    one write."""

    def __init__(self):
        super().__init__(parmrk=True)
        self.buffer = bytearray()

    def write(self, data):
        self.buffer += data
        return self.now()

    def poll(self, deadline):
        if self.buffer:
            os.write(self.fd_out, bytes(self.buffer))
            self.buffer.clear()
        return super().poll(deadline)


ap = argparse.ArgumentParser()
ap.add_argument("--cdt-ms", type=int, default=20)
ap.add_argument("--adt-ms", type=int, default=20)
ap.add_argument("--ignore-other-in-release", action="store_true")
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


def on_event(e):
    if isinstance(e, Status):
        sys.stderr.write(f"STATUS 16#{e.code:04X}\n")
        sys.stderr.flush()


st.power_on(ep.now())
try:
    drive_station(Host(st, "echo"), ep, on_event=on_event)
except (EOFError, BrokenPipeError):
    pass
