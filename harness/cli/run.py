"""``ptpcert run``: the suite against an IUT, with its reports; and what a command that drives
an IUT needs: reaching it (checked before the first case), and signals that stop the work
without costing the reports."""

from __future__ import annotations

import os
import signal
import sys

from ptpcert import __version__
from ptpcert.priority import MODES as PRIORITY_MODES

from .common import load_profile, now, number
from .reports import report_paths_problem, write_reports

#: the bounds of the numeric options (the messages name them)
TOLERANCE_MS = number(float, 0, 10_000, "milliseconds")
STARTUP_S = number(float, 0.1, 600, "seconds")
MAX_FAILURES = number(int, 0, None, "(0: no limit)")
EDGE_ATTEMPTS = number(int, 1, 100)
#: the files a run writes on request
REPORTS = ("junit", "json", "html", "pcap", "evidence")


def JOBS(text: str) -> int:
    """``--jobs``: a whole number from 1, or ``auto``."""
    import argparse

    from ptpcert.runner.parallel import parse_jobs
    try:
        return parse_jobs(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def SHARD(text: str) -> tuple[int, int]:
    """``--shard K/N``: shard K of N."""
    import argparse

    from ptpcert.results import parse_shard
    try:
        return parse_shard(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_commands(sub) -> None:
    """The ``run`` command."""
    from ptpcert.registry import procedures

    r = sub.add_parser("run", help="run the suite against an implementation under test",
                       description="Run the conformance cases against an IUT and write the reports. "
                                   "Exit status: 0 nothing failed, 1 a case failed or xpassed, "
                                   "2 bad usage or a harness error.",
                       epilog="procedures ([iut] procedure = ...): " + "; ".join(
                           f"{p.title}: {', '.join(p.names)}" for p in procedures()))
    r.add_argument("--iut", required=True, metavar="URL", action="append",
                   help="exec:COMMAND | pty:COMMAND (with {port}) | sim:[?opts] | a pyserial URL or device; "
                        "given several times: a pool of identical IUTs, the cases spread over them")
    r.add_argument("--profile", required=True, metavar="FILE", help="the IUT profile (TOML)")
    r.add_argument("--jobs", type=JOBS, default=1, metavar="N",
                   help="cases run at the same time where each gets an IUT of its own (exec:, pty:, sim:), "
                        "or over a pool; auto: the number of cores (default 1). A device or port server "
                        "is one line: it runs one case at a time")
    r.add_argument("--select", action="append", metavar="GLOB", help="only cases whose id matches (repeatable)")
    r.add_argument("--shard", type=SHARD, default=None, metavar="K/N",
                   help="run only shard K of N of the selected cases, for N CI jobs (GitLab parallel:, a GitHub "
                        "matrix); the split depends only on the profile and the selection, balanced by each "
                        "case's forced waits. 'ptpcert report --merge' joins the N results into one report")
    r.add_argument("--junit", metavar="PATH", help="write a JUnit XML file")
    r.add_argument("--json", metavar="PATH", help="write the results object as JSON")
    r.add_argument("--html", metavar="PATH", help="write the HTML report")
    r.add_argument("--pcap", metavar="PATH",
                   help="write the run's wire traffic as one capture (pcap, LINKTYPE_RTAC_SERIAL) for "
                        "Wireshark and 'ptpcert analyze'")
    from . import evidence as cli_evidence
    cli_evidence.add_run_arguments(r)
    r.add_argument("--vectors", action="append", default=[], metavar="DIR",
                   help="a directory of vectors to run in addition to the bundled golden vectors (repeatable)")
    r.add_argument("--vectors-only", action="store_true",
                   help="run only vectors, not the generated suite: those of --vectors, or the bundled ones")
    r.add_argument("--tolerance-ms", type=TOLERANCE_MS, default=50.0,
                   help="how late a reply may be beyond its window, plus 25%% of the window (default 50; 0 to 10000)")
    r.add_argument("--startup-timeout", type=STARTUP_S, default=2.0,
                   help="seconds a freshly started IUT may take before what it sends at start-up (default 2; 0.1 to 600)")
    r.add_argument("--edge-attempts", type=EDGE_ATTEMPTS, default=4, metavar="N",
                   help="attempts in all before a failure of a case close to a timer's edge stands; it passes "
                        "if one attempt passes (default 4; 1: every failure stands; at most 100)")
    r.add_argument("--max-failures", type=MAX_FAILURES, default=0, metavar="N",
                   help="stop after N failed cases (the rest are reported as not run)")
    r.add_argument("--priority", choices=PRIORITY_MODES, default="auto",
                   help="the harness's scheduling class: auto (default) takes the real-time class for its timing "
                        "threads where the system permits it, realtime insists on it, normal never asks; the IUT "
                        "stays in the normal class")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    r.set_defaults(func=cmd_run)


class Interrupts:
    """SIGINT (Ctrl-C) and SIGTERM while ptpcert drives an IUT. While armed, the first one
    stops the work where it is (as KeyboardInterrupt, which the runner turns into an
    interrupted run); every later one, and any that comes while the IUT is stopped and the
    reports are written, is only counted: a second Ctrl-C or a supervisor's SIGTERM cannot
    cost the reports."""

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self, args=None) -> None:
        self.count = 0
        self.armed = False
        self._told = False
        self._old: dict = {}
        #: the command is the process's last act (the ``ptpcert`` program, not a caller in
        #: the same process): signals after it are ignored, so that one that comes after
        #: the reports cannot turn the exit status into a death by signal
        self.keep = bool(getattr(args, "process_exits_after", False))

    def __enter__(self) -> "Interrupts":
        for sig in self.SIGNALS:
            self._old[sig] = signal.signal(sig, self._handle)
        self.armed = True
        return self

    def __exit__(self, *exc) -> None:
        self.armed = False
        for sig, handler in self._old.items():
            # the process ends now: ignore the signals (Python restores the default handlers
            # while it shuts down, which would turn the exit status into a death by signal)
            signal.signal(sig, signal.SIG_IGN if self.keep else handler)

    def disarm(self) -> None:
        self.armed = False

    def _handle(self, signum, frame) -> None:
        self.count += 1
        if self.armed:
            self.armed = False
            raise KeyboardInterrupt
        if not self._told:
            self._told = True
            try:
                os.write(2, b"ptpcert: interrupted; stopping the IUT and writing the reports first\n")
            except OSError:
                pass


def cmd_run(args) -> int:
    from ptpcert import report as rep
    from ptpcert import results as R
    from ptpcert.priority import PriorityError
    from ptpcert.priority import harness as harness_priority
    from ptpcert.runner import Runner, RunOptions
    from ptpcert.scenario import VectorError, load_vector_sets, vector_set_hash
    from ptpcert.suite import check_expected_failures, load_suite
    from ptpcert.transport import TransportError, make_factory, preflight

    profile = load_profile("run", args.profile)
    if profile is None:
        return 2
    if getattr(args, "priority", "normal") == "realtime":
        try:   # before anything runs: a run that cannot have what it insists on is bad usage
            with harness_priority("realtime"):
                pass
        except PriorityError as exc:
            print(f"ptpcert run: {exc}", file=sys.stderr)
            return 2
    try:
        vectors = load_vector_sets(args.vectors, only=args.vectors_only)
        everything = load_suite(profile, vectors)
        check_expected_failures(profile, everything)
        cases = load_suite(profile, vectors, include_suite=not args.vectors_only, select=args.select)
    except (VectorError, ValueError) as exc:
        print(f"ptpcert run: {exc}", file=sys.stderr)
        return 2
    if not cases:
        if args.select:
            why = ("no case matches --select " + " ".join(args.select)
                   + " (the HTML or JSON report of a full run lists the case ids)")
        else:   # --vectors-only, and none of the vectors is for the profile's procedure
            why = (f"no case to run: none of the vectors of {vector_set_label(args.vectors, args.vectors_only)} "
                   f"is for {profile.procedure.title}, the profile's procedure")
        print(f"ptpcert run: {why}", file=sys.stderr)
        return 2
    selection, shard = cases, getattr(args, "shard", None)
    if shard is not None:
        from ptpcert.suite import shard_of
        k, n = shard
        cases, mine, total = shard_of(profile, selection, k, n)
        print(f"shard {k}/{n}: {len(cases)} of {len(selection)} cases, forced waits {mine:.1f} s of "
              f"{total:.1f} s", flush=True)
    # before the first case: a run must never end without the reports it was asked for
    from ptpcert.evidence.output import options_problem, write_evidence
    problem = report_paths_problem(args, ("junit", "json", "html", "pcap")) or options_problem(args)
    if problem:
        print(f"ptpcert run: {problem}", file=sys.stderr)
        return 2
    # --iut given several times is a pool (the same device twice is one device)
    urls = list(dict.fromkeys(u.strip() for u in ([args.iut] if isinstance(args.iut, str) else args.iut)))
    jobs = getattr(args, "jobs", 1)
    result = R.RunResult(tool_version=__version__, started=now(), iut=" | ".join(urls), procedure=profile.procedure.title,
                         profile=profile.to_dict(), profile_path=str(args.profile),
                         vector_set=vector_set_label(args.vectors, args.vectors_only), vector_set_hash=vector_set_hash(selection),
                         html_path=args.html or "", iut_identity=dict(profile.identity),
                         shard="{}/{}".format(*shard) if shard else "")

    def progress(i, n, c, running=None):
        if not args.quiet:
            line = rep.progress_line(i, n, c)
            if running is not None:
                line += f"  [{running} running]"
            print(line, flush=True)

    factory = None
    pool: list = []
    startup_failure = fault = ""
    with Interrupts(args) as interrupts:
        try:
            try:
                for url in urls:
                    # with --jobs, as many fresh IUTs started ahead as cases run at once
                    pool.append((url, make_factory(url, profile, prespawn=max(2, min(jobs, 16)))))
                factory = pool[0][1]
            except TransportError as exc:   # a URL or port that cannot work: bad usage, nothing run
                interrupts.disarm()
                for _, f in pool:
                    f.shutdown()
                print(f"ptpcert run: {exc}", file=sys.stderr)
                return 2
            opts = RunOptions(late_ms=args.tolerance_ms, startup_timeout=args.startup_timeout,
                              echo=profile.echo, check_status=profile.status_from_stderr,
                              edge_attempts=args.edge_attempts)
            # a shard judges its part of the selection: the selection as a whole must be testable
            idle = Runner(factory, profile, opts).nothing_to_test(selection)
            if idle:   # a run that judges nothing is no pass: bad usage, nothing run
                interrupts.disarm()
                for _, f in pool:
                    f.shutdown()
                print(f"ptpcert run: {idle}", file=sys.stderr)
                return 2
            try:
                for url, f in pool:
                    preflight(url, f, profile.params)
            except TransportError as exc:   # the IUT cannot start: every case is an error, with the reason
                startup_failure = str(exc)
            if not startup_failure:
                more = {"jobs": jobs} if jobs > 1 else {}
                if len(pool) > 1:
                    more["pool"] = pool
                # in virtual time (sim:) there is no timing to keep: no reason to ask for a class
                virtual = all(u.startswith("sim:") for u in urls)
                with harness_priority("normal" if virtual else getattr(args, "priority", "normal")) as how:
                    result.harness_scheduling = "virtual time (sim:)" if virtual else how
                    Runner(factory, profile, opts).run(cases, result, progress, max_failures=args.max_failures, **more)
            interrupts.disarm()
        except KeyboardInterrupt:
            result.interrupted = True
        except Exception as exc:   # a fault of ptpcert itself: the reports still arrive, and say so
            fault = f"harness fault: {type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
        interrupts.disarm()
        # from here on signals are only counted: the IUT is stopped and the reports written
        if startup_failure:
            mark_not_run(result, cases, R.ERROR, f"the IUT could not be started: {startup_failure}")
        elif fault:
            mark_not_run(result, cases, R.ERROR, f"not run: {fault}")
        elif result.interrupted:
            mark_not_run(result, cases, R.NOT_RUN, "run interrupted")
        for _, f in pool:
            f.shutdown()
        result.finished = now()
        if interrupts.count:
            result.interrupted = True
        written = write_reports(result, args, "run", profile.procedure.report_view())
        if write_evidence(result, args, profile, cases, urls, profile.procedure.report_view()) and getattr(args, "evidence", None):
            written.add("evidence")
        if startup_failure or fault:
            print(f"ptpcert run: {' '.join((startup_failure or fault).split())[:600]}", file=sys.stderr)
        else:
            print(rep.summary(result))
        for kind in REPORTS:
            if getattr(args, kind, None) and kind in written:
                print(f"{kind}: {getattr(args, kind)}")
        sys.stdout.flush()
        if (startup_failure or fault or result.interrupted or interrupts.count
                or len(written) < sum(bool(getattr(args, k, None)) for k in REPORTS)):
            return 2
    if result.counts()[R.ERROR] and result.exit_status() == 0:
        return 2
    return result.exit_status()


def mark_not_run(result, cases, verdict: str, message: str) -> None:
    """Every case of ``cases`` without a result gets one: ``verdict`` with ``message``."""
    result.fill_missing(cases, verdict, message)


def vector_set_label(extra, only: bool) -> str:
    """What the run's vectors are, for the reports."""
    parts = [] if (only and extra) else ["bundled"]
    return " + ".join(parts + [str(d) for d in extra])


def connect(cmd: str, url: str, profile):
    """The transport factory for ``url``, checked by :func:`ptpcert.transport.preflight`, or None after
    telling why the IUT cannot be reached (the caller exits 2)."""
    from ptpcert.transport import TransportError, make_factory, preflight

    factory = None
    try:
        factory = make_factory(url, profile)
        preflight(url, factory, profile.params)
        return factory
    except TransportError as exc:
        if factory is not None:
            factory.shutdown()   # processes started ahead for the next cases
        print(f"ptpcert {cmd}: {' '.join(str(exc).split())[:600]}", file=sys.stderr)
        return None


