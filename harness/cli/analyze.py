"""The ``analyze`` and ``monitor`` commands: judge a recorded or live link between two
stations (see :mod:`ptpcert.analysis`)."""

from __future__ import annotations

import os
import re
import sys
import time
from pathlib import Path

from ptpcert import priority
from ptpcert.priority import MODES as PRIORITY_MODES

from .common import load_profile, now, number

#: schemes of ``--iut`` URLs whose transport starts a fresh IUT for every case
_RESTARTING = ("exec:", "pty:", "sim:")
_RUN_NOTE = re.compile(r"^run of \d+ cases? against (\S.*)$")


def add_commands(sub) -> None:
    from ptpcert.capture import FORMATS

    a = sub.add_parser(
        "analyze", help="judge a recorded link between two stations (a capture) against the model",
        description="Judge a recorded two-direction capture of both stations: each judged seat's station "
                    "is followed by the model, fed what the other seat sent; every rule a station broke is "
                    "reported with its manual reference and the STATUS events a CP 341 in each seat raises. "
                    "Reports as for 'run'. Exit status: 0 nothing failed, 1 a station broke a rule, 2 bad "
                    "usage or a capture that cannot be read.")
    a.add_argument("capture", metavar="CAPTURE",
                   help="capture JSON, results JSON (what 'run --json' writes), hex log or pcap")
    _common(a)
    a.add_argument("--from", dest="from_", choices=FORMATS, metavar="FMT", help="the capture's format")
    a.add_argument("--case", metavar="ID", help="from a results object: this case only")
    a.add_argument("--resolution-ms", type=MS, default=None, metavar="MS",
                   help="how much earlier than its timestamp a character may have been complete "
                        "(default: what the capture says of how its times were taken, e.g. a run against "
                        "exec:/pty: three character times + 2 ms, a serial port one + 2 ms, sim: 0; a capture "
                        "that does not say, and names no run: 0, the timestamps are exact)")
    a.add_argument("--restart-at-cases", choices=["auto", "a", "b", "both", "none"], default="auto",
                   help="the seats whose station is switched on where a case of a run begins (default auto: "
                        "seat b when the capture is a run against exec:, pty: or sim:)")
    a.add_argument("-v", "--verbose", action="store_true", help="one line per exchange, not only those with findings")
    a.set_defaults(func=cmd_analyze)

    m = sub.add_parser(
        "monitor", help="judge a live link between two stations from two receive-only ports",
        description="Watch a live link from two receive-only ports, each hearing one station's transmit "
                    "line (e.g. a Y cable): one console line per exchange with its verdict, findings as "
                    "they happen, a capture written as it goes. Ctrl-C (or --duration) ends it and writes "
                    "the reports. Exit status as for 'analyze'.")
    m.add_argument("--a", required=True, metavar="PORT", help="the port hearing seat a's station (pyserial URL or device)")
    m.add_argument("--b", required=True, metavar="PORT", help="the port hearing seat b's station")
    _common(m)
    m.add_argument("--capture", metavar="FILE",
                   help="the capture written as it goes: .pcap, or .hexlog/.log/.txt "
                        "(default: monitor-<UTC time>.pcap in the current directory)")
    m.add_argument("--parmrk", action="store_true",
                   help="the ports mark line conditions as termios PARMRK does (a real UART is told to; on a "
                        "pseudo-terminal the writer marks them)")
    m.add_argument("--fifo", type=number(int, 1, 4096, "characters"), default=8, metavar="CHARS",
                   help="how many characters the port's receiver may collect before it hands them over "
                        "(default 8: a 16550A UART's receive trigger; its 4-character timeout is less; 1: "
                        "a pseudo-terminal)")
    m.add_argument("--latency-ms", type=MS, default=2.0, metavar="MS",
                   help="how long the driver may hold what the receiver handed over before a read returns it "
                        "(default 2; a USB adapter: its latency timer, 16 unless set lower, plus 1)")
    m.add_argument("--resolution-ms", type=MS, default=None, metavar="MS",
                   help="the timing resolution itself (default: --fifo character times + --latency-ms)")
    m.add_argument("--duration", type=number(float, 0.001, 7 * 24 * 3600.0, "seconds"), default=None,
                   metavar="SECONDS", help="stop after this long (0.001 s to a week)")
    m.add_argument("--priority", choices=PRIORITY_MODES, default="auto",
                   help="the reader thread's scheduling class: auto (default) takes the real-time class where the "
                        "system permits it, realtime insists on it, normal never asks; the analysis stays normal")
    m.set_defaults(func=cmd_monitor)


