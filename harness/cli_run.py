"""Commands that drive an IUT: ``run``, ``iut`` and ``report``."""

from __future__ import annotations

import datetime as _dt
import signal
import sys
from pathlib import Path

from . import __version__


def add_commands(sub) -> None:
    r = sub.add_parser("run", help="run the suite against an implementation under test",
                       description="Run the conformance cases against an IUT and write the reports. "
                                   "Exit status: 0 nothing failed, 1 a case failed or xpassed, "
                                   "2 bad usage or a harness error.")
    r.add_argument("--iut", required=True, metavar="URL",
                   help="exec:COMMAND | pty:COMMAND (with {port}) | sim:[?opts] | a pyserial URL or device")
    r.add_argument("--profile", required=True, metavar="FILE", help="the IUT profile (TOML)")
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
    r.add_argument("--tolerance-ms", type=float, default=50.0,
                   help="how late a reply may be beyond its window, plus 25%% of the window (default 50)")
    r.add_argument("--startup-timeout", type=float, default=2.0,
                   help="seconds a freshly started IUT may take before its start-up NAK (default 2)")
    r.add_argument("--edge-attempts", type=int, default=4, metavar="N",
                   help="attempts in all before a failure of a case close to a timer's edge stands; it passes "
                        "if one attempt passes (default 4; 1: every failure stands)")
    r.add_argument("--max-failures", type=int, default=0, metavar="N",
                   help="stop after N failed cases (the rest are reported as not run)")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    r.set_defaults(func=cmd_run)

    from .procedures import PROCEDURES, all_names
    i = sub.add_parser("iut", help="run the bundled reference implementation (the model, in real time)",
                       description="The reference model as a real-time station on stdin/stdout (or --port), "
                                   "with its application (3964/3964R: the echo application). STATUS events "
                                   "go to stderr as 'STATUS 16#XXXX' lines.")
    i.add_argument("--procedure", choices=all_names(), default="3964R")
    i.add_argument("--cdt-ms", type=int, default=None, help="character delay time (default: the procedure's, 220 for 3964R)")
    i.add_argument("--baud", type=int, default=9600, help="baud rate; 0: do not pace the output")
    i.add_argument("--data-bits", type=int, choices=[7, 8], default=8)
    i.add_argument("--parity", choices=["none", "odd", "even"], default="even")
    i.add_argument("--stop-bits", type=int, choices=[1, 2], default=1)
    i.add_argument("--parmrk", action="store_true",
                   help="the input marks line conditions as termios PARMRK does (FF 00 00 BREAK, FF 00 xx error, FF FF data FF)")
    i.add_argument("--port", metavar="URL", help="use this serial port (pyserial URL or device) instead of stdin/stdout")
    i.add_argument("--app", default="echo", help="what to do with received data: echo (default) or none")
    i.add_argument("--mutant", metavar="NAME", help="run a deliberately broken variant (see --list-mutants)")
    i.add_argument("--list-mutants", action="store_true", help="list the broken variants and exit")
    i.add_argument("-v", "--verbose", action="store_true", help="also log deliveries and job results on stderr")
    for proc in PROCEDURES:
        proc.add_iut_arguments(i.add_argument_group(f"{proc.title} options"))
    i.set_defaults(func=cmd_iut)

    f = sub.add_parser("fuzz", help="fuzz an IUT with generated partner behaviour, the model as oracle",
                       description="Generate partner behaviour (hypothesis), predict a conforming IUT's answers "
                                   "with the reference model, and report every divergence as a shrunk "
                                   "transcript, saved as a vector. Exit status: 0 nothing found, 1 findings, "
                                   "2 bad usage or a harness error.")
    f.add_argument("--iut", required=True, metavar="URL", help="as for 'ptpcert run'")
    f.add_argument("--profile", required=True, metavar="FILE", help="the IUT profile (TOML)")
    f.add_argument("--budget", type=float, default=60.0, metavar="SECONDS", help="time budget (default 60)")
    f.add_argument("--seed", type=int, default=None, help="seed (printed, so any run can be replayed)")
    f.add_argument("--export", metavar="DIR", default=None,
                   help="where findings are written as vectors (default: ./vectors/regressions in the current directory)")
    f.add_argument("--settings", choices=["ptpcert-quick", "ptpcert-thorough"], default="ptpcert-quick",
                   help="hypothesis settings profile (both extend hypothesis's 'ci' profile)")
    f.add_argument("--database", metavar="DIR",
                   help="hypothesis example database, to share a campaign between runs or machines")
    f.add_argument("--max-actions", type=int, default=6, help="tester actions per example (default 6)")
    f.set_defaults(func=cmd_fuzz)

    rep = sub.add_parser("report", help="render a saved results object (JSON) as HTML or JUnit")
    rep.add_argument("results", metavar="RESULTS.json")
    rep.add_argument("--html", metavar="PATH")
    rep.add_argument("--junit", metavar="PATH")
    rep.set_defaults(func=cmd_report)


