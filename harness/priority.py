"""The harness's own place in the machine's scheduler.

On a loaded machine the harness is late when the kernel gives the CPU to other processes:
its bytes go out late and it reads the IUT's late. The runner measures that and turns an
attempt it could not time into *error*, never *fail* - but a harness that keeps its timing
under load turns those errors into verdicts. Where the system permits it (root, or the
capability CAP_SYS_NICE, or an ``rtprio`` limit), the threads that play the partner's role
run in the real-time class ``SCHED_FIFO`` at a low real-time priority: they preempt
ordinary processes as soon as a byte arrives or a send is due, and they sleep in between.

* Only the harness's timing threads are raised: the runner's thread (or each ``--jobs``
  worker thread) and the serial ports' reader threads, for the time of the cases. Report
  writing, and the IUT, stay in the normal class: ``SCHED_RESET_ON_FORK`` makes every
  process and thread they start (the IUT over ``exec:``) begin in the normal class, so the
  IUT is not favoured over the load it is tested under.
* Linux throttles the real-time class to 95 % of each CPU (``sched_rt_runtime_us``): a
  harness fault cannot take a machine over.
* ``--priority auto`` (the default of ``ptpcert run``) takes the real-time class where it is
  permitted and the normal one otherwise; ``realtime`` insists (an error, exit 2, where it
  is not permitted); ``normal`` never asks. Every report says which one the run had.
"""

from __future__ import annotations

import os
import threading
from contextlib import contextmanager
from typing import Iterator

MODES = ("auto", "realtime", "normal")
#: low among real-time priorities (1-99): above every ordinary process, below the kernel's
#: own real-time threads (interrupt handlers run at 50)
RT_PRIORITY = 10

_state = threading.local()
_mode = {"mode": "normal", "granted": False}


class PriorityError(RuntimeError):
    """--priority realtime where the system does not permit it."""


def _raise_this_thread() -> str | None:
    """The calling thread into the real-time class; None, or why it could not be."""
    fifo = getattr(os, "SCHED_FIFO", None)
    if fifo is None or not hasattr(os, "sched_setscheduler"):
        return "this system has no real-time scheduling class"
    try:
        old = (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority)
        os.sched_setscheduler(0, fifo | getattr(os, "SCHED_RESET_ON_FORK", 0), os.sched_param(RT_PRIORITY))
    except PermissionError:
        return ("the system does not permit the real-time class (run as root, grant CAP_SYS_NICE, or raise "
                "the rtprio limit)")
    except OSError as exc:
        return f"the real-time class could not be set: {exc.strerror or exc}"
    _state.old = old
    return None


def _restore_this_thread() -> None:
    old = getattr(_state, "old", None)
    if old is None:
        return
    _state.old = None
    try:
        os.sched_setscheduler(0, old[0], os.sched_param(old[1]))
    except OSError:
        # a real-time thread may always lower itself; should that fail, the normal class
        try:
            os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
        except OSError:
            pass


@contextmanager
def harness(mode: str, *, this_thread: bool = True) -> Iterator[str]:
    """Run the body with the calling thread in the class ``mode`` asks for (see the module
    docstring) and give the sentence every report shows; the thread's old class is back
    afterwards. Threads the body starts take the same class with :func:`thread`. With
    ``this_thread`` False the calling thread stays as it is (it does work that must not
    preempt others, e.g. the monitor's analysis) and only the threads take the class."""
    if mode not in MODES:
        raise ValueError(f"--priority: {mode!r} is not allowed; allowed values: " + ", ".join(MODES))
    why = None if mode == "normal" else _raise_this_thread()
    if mode == "realtime" and why:
        raise PriorityError(f"--priority realtime: {why}")
    granted = mode != "normal" and why is None
    if granted and not this_thread:
        _restore_this_thread()      # it was permitted: the threads will take it
    before = dict(_mode)
    _mode.update(mode=mode, granted=granted)
    try:
        yield describe(mode, granted, why)
    finally:
        _mode.clear()
        _mode.update(before)
        if granted and this_thread:
            _restore_this_thread()


