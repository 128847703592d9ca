"""The runner: the one blocking driver. It plays the tester's side of a vector against an
IUT behind a transport, with the timing the vector asks for, records everything on the
line, and judges the result.

All waiting happens here, through :meth:`Transport.read` with a deadline; the model never
waits. With the ``sim:`` transport the same code runs in virtual time.
"""

from __future__ import annotations

import collections
import os
import time
import weakref
from dataclasses import dataclass, replace
from typing import Any, Callable, Iterable

from ptpcert import priority
from ptpcert import results as R
from ptpcert.driver import Endpoint, drive_station
from ptpcert.model.events import Delivered, status_text
from ptpcert.model.hexbytes import hexstr
from ptpcert.profile import Profile
from ptpcert.scenario import Expr, Step, Vector, brief_hex, expand, names_in, timer_env
from ptpcert.transport.base import (
    BREAK,
    CHAR_ERROR,
    NETWORK,
    RESTART,
    SETUPS,
    STATUS,
    IUTDied,
    Transport,
    TransportError,
)

# ------------------------------------------------------------------ tolerances


@dataclass(frozen=True)
class Tolerance:
    """How far the IUT's timing may stray from a window, and how late the tester's own
    stimuli may be before the case is void (a harness timing fault, retried)."""

    early: float        # a reply may come this much before its window opens,
    early_rel: float    # ... plus this fraction of the window's nominal lower bound
    late_abs: float     # ... and this much after it closes,
    late_rel: float     # ... plus this fraction of the window's nominal upper bound
    stimulus: float     # the tester's bytes may go out this late
    #: how late an output that one of the IUT's own timers causes may come beyond the
    #: above (the profile's declared ``timer_tolerance_ms``): widens only the late side of
    #: a window whose lower bound is an IUT timer
    iut_timer: float = 0.0

    def late(self, nominal: float) -> float:
        return self.late_abs + self.late_rel * max(nominal, 0.0)


VIRTUAL = Tolerance(early=1e-9, early_rel=0.0, late_abs=1e-9, late_rel=0.0, stimulus=1e-6)


def realtime_tolerance(proc, params: Any, late_ms: float = 50.0) -> Tolerance:
    """Tolerances for real processes on a loaded machine: one character time plus 1 ms plus
    10 % early (the IUT may time from when it read our byte, not from its stop bit, and the
    harness may read the byte that starts a window a little late); 50 ms plus 25 % late;
    the tester's stimuli at most 15 % of the IUT's shortest timer late."""
    char = proc.char_time(params)
    return Tolerance(
        early=char + 0.001,
        early_rel=0.10,
        late_abs=late_ms / 1000.0 + 2 * char,
        late_rel=0.25,
        stimulus=max(0.002, 0.15 * min(proc.edge_timers(params))),
    )


class OwnCpuWait:
    """Linux: how long the thread that created it (the harness's) has waited for a CPU so
    far, in seconds (/proc/thread-self/schedstat, second field: time runnable on a run queue
    but not running), read through a descriptor kept open (a few microseconds a look). A
    harness that waited between two looks read the IUT's bytes and sent its own that much
    late, whatever its clock says. Calling it gives None where /proc does not tell."""

    def __init__(self) -> None:
        try:
            self.fd: int | None = os.open("/proc/thread-self/schedstat", os.O_RDONLY)
        except OSError:
            self.fd = None
        else:
            weakref.finalize(self, os.close, self.fd)

    def __call__(self) -> float | None:
        if self.fd is None:
            return None
        try:
            return priority.run_queue_wait_ns(self.fd) / 1e9
        except (OSError, ValueError, IndexError):
            return None


class RiseWithin:
    """How much cumulative counters (each of a tuple: one, or one per CPU) rose within the
    last ``span`` seconds, the most of them: fed at every look, it keeps the looks of one
    span. A counter that fell (a thread that ended took its count along) or a tuple of
    another length (a CPU came or went) starts it afresh."""

    def __init__(self, span: float) -> None:
        self.span = span
        self._q: collections.deque = collections.deque()    # (time, counters)

    def add(self, now: float, counters: tuple[float, ...]) -> float:
        q = self._q
        if q and (len(q[-1][1]) != len(counters) or any(b < a for a, b in zip(q[-1][1], counters))):
            q.clear()
        q.append((now, counters))
        while len(q) > 1 and q[1][0] <= now - self.span:
            q.popleft()
        return max(b - a for a, b in zip(q[0][1], counters))


class TimingFault(RuntimeError):
    """The harness could not keep the timing a stimulus needs (machine too loaded)."""


class Flood(RuntimeError):
    pass


class StepFailed(Exception):
    def __init__(self, div: R.Divergence, message: str, late_only: bool = False):
        self.div, self.message, self.late_only = div, message, late_only
        super().__init__(message)


# ------------------------------------------------------------------ options


@dataclass
class RunOptions:
    tolerance: Tolerance | None = None
    late_ms: float = 50.0
    startup_timeout: float = 2.0      # how long a freshly started IUT may take to say NAK
    timing_retries: int = 3           # reruns of a case voided by a harness timing fault
    confirm_late: bool = True         # reproduce a failure that the machine's timing may have caused
    edge_attempts: int = 4            # attempts in all for a failing case close to a timer's edge
    retry_pause: tuple[float, ...] = (0.2, 0.5, 1.0)  # seconds before the 1st, 2nd, 3rd+ repeat
    flood_limit: int = 20_000         # bytes from the IUT in one case before it counts as flooding
    echo: bool = True                 # the IUT echoes received blocks (profile send_trigger)
    check_status: bool = True         # compare reported STATUS events (profile status_from_stderr)
    check_model_events: bool = False  # sim: also check deliveries and completed jobs
    #: a failed real-time attempt is re-judged by the model fed the line as it was (see
    #: ptpcert.replay): a failure the harness's own timing explains is void, not the IUT's
    rejudge: bool = True
    #: a failed case whose tagged open points (``readings``) have another reading that
    #: explains the divergence is graded by that reading's grade (Procedure.reading_grade)
    grade_readings: bool = True


# ------------------------------------------------------------------ the case driver


#: an IUT process that waited for a CPU this share of a stretch as long as its shortest timer
#: may have missed that timer for the machine's load (a steady load: a little at every moment)
STARVED = 0.4


