"""A stand-in IUT that polls its timers: it acts on a timer that has run out only LAG_MS
later (like an implementation whose main loop looks at its clock a few times a second), and
is otherwise the reference model. Input is taken at once; what the station sends goes out
when it starts. STATUS lines on stderr, PARMRK marks read.

    polling.py LAG_MS [--cdt-ms N] [--adt-ms N]
"""
import argparse
import os
import select
import sys
import time

from ptpcert.model.parmrk import ParmrkDecoder
from ptpcert.model.app import Host
from ptpcert.model.events import Status
from ptpcert.procedures.p3964.model.params import Params3964
from ptpcert.procedures.p3964.model.station import Station3964

ap = argparse.ArgumentParser()
ap.add_argument("lag_ms", type=float)
ap.add_argument("--cdt-ms", type=int, default=20)
ap.add_argument("--adt-ms", type=int, default=20)
args = ap.parse_args()
lag = args.lag_ms / 1000.0

st = Station3964(Params3964(procedure="3964R", cdt_ms=args.cdt_ms, adt_ms=args.adt_ms), name="iut")
st.late_timers_act_now = True
host = Host(st, "echo")
decoder = ParmrkDecoder(True)
st.power_on(time.monotonic())
while True:
    now = time.monotonic()
    out = bytes(b for _, b in st.pop_output(now))
    if out:
        os.write(1, out)
    for e in host.drain():
        if isinstance(e, Status):
            sys.stderr.write(f"STATUS 16#{e.code:04X}\n")
            sys.stderr.flush()
    d = st.next_deadline()
    timer = st.timer
    if d is not None and timer is not None and d >= timer[1] - 1e-9:
        d = timer[1] + lag            # the timer is the next deadline: noticed LAG later
    timeout = None if d is None else max(0.0, d - now)
    r, _, _ = select.select([0], [], [], timeout)
    now = time.monotonic()
    if r:
        data = os.read(0, 65536)
        if not data:
            sys.exit(0)
        for _, kind, value in decoder.feed(now, data):
            st.line_event(max(now, st.now), kind, value)
    elif d is not None and d <= now:
        st.handle_timer(now)
