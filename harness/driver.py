"""Driving a model station in real (or virtual) time: the one loop that runs the reference
model against a line. ``ptpcert iut`` runs it on stdin/stdout or a serial port; the runner
runs it in the tester's seat where a vector lets the tester act as a conforming partner.
Kept free of the harness's heavier modules so that the IUT process starts fast.
"""

from __future__ import annotations

from typing import Callable


class Endpoint:
    """What a model station driven in real (or virtual) time talks through."""

    def now(self) -> float:
        raise NotImplementedError

    def poll(self, deadline: float) -> list[tuple[float, str, int]]:
        """Wait until input arrives or ``deadline``; return (time, kind, value) items,
        kind being "byte", "invalid" (a character with a parity/framing error) or "break".
        Raises EOFError when the input has ended."""
        raise NotImplementedError

    def write(self, data: bytes) -> float:
        raise NotImplementedError

    def late(self, seconds: float) -> None:
        """A byte went out ``seconds`` after the station's plan had it due (the loop was
        busy or kept from a CPU). An endpoint that answers for its own timing (the runner's,
        with the tester's partner on it) counts it; others need not."""


def drive_station(host, ep: Endpoint, *, stop: Callable[[], bool] | None = None,
                  on_event: Callable | None = None, until: float = float("inf"),
                  recheck: Callable[[], float] | None = None) -> None:
    """Run a model station (with its application) against an endpoint until ``stop()``
    says so, ``until`` is reached, or the input ends. Inputs of an instant are delivered
    before the deadlines of that instant (the station's ordering rule). Each byte is written
    when its transmission is complete (start + one character time), which is when a UART on
    the other side would hand it over; so the station's pacing is kept and a pipe behaves
    like a line. ``recheck()`` gives the earliest time at which ``stop()`` may turn true
    without new input (e.g. after a quiet period), so the loop wakes up for it."""
    st = host.station
    st.late_timers_act_now = True
    char = st.params.char_time
    pending: list[tuple[float, int]] = []   # started on the line, not yet complete
    while True:
        now = ep.now()
        pending += st.pop_output(now)
        # a character reaches the other side when its stop bit is out
        while pending and pending[0][0] + char <= now:
            start, b = pending.pop(0)
            ep.late(ep.write(bytes([b])) - (start + char))
            late = now - (start + char)
            if late > 0.0005:  # woke up late: the line carries it late; keep the model in step
                st.delay_output(late)
                pending = [(t + late, x) for t, x in pending]
        for e in host.drain():
            if on_event is not None:
                on_event(e)
        if (stop is not None and stop() and not pending) or now >= until:
            return
        d = st.next_deadline()
        wake = until if d is None else min(d, until)
        if pending:
            wake = min(wake, pending[0][0] + char)
        if recheck is not None:
            r = recheck()
            if r > now:  # a recheck time already past would only spin
                wake = min(wake, r)
        for t, kind, value in _runs(ep.poll(wake)):
            # Input found on the first look after one of the station's deadlines has passed
            # was waiting while the process was descheduled (or came with the deadline): it
            # is taken as arriving at that deadline, so it goes before the timer (inputs of
            # an instant before its deadlines). A timer that expired while the process was
            # not running must not win over input that was already there.
            if d is not None and t > d:
                t = d
            t = max(t, st.now)
            # input read in a batch is taken as it came: the deadlines before each input
            # first, and the application runs in between (it must not find a buffer full
            # that it would have emptied, or a frame not yet ended that had ended)
            prev = None
            while True:
                nd = st.next_deadline()
                # (a deadline that stays is a character to send: the loop above writes it)
                if nd is None or nd >= t or nd == prev:
                    break
                prev = nd
                st.handle_timer(max(nd, st.now))
                _drain(host, on_event)
            st.line_event(t, kind, value)
            _drain(host, on_event)
        now = ep.now()
        d = st.next_deadline()
        if d is not None and d <= now:
            st.handle_timer(now)


def _drain(host, on_event) -> None:
    for e in host.drain():
        if on_event is not None:
            on_event(e)


def _runs(items: list[tuple[float, str, int]]) -> list[tuple[float, str, object]]:
    """Consecutive bytes that arrived at one instant as one ``"bytes"`` event (a station
    takes a run of data in one step; a 1024-byte block read at once costs one call, not
    1024), every other item as it is."""
    out: list[tuple[float, str, object]] = []
    run = bytearray()
    at = 0.0
    for t, kind, value in items:
        if kind == "byte" and (not run or t == at):
            if not run:
                at = t
            run.append(value)
            continue
        if run:
            out.append((at, "bytes" if len(run) > 1 else "byte", bytes(run) if len(run) > 1 else run[0]))
            run = bytearray()
        if kind == "byte":
            at = t
            run.append(value)
        else:
            out.append((t, kind, value))
    if run:
        out.append((at, "bytes" if len(run) > 1 else "byte", bytes(run) if len(run) > 1 else run[0]))
    return out