def _common(p) -> None:
    p.add_argument("--profile", required=True, metavar="FILE",
                   help="the profile of the station in seat b (in a capture 'run' wrote: the IUT's); seat a is "
                        "its conforming partner (the same settings, the other priority) unless --profile-a")
    p.add_argument("--profile-a", metavar="FILE", help="seat a's own profile")
    p.add_argument("--profile-b", metavar="FILE", help="seat b's own profile (instead of --profile's)")
    p.add_argument("--judge", choices=["a", "b", "both"], default=None,
                   help="whose deviations count (default: b, the IUT's seat, in a capture of a 'ptpcert run', whose "
                        "seat a is the suite's tester with its deliberate deviations; both for any other capture)")
    p.add_argument("--tolerance-ms", type=MS, default=50.0,
                   help="how late a station may act on its own timer, plus 25%% of the timer (default 50)")
    p.add_argument("--junit", metavar="PATH", help="write a JUnit XML file")
    p.add_argument("--json", metavar="PATH", help="write the results object as JSON")
    p.add_argument("--html", metavar="PATH", help="write the HTML report")
    p.add_argument("-q", "--quiet", action="store_true", help="only the summary")


# ------------------------------------------------------------------ shared


class Setup:
    """The stations' parameters, their applications and the procedure's analyzer."""

    def __init__(self, proc, params: dict, profiles: dict, kit, paths: dict):
        self.proc, self.params, self.profiles, self.kit, self.paths = proc, params, profiles, kit, paths

    def profile_dict(self, judged, resolution: float) -> dict:
        d = dict(self.proc.profile_dict(self.params["b"]))
        d["seat a"] = ", ".join(f"{k} {v}" for k, v in self.proc.profile_dict(self.params["a"]).items())
        d["judged"] = ", ".join(f"seat {s}" for s in judged) or "none"
        d["timing resolution"] = f"{resolution * 1000:.3f} ms"
        d["send trigger"] = f"seat a {self.kit.apps['a']}, seat b {self.kit.apps['b']}"
        return d


#: a time option in milliseconds: finite, 0 to a minute
MS = number(float, 0, 60000, "ms")


def _setup(cmd: str, args) -> Setup | None:
    from ptpcert.cli.reports import report_paths_problem
    from ptpcert.results import report_path_problem

    # every file this command writes, checked before anything is read or watched: absent or
    # a regular file, writable, and no two of them (nor the capture read) the same file
    reading = getattr(args, "capture", None) if cmd == "analyze" else None
    problem = report_paths_problem(args, ("junit", "json", "html"), reading=reading)
    if not problem and cmd == "monitor" and args.capture:
        written = {os.path.realpath(p) for p in (args.junit, args.json, args.html) if p}
        if os.path.realpath(args.capture) in written:
            problem = f"--capture {args.capture}: is also a report; give each file its own name"
        else:
            why = report_path_problem(args.capture)
            problem = f"--capture {args.capture}: {why}" if why else None
    if problem:
        print(f"ptpcert {cmd}: {problem}", file=sys.stderr)
        return None

    base = load_profile(cmd, args.profile)
    if base is None:
        return None
    prof_b = load_profile(cmd, args.profile_b) if args.profile_b else base
    prof_a = load_profile(cmd, args.profile_a) if args.profile_a else None
    if prof_b is None or (args.profile_a and prof_a is None):
        return None
    proc = prof_b.procedure
    if prof_a is not None and prof_a.procedure is not proc:
        print(f"ptpcert {cmd}: the profiles are for {prof_a.procedure.title} and {proc.title}; "
              "a link carries one procedure", file=sys.stderr)
        return None
    params = {"b": prof_b.params,
              "a": prof_a.params if prof_a is not None else proc.tester_params(base.params)}
    apps = {"b": "echo" if prof_b.echo else "none",
            "a": "echo" if prof_a is not None and prof_a.echo else "none"}
    kit = proc.analyzer(params["a"], params["b"], apps=apps, late_ms=args.tolerance_ms)
    if kit is None:
        print(f"ptpcert {cmd}: line analysis of {proc.title} is not available yet", file=sys.stderr)
        return None
    paths = {"a": args.profile_a or f"{args.profile} (the other priority)", "b": args.profile_b or args.profile}
    return Setup(proc, params, {"a": prof_a, "b": prof_b}, kit, paths)