class CaseRun:
    """Executes one vector once against an open transport."""

    def __init__(self, vector: Vector, steps: tuple[Step, ...], tr: Transport,
                 params: Any, tol: Tolerance, opts: RunOptions):
        self.v, self.steps, self.tr, self.p, self.tol, self.opts = vector, steps, tr, params, tol, opts
        self.proc = proc = vector.proc
        #: the conforming partner the tester plays where a vector lets it
        self.tp = proc.tester_params(params, vector.tester_params)
        self.char = proc.char_time(params)
        self.tester_char = proc.char_time(self.tp)
        edges = proc.edge_timers(params)
        #: a late stimulus matters only near the IUT's shortest timer; the line is quiet
        #: after the longest
        self.shortest, self.longest = min(edges), max(edges)
        self.env = timer_env(vector, params, opts.startup_timeout)
        self.t0 = tr.now()
        self.ref = self.t0
        self.rx: list[tuple[float, int]] = []
        self.rx_log: list[int] = []   # where each received byte is in the transcript
        #: per received byte, the earliest it may have left the IUT (real time: the look
        #: before the read that returned it; otherwise its stamp)
        self.rx_floor: list[float] = []
        #: (ref, floor): when ``ref`` was set from a received byte, the earliest that byte
        #: may have left the IUT - how long before its own reply the IUT's timer may have run
        self._ref_floor: tuple[float, float] = (self.t0, self.t0)
        self.pos = 0
        self.log: list[dict] = []
        #: bytes on the line not kept in the transcript (beyond the flood limit), per side
        self.dropped: dict[str, int] = {}
        self.dropped_at: dict[str, tuple[float, int]] = {}
        self.kept: dict[str, int] = {"tester": 0, "iut": 0}
        self.grade = R.PASS
        self.forced = 0.0
        self.notes: list[str] = []
        self.step_index = -1
        self.sent_end = self.t0
        self.mark_time = self.t0
        #: bytes an expect step passes over where it does not expect them
        self.skippable = frozenset(proc.interleaved(params))
        #: (data, bytes received) of the last partial expect step, for a step that resumes it
        self.last_partial: tuple[bytes, int] | None = None
        names = proc.iut_timers if proc.iut_timers is not None else proc.time_names
        self.iut_timers = frozenset(names)
        # What was on the line when, as exactly as the harness can know it (real time only):
        # the harness looks at the line at least every ``look`` seconds while it waits, so an
        # IUT byte it reads left the IUT after the look before (its lower bound, by log
        # index); a descheduled harness misses looks, and the bound shows it.
        self.realtime = not tr.virtual
        self.look = max(0.001, min(0.005, self.shortest / 10))
        self.last_look = self.t0
        self.lower_bound: dict[int, float] = {}
        #: the longest the harness found itself stalled (woke up or sent late), seconds
        self.max_stall = 0.0
        #: the longest the IUT's process was found runnable but kept from a CPU by the
        #: machine's load (seconds; where the transport tells, see Transport.cpu_wait): an
        #: IUT stalled that long may have let a timer run out that it would have met
        self.iut_stall = 0.0
        #: the most the IUT's process waited for a CPU within any stretch as long as its
        #: shortest timer in this attempt (seconds): a steady load takes a little at every
        #: moment, never long at once
        self.iut_wait = 0.0
        #: how late the tester's reply as a conforming partner went out after its model had
        #: it due (seconds; the most in this attempt): a partner busy taking in a long block,
        #: or kept from a CPU, replies later than planned, and an IUT that lost part of its
        #: timer to its own lag may then time out where an on-time partner would not have
        #: made it
        self.partner_late = 0.0
        #: when the first reply of the partner that went out later than the harness keeps its
        #: timing to was due (absolute time; None: every reply went out in time)
        self.partner_due: float | None = None
        #: the most steal time (priority.steal_time) of one CPU within any stretch as long
        #: as the IUT's shortest timer in this attempt (seconds; sampled only for an IUT
        #: process on this machine): the hypervisor may have kept the IUT from its CPU that
        #: long, unseen by any run queue. It never excuses a failure (it cannot tell which
        #: CPU the IUT was on); a failed attempt with it is only reproduced before it stands
        self.stolen = 0.0
        self._next_steal = 0.0
        self._cpu: tuple[float, float | None] = (0.0, None)
        self._own: float | None = None      # the harness thread's run-queue wait at the last look
        self._own_wait = OwnCpuWait() if self.realtime else (lambda: None)
        self._waits = RiseWithin(self.shortest)      # the IUT's run-queue wait
        self._steals = RiseWithin(self.shortest)     # steal time, per CPU
        self._starved = 0.0
        #: per stimulus (a send, character error or BREAK step): (step, IUT bytes read
        #: before its first byte went out)
        self.stimuli: list[tuple[int, int]] = []
        #: (stimulus step, partial step) when an IUT block that a stimulus was meant to
        #: interrupt had ended before the stimulus went out
        self.displaced: tuple[int, int] | None = None
        #: the STATUS events the IUT reported (None: not collected)
        self.status_codes: list[int] | None = None
        self.skipping = 0

    # -- helpers -----------------------------------------------------------------------
    def rel(self, t: float) -> float:
        return round(t - self.t0, 6)

    def ev(self, e: Expr) -> float:
        return e.eval(self.env)

    def _pump(self, deadline: float) -> None:
        if self.realtime:
            looked = self.last_look
            until = min(deadline, looked + self.look) if deadline > looked else deadline
            items = self.tr.read(until)
            self.last_look = items[-1][0] if items else self.tr.now()
            # a read returns by its deadline: later, the machine stalled this process
            self.max_stall = max(self.max_stall, self.tr.now() - until)
            # ... and a read that returned in time may still have been taken late: the harness
            # waited for a CPU after its input came (or while it handled it), and stamped the
            # IUT's bytes that much after they arrived
            own = self._own_wait()
            if own is not None:
                if self._own is not None:
                    self.max_stall = max(self.max_stall, own - self._own)
                self._own = own
            self._sample_iut()
        else:
            items = self.tr.read(deadline)
        limit = self.opts.flood_limit
        room = max(0, limit - len(self.rx))
        if items:
            self._take_in(items[:room], looked if self.realtime else None)
        if len(items) > room:
            self._drop("iut", len(items) - room, items[room][0])
            raise Flood(f"the IUT sent more than {limit} bytes in one case (the transcript keeps the first {limit})")

    def _take_in(self, items: list[tuple[float, int]], looked: float | None) -> None:
        """Keep the IUT's bytes of one read: received, stamped and logged. This is the
        harness's inner loop while an IUT sends a long block (a 1024-byte block stuffed with
        DLEs is 2,051 bytes in one read), and the tester's reply as a partner waits for it: so
        it is kept to plain list and dict work per byte (the same as ``_record`` per byte)."""
        self.rx.extend(items)
        log, rx_log, step = self.log, self.rx_log, self.step_index
        t0, last_t, rt = self.t0, None, 0.0
        if looked is None:
            self.rx_floor.extend(t for t, _ in items)
        else:
            self.rx_floor.extend([looked] * len(items))
            lb, lower_bound = self.rel(looked), self.lower_bound
        # (the caller keeps the IUT's bytes within the flood limit: all of these are logged)
        for t, b in items:
            i = len(log)
            if looked is not None:
                lower_bound[i] = lb
            rx_log.append(i)
            if t != last_t:
                last_t, rt = t, round(t - t0, 6)
            log.append({"t": rt, "dir": "iut", "kind": "byte", "byte": b, "step": step})
        self.kept["iut"] += len(items)

    def _sample_iut(self) -> None:
        """Between two looks, did the IUT wait for a CPU most of the time? Consecutive such
        looks make one stall (how long the IUT could not act)."""
        t0, w0 = self._cpu
        now, w = self.tr.now(), self.tr.cpu_wait()
        self._cpu = (now, w)
        if w is not None and now >= self._next_steal:
            self._sample_steal(now)
        if w0 is None or w is None:
            self._starved = 0.0
            return
        dt, dw = now - t0, w - w0
        self.iut_wait = max(self.iut_wait, self._waits.add(now, (w,)))
        if dt <= 0:
            return
        if dw >= 0.5 * dt:
            self._starved += dw
            self.iut_stall = max(self.iut_stall, self._starved)
        else:
            self._starved = 0.0

    @property
    def starved(self) -> bool:
        """The IUT's process waited for a CPU for STARVED of its shortest timer within one
        such stretch (a steady load, never one long stall)."""
        return self.iut_wait >= STARVED * self.shortest

    #: how often the steal time is read (it counts in clock ticks of 10 ms)
    STEAL_LOOK = 0.005

    def _sample_steal(self, now: float) -> None:
        """The most steal time of one CPU within a stretch as long as the IUT's shortest
        timer, so far in this attempt (see ``stolen``)."""
        s = priority.steal_time()
        if s is None:
            self._next_steal = float("inf")
            return
        self._next_steal = now + self.STEAL_LOOK
        self.stolen = max(self.stolen, self._steals.add(now, s))

    #: the part of the IUT's shortest timer that a disturbance must reach to count: a correct
    #: IUT loses a timer window it would have met only when it is kept from acting for most of
    #: it (less is covered by the tolerance of the late side and the stalled timeline)
    MATERIAL = 0.5

    def disturbance(self) -> str | None:
        """What of the machine's may have cost the IUT a timer window in this attempt, in
        words: the harness or the IUT's process stalled, the IUT kept waiting for a CPU, a
        partner reply late, or steal time of one CPU (at least two clock ticks: one tick may
        be a little steal at a tick's edge), each for at least MATERIAL of the IUT's shortest
        timer; None for an attempt the machine left alone."""
        least = self.MATERIAL * self.shortest
        what = []
        if self.max_stall >= least:
            what.append(f"the harness was stalled for up to {1000 * self.max_stall:.1f} ms")
        if self.iut_stall >= least or self.starved:
            what.append(f"the IUT's process waited for a CPU for up to {1000 * self.iut_stall:.1f} ms at a time "
                        f"({1000 * self.iut_wait:.1f} ms in all within {1000 * self.shortest:.0f} ms)")
        if self.partner_late >= least:
            what.append(f"the tester's reply as the IUT's partner went out up to {1000 * self.partner_late:.1f} ms "
                        "late")
        if self.stolen >= max(2 * priority.TICK, least) - 1e-9:
            what.append(f"the hypervisor ran other work on one of this machine's CPUs for {1000 * self.stolen:.0f} ms "
                        f"within {1000 * self.shortest:.0f} ms (steal time), unseen by any run queue: the IUT's "
                        "process may have been kept from its CPU that long")
        return "; ".join(what) or None

    def _record(self, entry: dict) -> None:
        """Log a byte, a character error or a BREAK on the line; beyond the flood limit of
        one side, only count it (a transcript is bounded, whatever the IUT does)."""
        d = entry["dir"]
        if self.kept[d] >= self.opts.flood_limit:
            self._drop(d, 1, self.t0 + entry["t"])
            return
        self.kept[d] += 1
        self.log.append(entry)

    def _drop(self, d: str, n: int, t: float) -> None:
        self.dropped[d] = self.dropped.get(d, 0) + n
        self.dropped_at.setdefault(d, (t, self.step_index))

    def transcript(self) -> list[dict]:
        """The transcript as the results keep it: bytes as runs, and a marker of what was
        not kept."""
        out = R.pack_transcript(self.log)
        for d, n in self.dropped.items():
            t, step = self.dropped_at[d]
            out.append({"t": self.rel(t), "dir": d, "kind": "dropped", "bytes": n,
                        "kept": self.opts.flood_limit, "step": step})
        return out

    def wait_until(self, t: float) -> None:
        now = self.tr.now()
        if self.realtime and now - self.last_look > self.look and now >= t:
            self._pump(now)   # behind time (sending a long block): still look at the line
        while self.tr.now() < t:
            self._pump(t)

    def consume(self) -> tuple[float, int]:
        """Take the next received byte; the transcript then shows it under the step that
        consumed it (not the one that was running when it arrived)."""
        item = self.rx[self.pos]
        self.log[self.rx_log[self.pos]]["step"] = self.step_index
        self.pos += 1
        return item

    def next_byte(self, deadline: float) -> tuple[float, int] | None:
        while self.pos >= len(self.rx):
            if self.tr.now() >= deadline:
                return None
            self._pump(deadline)
        return self.rx[self.pos]

    def next_wanted(self, deadline: float, wanted: set[int]) -> tuple[float, int] | None:
        """The next received byte, passing over the procedure's interleaved bytes (e.g. an
        XON) that arrive in time and are not among those ``wanted`` here."""
        while True:
            item = self.next_byte(deadline)
            if item is None or item[0] > deadline or item[1] not in self.skippable or item[1] in wanted:
                return item
            self.consume()
            self.log[self.rx_log[self.pos - 1]]["skipped"] = True

    #: how long a process IUT that sent nothing in a window is given to show it has ended
    DEATH_GRACE = 0.1

    def _look_for_death(self) -> None:
        """Nothing came in the window: an IUT process that has ended, or ends within
        DEATH_GRACE (a crash on a loaded machine takes a while), is reported as ended
        (IUTDied) rather than as silence. The verdict is a fail either way."""
        if self.realtime and RESTART in self.tr.capabilities:
            # the grace comes after the window that decided: what the machine does to either
            # process meanwhile does not touch the verdict's footing
            kept = self.max_stall, self.iut_stall, self.iut_wait, self.stolen
            end = self.tr.now() + self.DEATH_GRACE
            while self.tr.now() < end:
                self._pump(end)
            self.max_stall, self.iut_stall, self.iut_wait, self.stolen = kept

    def fail(self, expected: str, observed: str, t: float, window=None, late_only=False):
        div = R.Divergence(self.step_index, self.rel(t), expected, observed,
                           None if window is None else (self.rel(window[0]), self.rel(window[1])))
        raise StepFailed(div, f"step {self.step_index + 1}: expected {expected}; {observed}", late_only)

    def mark(self, kind: str, **kw) -> None:
        self.log.append({"kind": kind, "dir": "note", "step": self.step_index, **kw})

    # -- steps -------------------------------------------------------------------------
    def run_steps(self) -> None:
        skip = 0
        for i, step in enumerate(self.steps):
            if skip:
                skip -= 1   # the rest of a block the IUT did not send (an optional expect's skip)
                continue
            self.step_index = i
            self.skipping = 0
            getattr(self, "_" + step.kind)(step)
            if step.mark:
                self.mark_time = self.ref
            skip = self.skipping

    def _send_bytes(self, step: Step, data: bytes, writer: Callable[[int], float], kind: str) -> None:
        """Send characters paced as on the line: the k-th starts at ref + at + k*(CHAR+gap)
        and is handed over when it is complete, one character time later."""
        at, gap = self.ev(step.at), self.ev(step.gap)
        char = self.tester_char
        start = self.ref + at
        t = start
        # A late byte matters only where one of the IUT's timers could have run out because
        # of it: when the time since the previous event nears the shortest timer. Where that
        # event is the IUT's byte, its timer may have started as early as the byte may have
        # left it (a block written in one piece and read late, then handled for a while).
        prev = self._ref_floor[1] if self._ref_floor[0] == self.ref else self.ref
        critical = 0.9 * self.shortest
        for k, b in enumerate(data):
            target = start + k * (char + gap) + char
            self.wait_until(target)
            if k == 0:
                self._stimulus()
            t = writer(b)
            self._record({"t": self.rel(t), "dir": "tester", "kind": kind, "byte": b, "step": self.step_index})
            late = t - target
            self.max_stall = max(self.max_stall, late)
            if late > self.tol.stimulus and t - prev > critical:
                raise TimingFault(f"step {self.step_index + 1}: the tester's byte {k + 1} went out "
                                  f"{late * 1000:.1f} ms late (allowed {self.tol.stimulus * 1000:.1f} ms)")
            prev = t
        self.ref = self.sent_end = t
        self.forced += at + len(data) * char + max(0, len(data) - 1) * gap

    def _stimulus(self) -> None:
        """A stimulus is about to go out: take in what the IUT has sent by now (the state
        it is in when the stimulus reaches it) and note it."""
        if self.realtime:
            self._pump(self.tr.now())
        self.stimuli.append((self.step_index, len(self.rx)))

    def _send(self, step: Step) -> None:
        self._send_bytes(step, step.data, lambda b: self.tr.write(bytes([b])), "byte")

    def _send_error(self, step: Step) -> None:
        self._send_bytes(step, step.data, self.tr.send_char_error, "char_error")

    def _break(self, step: Step) -> None:
        at, dur = self.ev(step.at), self.ev(step.duration)
        target = self.ref + at
        self.wait_until(target)
        self._stimulus()
        t = self.tr.send_break(dur)
        if t - target > self.tol.stimulus and t - self.ref > 0.9 * self.shortest:
            raise TimingFault(f"step {self.step_index + 1}: BREAK went out {1000 * (t - target):.1f} ms late")
        self._record({"t": self.rel(t), "dir": "tester", "kind": "break", "duration": dur, "step": self.step_index})
        self.ref = self.sent_end = t + dur
        self.wait_until(self.ref)
        self.forced += at + dur

    def _wait(self, step: Step) -> None:
        d = self.ev(step.duration)
        self.ref += d
        self.wait_until(self.ref)
        self.forced += d

    def _silence(self, step: Step) -> None:
        d = self.ev(step.duration)
        end = self.ref + d
        self.mark("window", t0=self.rel(self.ref), t1=self.rel(end), label=f"silence {step.duration}")
        self.wait_until(end)
        if self.pos < len(self.rx) and self.rx[self.pos][0] <= end:
            t, b = self.rx[self.pos]
            self.fail(f"silence for {step.duration}", f"received {b:02X} at {1000 * (t - self.ref):.1f} ms",
                      t, (self.ref, end))
        self.ref = end
        self.forced += d

    def _expect(self, step: Step) -> None:
        last_partial, self.last_partial = self.last_partial, None
        if step.resume and last_partial is not None and last_partial[0] == step.data:
            rest = step.data[last_partial[1]:]
            if not rest:
                return  # the interrupted step received everything already
            step = replace(step, data=rest, alternatives=())
        if step.since == "sent":
            self.ref = self.sent_end
        elif step.since == "mark":
            self.ref = self.mark_time
        lo_nom, hi_nom = self.ev(step.after), self.ev(step.within)
        lo = self.ref + lo_nom - self.tol.early - self.tol.early_rel * max(lo_nom, 0.0)
        hi = self.ref + hi_nom + self.tol.late(hi_nom)
        if self.tol.iut_timer and self._ends_on_iut_timer(step):
            hi += self.tol.iut_timer
        what = brief_hex(step.data)
        if step.alternatives:
            what += " (or " + " or ".join(brief_hex(a) for a in step.alternatives) + ")"
        label = f"expect {what} in [{step.after}, {step.within}]"
        self.mark("window", t0=self.rel(self.ref + lo_nom), t1=self.rel(self.ref + hi_nom), label=label)
        cands = [step.data] + list(step.alternatives)
        first = self.next_wanted(hi, {c[0] for c in cands})
        if first is None or first[0] > hi:
            if step.partial:
                self.last_partial = (step.data, 0)
            if step.optional or step.partial:
                if step.optional:
                    self._grade(step.absent_grade, f"step {self.step_index + 1}: optional {what} not sent")
                    # the next step follows the window watched in vain (its tolerance included)
                    self.ref = max(self.ref + hi_nom, min(self.tr.now(), hi))
                    self.skipping = step.skip
                self.forced += max(hi_nom, 0.0)  # the whole window had to be watched
                return
            if first is None:
                self._look_for_death()
                self.fail(what + f" within {step.within}", "nothing received", hi, (self.ref + lo_nom, self.ref + hi_nom))
            t, b = first
            self.fail(what + f" within {step.within}",
                      f"{b:02X} came {1000 * (t - self.ref):.1f} ms after the reference, too late",
                      t, (self.ref + lo_nom, self.ref + hi_nom), late_only=(b == step.data[0]))
        t, b = first
        live = [c for c in cands if c[0] == b]
        if not live:
            if step.partial:
                self.last_partial = (step.data, 0)
                return
            if step.optional:
                self._grade(step.absent_grade, f"step {self.step_index + 1}: optional {what} not sent")
                self.skipping = step.skip
                return
            self.fail(what, f"received {b:02X}", t, (self.ref + lo_nom, self.ref + hi_nom))
        # the rest of a block the stimulus interrupts may have been on the line before the
        # stimulus went out: those bytes are not a reaction to it, early or not
        before = step.partial and bool(self.stimuli) and self.pos < self.stimuli[-1][1]
        if t < lo and not before:
            self.fail(f"{what} no earlier than {step.after}",
                      f"{b:02X} came {1000 * (t - self.ref):.1f} ms after the reference, too early",
                      t, (self.ref + lo_nom, self.ref + hi_nom), late_only=True)
        got = bytearray([b])
        self.consume()
        last_t = t
        gap_nom = self.ev(step.max_gap)
        gap_lim = gap_nom + self.tol.late(gap_nom)
        while True:
            done = [c for c in live if len(c) == len(got)]
            longer = [c for c in live if len(c) > len(got)]
            if not longer:
                break
            nxt = self.next_wanted(last_t + gap_lim, {c[len(got)] for c in longer})
            if nxt is None or nxt[0] > last_t + gap_lim:
                if done or step.partial:
                    break
                self.fail(f"{what} with gaps of at most {step.max_gap}",
                          f"got {brief_hex(bytes(got))}, then nothing for {1000 * gap_lim:.0f} ms",
                          last_t + gap_lim, late_only=nxt is not None)
            nt, nb = nxt
            still = [c for c in longer if c[len(got)] == nb]
            if not still:
                if done or step.partial:
                    break
                self.fail(what, f"byte {len(got) + 1} is {nb:02X} (after {brief_hex(bytes(got))})", nt)
            if step.partial and nt > hi:
                self.fail(f"the IUT to stop sending within {step.within}",
                          f"it still sent {nb:02X} {1000 * (nt - self.ref):.1f} ms after the reference", nt,
                          (self.ref, self.ref + hi_nom))
            live = still
            got.append(nb)
            self.consume()
            last_t = nt
        matched = bytes(got)
        if step.partial:
            self.last_partial = (step.data, len(matched))
        if matched != step.data and not step.partial:
            if matched in step.alternatives:
                self._grade(step.alt_grade, f"step {self.step_index + 1}: the IUT sent {hexstr(matched)}")
        if (step.partial and matched == step.data and self.stimuli and self.pos <= self.stimuli[-1][1]
                and self.displaced is None):
            # the whole block was on the line before the stimulus went out: the stimulus
            # reached an IUT whose block had ended (e.g. written in one piece over a pipe)
            self.displaced = (self.stimuli[-1][0], self.step_index)
        self.ref = last_t
        if got:
            self._ref_floor = (last_t, min(last_t, self.rx_floor[self.pos - 1]))
        self.forced += max(lo_nom, 0.0) + len(matched) * self.char

    def _ends_on_iut_timer(self, step: Step) -> bool:
        """The window waits for what one of the IUT's own timers causes: its lower bound
        names one (e.g. ``after = "CDT"``: a NAK due when the IUT's CDT runs out)."""
        return bool(names_in(step.after) & self.iut_timers)

    def _grade(self, grade: str, why: str) -> None:
        if grade != R.PASS:
            self.notes.append(f"{grade}: {why}")
        self.grade = R.worse_grade(self.grade, grade)

    def _prime(self, step: Step) -> None:  # pragma: no cover - expanded before running
        raise AssertionError("prime steps are expanded before the run")

    _receive = _prime

    # -- before and after the steps ----------------------------------------------------
    def prologue(self, state: "RunnerState") -> None:
        """Wait for what a freshly started IUT sends on its own (3964's start-up NAK;
        bounded), so the steps start with the IUT idle; on a persistent IUT, wait for the
        line to be quiet."""
        if self.v.start == "power-on":
            return
        if RESTART in self.tr.capabilities:
            startup = self.proc.startup_bytes(self.p)
            if startup:
                limit = self.opts.startup_timeout if state.startup_nak_seen is not False else 0.1
                first = self.next_byte(self.tr.now() + limit)
                if first is not None and first[1] == startup[0]:
                    self.consume()
                    for b in startup[1:]:
                        nxt = self.next_byte(self.tr.now() + limit)
                        if nxt is None or nxt[1] != b:
                            break
                        self.consume()
                    state.startup_nak_seen = True
                elif first is None and state.startup_nak_seen is None:
                    state.startup_nak_seen = False
            else:
                self._await_ready()
            self.ref = max(self.tr.now(), self.rx[self.pos - 1][0] if self.pos else self.tr.now())
        else:
            quiet = self.longest + self.tol.late(0)
            if not state.persistent_settled:
                # the first case on a persistent line: the IUT may still be starting up
                quiet = max(quiet, self.opts.startup_timeout / 2)
                state.persistent_settled = True
            end = self.tr.now() + 10 * quiet + 5.0
            last = self.tr.now()
            while self.tr.now() < min(last + quiet, end):
                n = len(self.rx)
                self._pump(min(last + quiet, end))
                if len(self.rx) > n:
                    last = self.rx[-1][0]
            self.pos = len(self.rx)
            self.ref = self.tr.now()
        self.mark("start", t=self.rel(self.ref))

    def _await_ready(self) -> None:
        """An IUT that announces nothing at start-up: before the first stimulus, wait until
        it waits for input (a stimulus written earlier would sit in a pipe and lose its
        timing), at most the start-up timeout."""
        if self.tr.virtual:
            return
        end = self.tr.now() + self.opts.startup_timeout
        while True:
            ready = self.tr.ready()
            if ready is None or ready:
                return
            if self.tr.now() >= end:
                self.notes.append(f"the IUT did not wait for input within {self.opts.startup_timeout:g} s of its start")
                return
            self._pump(min(end, self.tr.now() + 0.01))

    def epilogue(self) -> None:
        """After the steps: an echo IUT sends back the blocks the vector names; the tester
        receives them as a conforming partner would. Then the line must stay quiet."""
        self.step_index = len(self.steps)
        echo = list(self.v.expected.echo_after) if self.opts.echo else []
        if echo:
            self._receive_echoes(echo)
        quiet = self.longest + self.char * 4
        end = self.ref + quiet
        self.mark("window", t0=self.rel(self.ref), t1=self.rel(end), label="no further bytes")
        self.wait_until(end)
        self.forced += quiet  # silence is proven only by watching for the longest timer
        if self.pos < len(self.rx):
            t, b = self.rx[self.pos]
            rest = hexstr(bytes(x[1] for x in self.rx[self.pos:self.pos + 16]))
            self.fail("nothing more from the IUT" + (" after its echo" if echo else ""),
                      f"it sent {rest}", t, (self.ref, end))
        self.ref = end

    def observe_rest(self) -> None:
        """After a divergence: go on as a conforming partner until the line is quiet, so
        that the whole exchange is on record to be judged (by the model) as it went."""
        self.step_index = len(self.steps)
        v = self.v
        blocks = list(v.expected.echo_after) or list(v.expected.sent) or list(v.expected.delivered) or [b"\x00"]
        limit = self.tr.now() + self.proc.echo_time_limit(self.p, blocks)
        self._play_partner(self.tp, limit, want=None, label="after the divergence: the tester answers as a "
                                                            "conforming partner, for the record")

    def _receive_echoes(self, echo: list[bytes]) -> None:
        limit = self.tr.now() + self.proc.echo_time_limit(self.p, echo)
        got = self._play_partner(self.tp, limit, want=len(echo),
                                 label="echo: the tester receives as a conforming partner")
        for i, (want, have) in enumerate(zip(echo, got)):
            if want != have:
                self.fail(f"echo {i + 1}: {brief_hex(want)}", f"the IUT sent back {brief_hex(have)}", self.ref)
        if len(got) > len(echo):
            self.fail(f"{len(echo)} block(s) back from the IUT",
                      f"it also sent back {', '.join(brief_hex(x) for x in got[len(echo):])}", self.ref)
        self.forced += sum(len(self.proc.frame(e, self.p)) + 2 for e in echo) * self.char

    def _partner(self, step: Step) -> None:
        t0 = self.tr.now()
        limit = self.ref + self.ev(step.duration)
        self._play_partner(self.tp, limit, want=None, label="the tester plays a conforming partner")
        self.forced += self.tr.now() - t0  # the protocol's own retries decide how long this takes

    def _play_partner(self, params: Any, limit: float, want: int | None, label: str) -> list[bytes]:
        """Let a model station in the tester's seat answer the IUT until it has received
        ``want`` blocks (None: until both sides are quiet), or until ``limit``. Returns the
        blocks it received."""
        proc = self.proc
        host = proc.host(proc.station(params, name="tester"), app="none")
        partner = host.station
        start = min(self.rx[self.pos][0] if self.pos < len(self.rx) else self.ref, self.ref)
        partner.power_on(start)
        partner.pop_output()          # it is already running: nothing of its start-up here
        ep = _CaseEndpoint(self)
        # quiet for the longest timer, with the lateness a real-time IUT is allowed
        # (the IUT's timers and the partner's: they may differ, e.g. an ASCII partner's CDT)
        quiet = (max(proc.edge_timers(params) + proc.edge_timers(self.p)) + 4 * proc.char_time(params)
                 + self.tol.late(0))
        got: list[bytes] = []

        def on_event(e) -> None:
            if isinstance(e, Delivered):
                got.append(e.payload)

        def stop() -> bool:
            if not proc.partner_done(host):
                return False
            if want is not None and len(got) >= want:
                return True
            # the line has gone quiet: the IUT has nothing more to send (or gave up)
            return ep.now() - ep.last >= quiet

        self.mark("window", t0=self.rel(self.ref), t1=self.rel(limit), label=label)
        drive_station(host, ep, stop=stop, on_event=on_event, until=limit,
                      recheck=lambda: ep.last + quiet)
        if want is not None and len(got) < want:
            self.fail(f"{want} block(s) from the IUT",
                      f"received {len(got)} intact block(s) before the line went quiet", self.tr.now())
        self.ref = max(self.ref, min(self.tr.now(), ep.last))
        return got