def current() -> str:
    """The class of the calling thread, in words (for tests and diagnostics)."""
    try:
        policy = os.sched_getscheduler(0) & ~getattr(os, "SCHED_RESET_ON_FORK", 0)
    except (AttributeError, OSError):
        return "unknown"
    return "realtime" if policy in (getattr(os, "SCHED_FIFO", -1), getattr(os, "SCHED_RR", -1)) else "normal"


@contextmanager
def thread() -> Iterator[None]:
    """For a timing thread the harness starts (a ``--jobs`` worker, a port's reader): the
    class the run was granted, for the thread's life (a new thread begins in the normal
    class, SCHED_RESET_ON_FORK)."""
    raised = _mode["granted"] and _raise_this_thread() is None
    try:
        yield
    finally:
        if raised:
            _restore_this_thread()


def sync() -> None:
    """For a long-lived thread that may have started before the run took its class (a
    serial port's reader, opened before the first case): called at every turn of its loop,
    it takes the run's class, or gives it back when the run is over."""
    want, have = _mode["granted"], getattr(_state, "raised", False)
    if want and not have:
        _state.raised = _raise_this_thread() is None
    elif have and not want:
        _restore_this_thread()
        _state.raised = False


#: how much lower the processes the harness starts ahead of their case run (their start-up,
#: a Python interpreter's imports, must not take a CPU from the IUT under test); they are
#: back at the normal level when their case takes them
BACKGROUND_NICE = 10


def granted() -> bool:
    """Does the run have the real-time class (and so the privilege to give a process it
    lowered its normal level back)?"""
    return bool(_mode["granted"])


def background(pid: int) -> bool:
    """Lower the process group ``pid`` (an IUT started ahead, in a session of its own) while
    it waits for its case, where the run may raise it again (:func:`granted`). True when
    lowered."""
    if not granted():
        return False
    try:
        os.setpriority(os.PRIO_PGRP, pid, BACKGROUND_NICE)
        return True
    except OSError:
        return False


def foreground(pid: int) -> None:
    """The process group ``pid``, lowered by :func:`background`, back at the normal level
    for its case."""
    try:
        os.setpriority(os.PRIO_PGRP, pid, 0)
    except OSError:
        pass


def run_queue_wait_ns(fd: int) -> int:
    """The run-queue wait of a thread so far, in nanoseconds, from its /proc schedstat
    opened as ``fd`` (second field: time runnable on a run queue but not running). Raises
    OSError when the thread has ended, ValueError/IndexError on a file of another form."""
    return int(os.pread(fd, 256, 0).split()[1])


_STAT = {"fd": None, "opened": False}
#: steal time counts in clock ticks (10 ms where USER_HZ is 100)
TICK = 1.0 / (os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100)


def steal_time() -> tuple[float, ...] | None:
    """Linux on a virtual machine: for each CPU, the time so far that the hypervisor ran
    other work while that CPU had work to do, in seconds (/proc/stat, the cpuN lines'
    eighth number, in clock ticks). A process kept from its CPU this way waits on no run
    queue of this machine: its schedstat does not show it. None where /proc does not tell
    (about 20 microseconds a look, through a descriptor kept open)."""
    if not _STAT["opened"]:
        _STAT["opened"] = True
        try:
            _STAT["fd"] = os.open("/proc/stat", os.O_RDONLY | os.O_CLOEXEC)
        except OSError:
            _STAT["fd"] = None
    fd = _STAT["fd"]
    if fd is None:
        return None
    try:
        lines = os.pread(fd, 65536, 0).split(b"\n")
        per_cpu = tuple(int(x.split()[8]) * TICK for x in lines if x.startswith(b"cpu") and x[3:4].isdigit())
    except (OSError, ValueError, IndexError):
        return None
    return per_cpu or None


def describe(mode: str, granted: bool, why: str | None = None) -> str:
    if granted:
        return (f"real-time (SCHED_FIFO, priority {RT_PRIORITY}) for the harness's timing threads; the IUT and "
                "everything else in the normal class")
    if mode == "normal":
        return "normal (--priority normal)"
    return f"normal ({why})" if why else "normal"