def _judged(args) -> str:
    return "ab" if args.judge in ("both", None) else args.judge


class ConsoleListener:
    """Prints findings as they stand and one line per finished exchange."""

    def __init__(self, seats: dict, *, quiet: bool = False, every: bool = True, out=None):
        self.seats, self.quiet, self.every = seats, quiet, every
        self.out = out or sys.stdout
        self.exchanges = 0
        self.findings = 0

    def finding(self, f) -> None:
        from ptpcert import results as R

        self.findings += 1
        if not self.quiet and f.grade == R.FAIL:
            print(f"  ! {f.text(self.seats)}", file=self.out, flush=True)

    def exchange(self, line, e) -> None:
        from ptpcert.analysis import summary_line

        self.exchanges += 1
        if not self.quiet and (self.every or e.findings):
            print(summary_line(line, e, self.seats), file=self.out, flush=True)


def _finish(result, args, t0: float, view=None, judged: str = "") -> int:
    from ptpcert import report as rep
    from ptpcert import results as R
    from ptpcert.cli.reports import write_reports

    result.wall_time = round(time.monotonic() - t0, 3)
    result.finished = now()
    if args.html:
        result.html_path = args.html
    written = write_reports(result, args, args.command, view)
    if judged:     # whose deviations the verdict counts, and why
        print(judged)
    print(rep.summary(result).replace(" cases in ", " results in "))
    for kind in ("junit", "json", "html"):
        if getattr(args, kind) and kind in written:
            print(f"{kind}: {getattr(args, kind)}")
    if len(written) < sum(bool(getattr(args, k)) for k in ("junit", "json", "html")):
        return 2
    if result.counts()[R.ERROR] and result.exit_status() == 0:
        return 2
    return result.exit_status()


# ------------------------------------------------------------------ analyze


def _run_url(path: str, cap) -> str | None:
    """The --iut URL of the run a capture comes from, if it says."""
    import json

    from ptpcert import capture as C

    if str(path).lower().endswith(".json"):
        try:
            d = json.loads(Path(path).read_text("utf-8"))
        except (OSError, ValueError, RecursionError):
            d = None
        cases = d.get("cases") if isinstance(d, dict) else None
        converted = isinstance(cases, list) and bool(cases) and all(
            isinstance(c, dict) and c.get("group") == C.CAPTURE_GROUP for c in cases)
        if isinstance(d, dict) and "schema" in d and not converted:   # a converted capture: its notes say
            return str(d.get("iut") or "") or None
    for n in cap.notes:
        m = _RUN_NOTE.match(n)
        if m:
            return m.group(1)
        if n.startswith("IUT: "):
            return n[5:]
    return None


def _seats_judged(args, cap, url: str | None) -> tuple[str, str]:
    """The seats ``analyze`` judges and why: ``--judge``; else, in a capture of a ``ptpcert
    run`` (it names the run's IUT, or its times were taken by a run's transport), seat b
    only: seat a is the suite's tester, whose deviations are the cases' deliberate stimuli;
    else both."""
    if args.judge is not None:
        return _judged(args), f"--judge {args.judge}"
    if url is not None or (cap.timing is not None and cap.timing.transport in ("sim", "pipe", "port")):
        run = f"a run against {url}" if url else "a run"
        return "b", (f"the IUT's: the capture is of {run}, whose seat a is the suite's tester with its "
                     "deliberate deviations; --judge both judges it too")
    return "ab", "the capture names no run, so both stations count; --judge a or b for one"


def _nothing_to_judge(path: str, cap) -> str | None:
    """Why ``cap`` gives nothing to judge (it holds no character and no line condition), or None."""
    if cap.chunks:
        return None
    skipped = [n for n in cap.notes if n.endswith("is unknown; skipped")]
    why = f" ({len(skipped)} record(s) of an unknown event type skipped: {skipped[0]})" if skipped else ""
    return f"{path}: the capture holds no characters and no line conditions{why}: nothing to judge"


def _procedure_mismatch(path: str, cap, proc) -> str | None:
    """Where a capture of a run names its procedure and the profile's is another, what to say."""
    from ptpcert import capture as C

    said = next((n[len(C.PROCEDURE_NOTE):] for n in cap.notes if n.startswith(C.PROCEDURE_NOTE)), None)
    if said is None or said == proc.title:
        return None
    return (f"{path}: the capture is of a run of {said}, the profile is for {proc.title}: "
            f"judge it with a profile of {said}")