class _CaseEndpoint(Endpoint):
    """The case's line as an endpoint for a model station in the tester's seat."""

    def __init__(self, run: "CaseRun"):
        self.run = run
        self.last = run.tr.now()

    def now(self) -> float:
        return self.run.tr.now()

    def poll(self, deadline: float) -> list[tuple[float, str, int]]:
        run = self.run
        if run.pos >= len(run.rx):
            run._pump(max(deadline, run.tr.now()))
        items = [(t, "byte", b) for t, b in run.rx[run.pos:]]
        if items:   # consumed (as ``consume`` does each), in one go
            log, step = run.log, run.step_index
            for i in run.rx_log[run.pos:]:
                log[i]["step"] = step
            run.pos = len(run.rx)
            self.last = max(self.last, items[-1][0])
        return items

    def late(self, seconds: float) -> None:
        # the partner's reply went out this late after its model had it due (the harness was
        # busy taking in a long block, or kept from a CPU): a failed attempt is then judged
        # again with the tester's bytes reaching the IUT that much later and more (Runner._rejudge)
        run = self.run
        run.partner_late = max(run.partner_late, seconds)
        if seconds > run.tol.stimulus and run.partner_due is None:
            run.partner_due = run.tr.now() - seconds

    def write(self, data: bytes) -> float:
        run = self.run
        w = run.tr.write(data)
        self.last = max(self.last, w)
        for b in data:
            run._record({"t": run.rel(w), "dir": "tester", "kind": "byte", "byte": b, "step": run.step_index})
        return w


