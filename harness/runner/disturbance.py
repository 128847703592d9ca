"""What the machine did to either process during one attempt: the harness stalled (a read
that returned late, its own thread waiting for a CPU), the IUT's process kept from a CPU
(its run-queue wait, where the transport tells), and steal time the hypervisor took from a
CPU of this machine.

The lowest stateful layer of a case's run (:class:`MachineWatch`, under
:class:`ptpcert.runner.pump.CaseLine`): the byte pump calls :meth:`MachineWatch.watch` after
every look at the line. The figures decide nothing here; the re-judgement
(:mod:`ptpcert.runner.rejudge`) and the rerun policy (:mod:`ptpcert.runner.attempts`) read
them, and :meth:`MachineWatch.disturbance` says in words what was material.
"""

from __future__ import annotations

import collections
import os
import weakref

from ptpcert import priority
from ptpcert.transport.base import Transport

#: an IUT process that waited for a CPU this share of a stretch as long as its shortest timer
#: may have missed that timer for the machine's load (a steady load: a little at every moment)
STARVED = 0.4


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


class MachineWatch:
    """The disturbances of one attempt. The byte pump samples the machine at every look at
    the line in real time (:meth:`watch`); the steps add how late the tester's own bytes
    went out (``max_stall``), the partner play how late its replies did (``partner_late``,
    ``partner_due``)."""

    def __init__(self, tr: Transport, shortest: float):
        self.tr = tr
        #: the IUT's shortest timer: the stretch within which waits and steal add up
        self.shortest = shortest
        self.realtime = not tr.virtual
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

    def watch(self, until: float) -> None:
        """After a look at the line (a read meant to return by ``until``): was the harness
        stalled, and did the IUT wait for a CPU most of the time since the look before?
        Consecutive such looks make one stall of the IUT (how long it could not act)."""
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
