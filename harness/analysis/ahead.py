"""What a seat run's model sends next without further input: a copy of the run's model runs
ahead (from the snapshot taken when the seat's byte began, where there is one), so that a
finding can say what the model does instead of what the seat sent."""

from __future__ import annotations

import copy
from typing import TYPE_CHECKING

from ptpcert.analysis.interface import Cause, Item

if TYPE_CHECKING:
    from ptpcert.analysis.seat import SeatRun


def peek(run: "SeatRun", o: Item) -> tuple[float, int, Cause] | None:
    """What the model (as it was when the seat's byte began) sends next without further
    input: a copy of it runs ahead."""
    horizon = o.t + run.judge.analysis.horizon
    probe = copy.copy(run)
    if run._snapshot is not None:
        host, probe._log_pos, probe._log_k = run._snapshot
        probe.host = copy.deepcopy(host)
    else:
        probe.host = copy.deepcopy(run.host)
    probe.st = st = probe.host.station
    for _ in range(10_000):
        out = st.pop_output(st.now)
        if out:
            s, b = out[0]
            return (s + run.char, b, probe._cause_of(s, b)[0])
        d = st.next_deadline()
        if d is None or d > horizon:
            return None
        st.handle_timer(d)
        probe.host.drain(d)
    return None