def earlier_interrupt(steps: tuple[Step, ...], stim: int) -> tuple[Step, ...] | None:
    """The steps with the stimulus of step ``stim`` sent after the first byte of the block
    it interrupts instead of after several: the expect step before it keeps only its first
    byte, the partial expectation after it takes the rest. None when the steps around it
    are not an expected block, the stimulus and the rest of that block."""
    if stim < 1 or stim + 1 >= len(steps):
        return None
    before, after = steps[stim - 1], steps[stim + 1]
    if before.kind != "expect" or before.partial or before.optional or before.alternatives or len(before.data) < 2:
        return None
    if after.kind != "expect" or not after.partial:
        return None
    return (steps[:stim - 1] + (replace(before, data=before.data[:1]), steps[stim],
                                replace(after, data=before.data[1:] + after.data)) + steps[stim + 2:])


@dataclass
class RunnerState:
    """What the runner learns across cases of one run."""

    startup_nak_seen: bool | None = None
    persistent_settled: bool = False


# ------------------------------------------------------------------ the runner


class Runner:
    def __init__(self, factory, profile: Profile | None = None,
                 options: RunOptions | None = None):
        self.factory = factory
        self.profile = profile
        self.opts = options or RunOptions()
        self.state = RunnerState()
        #: the last attempt's case driver (its log and what it noted), for tools and tests
        self.last_run: CaseRun | None = None

    # -- applicability -------------------------------------------------------------
    def effective_params(self, v: Vector) -> Any:
        """The vector's parameters, with the profile's where the vector does not bind them."""
        if self.profile is None:
            return v.params
        p = self.profile.params
        fixed = {name: getattr(v.params, name) for name in v.binds}
        try:
            return p.with_(**fixed) if fixed else p
        except ValueError:
            return v.params  # no such IUT: the bound values do not go with the profile's (unsupported)

    def unsupported_reason(self, v: Vector, caps: frozenset[str]) -> str | None:
        if self.profile is not None:
            if v.procedure != self.profile.procedure.id:
                return (f"the vector is for {v.proc.title}; the IUT profile is for "
                        f"{self.profile.procedure.title}")
            for name in v.binds:
                want, have = getattr(v.params, name), getattr(self.profile.params, name)
                if want != have:
                    return f"the vector is for {name} = {want}; the IUT profile has {have}"
            if "echo" in v.needs and not self.profile.echo:
                return "needs an IUT that sends back what it receives (profile send_trigger = \"none\")"
            # a transport with real line conditions (a UART, RFC 2217) needs no marking by the
            # IUT; which of them it carries is checked below, kind by kind
            if "line_conditions" in v.needs and self.profile.line_conditions == "none" and \
                    "native_line_conditions" not in caps:
                return "needs BREAK / character errors; the profile says the IUT reads no line conditions"
        if "line_conditions" in v.needs:
            kinds = {s.kind for s in v.steps}
            if "break" in kinds and BREAK not in caps:
                return "needs BREAK, which this transport cannot carry"
            if "send_error" in kinds and CHAR_ERROR not in caps:
                return "needs characters with parity/framing errors, which this transport cannot carry"
        if "restart" in v.needs and RESTART not in caps:
            return "needs to see the IUT start up; this transport does not start the IUT"
        if v.setup is not None and not getattr(self.factory, "virtual", False):
            name = v.setup[0]
            if self.profile is None or name not in self.profile.setups:
                return (f"needs the IUT in the state of setup {name!r}, which the profile's [iut.setups] "
                        "does not name")
            if SETUPS not in caps:
                return f"needs the IUT started with setup {name!r}; this transport does not start the IUT"
        return v.proc.unsupported_reason(v, self.profile, caps, self.factory)

    # -- one case ------------------------------------------------------------------
    def run_case(self, v: Vector) -> R.CaseResult:
        res = R.CaseResult(id=v.id, title=v.title, reference=v.reference, rule=v.rule, group=v.group,
                           iut_role=v.iut_role, readings=list(v.readings), source=v.source, rules=list(v.rules))
        res.expected_status = v.expected.iut_status.describe()
        res.expected_status_codes = [sorted(f"16#{c:04X}" for c in g) for g in v.expected.iut_status.required]
        res.tester_status = v.expected.tester_status.describe()
        params = self.effective_params(v)
        res.params = v.proc.params_table(params)
        steps = expand(replace(v, params=params))
        res.steps = [{"kind": s.kind, "data": hexstr(s.data), **s.to_toml()} for s in steps]
        wall0 = time.monotonic()
        reason = self.unsupported_reason(v, self.factory.capabilities)
        if reason:
            res.verdict, res.message = R.UNSUPPORTED, reason
            return res
        attempts = voided = reruns = 0
        realtime = not getattr(self.factory, "virtual", False)
        earlier_tried = False
        while True:
            attempts += 1
            outcome = self._attempt(v, steps, params, res, may_interrupt_earlier=not earlier_tried)
            if outcome.startswith("displaced:"):
                # the stimulus found the IUT's block ended: once more, interrupting earlier
                earlier_tried = True
                steps = earlier_interrupt(steps, int(outcome.split(":")[1]))
                res.notes.append(f"attempt {attempts} voided: {res.message}")
                continue
            if outcome == "timing" and voided < self.opts.timing_retries:
                voided += 1
                res.notes.append(f"attempt {attempts} voided: {res.message}")
                self._pause(voided + reruns, realtime)
                continue
            if res.verdict == R.FAIL and reruns < self._rerun_budget(v, outcome, realtime):
                reruns += 1
                why = ("failed by timing only" if outcome == "late" else
                       "failed in an attempt the machine disturbed (see the note before); a failure is reproduced "
                       "before it stands, so it runs again" if outcome == "disturbed" else
                       "failed; the case works close to a timer's edge, so it runs again" if v.timing_sensitive else
                       "failed over a network serial server, whose delays can stretch a gap on the line; "
                       "it runs again")
                res.notes.append(f"attempt {attempts} {why}: {res.message}")
                self._pause(voided + reruns, realtime)
                continue
            break
        if res.verdict == R.FAIL and v.readings and self.opts.grade_readings:
            self._grade_by_readings(v, res)
        if res.verdict in (R.PASS, R.NON_STRICT, R.INFORMATIONAL) and reruns:
            res.message = "; ".join(x for x in (res.message, f"passed on attempt {attempts} after {reruns} failed "
                                                              f"attempt(s) (see notes)") if x)
        res.attempts = attempts
        res.duration = round(time.monotonic() - wall0, 4)
        xf = (self.profile.expected_failures if self.profile else {}).get(v.id)
        if xf is not None:
            if res.verdict == R.FAIL:
                res.verdict, res.message = R.XFAIL, f"expected failure ({xf}): {res.message}"
            elif res.verdict in (R.PASS, R.NON_STRICT, R.INFORMATIONAL):
                res.verdict, res.message = R.XPASS, f"listed as an expected failure ({xf}) but passed"
        return res

    def _grade_by_readings(self, v: Vector, res: R.CaseResult) -> None:
        """A failed case tagged with open points of the manual: when the model with the
        other reading of one of them (through the one ``sim:`` builder, in virtual time)
        diverges from the case as the IUT did (the same step and the same bytes, or the
        same complaint about what the IUT reported), the IUT takes that reading, and the
        case gets the grade the procedure gives it."""
        from ptpcert.transport import sim_factory
        proc = v.proc
        app = "echo" if (self.profile is None or self.profile.echo) else "none"
        if app not in proc.apps():
            app = proc.apps()[0]
        opts = replace(self.opts, grade_readings=False, rejudge=False)
        for name in v.readings:
            grade = proc.reading_grade(name)
            other = proc.other_reading(name) if grade is not None else None
            if other is None:
                continue
            alt = Runner(sim_factory(proc, {"app": app}, readings=other), self.profile, opts).run_case(v)
            d, mine = alt.divergence, res.divergence
            if mine is None:   # a divergence in what the IUT reported, not on the wire
                same = d is None and alt.verdict == R.FAIL and alt.message == res.message
            else:
                same = d is not None and d.step == mine.step and d.observed == mine.observed
            if not same:
                continue
            res.notes.append(f"failed: {res.message}")
            res.verdict = grade
            res.message = (f"the IUT takes the other reading of open point {name} (docs/readings.md), which "
                           f"the procedure grades {grade}: the model with that reading does the same "
                           f"({res.message})")
            return

    def _rerun_budget(self, v: Vector, outcome: str, realtime: bool) -> int:
        """How many times a failed case runs again before its failure stands. A failure is
        reproduced before it is reported where the machine's own timing could have caused
        it: a case that failed only by a late reply, or in an attempt the machine disturbed
        (CaseRun.disturbance), runs once more; a case close to a timer's
        edge (an acceptance at 80 % of CDT or ADT, an initialization conflict) runs up to
        ``edge_attempts`` times in all over a real-time transport, and passes if any attempt
        passes: one acceptance proves the IUT waits long enough, while a refusal may come
        from a process that was scheduled a few milliseconds late. A deterministic early
        timeout fails every attempt. Over a network serial server (rfc2217://, socket://)
        every failed case runs once more: a server that stalls longer than CDT puts a gap on
        the line that the harness never sent."""
        if not self.opts.confirm_late:
            return 0
        budget = 1 if outcome in ("late", "disturbed") else 0
        if v.timing_sensitive and realtime:
            budget = max(budget, self.opts.edge_attempts - 1)
        if NETWORK in self.factory.capabilities and realtime:
            budget = max(budget, 1)   # a server that stalls longer than CDT puts a gap on the line
        return budget

    def _pause(self, n: int, realtime: bool) -> None:
        """Before the n-th repeated attempt, let a burst of load on the machine pass."""
        if realtime and self.opts.retry_pause:
            time.sleep(self.opts.retry_pause[min(n, len(self.opts.retry_pause)) - 1])

    def _attempt(self, v: Vector, steps, params: Any, res: R.CaseResult, may_interrupt_earlier: bool = False) -> str:
        """Run once; fill ``res``; return "ok", "timing" (voided), "late" (failed by
        lateness only), "disturbed" (failed in an attempt the machine disturbed: reproduce
        it) or "displaced:N" (the stimulus of step N was meant to interrupt a block that had
        ended; run again interrupting earlier)."""
        try:
            tr = self.factory(v, params)
        except TransportError as exc:
            res.verdict, res.message = R.ERROR, f"transport: {exc}"
            return "ok"
        tol = self.opts.tolerance or (VIRTUAL if tr.virtual else realtime_tolerance(v.proc, params, self.opts.late_ms))
        if self.profile is not None and self.profile.timer_tolerance_ms:
            tol = replace(tol, iut_timer=self.profile.timer_tolerance_ms / 1000.0)
        outcome = "ok"
        run: CaseRun | None = None
        info = None
        res.divergence = None
        try:
            tr.open()
            run = self.last_run = CaseRun(v, steps, tr, params, tol, self.opts)
            run.prologue(self.state)
            try:
                run.run_steps()
                run.epilogue()
            except StepFailed:
                if run.displaced is not None and run.realtime and self.opts.rejudge and not (
                        may_interrupt_earlier and earlier_interrupt(steps, run.displaced[0]) is not None):
                    try:    # the case will be judged by the model: get the rest of the exchange
                        run.observe_rest()
                    except (StepFailed, Flood):
                        pass
                raise
            res.verdict, res.message = run.grade, "; ".join(run.notes)
        except StepFailed as exc:
            res.verdict, res.message, res.divergence = R.FAIL, exc.message, exc.div
            outcome = "late" if exc.late_only else "ok"
        except TimingFault as exc:
            res.verdict, res.message = R.ERROR, f"harness timing fault: {exc}"
            outcome = "timing"
        except Flood as exc:
            res.verdict, res.message = R.FAIL, str(exc)
        except IUTDied as exc:
            res.verdict, res.message = R.FAIL, f"{exc} during step {run.step_index + 1 if run else 0}"
            res.stderr_tail = exc.stderr_tail
        except TransportError as exc:
            res.verdict, res.message = R.ERROR, f"transport: {exc}"
        except (KeyboardInterrupt, SystemExit):
            raise
        except Exception as exc:  # a harness bug: an error, never blamed on the IUT
            import traceback
            res.verdict = R.ERROR
            res.message = f"harness fault: {type(exc).__name__}: {exc}"
            res.notes.append(traceback.format_exc(limit=6))
        finally:
            try:
                info = tr.close()
            except Exception as exc:  # never lose the result because closing failed
                res.notes.append(f"closing the transport failed: {exc}")
        if info is not None:
            if info.stderr:
                res.stderr_tail = info.stderr[-2000:]
            res.notes.extend(info.notes)
        if run is not None:
            res.transcript = run.transcript()
            try:
                res.frames = v.proc.describe_frames(run.log, params)
                mark_divergence_frame(v.proc, res, run.log, steps, params)
            except Exception as exc:  # a decoder's fault must not cost the verdict
                res.notes.append(f"frames could not be decoded: {type(exc).__name__}: {exc}")
            res.origin = run.t0
            res.forced_wait = round(run.forced, 6)
            res.case_time = round(tr.now() - run.t0, 6) if tr.virtual else 0.0
            if res.verdict != R.ERROR:  # also for a failed attempt: the report shows what the IUT raised
                self._judge_events(v, tr, res, run)
            if res.verdict == R.FAIL and run.realtime and self.opts.rejudge:
                outcome = self._rejudge(v, steps, params, tr, run, res, outcome, may_interrupt_earlier)
        return outcome

    def _rejudge(self, v: Vector, steps, params: Any, tr: Transport, run: CaseRun, res: R.CaseResult,
                 outcome: str, may_interrupt_earlier: bool) -> str:
        """A failed real-time attempt, judged again by the model fed the line as it was
        (:mod:`ptpcert.replay`):

        * a stimulus meant to interrupt a block of the IUT went out when the whole block
          was already on the line: the attempt is repeated once with the stimulus after the
          block's first byte; if the block has ended again (an IUT that writes it in one
          piece), the exchange is judged by the rule for the state the IUT was really in:
          the model, fed the same line, must send what the IUT sent and raise what it
          raised;
        * otherwise, if the model fed the tester's bytes as early or as late as they may
          have reached the IUT (the harness reads a byte late when it is descheduled, and
          times its reply from that read) does what the IUT did, the divergence is the
          harness's timing, not the IUT's: the attempt is void (run again; an error if it
          keeps happening)."""
        from ptpcert import replay as RP
        from ptpcert.procedure import ProcedureError
        from ptpcert.transport import sim_factory

        proc = v.proc
        if run.displaced is not None:
            stim, part = run.displaced
            why = (f"the IUT's block (step {part + 1}) was on the line whole before the tester's stimulus (step "
                   f"{stim + 1}) went out, so the stimulus reached an IUT whose block had ended")
            if may_interrupt_earlier and earlier_interrupt(steps, stim) is not None:
                res.message = f"{why}; the attempt is repeated with the stimulus after the block's first byte"
                return f"displaced:{stim}"
        elif res.divergence is None and not res.message.startswith("STATUS: "):
            return outcome
        tol = run.tol
        margin = RP.Margin(early=lambda d: tol.early + tol.early_rel * max(d, 0.0),
                           late=lambda d: tol.late(d) + (tol.iut_timer if d > 3 * run.char + 0.001 else 0.0))
        wire = RP.Wire.from_log(run.log, run.lower_bound, run.rel(run.last_look))
        # the procedure's own application unless the profile has none (RK 512: its script)
        options = {} if (self.profile is None or self.profile.echo) else {"app": "none"}
        try:
            factory = sim_factory(proc, options)
        except (ValueError, ProcedureError):
            factory = sim_factory(proc, {})
        startup = RESTART in tr.capabilities

        def model(late: bool, stall: float = 0.0):
            return RP.replay(factory(v, params), wire, margin, late=late, startup_on_line=startup,
                             longest=run.longest, char=run.char, stall=stall)

        try:
            if run.displaced is not None:
                rep = model(late=False)
                problems = self._status_by_model(v, run, rep.codes) if rep.agrees else []
                if rep.agrees and not problems:
                    res.verdict, res.divergence = R.PASS, None
                    res.message = (f"{why}; the case's rule could not be exercised, so the exchange was judged by the "
                                   "rule for that state (the reference model fed the same line does what the IUT did)")
                else:
                    res.verdict = R.FAIL
                    res.message = (f"{why}; judged by the rule for that state (the reference model fed the same "
                                   "line): " + (rep.why or "STATUS: " + "; ".join(problems)))
                    if rep.at is not None:
                        res.divergence = R.Divergence(-1, round(rep.at, 6), "what the reference model does on the "
                                                      "same line", rep.why)
                return "ok"
            worst = max(run.max_stall, run.iut_stall)
            if worst <= tol.stimulus and not run.starved and run.partner_late <= tol.stimulus:
                # the harness kept its own timing in this attempt (no read or write came
                # later than its tolerance), and the IUT's process was not seen kept from a
                # CPU as long: the tester's bytes went out and the IUT's were read as
                # planned, so the divergence is the IUT's; judging it again by a model fed
                # other timings would only explain real defects away (steal time the
                # hypervisor took may still have kept the IUT from its CPU: then the failure
                # is reproduced before it stands)
                return self._confirm(run, res, outcome)
            if run.iut_stall > run.max_stall or run.starved:
                res.notes.append(f"the IUT's process was kept from a CPU by the machine's load for up to "
                                 f"{1000 * run.iut_stall:.1f} ms at a time, and for {1000 * run.iut_wait:.1f} ms in all "
                                 f"within {1000 * run.shortest:.0f} ms (its shortest timer), in this attempt (its "
                                 "run-queue wait)")
            differences = []
            first_at = None     # where the model fed the line as it was first does otherwise
            # the machine stalled the harness or the IUT noticeably: the IUT process may have
            # been stalled that long (a third timeline); a stall under a character time is noise
            stall = worst + run.look if worst > run.char else 0.0
            timelines = [(False, 0.0), (True, 0.0)] + ([(False, stall)] if stall else [])
            # The tester, as the IUT's conforming partner, replied later than its model had it
            # due: the wire shows the reply within the IUT's timer, but an IUT that starts its
            # timer as its process hands over a block, and writes the block some milliseconds
            # later, whole, had less of that timer left than the wire shows. The harness's
            # lateness and the IUT's add up; the IUT's is not seen, so it is taken as up to its
            # shortest timer (a longer one shows as its process's stall).
            partner = run.partner_late + run.shortest if run.partner_late > tol.stimulus else 0.0
            if partner > stall:
                timelines.append((False, partner))
            for late, stalled in timelines:
                rep = model(late, stalled)
                if not late and not stalled:
                    first_at = rep.at
                problems = self._status_by_model(v, run, rep.codes) if rep.agrees and res.divergence is None else []
                differences.append(f"{rep.timeline} timeline: " + (rep.why or "STATUS: " + "; ".join(problems)))
                if rep.agrees and not problems:
                    whose = ("the IUT's process, kept from a CPU by the machine's load" if run.iut_stall > run.max_stall
                             else "the harness")
                    how = (f"up to {1000 * stalled:.1f} ms later than they went out (the tester's reply as the "
                           f"IUT's partner went out {1000 * run.partner_late:.1f} ms later than its model had it "
                           "due, and an IUT that writes a block whole may have started its timer up to its shortest "
                           "timer before the block reached the line)" if stalled and stalled == partner else
                           f"as late as a process stalled for up to {1000 * stalled:.1f} ms (the longest stall "
                           f"measured in this attempt, of {whose}, plus the harness's look period) may have taken "
                           "them, with as many of its own bytes out as a stalled IUT may have had" if stalled else
                           "as late after the IUT's bytes as they may have reached it (the harness read an IUT byte "
                           "late and timed its reply from that read)" if late else
                           "when they really went out (the IUT had acted before the tester's reply reached it)")
                    res.notes.append(f"failed attempt: {res.message}")
                    res.verdict = R.ERROR
                    res.message = ("harness timing fault: the reference model, fed the tester's bytes " + how +
                                   ", does what the IUT did; the divergence is the harness's timing, not the IUT's")
                    return "timing"
            res.notes.append("the reference model fed the line as it was does not do what the IUT did, however "
                             "late the tester's bytes reached it (" + "; ".join(differences) + ")")
            known = [t for t in (first_at, None if res.divergence is None else res.divergence.time) if t is not None]
            if run.partner_due is not None and known and min(known) >= run.rel(run.partner_due):
                # The tester, as the IUT's partner, sent a reply later than the harness keeps
                # its timing to, and everything the IUT did otherwise than the case and the
                # model came after that reply was due. Once a reply comes late, the IUT may
                # have run out a timer it would have met (its own lag is not on the wire), and
                # what follows from that, its repetitions crossing the partner's late replies,
                # no model can replay. The attempt is void (run again; an error if it keeps
                # happening), never a fail; a divergence before the late reply still fails.
                res.notes.append(f"failed attempt: {res.message}")
                res.verdict = R.ERROR
                res.message = (f"harness timing fault: the tester's reply as the IUT's partner, due at "
                               f"{1000 * run.rel(run.partner_due):.1f} ms, went out later than the harness keeps its "
                               f"timing to ({1000 * tol.stimulus:.1f} ms; up to {1000 * run.partner_late:.1f} ms late in "
                               f"this attempt), and the IUT's divergence came after it (at {1000 * min(known):.1f} ms): "
                               "it cannot be told from the harness's timing")
                return "timing"
        except Exception as exc:   # the re-judgement must never cost the verdict
            res.notes.append(f"re-judging by the model failed: {type(exc).__name__}: {exc}")
        if max(run.max_stall, run.iut_stall) >= run.shortest or run.starved:
            # The machine stalled the harness (and so, as likely, the IUT process) or the IUT
            # process itself as long as the IUT's shortest timer in this attempt: the IUT may
            # then have missed a whole timer window, and what it saw on the line cannot be
            # known well enough to blame it. (A shorter stall is covered by the stalled
            # timeline above.)
            res.notes.append(f"failed attempt: {res.message}")
            res.verdict = R.ERROR
            if run.max_stall >= run.shortest:
                what = f"the harness was stalled for up to {1000 * run.max_stall:.1f} ms"
            elif run.iut_stall >= run.shortest:
                what = f"the IUT's process was kept from a CPU for up to {1000 * run.iut_stall:.1f} ms"
            else:
                what = (f"the IUT's process was kept from a CPU for {1000 * run.iut_wait:.1f} ms in all within "
                        f"{1000 * run.shortest:.0f} ms, its shortest timer")
            res.message = (f"harness timing fault: {what} in this attempt (the harness keeps its own timing to "
                           f"{1000 * tol.stimulus:.1f} ms); the IUT's divergence cannot be told from the machine's "
                           "load")
            return "timing"
        return self._confirm(run, res, outcome)

    @staticmethod
    def _confirm(run: CaseRun, res: R.CaseResult, outcome: str) -> str:
        """A failure that stands in an attempt the machine disturbed (the harness or the IUT's
        process stalled or kept waiting for a CPU, a partner reply late, the hypervisor
        taking a CPU away) is reproduced before it is reported: "disturbed", which runs the
        case once more. A defect fails again; a divergence that the machine caused, in a way
        no measurement here could pin on it, does not come back. It never turns a failure
        into a pass or an error by itself."""
        if outcome != "ok" or res.verdict != R.FAIL:
            return outcome
        what = run.disturbance()
        if what is None:
            return outcome
        res.notes.append(f"the machine disturbed this failed attempt: {what}")
        return "disturbed"

    def _status_by_model(self, v: Vector, run: CaseRun, model_codes: list[int]) -> list[str]:
        """STATUS judged by the model's own events on the same line: everything the IUT
        raised is allowed by the case or raised by the model, and every event the case
        requires is raised unless the model does not raise it either."""
        if run.status_codes is None:
            return []
        spec = v.expected.iut_status
        seen, model = set(run.status_codes), set(model_codes)
        problems = ["missing " + " or ".join(f"16#{c:04X}" for c in sorted(g))
                    for g in spec.required if not g & seen and g & model]
        extra = sorted(c for c in seen if c not in spec.allowed and c not in model)
        if extra:
            problems.append("unexpected " + ", ".join(f"16#{c:04X}" for c in extra))
        return problems

    def _judge_events(self, v: Vector, tr: Transport, res: R.CaseResult, run: CaseRun) -> None:
        if STATUS in tr.capabilities and self.opts.check_status:
            codes = [c for _, c in tr.status_reports()]
            run.status_codes = codes
            res.observed_status = [status_text(c) for c in codes]
            res.status_checked = True
            problems = v.expected.iut_status.judge(codes)
            if problems and res.verdict != R.FAIL:
                res.verdict = R.FAIL
                res.message = "STATUS: " + "; ".join(problems) + (f" (reported: {', '.join(res.observed_status) or 'none'})")
            soft = v.expected.iut_status.soft_missing(codes)
            if soft and res.verdict in R.GRADE_ORDER:
                res.verdict = R.worse_grade(res.verdict, R.INFORMATIONAL)
                res.message = "; ".join(x for x in (res.message, "STATUS: the IUT took another reading of an open "
                                                    "point: " + ", ".join(soft) + " not reported (reported: "
                                                    + (", ".join(res.observed_status) or "none") + ")") if x)
            # what the procedure's IUT reports beyond STATUS (e.g. RK 512 request results)
            lines = [text for _, text in tr.report_lines()]
            more = v.proc.judge_reports(v, lines)
            if more and res.verdict != R.FAIL:
                res.verdict = R.FAIL
                res.message = "reported: " + "; ".join(more)
        if self.opts.check_model_events and hasattr(tr, "delivered") and res.verdict != R.FAIL:
            want = list(v.expected.delivered)
            have = tr.delivered()
            if have != want:
                res.verdict = R.FAIL
                res.message = ("delivered " + (", ".join(hexstr(x) for x in have) or "nothing")
                               + "; the vector says " + (", ".join(hexstr(x) for x in want) or "nothing"))
            elif v.expected.sent and tr.sent()[: len(v.expected.sent)] != list(v.expected.sent):
                res.verdict = R.FAIL
                res.message = "completed send jobs differ from the vector's 'sent'"

    # -- a whole run -----------------------------------------------------------------
    def run(self, vectors: Iterable[Vector], result: R.RunResult,
            progress: Callable[[int, int, R.CaseResult], None] | None = None,
            max_failures: int = 0, jobs: int = 1,
            pool: list[tuple[str, Any]] | None = None) -> R.RunResult:
        """Run ``vectors`` and append their results to ``result`` in order. ``jobs`` > 1
        runs cases concurrently where the factory starts an IUT per case; ``pool`` (device
        name, factory) spreads the cases over several identical IUTs and names in each result
        the device that ran it (see :mod:`ptpcert.parallel`)."""
        vs = list(vectors)
        if pool or (jobs > 1 and getattr(self.factory, "concurrency", 1) > 1):
            from .parallel import ParallelRun

            devices = list(pool) if pool else [(getattr(self.factory, "url", ""), self.factory)]
            # a runner per worker; what the runner learns about an IUT (does a fresh one send
            # its start-up NAK? is the line settled?) is shared by the workers of one device:
            # a worker whose first IUT was slow to start must not teach itself that none does
            states: dict[int, RunnerState] = {id(self.factory): self.state}

            def make(f) -> "Runner":
                r = Runner(f, self.profile, self.opts)
                r.state = states.setdefault(id(f), RunnerState())
                return r
            return ParallelRun(make, devices, jobs, name_devices=bool(pool)).run(vs, result, progress, max_failures)
        t0 = time.monotonic()
        stop_reason = ""
        failures = 0
        try:
            prepare = getattr(self.factory, "prepare", None)
            for i, v in enumerate(vs):
                if prepare is not None and i + 1 < len(vs):
                    # let the transport start what the next case needs while this one runs
                    # (not for a case that will not run: its process would wait for nothing)
                    nxt = vs[i + 1]
                    if self.unsupported_reason(nxt, self.factory.capabilities) is None:
                        prepare(nxt, self.effective_params(nxt))
                c = self.run_case(v)
                result.cases.append(c)
                if progress:
                    progress(i + 1, len(vs), c)
                failures += c.verdict in R.FAILING
                if max_failures and failures >= max_failures:
                    stop_reason = f"not run: the run stopped after {failures} failed case(s) (--max-failures)"
                    break
        except KeyboardInterrupt:
            result.interrupted = True
            stop_reason = "run interrupted"
        finally:
            if stop_reason:
                done = {c.id for c in result.cases}
                for v in vs:
                    if v.id not in done:
                        result.cases.append(R.CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role,
                                                         verdict=R.NOT_RUN, message=stop_reason))
            result.wall_time = round(time.monotonic() - t0, 3)
        return result