def _resolution(args, cap, url: str | None, char: float) -> float:
    """The timing resolution to judge ``cap`` with: ``--resolution-ms``, else what the
    capture says of how its times were taken, else (a capture written before captures said
    it) from the run it names, else 0 (exact)."""
    from ptpcert import capture as C

    if args.resolution_ms is not None:
        return args.resolution_ms / 1000.0
    if cap.timing is not None:
        return cap.timing.resolution
    if url is not None:
        return C.run_timing(url, char).resolution
    return 0.0


def cmd_analyze(args) -> int:
    from ptpcert import analysis as A
    from ptpcert import capture as C

    t0 = time.monotonic()
    setup = _setup("analyze", args)
    if setup is None:
        return 2
    try:
        cap = C.load(args.capture, args.from_, args.case)
    except C.CaptureError as exc:
        print(f"ptpcert analyze: {exc}", file=sys.stderr)
        return 2
    problem = _nothing_to_judge(args.capture, cap) or _procedure_mismatch(args.capture, cap, setup.proc)
    if problem:
        print(f"ptpcert analyze: {problem}", file=sys.stderr)
        return 2
    url = _run_url(args.capture, cap)
    restarting = url is not None and url.startswith(_RESTARTING)
    if args.restart_at_cases == "auto":
        restart = {"b"} if restarting else set()
    else:
        restart = {"none": set(), "both": {"a", "b"}}.get(args.restart_at_cases, {args.restart_at_cases})
    if args.case and restart and not any(m.text.lower().startswith("case ") for m in cap.marks):
        # one case of a run: it began at t = 0, with the stations switched on as the run did
        cap.marks.insert(0, C.Mark(0.0, f"case {args.case}"))
    resolution = _resolution(args, cap, url, max(setup.kit.char("a"), setup.kit.char("b")))
    notes = []
    ours = setup.proc.line(setup.params["b"])
    if cap.line is not None and str(cap.line) != str(ours):
        notes.append(f"the capture says the line is {cap.line}; the analysis uses the profiles' {ours}")
    judged, why = _seats_judged(args, cap, url)
    said = f"judged: seat{'s' if len(judged) > 1 else ''} {' and '.join(judged)} ({why})"
    notes.append(said)
    listener = ConsoleListener(dict(cap.seats), quiet=args.quiet, every=args.verbose)
    if not args.quiet:
        print(f"ptpcert analyze: {args.capture}: {len(cap.chunks)} chunks, {cap.duration:.3f} s; "
              f"judging seat{'s' if len(judged) > 1 else ''} {' and '.join(judged)} ({why}); "
              f"timing resolution {resolution * 1000:.3f} ms"
              + (f"; seat b restarts at each case ({url})" if restart else ""), flush=True)
    if judged == "b" and args.judge is None and setup.kit.apps["b"] == "echo":
        # the run's IUT had the suite's echo interface: it sends back what it gets, nothing else
        setup.kit.apps["b"] = "echo-only"
    an = A.analyze(cap, setup.kit, judge=judged, resolution=resolution, restart_at_cases=restart,
                   source=str(args.capture), listener=listener)
    notes.append(f"timing resolution {resolution * 1000:.3f} ms" + (
        "" if args.resolution_ms is not None or cap.timing is None else f" (the capture's {cap.timing.describe()})"))
    result = A.to_results(an, profile=setup.profile_dict(an.line.judged, resolution), notes=notes)
    result.profile_path = f"seat a: {setup.paths['a']}; seat b: {setup.paths['b']}"
    if not result.cases:      # nothing judged is not a pass
        print(f"ptpcert analyze: {args.capture}: no exchange and no finding came of the capture: nothing was judged",
              file=sys.stderr)
        return 2
    return _finish(result, args, t0, setup.proc.report_view(), judged=said)


# ------------------------------------------------------------------ monitor


def resolution_for(line, latency: float, fifo: int = 8) -> float:
    """The timing resolution of timestamps taken when a port's read returns: a UART hands
    characters over when ``fifo`` of them are in its receive FIFO (a lone one after its
    receive timeout, about 4 character times), and the driver may hold them ``latency``
    seconds more."""
    return max(fifo, 1) * line.char_time + latency


