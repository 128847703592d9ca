"""Running cases concurrently (``ptpcert run --jobs N``, device pools).

Most of a suite run at the manual's timers is waiting the protocol forces (a case that
exhausts its connection set-up attempts waits several times ADT). Cases whose IUTs are
independent (a fresh process per case: ``exec:``, ``pty:``; the model in virtual time:
``sim:``; or one device of a pool each) can wait at the same time.

The design:

- Workers are threads; each drives its cases with its own :class:`~ptpcert.runner.Runner`
  (so its own ``RunnerState``) bound to one factory. A factory that is one line (a device,
  ``rfc2217://``, ``socket://``: ``Factory.concurrency == 1``) gets one worker; one that
  starts an IUT per case gets as many as ``jobs`` allows.
- Workers take the next case from one shared queue, so the cases spread over the pool.
- The results keep the order of the cases, and the progress lines come in that order too
  (a line is printed when every case before it is done), each also saying how many cases
  are running; the reports are the same as a serial run's.
- Concurrency never costs a verdict: the runner's timing checks stay in force (an attempt
  the harness could not time is void and repeated, or the case is an *error*), and a case
  that failed, or ended in a harness timing fault, while other cases ran beside it runs
  again alone, after the others, on the same device, up to twice: the first alone run that
  does not fail stands (else the last). A deterministic failure fails every run; the runs
  beside others are kept in the notes.
"""

from __future__ import annotations

import os
import queue
import threading
import time
from typing import Callable, Sequence

from ptpcert import priority
from ptpcert import results as R

#: what a progress callback gets: (cases done in order, cases in all, the case, cases running)
Progress = Callable[..., None]


def parse_jobs(text: str) -> int:
    """``--jobs``: a whole number from 1, or ``auto`` (the number of cores)."""
    t = str(text).strip().lower()
    if t == "auto":
        return max(1, os.cpu_count() or 1)
    try:
        n = int(t)
    except ValueError:
        raise ValueError(f"{text!r} is not a number of jobs (a whole number from 1, or auto)") from None
    if n < 1:
        raise ValueError(f"{text!r}: at least 1 job (or auto)")
    return n


def concurrency(factory) -> int:
    """How many cases one factory can carry at the same time: one for a line (a device or a
    port server), any number where every case gets its own IUT."""
    return getattr(factory, "concurrency", 1)


def plan_workers(pool: Sequence[tuple[str, object]], jobs: int, cases: int) -> list[int]:
    """The pool index each worker uses: one worker per line, and ``jobs`` (at least one per
    entry of the pool) spread over the entries that start an IUT per case."""
    slots = [1 for _ in pool]
    want = max(jobs, len(pool))
    free = [i for i, (_, f) in enumerate(pool) if concurrency(f) > 1]
    k = 0
    while sum(slots) < want and free:
        i = free[k % len(free)]
        if slots[i] < concurrency(pool[i][1]):
            slots[i] += 1
        elif all(slots[j] >= concurrency(pool[j][1]) for j in free):
            break
        k += 1
    plan = [i for i, n in enumerate(slots) for _ in range(n)]
    return plan[:max(1, min(len(plan), cases))] if cases else plan[:1]


#: how often a case that failed beside other cases runs again alone, at most: a machine
#: loaded by others can make even an alone run of a correct IUT late once
CONFIRM_RUNS = 2
CONFIRM_PAUSE = 0.5   # seconds before the second


def _needs_confirming(c: R.CaseResult) -> bool:
    return c.verdict == R.FAIL or (c.verdict == R.ERROR and "harness timing fault" in c.message)