def mark_divergence_frame(proc: Any, res: R.CaseResult, log: list[dict], steps: tuple[Step, ...],
                          params: Any) -> None:
    """Mark the frame the first divergence falls in (``diverged``) and, where the step that
    diverged expected bytes from the IUT, name the frame expected in its place
    (``expected``): the procedure decodes the transcript with those bytes put in for what
    came at that step."""
    f = R.divergence_frame(res)
    if f is None:
        return
    f["diverged"] = True
    div = res.divergence
    if f.get("dir") != "iut" or not 0 <= div.step < len(steps):
        return
    step = steps[div.step]
    if step.kind != "expect" or not step.data:
        return
    before = [e for e in log if e.get("dir") in ("tester", "iut") and e.get("step", -1) < div.step]
    # the expected bytes take the times of the bytes that came instead (so that a decoder
    # that splits by pauses splits alike), those beyond them follow at once
    came = [float(e["t"]) for e in log if e.get("dir") == "iut" and e.get("step") == div.step
            and e.get("kind") in ("byte", "char_error") and "t" in e]
    t = max([float(e.get("t", 0.0)) for e in before] + came + [float(f["t0"])])
    synth = before + [{"t": came[k] if k < len(came) else round(t + (k - len(came) + 1) * 1e-6, 7),
                       "dir": "iut", "kind": "byte", "byte": b, "step": div.step}
                      for k, b in enumerate(step.data)]
    try:
        frames = proc.describe_frames(synth, params)
    except Exception:  # a decoder's fault must not cost the verdict
        return
    same = [g for g in frames if g.get("dir") == "iut" and abs(float(g["t0"]) - float(f["t0"])) < 1e-6]
    if same:
        f["expected"] = same[0]["label"]
