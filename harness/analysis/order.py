"""The ordering rule: the order of two seats' characters stamped within the capture's timing
resolution of each other is not known, so the seat run (:mod:`ptpcert.analysis.seat`) may
take them in either order, and only in those cases.

A stamp may lag the character's completion by up to the resolution (``LineAnalysis.resolution``),
never lead it. So the seat's character stamped ``o.t`` and the other seat's stamped ``u``
may have come in the other order than their stamps only if ``o.t - u`` is less than the
resolution. Three places use that, each bounded by it:

* :func:`local_from` and :func:`taken_at`: the alternative (``Variant.local``) in which the
  other seat's characters since the seat's last character before them came after the seat's
  bytes of the transmission the model is sending that are stamped within the resolution
  after them (a tester that interrupts once a block written in one piece is whole), and
  moved no further (the uniform shift by the whole resolution moves the characters the
  seat answered too);
* :func:`timer_first`: a seat's byte stamped before the other seat's character, which the
  model sends on a timer of its own that runs out within the byte's pending window: the
  timer ran out before the character came (the timer runs from the end of the seat's own
  transmission, whose stamps lag);
* the seat run's rest point (``SeatRun._nothing_due``): not before a byte of the seat stamped
  within the resolution after a character of the other seat's that came while the model was
  sending (:func:`cut`): that byte may have been on the line before it.

And one allowance that is the analysis's late tolerance (``--tolerance-ms``, the run's own for
real processes), not the resolution: in a real-time capture a seat may go on with the bytes of
the transmission an interruption (BREAK, NAK, the partner's STX) ended for up to that long
after it (:func:`tail_explains`, told in a note): a pipe or a relay delivers what the station
wrote before it learnt of the interruption at its own pace, and the run grants the same.

A violation further from the other seat's character than the resolution is outside all
three, and stands.
"""

from __future__ import annotations

import bisect
import copy
from math import inf
from typing import TYPE_CHECKING

from ptpcert.analysis.interface import QUANTUM, Item

if TYPE_CHECKING:
    from ptpcert.analysis.seat import SeatRun


def local_from(inputs: list[Item], obs: list[Item], t: float) -> float:
    """Where a local shift of the other seat's characters (``inputs``) before the seat's
    difference at ``t`` begins: at the stamp of the seat's last character (``obs``) stamped
    before the last of them; inf when the other seat sent nothing by ``t``."""
    j = bisect.bisect_right(inputs, t, key=lambda it: it.t) - 1
    if j < 0:
        return inf
    k = bisect.bisect_left(obs, inputs[j].t, key=lambda it: it.t) - 1
    return obs[k].t if k >= 0 else -inf


def taken_at(run: "SeatRun", it: Item) -> float:
    """When the run takes the other seat's character ``it`` under a local shift: after the
    seat's next byte if the model is sending and that byte is stamped within the resolution
    after ``it`` (and, once deferred, no earlier than the seat's bytes it was deferred past)."""
    obs = run.judge.obs
    if run.st.transmitting and run.i_obs < len(obs) and obs[run.i_obs].t <= it.t + run.res:
        run.order_floor = max(run.order_floor, obs[run.i_obs].t + QUANTUM)
    return max(it.t, run.order_floor)


def timer_first(run: "SeatRun", o: Item, t_in: float, t_dl: float) -> bool:
    """The seat's byte ``o`` waits for the model (the run's pending stage) and the other
    seat's character at ``t_in`` comes before the model's next deadline ``t_dl``: if ``o`` is
    stamped before ``t_in`` or within the resolution after it, the deadline falls within the
    byte's pending window (``SeatRun.early_wait``: a conforming timer may run out that much
    sooner, on top of the resolution) and the model's timer sends that very byte, the timer
    is brought forward to the byte's start (once per byte). True when it moved."""
    r = run.res
    st = run.st
    if (r <= 0 or o.kind != "byte" or o.t > t_in + r or t_dl <= t_in or run.moved_for == run.i_obs
            or not hasattr(st, "advance_output")):
        return False
    target = max(st.now, o.start)
    if target >= t_in or t_dl > o.t + run.early_wait:
        return False
    probe = copy.deepcopy(run.host).station      # does the timer send this byte?
    probe.handle_timer(t_dl)
    out = probe.pop_output(t_dl + QUANTUM)
    if not out or out[0][1] != o.value:
        return False
    run.moved_for = run.i_obs
    return st.advance_output(t_dl - target) > 0


def cut(run: "SeatRun", it: Item) -> None:
    """The other seat's character ``it`` comes while the model is sending: remember when, and
    which bytes the model had yet to send (a copy of it hands them out)."""
    run.cut_at = it.t
    if run.res > 0:
        probe = copy.deepcopy(run.host).station
        run.tail = [b for _, b in probe.pop_output(inf)]
        # until the interruption is over (a BREAK lasts its duration), four characters more for
        # the station's transmitter to stop (the window the suite's BREAK cases give), and the
        # late tolerance
        over = it.t + ((it.value or 0.0) if it.kind == "break" else 0.0)
        run.tail_until = over + 4 * run.char + run.kit.late_abs


def tail_explains(run: "SeatRun", o: Item) -> bool:
    """The seat's byte ``o``, which the model no longer sends, is the next byte of the
    transmission an interruption ended, within the late tolerance of it: taken as that."""
    if not run.tail or o.kind != "byte" or o.value != run.tail[0] or o.start > run.tail_until:
        run.tail = []
        return False
    if not run.notes or run.notes[-1][0] < run.cut_at:
        run.notes.append((o.t, f"went on with the transmission that the other seat's character at "
                               f"{1000 * run.cut_at:.3f} ms ended, within four characters and the late "
                               f"tolerance ({1000 * run.kit.late_abs:.0f} ms) of it"))
    run.tail.pop(0)
    run.i_obs += 1
    return True
