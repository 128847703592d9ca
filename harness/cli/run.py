"""Commands that drive an IUT: ``run``, ``iut`` and ``report``."""

from __future__ import annotations

import os
import signal
import sys

from ptpcert import __version__
from ptpcert.cli.common import load_profile, now, number
from ptpcert.priority import MODES as PRIORITY_MODES

#: the bounds of the numeric options (the messages name them)
TOLERANCE_MS = number(float, 0, 10_000, "milliseconds")
STARTUP_S = number(float, 0.1, 600, "seconds")
MAX_FAILURES = number(int, 0, None, "(0: no limit)")
EDGE_ATTEMPTS = number(int, 1, 100)
BUDGET_S = number(float, 1, 7 * 24 * 3600, "seconds")
MAX_ACTIONS = number(int, 1, 100)
WORKERS = number(int, 1, 64)


def JOBS(text: str) -> int:
    """``--jobs``: a whole number from 1, or ``auto``."""
    import argparse

    from ptpcert.runner.parallel import parse_jobs
    try:
        return parse_jobs(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_commands(sub) -> None:
    r = sub.add_parser("run", help="run the suite against an implementation under test",
                       description="Run the conformance cases against an IUT and write the reports. "
                                   "Exit status: 0 nothing failed, 1 a case failed or xpassed, "
                                   "2 bad usage or a harness error.")
    r.add_argument("--iut", required=True, metavar="URL", action="append",
                   help="exec:COMMAND | pty:COMMAND (with {port}) | sim:[?opts] | a pyserial URL or device; "
                        "given several times: a pool of identical IUTs, the cases spread over them")
    r.add_argument("--profile", required=True, metavar="FILE", help="the IUT profile (TOML)")
    r.add_argument("--jobs", type=JOBS, default=1, metavar="N",
                   help="cases run at the same time where each gets an IUT of its own (exec:, pty:, sim:), "
                        "or over a pool; auto: the number of cores (default 1). A device or port server "
                        "is one line: it runs one case at a time")
    r.add_argument("--select", action="append", metavar="GLOB", help="only cases whose id matches (repeatable)")
    r.add_argument("--junit", metavar="PATH", help="write a JUnit XML file")
    r.add_argument("--json", metavar="PATH", help="write the results object as JSON")
    r.add_argument("--html", metavar="PATH", help="write the HTML report")
    r.add_argument("--pcap", metavar="PATH",
                   help="write the run's wire traffic as one capture (pcap, LINKTYPE_RTAC_SERIAL) for "
                        "Wireshark and 'ptpcert analyze'")
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

    from ptpcert.registry import all_names, procedures
    i = sub.add_parser("iut", help="run the bundled reference implementation (the model, in real time)",
                       description="The reference model as a real-time station on stdin/stdout (or --port), "
                                   "with its application. STATUS events go to stderr as 'STATUS 16#XXXX' lines.")
    i.add_argument("--procedure", choices=all_names(), default=None,
                   help=f"the procedure (default {procedures()[0].names[0]})")
    i.add_argument("--cdt-ms", type=int, default=None, help="character delay time (default: the procedure's)")
    i.add_argument("--baud", type=int, default=9600, help="baud rate; 0: do not pace the output")
    i.add_argument("--data-bits", type=int, choices=[7, 8], default=8)
    i.add_argument("--parity", choices=["none", "odd", "even"], default="even")
    i.add_argument("--stop-bits", type=int, choices=[1, 2], default=1)
    i.add_argument("--parmrk", action="store_true",
                   help="the input marks line conditions as termios PARMRK does (FF 00 00 BREAK, FF 00 xx error, FF FF data FF)")
    i.add_argument("--port", metavar="URL", help="use this serial port (pyserial URL or device) instead of stdin/stdout")
    i.add_argument("--app", default=None,
                   help="the application: "
                        + "; ".join(f"{p.title}: {', '.join(p.apps())} (default {p.apps()[0]})" for p in procedures()))
    i.add_argument("--mutant", metavar="NAME", help="run a deliberately broken variant (see --list-mutants)")
    i.add_argument("--list-mutants", action="store_true", help="list the broken variants and exit")
    i.add_argument("--send", action="append", default=[], metavar="HEX",
                   help="data the application hands over at start-up (repeatable; what it is, the procedure's "
                        "options say)")
    i.add_argument("-v", "--verbose", action="store_true", help="also log deliveries and job results on stderr")
    for proc in procedures():
        proc.add_iut_arguments(i.add_argument_group(f"{proc.title} options"))
    i.set_defaults(func=cmd_iut)

    f = sub.add_parser("fuzz", help="fuzz an IUT with generated partner behaviour, the model as oracle",
                       description="Generate partner behaviour (hypothesis), predict a conforming IUT's answers "
                                   "with the reference model, and report every divergence as a shrunk "
                                   "transcript, saved as a vector. Exit status: 0 nothing found, 1 findings, "
                                   "2 bad usage or a harness error.")
    f.add_argument("--iut", required=True, metavar="URL", help="as for 'ptpcert run'")
    f.add_argument("--profile", required=True, metavar="FILE", help="the IUT profile (TOML)")
    f.add_argument("--budget", type=BUDGET_S, default=60.0, metavar="SECONDS",
                   help="time budget (default 60; 1 to 604800, a week)")
    f.add_argument("--seed", type=int, default=None, help="seed (printed, so any run can be replayed)")
    f.add_argument("--export", metavar="DIR", default=None,
                   help="where findings are written as vectors (default: ./vectors/regressions in the current directory)")
    f.add_argument("--settings", choices=["ptpcert-quick", "ptpcert-thorough"], default="ptpcert-quick",
                   help="hypothesis settings profile (both extend hypothesis's 'ci' profile)")
    f.add_argument("--database", metavar="DIR",
                   help="hypothesis example database, to share a campaign between runs or machines")
    f.add_argument("--max-actions", type=MAX_ACTIONS, default=6, help="tester actions per example (default 6; 1 to 100)")
    f.add_argument("--workers", type=WORKERS, default=1, metavar="N",
                   help="example streams at once, each a process with its own IUT instance (exec:, pty:, "
                        "sim:), all sharing the example database (default 1; 1 to 64)")
    f.set_defaults(func=cmd_fuzz)

    rep = sub.add_parser("report", help="render a saved results object (JSON) as HTML or JUnit")
    rep.add_argument("results", metavar="RESULTS.json")
    rep.add_argument("--html", metavar="PATH")
    rep.add_argument("--junit", metavar="PATH")
    rep.set_defaults(func=cmd_report)


def cmd_iut(args) -> int:
    from ptpcert.iut import run_iut
    from ptpcert.registry import by_name, procedures

    proc = by_name(args.procedure) if args.procedure else procedures()[0]
    args.procedure = args.procedure or proc.names[0]
    if args.list_mutants:
        for name, m in proc.mutants().items():
            print(f"{name:<28} {m.rule}")
        return 0
    if args.mutant and args.mutant not in proc.mutants():
        print(f"ptpcert iut: unknown mutant {args.mutant!r} for {proc.title}; --list-mutants shows them",
              file=sys.stderr)
        return 2
    if args.app is None:
        args.app = proc.apps()[0]
    if args.app not in proc.apps():
        print(f"ptpcert iut: --app {args.app!r}: allowed values are {', '.join(proc.apps())}", file=sys.stderr)
        return 2
    from ptpcert.procedure import ProcedureError
    try:
        params = proc.params_from_iut(args)
        host = proc.iut_host(params, args)
    except ProcedureError as exc:
        print(f"ptpcert iut: {exc}", file=sys.stderr)
        return 2
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    return run_iut(host, proc.line(params), parmrk=args.parmrk, port=args.port, verbose=args.verbose)


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
    from ptpcert.transport import TransportError, make_factory

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
        print("ptpcert run: no case matches --select " + " ".join(args.select or [])
              + " (the HTML or JSON report of a full run lists the case ids)", file=sys.stderr)
        return 2
    # before the first case: a run must never end without the reports it was asked for
    problem = report_paths_problem(args, ("junit", "json", "html", "pcap"))
    if problem:
        print(f"ptpcert run: {problem}", file=sys.stderr)
        return 2
    # --iut given several times is a pool (the same device twice is one device)
    urls = list(dict.fromkeys(u.strip() for u in ([args.iut] if isinstance(args.iut, str) else args.iut)))
    jobs = getattr(args, "jobs", 1)
    result = R.RunResult(tool_version=__version__, started=now(), iut=" | ".join(urls), procedure=profile.procedure.title,
                         profile=profile.to_dict(), profile_path=str(args.profile),
                         vector_set=vector_set_label(args.vectors, args.vectors_only), vector_set_hash=vector_set_hash(cases),
                         html_path=args.html or "")

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
            try:
                for url, f in pool:
                    preflight(url, f, profile)
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
        if startup_failure or fault:
            print(f"ptpcert run: {' '.join((startup_failure or fault).split())[:600]}", file=sys.stderr)
        else:
            print(rep.summary(result))
        for kind in ("junit", "json", "html", "pcap"):
            if getattr(args, kind, None) and kind in written:
                print(f"{kind}: {getattr(args, kind)}")
        sys.stdout.flush()
        if (startup_failure or fault or result.interrupted or interrupts.count
                or len(written) < sum(bool(getattr(args, k, None)) for k in ("junit", "json", "html", "pcap"))):
            return 2
    if result.counts()[R.ERROR] and result.exit_status() == 0:
        return 2
    return result.exit_status()


def mark_not_run(result, cases, verdict: str, message: str) -> None:
    """Every case of ``cases`` without a result gets one: ``verdict`` with ``message``."""
    from ptpcert import results as R

    done = {c.id for c in result.cases}
    for v in cases:
        if v.id not in done:
            result.cases.append(R.CaseResult(v.id, v.title, v.reference, v.rule, v.group, v.iut_role,
                                             verdict=verdict, message=message, source=v.source))


def vector_set_label(extra, only: bool) -> str:
    """What the run's vectors are, for the reports."""
    parts = [] if (only and extra) else ["bundled"]
    return " + ".join(parts + [str(d) for d in extra])


def report_paths_problem(args, kinds: tuple[str, ...], reading: str | None = None) -> str | None:
    """Why one of the report options (``--junit`` ...) cannot be written, checked before
    anything runs; None when all can."""
    from ptpcert.results import report_path_problem

    seen: dict[str, str] = {}
    if reading is not None:
        seen[os.path.realpath(reading)] = "the results file read"
    for kind in kinds:
        path = getattr(args, kind, None)
        if path is None:
            continue
        real = os.path.realpath(path) if str(path).strip() else ""
        if real in seen:
            return f"--{kind} {path}: is also {seen[real]}; give each report its own file"
        seen[real] = f"--{kind}"
        problem = report_path_problem(path)
        if problem:
            return f"--{kind} {path}: {problem}"
    return None


def write_reports(result, args, cmd: str, view=None) -> set[str]:
    """Write the reports the options ask for: JUnit first (what CI reads), then JSON and
    HTML, each whole or not at all. Returns the kinds written; a report that cannot be
    written is said on stderr and does not stop the others. ``view``: the procedure's
    :class:`~ptpcert.view.ReportView` for the HTML (None: neutral)."""
    from ptpcert import capture as C
    from ptpcert import report as rep
    from ptpcert import results as R
    from ptpcert.report.html import write_html

    def write_pcap(r, p) -> None:       # run --pcap: the run's wire traffic as one capture
        C.save(C.from_results(r), p, "pcap")

    if view is not None and not result.root_causes:   # the procedure names the bytes that steer it
        result.root_causes = R.root_causes(result.cases, view.names)
    writers = (("junit", rep.write_junit), ("json", lambda r, p: r.write_json(p)),
               ("html", lambda r, p: write_html(r, p, view)), ("pcap", write_pcap))
    written = set()
    for kind, write in writers:
        path = getattr(args, kind, None)
        if not path:
            continue
        try:
            write(result, path)
            written.add(kind)
        except OSError as exc:
            print(f"ptpcert {cmd}: --{kind} {path}: cannot be written ({exc.strerror or exc})", file=sys.stderr)
        except C.CaptureError as exc:
            print(f"ptpcert {cmd}: --{kind} {path}: {exc}", file=sys.stderr)
    return written


def _connect(cmd: str, url: str, profile):
    """The transport factory for ``url``, checked by :func:`preflight`, or None after
    telling why the IUT cannot be reached (the caller exits 2)."""
    from ptpcert.transport import TransportError, make_factory

    factory = None
    try:
        factory = make_factory(url, profile)
        preflight(url, factory, profile)
        return factory
    except TransportError as exc:
        if factory is not None:
            factory.shutdown()   # processes started ahead for the next cases
        print(f"ptpcert {cmd}: {' '.join(str(exc).split())[:600]}", file=sys.stderr)
        return None


def preflight(url: str, factory, profile) -> None:
    """Start the IUT once before the run: a command that cannot start, or a port that cannot
    be opened, is found before the first case, not as 50 failed cases."""
    from ptpcert.transport import RESTART, IUTDied, TransportError

    if RESTART not in factory.capabilities or factory.virtual:
        return
    tr = factory(None, profile.params)
    try:
        tr.open()
        tr.read(tr.now() + 1.0)
    except IUTDied as exc:
        what = (f"the IUT ended at start-up (exit status {exc.returncode})" if exc.returncode is not None
                else f"at start-up, {exc}")
        raise TransportError(f"{url}: {what}"
                             + (f": {exc.stderr_tail.strip()[-600:]}" if exc.stderr_tail.strip() else "")) from None
    finally:
        tr.close()


def cmd_fuzz(args) -> int:
    import random
    import time

    from ptpcert.fuzz import Campaign, export, register_profiles
    from ptpcert.paths import findings_dir
    from ptpcert.runner import Runner, RunOptions

    register_profiles()

    profile = load_profile("fuzz", args.profile)
    if profile is None:
        return 2
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(1, 2**31)
    out_dir = args.export or str(findings_dir())
    if args.workers > 1:
        if not args.iut.startswith(("exec:", "pty:", "sim:")):
            print(f"ptpcert fuzz: --workers {args.workers} needs an IUT that can be started several times "
                  f"(exec:, pty:, sim:); {args.iut} is one line", file=sys.stderr)
            return 2
        try:
            from ptpcert.fuzz import open_database
            open_database(args.database)
        except (ValueError, OSError) as exc:
            print(f"ptpcert fuzz: {exc}", file=sys.stderr)
            return 2
        return _fuzz_workers(args, profile, seed, out_dir)
    with Interrupts(args) as interrupts:
        camp = None
        interrupted = False
        factory = None
        try:
            factory = _connect("fuzz", args.iut, profile)
            if factory is None:
                interrupts.disarm()
                return 2
            print(f"ptpcert fuzz {__version__}: iut {args.iut}, profile {args.profile}")
            print(f"seed {seed}, settings {args.settings}, budget {args.budget:g} s"
                  + (f", database {args.database}" if args.database else ""))
            print(f"replay: ptpcert fuzz --iut '{args.iut}' --profile {args.profile} --seed {seed} "
                  f"--settings {args.settings} --budget {args.budget:g}", flush=True)
            kit = profile.procedure.fuzz_kit()
            check = bool(kit is not None and kit.check_reports and profile.status_from_stderr)
            runner = Runner(factory, profile, RunOptions(check_status=check, late_ms=50.0))
            camp = Campaign(profile, runner, args.budget, seed, args.settings, args.database,
                            progress=lambda line: print(line, flush=True), max_actions=args.max_actions)
            camp.run()
            interrupts.disarm()
        except KeyboardInterrupt:
            interrupted = True
        interrupts.disarm()
        if factory is not None:
            factory.shutdown()
        interrupted = interrupted or interrupts.count > 0
        if camp is None:
            return 2
        try:
            paths = export(camp.findings, out_dir) if camp.findings else []
        except OSError as exc:
            print(f"ptpcert fuzz: findings cannot be written to {out_dir} ({exc.strerror or exc})", file=sys.stderr)
            paths, interrupted = [], True
    elapsed = time.monotonic() - camp.started if camp.started else 0.0
    print(f"\n{camp.examples} examples in {elapsed:.1f} s ({camp.examples / max(elapsed, 1e-9):.1f}/s), "
          f"{len(camp.findings)} finding(s), {camp.informational} divergence(s) explained by another reading, "
          f"{camp.not_reproduced} not reproduced, {camp.void} void (interruption reached the IUT late)"
          + (", INTERRUPTED" if interrupted else ""))
    for p in paths:
        print(f"  written: {p}")
    if interrupted:
        return 2
    return 1 if camp.findings else 0


def _fuzz_workers(args, profile, seed: int, out_dir: str) -> int:
    """``ptpcert fuzz --workers N``: N campaigns at once (:func:`ptpcert.fuzz.run_workers`)."""
    from ptpcert.fuzz import WorkerSpec, export, run_workers

    factory = _connect("fuzz", args.iut, profile)   # the IUT starts: checked once, here
    if factory is None:
        return 2
    factory.shutdown()
    print(f"ptpcert fuzz {__version__}: iut {args.iut}, profile {args.profile}, {args.workers} workers")
    print(f"seed {seed}, settings {args.settings}, budget {args.budget:g} s"
          + (f", database {args.database}" if args.database else ""))
    print(f"replay: ptpcert fuzz --iut '{args.iut}' --profile {args.profile} --seed {seed} "
          f"--settings {args.settings} --budget {args.budget:g} --workers {args.workers}", flush=True)
    spec = WorkerSpec(args.iut, str(args.profile), args.budget, seed, args.settings, args.database,
                      args.max_actions, args.workers)
    with Interrupts(args) as interrupts:
        res = run_workers(spec, progress=lambda line: print(line, flush=True))
        interrupts.disarm()
    interrupted = res.interrupted or interrupts.count > 0
    for i, why in res.errors:
        print(f"ptpcert fuzz: worker {i}: {why}", file=sys.stderr)
    try:
        paths = export(res.findings, out_dir) if res.findings else []
    except OSError as exc:
        print(f"ptpcert fuzz: findings cannot be written to {out_dir} ({exc.strerror or exc})", file=sys.stderr)
        paths, interrupted = [], True
    print(f"\n{res.examples} examples in {res.elapsed:.1f} s ({res.examples / max(res.elapsed, 1e-9):.1f}/s, "
          f"{args.workers} workers), {len(res.findings)} finding(s), {res.informational} divergence(s) "
          f"explained by another reading, {res.not_reproduced} not reproduced, {res.void} void "
          "(interruption reached the IUT late)" + (", INTERRUPTED" if interrupted else ""))
    for p in paths:
        print(f"  written: {p}")
    if interrupted or (res.errors and not res.findings):
        return 2
    return 1 if res.findings else 0


def cmd_report(args) -> int:
    from ptpcert import report as rep
    from ptpcert.results import ResultsError, RunResult

    problem = report_paths_problem(args, ("junit", "html"), reading=args.results)
    if problem:
        print(f"ptpcert report: {problem}", file=sys.stderr)
        return 2
    try:
        result = RunResult.read_json(args.results)
    except ResultsError as exc:
        print(f"ptpcert report: {exc}", file=sys.stderr)
        return 2
    if not args.html and not args.junit:
        print(rep.summary(result))
        return 0
    if args.html:
        result.html_path = args.html
    written = write_reports(result, args, "report", report_view_of(result))
    for kind in ("junit", "html"):
        if kind in written:
            print(f"{kind}: {getattr(args, kind)}")
    return 0 if len(written) == bool(args.html) + bool(args.junit) else 2


def report_view_of(result):
    """The report view of the procedure whose title the results carry (a saved run), or
    None (neutral) when no procedure has it."""
    from ptpcert.registry import by_title

    proc = by_title(result.procedure) if result.procedure else None
    return proc.report_view() if proc is not None else None
