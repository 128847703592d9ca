"""The reports of a run: their paths checked before the work starts, every report written
whole or not at all (JUnit first, what CI reads), and ``ptpcert report``, which renders saved
results again."""

from __future__ import annotations

import os
import sys


def add_commands(sub) -> None:
    """The ``report`` command."""
    rep = sub.add_parser("report", help="render a saved results object (JSON) as HTML or JUnit, or merge shards",
                         description="Render the results 'ptpcert run --json' saved as HTML, JUnit or JSON again "
                                     "(without an output option: the summary), or with --merge join the results "
                                     "of the shards of one run ('ptpcert run --shard K/N') into one report. "
                                     "Exit status: 0 written, 2 bad usage or a file that cannot be read or "
                                     "written (the verdict is in the reports).")
    rep.add_argument("results", metavar="RESULTS.json", nargs="?", help="a saved results object")
    rep.add_argument("--merge", metavar="RESULTS.json", nargs="+",
                     help="the results of every shard of one run (K/N for K = 1..N), merged into one report; "
                          "refused for results of different profiles, procedures or selections, with a case "
                          "twice, or with a shard missing")
    rep.add_argument("--html", metavar="PATH")
    rep.add_argument("--junit", metavar="PATH")
    rep.add_argument("--json", metavar="PATH", help="the results object (merged, with --merge)")
    rep.set_defaults(func=cmd_report)


def report_paths_problem(args, kinds: tuple[str, ...], reading: str | list[str] | None = None) -> str | None:
    """Why one of the report options (``--junit`` ...) cannot be written, checked before
    anything runs; None when all can. ``reading``: the file or files read (no report may
    overwrite one)."""
    from ptpcert.results import report_path_problem

    seen: dict[str, str] = {}
    for path in [reading] if isinstance(reading, str) else reading or []:
        seen[os.path.realpath(path)] = f"the file read ({path})"
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
    writers = (("junit", lambda r, p: rep.write_junit(r, p, view)), ("json", lambda r, p: r.write_json(p)),
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


def cmd_report(args) -> int:
    from ptpcert import report as rep
    from ptpcert.results import ResultsError, RunResult

    merge = getattr(args, "merge", None)
    if bool(args.results) == bool(merge):
        print("ptpcert report: give one RESULTS.json to render, or --merge with the results of every shard "
              "(not both)", file=sys.stderr)
        return 2
    kinds = ("junit", "html", "json")
    problem = report_paths_problem(args, kinds, reading=merge or args.results)
    if problem:
        print(f"ptpcert report: {problem}", file=sys.stderr)
        return 2
    try:
        result = merged(merge) if merge else RunResult.read_json(args.results)
    except ResultsError as exc:
        print(f"ptpcert report: {'--merge: ' if merge else ''}{exc}", file=sys.stderr)
        return 2
    if not any(getattr(args, k, None) for k in kinds):
        print(rep.summary(result))
        return 0
    if args.html:
        result.html_path = args.html
    written = write_reports(result, args, "report", report_view_of(result))
    for kind in kinds:
        if kind in written:
            print(f"{kind}: {getattr(args, kind)}")
    return 0 if len(written) == sum(bool(getattr(args, k, None)) for k in kinds) else 2


def merged(paths: list[str]):
    """The results of the shards in ``paths`` as one, its cases in the order an unsharded
    run has them. Raises ResultsError naming the file."""
    from ptpcert.registry import by_title
    from ptpcert.results import RunResult, merge_runs
    from ptpcert.suite import order

    named = [(p, RunResult.read_json(p)) for p in paths]
    proc = by_title(named[0][1].procedure) if named[0][1].procedure else None
    return merge_runs(named, (lambda cases: order(cases, proc.groups)) if proc is not None else None)


def report_view_of(result):
    """The report view of the procedure whose title the results carry (a saved run), or
    None (neutral) when no procedure has it."""
    from ptpcert.registry import by_title

    proc = by_title(result.procedure) if result.procedure else None
    return proc.report_view() if proc is not None else None
