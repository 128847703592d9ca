"""A whole run: the :class:`Runner` the command line, the pytest plugin, the fuzzers and
the tools drive. It runs the vectors in order and appends their results, letting the
transport prepare the next case's IUT while one runs, stopping after ``max_failures``
failed cases and on an interrupt (the rest are not run); with ``jobs`` or a device pool it
hands the cases to workers (:mod:`ptpcert.runner.parallel`), one runner each.

Each case runs through :class:`ptpcert.runner.attempts.CaseRunner`, which this extends.
"""

from __future__ import annotations

import time
from typing import Any, Callable, Iterable

from ptpcert import results as R
from ptpcert.scenario import Vector

from .attempts import CaseRunner
from .steps import RunnerState


class Runner(CaseRunner):
    """Runs cases, one at a time or a whole run of them, against the IUTs a transport
    factory makes."""

    def run(self, vectors: Iterable[Vector], result: R.RunResult,
            progress: Callable[[int, int, R.CaseResult], None] | None = None,
            max_failures: int = 0, jobs: int = 1,
            pool: list[tuple[str, Any]] | None = None) -> R.RunResult:
        """Run ``vectors`` and append their results to ``result`` in order. ``jobs`` > 1
        runs cases concurrently where the factory starts an IUT per case; ``pool`` (device
        name, factory) spreads the cases over several identical IUTs and names in each result
        the device that ran it (see :mod:`ptpcert.runner.parallel`)."""
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