def cmd_monitor(args) -> int:
    import datetime as dt
    import signal

    from ptpcert import analysis as A
    from ptpcert import capture as C
    from ptpcert.analysis.monitor import Monitor, MonitorError

    t0 = time.monotonic()
    setup = _setup("monitor", args)
    if setup is None:
        return 2
    line_b = setup.proc.line(setup.params["b"])
    resolution = (args.resolution_ms / 1000.0 if args.resolution_ms is not None
                  else resolution_for(line_b, args.latency_ms / 1000.0, args.fifo))
    started = dt.datetime.now(dt.timezone.utc)
    path = args.capture or f"monitor-{started.strftime('%Y%m%dT%H%M%SZ')}.pcap"
    try:
        fmt = C.format_of(path)
    except C.CaptureError:
        fmt = None
    if fmt not in ("pcap", "hexlog"):   # monitor has no --to: the extension says the format
        print(f"ptpcert monitor: --capture {path}: the capture is written as it goes, as pcap or hex log: "
              "name it .pcap, .cap, .hexlog, .log or .txt", file=sys.stderr)
        return 2
    judged = _judged(args)
    seats = {"a": args.a, "b": args.b}
    listener = ConsoleListener(seats, quiet=args.quiet, every=True)
    line = A.LineAnalysis(setup.kit, judge=judged, resolution=resolution, listener=listener)
    timing = C.Timing("monitor", resolution, line_b.char_time if line_b.baud_rate else None)
    # the procedure and seat b's parameters, for a reader of the capture (the Wireshark dissector)
    meta = C.Capture([], seats, line_b, started, None,
                     [f"ptpcert monitor, timing resolution {resolution * 1000:.3f} ms",
                      C.PROCEDURE_NOTE + setup.proc.title,
                      C.params_text(setup.proc.params_table(setup.params["b"]))], timing=timing)
    try:
        mon = Monitor(args.a, args.b, line_b, parmrk=args.parmrk)
    except MonitorError as exc:
        print(f"ptpcert monitor: {exc}", file=sys.stderr)
        return 2
    print(f"ptpcert monitor: seat a on {args.a}, seat b on {args.b}, {line_b.describe()}; timing resolution "
          f"{resolution * 1000:.3f} ms; capture {path}; Ctrl-C ends it", flush=True)
    interrupted = []

    def stop(*_):
        interrupted.append(True)

    old = signal.signal(signal.SIGTERM, stop)
    old_int = signal.signal(signal.SIGINT, stop)
    try:
        with open(path, "wb" if fmt == "pcap" else "w", **({} if fmt == "pcap" else {"encoding": "utf-8"})) as fp:
            writer = C.PcapWriter(fp, started, timing, meta) if fmt == "pcap" else C.HexLogWriter(fp, meta)
            with priority.harness(args.priority, this_thread=False) as how:
                end = mon.run(line, writer, stop=lambda: bool(interrupted), duration=args.duration,
                              resolution=resolution)
            writer.close(end)
    except OSError as exc:
        print(f"ptpcert monitor: {path}: {exc.strerror}", file=sys.stderr)
        return 2
    except priority.PriorityError as exc:
        print(f"ptpcert monitor: {exc}", file=sys.stderr)
        return 2
    finally:
        signal.signal(signal.SIGTERM, old)
        signal.signal(signal.SIGINT, old_int)
        mon.close()
    line.close(end)
    cap = C.Capture(list(line.chunks), seats, line_b, started, end, list(meta.notes), list(line.marks), timing)
    an = A.Analysis(line, cap, setup.kit, path)
    result = A.to_results(an, profile=setup.profile_dict(line.judged, resolution),
                          notes=[f"timing resolution {resolution * 1000:.3f} ms (timestamps taken when a read returned)"])
    result.iut = f"seat a: {args.a}, seat b: {args.b}"
    result.harness_scheduling = how
    result.profile_path = f"seat a: {setup.paths['a']}; seat b: {setup.paths['b']}"
    if mon.stalls:
        print(f"ptpcert monitor: {mon.stalls} time(s) the monitor was not scheduled in time: the timing of what "
              "came in meanwhile is lost (marked in the capture; findings there are informational)")
    print(f"\n{listener.exchanges} exchanges, {end:.1f} s watched; capture: {path}")
    return _finish(result, args, t0, setup.proc.report_view())