class ParallelRun:
    """One run of ``vectors`` over ``pool`` ([(device name, factory)]) with ``jobs``
    workers; :meth:`run` fills ``result`` as :meth:`Runner.run` does."""

    def __init__(self, make_runner: Callable[[object], object], pool: Sequence[tuple[str, object]],
                 jobs: int, name_devices: bool):
        self.make_runner = make_runner
        self.pool = list(pool)
        self.jobs = jobs
        self.name_devices = name_devices
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._idle = threading.Event()   # set when no worker is left
        self._idle.set()
        self._alive = 0

    def run(self, vs, result: R.RunResult, progress: Progress | None, max_failures: int) -> R.RunResult:
        n = len(vs)
        plan = plan_workers(self.pool, self.jobs, n)
        runners = [self.make_runner(self.pool[i][1]) for i in plan]
        devices = [self.pool[i][0] for i in plan]
        concurrent = len(plan) > 1
        virtual = all(getattr(f, "virtual", False) for _, f in self.pool)
        done: list[R.CaseResult | None] = [None] * n
        by: list[int] = [0] * n       # the worker (so the device) that ran each case
        final = [False] * n
        running = [0]
        emitted = [0]
        failures = [0]
        stop_reason = ""
        t0 = time.monotonic()
        before = len(result.cases)
        todo: queue.Queue[int] = queue.Queue()
        for i in range(n):
            todo.put(i)

        def emit() -> None:
            """Progress lines in the cases' order, as far as the cases are final."""
            while emitted[0] < n and final[emitted[0]]:
                c = done[emitted[0]]
                emitted[0] += 1
                if progress:
                    progress(emitted[0], n, c, running=running[0])

        def work(w: int) -> None:
            try:
                with priority.thread():     # the run's scheduling class (a thread begins in the normal one)
                    work_on(w)
            finally:
                with self._lock:
                    self._alive -= 1
                    if not self._alive:
                        self._idle.set()

        def work_on(w: int) -> None:
            runner = runners[w]
            factory = runner.factory
            prepare = getattr(factory, "prepare", None)
            while not self._stop.is_set():
                try:
                    i = todo.get_nowait()
                except queue.Empty:
                    return
                with self._lock:
                    running[0] += 1
                if prepare is not None and i + 1 < n:
                    # the case the next free worker takes: its IUT starts while this one runs
                    nxt = vs[i + 1]
                    if runner.unsupported_reason(nxt, factory.capabilities) is None:
                        try:
                            prepare(nxt, runner.effective_params(nxt))
                        except Exception:   # starting ahead is an optimisation only
                            pass
                try:
                    c = runner.run_case(vs[i])
                except BaseException as exc:   # never lose a case without a result
                    c = R.CaseResult(vs[i].id, vs[i].title, vs[i].reference, vs[i].rule, vs[i].group,
                                     vs[i].iut_role, verdict=R.ERROR,
                                     message=f"harness fault: {type(exc).__name__}: {exc}")
                if self.name_devices:
                    c.device = devices[w]
                with self._lock:
                    running[0] -= 1
                    done[i], by[i] = c, w
                    if not (concurrent and not virtual and _needs_confirming(c)):   # else: once confirmed
                        final[i] = True
                        failures[0] += c.verdict in R.FAILING
                    pending = sum(1 for j in range(n) if done[j] is not None and not final[j])
                    if max_failures and failures[0] + pending >= max_failures:
                        self._stop.set()
                    emit()

        def confirm() -> None:
            """Run the cases that failed beside others again, alone, on their device: up to
            CONFIRM_RUNS times; the first alone run that does not fail stands, else the last."""
            for i in range(n):
                if done[i] is None or final[i]:
                    continue
                first = done[i]
                runner = runners[by[i]]
                notes = [f"ran beside other cases (--jobs) with verdict {first.verdict}: {first.message}"]
                duration, attempts = first.duration, first.attempts
                for k in range(CONFIRM_RUNS):
                    if k:
                        time.sleep(CONFIRM_PAUSE)   # let a burst of load on the machine pass
                    again = runner.run_case(vs[i])
                    duration += again.duration
                    attempts += again.attempts
                    if not _needs_confirming(again) or k + 1 == CONFIRM_RUNS:
                        break
                    notes.append(f"ran again alone with verdict {again.verdict}: {again.message}")
                notes.append(f"ran alone {k + 1} time(s); the last run's verdict stands")
                if self.name_devices:
                    again.device = first.device
                again.notes[:0] = notes
                again.duration = round(duration, 4)
                again.attempts = attempts
                with self._lock:
                    done[i], final[i] = again, True
                    failures[0] += again.verdict in R.FAILING
                    emit()

        try:
            while True:
                self._stop.clear()
                threads = [threading.Thread(target=work, args=(w,), name=f"ptpcert-job-{w}", daemon=True)
                           for w in range(len(plan))]
                # before they start: an interrupt may come at any point
                self._alive = len(threads)
                self._idle.clear()
                for t in threads:
                    t.start()
                self._join()
                confirm()
                if todo.empty():
                    break
                if max_failures and failures[0] >= max_failures:
                    break
        except KeyboardInterrupt:
            self._stop.set()
            result.interrupted = True
            stop_reason = "run interrupted"
            self._join_quietly()
        finally:
            # the serial run's semantics: the results in order, up to where it would have stopped
            count = 0
            for i, v in enumerate(vs):
                c = done[i]
                if c is not None and final[i]:
                    result.cases.append(c)
                    count += c.verdict in R.FAILING
                    if max_failures and count >= max_failures:
                        stop_reason = f"not run: the run stopped after {count} failed case(s) (--max-failures)"
                        break
                    continue
                why = stop_reason or "run interrupted"
                if c is not None:   # interrupted before its failure beside other cases was confirmed alone
                    why = (f"{why} before the case could run again alone (beside other cases it ended "
                           f"{c.verdict}: {c.message})")
                result.cases.append(R.CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role,
                                                 verdict=R.NOT_RUN, message=why))
            for v in vs[len(result.cases) - before:]:
                result.cases.append(R.CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role,
                                                 verdict=R.NOT_RUN, message=stop_reason))
            result.wall_time = round(time.monotonic() - t0, 3)
        return result

    def _join(self) -> None:
        """Wait for the workers. Not with Thread.join: a KeyboardInterrupt inside it can
        leave a running thread marked as ended (CPython gh-90882), and then the cases in
        flight would be lost."""
        while not self._idle.wait(0.2):
            pass

    def _join_quietly(self) -> None:
        """After an interrupt: the cases in flight end (each within its own bounds) before
        their IUTs are stopped and the reports written."""
        while True:
            try:
                self._join()
                return
            except KeyboardInterrupt:
                pass