def cmd_iut(args) -> int:
    from .iut import run_iut
    from .procedures import by_name

    proc = by_name(args.procedure)
    if args.list_mutants:
        for name, m in proc.mutants().items():
            print(f"{name:<28} {m.rule}")
        return 0
    if args.mutant and args.mutant not in proc.mutants():
        print(f"ptpcert iut: unknown mutant {args.mutant!r} for {proc.title}; --list-mutants shows them",
              file=sys.stderr)
        return 2
    if args.app not in proc.apps():
        print(f"ptpcert iut: --app {args.app!r}: allowed values are {', '.join(proc.apps())}", file=sys.stderr)
        return 2
    from .procedure import ProcedureError
    try:
        params = proc.params_from_iut(args)
        host = proc.iut_host(params, args)
    except ProcedureError as exc:
        print(f"ptpcert iut: {exc}", file=sys.stderr)
        return 2
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    return run_iut(host, proc.line(params), parmrk=args.parmrk, port=args.port, verbose=args.verbose)


def _interrupt(*_):
    raise KeyboardInterrupt


def cmd_run(args) -> int:
    from . import report as rep
    from . import results as R
    from .runner import RunOptions, Runner
    from .scenario import VectorError, load_vector_sets, vector_set_hash
    from .suite import load_suite

    if args.edge_attempts < 1:
        print(f"ptpcert run: --edge-attempts must be 1 or more, not {args.edge_attempts}", file=sys.stderr)
        return 2
    profile = _load_profile("run", args.profile)
    if profile is None:
        return 2
    try:
        vectors = load_vector_sets(args.vectors, only=args.vectors_only)
        cases = load_suite(profile, vectors, include_suite=not args.vectors_only, select=args.select)
    except (VectorError, ValueError) as exc:
        print(f"ptpcert run: {exc}", file=sys.stderr)
        return 2
    if not cases:
        print("ptpcert run: no case matches " + " ".join(args.select or []), file=sys.stderr)
        return 2
    factory = _connect("run", args.iut, profile)
    if factory is None:
        return 2
    opts = RunOptions(late_ms=args.tolerance_ms, startup_timeout=args.startup_timeout,
                      echo=profile.echo, check_status=profile.status_from_stderr,
                      edge_attempts=args.edge_attempts)
    runner = Runner(factory, profile, opts)
    result = R.RunResult(tool_version=__version__, started=_now(), iut=args.iut, procedure=profile.procedure.title,
                         profile=profile.to_dict(), profile_path=str(args.profile),
                         vector_set=vector_set_label(args.vectors, args.vectors_only), vector_set_hash=vector_set_hash(cases),
                         html_path=args.html or "")

    def progress(i, n, c):
        if not args.quiet:
            print(rep.progress_line(i, n, c), flush=True)

    old = signal.signal(signal.SIGTERM, _interrupt)
    try:
        runner.run(cases, result, progress, max_failures=args.max_failures)
    finally:
        signal.signal(signal.SIGTERM, old)
        factory.shutdown()
        result.finished = _now()
        write_reports(result, args)
    print(rep.summary(result))
    for kind in ("junit", "json", "html", "pcap"):
        if getattr(args, kind, None):
            print(f"{kind}: {getattr(args, kind)}")
    if result.counts()[R.ERROR] and result.exit_status() == 0:
        return 2
    return result.exit_status()


def vector_set_label(extra, only: bool) -> str:
    """What the run's vectors are, for the reports."""
    parts = [] if (only and extra) else ["bundled"]
    return " + ".join(parts + [str(d) for d in extra])


def write_reports(result, args) -> None:
    from . import report as rep

    if getattr(args, "json", None):
        result.write_json(args.json)
    if getattr(args, "html", None):
        from .html import write_html
        write_html(result, args.html)
    if getattr(args, "junit", None):
        rep.write_junit(result, args.junit)
    if getattr(args, "pcap", None):
        from . import capture as C
        try:
            C.save(C.from_results(result), args.pcap, "pcap")
        except C.CaptureError as exc:
            print(f"ptpcert run: {exc}", file=sys.stderr)


