"""``ptpcert fuzz --workers N``: N campaigns at once, each a process of its own with its own
IUT, all sharing one hypothesis example database; their findings are merged."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

from ..profile import load_profile
from ..runner import Runner, RunOptions
from ..transport import make_factory
from .campaign import Campaign, Finding, finding_key
from .settings import register_profiles


@dataclass(frozen=True)
class WorkerSpec:
    """What a worker process needs to set up its own IUT and campaign (picklable)."""
    iut: str
    profile: str
    budget: float
    seed: int
    settings_profile: str = "ptpcert-quick"
    database: str | None = None
    max_actions: int = 6
    workers: int = 1


@dataclass
class WorkersResult:
    examples: int = 0
    informational: int = 0
    #: findings whose exported vector passed on replay, and examples voided by a late
    #: interruption (see Campaign)
    not_reproduced: int = 0
    void: int = 0
    findings: list[Finding] = field(default_factory=list)
    elapsed: float = 0.0
    #: workers that ended without their results: (worker, why)
    errors: list[tuple[int, str]] = field(default_factory=list)
    interrupted: bool = False


def _worker_main(spec: WorkerSpec, index: int, queue) -> None:
    """One worker process: its own IUT (a new instance of ``spec.iut``), its own campaign,
    the shared example database; progress and results go to ``queue``."""
    camp = factory = None
    interrupted, error = False, ""
    register_profiles()   # a spawned process: the settings profiles are registered here
    try:
        profile = load_profile(spec.profile)
        factory = make_factory(spec.iut, profile)
        kit = profile.procedure.fuzz_kit()
        check = bool(kit is not None and kit.check_reports and profile.status_from_stderr)
        runner = Runner(factory, profile, RunOptions(check_status=check, late_ms=50.0))
        camp = Campaign(profile, runner, spec.budget, spec.seed, spec.settings_profile, spec.database,
                        progress=lambda line: queue.put(("progress", index, line)),
                        max_actions=spec.max_actions, worker=index, workers=spec.workers)
        camp.run()
    except KeyboardInterrupt:
        interrupted = True
    except Exception as exc:   # reported by the parent as this worker's error
        error = f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
    finally:
        if factory is not None:
            try:
                factory.shutdown()
            except KeyboardInterrupt:
                interrupted = True
    queue.put(("done", index, camp.examples if camp else 0, camp.informational if camp else 0,
               camp.findings if camp else [], interrupted, error,
               camp.not_reproduced if camp else 0, camp.void if camp else 0))


def run_workers(spec: WorkerSpec, progress: Callable[[str], None] | None = None) -> WorkersResult:
    """``spec.workers`` campaigns at once, each in a process of its own with its own IUT,
    all sharing ``spec.database`` (hypothesis's example database: a failing example one
    worker saves is replayed and shrunk further by the others in their next round). Their
    findings are merged (one per :func:`finding_key`) and their example counts added up."""
    import multiprocessing as mp
    import queue as queue_mod

    ctx = mp.get_context("spawn")   # a fresh interpreter: no inherited threads or IUT pipes
    q = ctx.Queue()
    out = WorkersResult()
    started = time.monotonic()
    procs = {i: ctx.Process(target=_worker_main, args=(spec, i, q), name=f"ptpcert-fuzz-worker-{i}")
             for i in range(spec.workers)}
    for p in procs.values():
        p.start()
    pending = set(procs)
    seen: set[str] = set()
    grace_until = None
    try:
        while pending:
            try:
                msg = q.get(timeout=0.5)
            except queue_mod.Empty:
                for i in sorted(pending):
                    if not procs[i].is_alive():     # ended without its results
                        pending.discard(i)
                        out.errors.append((i, f"the worker ended (exit status {procs[i].exitcode})"))
                if grace_until is not None and time.monotonic() > grace_until:
                    break
                continue
            except KeyboardInterrupt:
                out.interrupted = True
                grace_until = time.monotonic() + 15.0   # the workers stop and send what they have
                continue
            if msg[0] == "progress":
                if progress:
                    progress(f"[worker {msg[1]}] {msg[2]}")
                continue
            _, i, examples, informational, findings, interrupted, error, not_reproduced, void = msg
            out.not_reproduced += not_reproduced
            out.void += void
            pending.discard(i)
            out.errors = [e for e in out.errors if e[0] != i]   # its results came after all
            out.examples += examples
            out.informational += informational
            out.interrupted = out.interrupted or interrupted
            if error:
                out.errors.append((i, error))
            for f in findings:
                if finding_key(f) not in seen:
                    seen.add(finding_key(f))
                    out.findings.append(f)
    finally:
        for i, p in procs.items():
            p.join(timeout=5.0 if i not in pending else 0.1)
            if p.is_alive():
                p.terminate()
                p.join(timeout=5.0)
                out.errors.append((i, "stopped: no results"))
    out.elapsed = time.monotonic() - started
    return out