def _load_profile(cmd: str, path):
    """The IUT profile, or None after telling why it is bad (the caller exits 2)."""
    from .profile import ProfileError, load_profile

    try:
        return load_profile(path)
    except ProfileError as exc:
        print(f"ptpcert {cmd}: bad profile: {exc}", file=sys.stderr)
        return None


def _connect(cmd: str, url: str, profile):
    """The transport factory for ``url``, checked by :func:`preflight`, or None after
    telling why the IUT cannot be reached (the caller exits 2)."""
    from .transport import TransportError, make_factory

    factory = None
    try:
        factory = make_factory(url, profile)
        preflight(url, factory, profile)
        return factory
    except TransportError as exc:
        if factory is not None:
            factory.shutdown()   # processes started ahead for the next cases
        print(f"ptpcert {cmd}: {exc}", file=sys.stderr)
        return None


def preflight(url: str, factory, profile) -> None:
    """Start the IUT once before the run: a command that cannot start, or a port that cannot
    be opened, is a usage error (exit 2), not 50 failed cases."""
    from .transport import IUTDied, RESTART, TransportError

    if RESTART not in factory.capabilities or factory.virtual:
        return
    tr = factory(None, profile.params)
    try:
        tr.open()
        tr.read(tr.now() + 1.0)
    except IUTDied as exc:
        raise TransportError(f"{url}: the IUT ended at start-up (exit status {exc.returncode})"
                             + (f": {exc.stderr_tail.strip()[-600:]}" if exc.stderr_tail.strip() else "")) from None
    finally:
        tr.close()


def cmd_fuzz(args) -> int:
    import random
    import time

    from .fuzz import Campaign, export
    from .paths import findings_dir
    from .runner import RunOptions, Runner

    profile = _load_profile("fuzz", args.profile)
    if profile is None:
        return 2
    if args.budget <= 0:
        print("ptpcert fuzz: --budget must be positive", file=sys.stderr)
        return 2
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(1, 2**31)
    factory = _connect("fuzz", args.iut, profile)
    if factory is None:
        return 2
    out_dir = args.export or str(findings_dir())
    print(f"ptpcert fuzz {__version__}: iut {args.iut}, profile {args.profile}")
    print(f"seed {seed}, settings {args.settings}, budget {args.budget:.0f} s"
          + (f", database {args.database}" if args.database else ""))
    print(f"replay: ptpcert fuzz --iut '{args.iut}' --profile {args.profile} --seed {seed} "
          f"--settings {args.settings} --budget {args.budget:.0f}", flush=True)
    runner = Runner(factory, profile, RunOptions(check_status=False, late_ms=50.0))
    camp = Campaign(profile, runner, args.budget, seed, args.settings, args.database,
                    progress=lambda line: print(line, flush=True), max_actions=args.max_actions)
    old = signal.signal(signal.SIGTERM, _interrupt)
    interrupted = False
    try:
        camp.run()
    except KeyboardInterrupt:
        interrupted = True
    finally:
        signal.signal(signal.SIGTERM, old)
        factory.shutdown()
    paths = export(camp.findings, out_dir) if camp.findings else []
    elapsed = time.monotonic() - camp.started
    print(f"\n{camp.examples} examples in {elapsed:.1f} s ({camp.examples / max(elapsed, 1e-9):.1f}/s), "
          f"{len(camp.findings)} finding(s), {camp.informational} divergence(s) explained by another reading"
          + (", INTERRUPTED" if interrupted else ""))
    for p in paths:
        print(f"  written: {p}")
    if interrupted:
        return 2
    return 1 if camp.findings else 0


def cmd_report(args) -> int:
    from . import report as rep
    from .results import RunResult

    try:
        result = RunResult.read_json(args.results)
    except ValueError as exc:
        print(f"ptpcert report: {exc}", file=sys.stderr)
        return 2
    if not args.html and not args.junit:
        print(rep.summary(result))
        return 0
    if args.html:
        result.html_path = args.html
        from .html import write_html
        write_html(result, args.html)
        print(f"html: {args.html}")
    if args.junit:
        rep.write_junit(result, args.junit)
        print(f"junit: {args.junit}")
    return 0


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")
