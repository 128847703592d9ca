"""The ``ptpcert`` command line: the parser of every command, and the small commands that
explain (``vectors``, ``status``, ``model``); the commands that drive an IUT are
:mod:`.run`, those that judge recorded or live links :mod:`.analyze`, then :mod:`.capture` and
:mod:`.rules`."""

from __future__ import annotations

import argparse
import fnmatch
import os
import sys

from ptpcert import __version__

from .common import Parser


def _vectors(args) -> int:
    from ptpcert.check import check_vector
    from ptpcert.cli.run import vector_set_label
    from ptpcert.scenario import VectorError, load_vector_sets

    extra, only = list(args.vectors), args.vectors_only
    if args.dir:
        extra, only = extra + [args.dir], True
    try:
        vectors = load_vector_sets(extra, only=only)
    except VectorError as exc:
        print(f"ptpcert vectors: {exc}", file=sys.stderr)
        return 2
    root = vector_set_label(extra, only)
    if args.select:
        vectors = [v for v in vectors if any(fnmatch.fnmatchcase(v.id, g) for g in args.select)]
        if not vectors:
            print("ptpcert vectors: no vector matches --select " + " ".join(args.select)
                  + f" (in {root}; 'ptpcert vectors' lists the ids)", file=sys.stderr)
            return 2
    if not args.check:
        w = max((len(v.id) for v in vectors), default=10)
        for v in vectors:
            print(f"{v.id:<{w}}  {v.group:<15} {v.iut_role:<8}  {v.reference}")
            if args.verbose:
                print(f"{'':<{w}}  {v.title}\n{'':<{w}}  rule: {v.rule}\n")
        print(f"{len(vectors)} vectors in {root}")
        return 0
    passed = failed = 0
    for v in vectors:
        outcomes = check_vector(v)
        bad = [o for o in outcomes if not o.ok]
        if bad:
            failed += 1
            for o in bad:
                print(f"FAIL {v.id} [app={o.app}] {o.result.verdict}: {o.result.message}")
                if o.result.divergence and args.verbose:
                    d = o.result.divergence
                    print(f"     step {d.step + 1} at {d.time * 1000:.3f} ms: expected {d.expected}; {d.observed}")
        else:
            passed += 1
            if args.verbose:
                grades = {o.result.verdict for o in outcomes}
                print(f"ok   {v.id} ({', '.join(sorted(grades))})")
    print(f"{len(vectors)} vectors, {passed} passed, {failed} failed")
    return 1 if failed else 0


def _status(args) -> int:
    from ptpcert.registry import procedures
    from ptpcert.status import UnknownStatus, catalogue, lookup

    for proc in procedures():   # an option of a procedure's own (e.g. an error number of its frames)
        status = proc.status_command(args)
        if status is not None:
            return status
    if args.list:
        for code, e in sorted(catalogue().items()):
            print(f"{e.notation}  {e.event_class}  {e.side:<8} {', '.join(e.protocols):<24} {e.short}")
        print(f"{len(catalogue())} events (Tables 8-1, 8-2)")
        return 0
    if not args.code:
        print("ptpcert status: give a code (e.g. 16#0808), --list, or an option of a procedure "
              "(ptpcert status --help)", file=sys.stderr)
        return 2
    status = 0
    for code in args.code:
        try:
            e = lookup(code)
            print(e.describe())
            for proc in procedures():
                for line in proc.status_notes(e.code):
                    print(line)
        except UnknownStatus as exc:
            print(f"ptpcert status: {exc}", file=sys.stderr)
            status = 2
    return status


def _model(args) -> int:
    from ptpcert.registry import by_name, procedures

    charted = [p for p in procedures() if p.chart() is not None]
    if args.procedure:
        proc = by_name(args.procedure)
        if proc.chart() is None:
            print(f"ptpcert model: {proc.title} has no state chart (charts: "
                  + (", ".join(p.title for p in charted) or "none") + ")", file=sys.stderr)
            return 2
    elif len(charted) == 1:
        proc = charted[0]
    else:
        print("ptpcert model: name the procedure with --procedure (charts: "
              + (", ".join(p.title for p in charted) or "none") + ")", file=sys.stderr)
        return 2
    chart = proc.chart()
    if args.svg:
        with open(args.svg, "w", encoding="utf-8") as f:
            f.write(chart.svg())
        print(f"ptpcert: state machine drawn into {args.svg}")
    else:
        sys.stdout.write(chart.table_text())
    return 0


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line; with ``command="iut"`` the commands whose modules the
    reference IUT's start-up need not load (capture, analyze, monitor, rules) are left out:
    an exec: IUT is started for every case, so its start-up is part of every case's time."""
    from ptpcert.registry import all_names, procedures

    ap = Parser(
        prog="ptpcert",
        description="Conformance test suite and fuzzer for the CP 340/341/441 point-to-point "
                    "procedures: " + ", ".join(p.title for p in procedures()) + ".")
    ap.add_argument("--version", action="version", version=f"ptpcert {__version__}")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")

    v = sub.add_parser("vectors", help="list the golden vectors, or check them against the model",
                       description="List the golden vectors (bundled, and any directory of your own), or with "
                                   "--check replay each against the reference model. Exit status: 0 listed or "
                                   "all agree, 1 a vector disagrees with the model, 2 bad usage or a broken file.")
    v.add_argument("--check", action="store_true", help="replay every vector against the reference model")
    v.add_argument("--vectors", action="append", default=[], metavar="DIR",
                   help="a directory of vectors in addition to the bundled golden vectors (repeatable)")
    v.add_argument("--vectors-only", action="store_true",
                   help="only the vectors of --vectors, not the bundled ones")
    v.add_argument("--dir", help="only the vectors of this directory (--vectors DIR --vectors-only)")
    v.add_argument("--select", action="append", metavar="GLOB", help="only vectors whose id matches")
    v.add_argument("-v", "--verbose", action="store_true")
    v.set_defaults(func=_vectors)

    s = sub.add_parser("status", help="explain a STATUS event code (e.g. 16#0808)",
                       description="Explain CP 340/341/441 STATUS event codes (Tables 8-1, 8-2): class, side, "
                                   "the procedures that raise them and what they mean. Exit status: 0 explained, "
                                   "2 an unknown code or bad usage.")
    s.add_argument("code", nargs="*", help="16#0808, 0x0808 or 0808")
    s.add_argument("--list", action="store_true", help="list all 80 events")
    for proc in procedures():
        proc.add_status_arguments(s.add_argument_group(proc.title))
    s.set_defaults(func=_status)

    m = sub.add_parser("model", help="a procedure's transition table, as text or drawn (--svg)",
                       description="Print the transition table of a procedure's reference model, or draw its "
                                   "state machine into a self-contained SVG. Exit status: 0 done, 2 bad usage.")
    m.add_argument("--procedure", choices=all_names(), help="whose state machine (needed where several have one)")
    m.add_argument("--svg", metavar="FILE", help="draw the state machine into FILE (a self-contained SVG)")
    m.set_defaults(func=_model)

    from ptpcert.cli import iut as cli_iut
    cli_iut.add_commands(sub)
    if command == "iut":
        return ap
    from ptpcert.cli import fuzz as cli_fuzz
    from ptpcert.cli import reports as cli_reports
    from ptpcert.cli import run as cli_run
    cli_run.add_commands(sub)
    cli_fuzz.add_commands(sub)
    cli_reports.add_commands(sub)
    from ptpcert.cli import capture as cli_capture
    cli_capture.add_commands(sub)
    from ptpcert.cli import analyze as cli_analyze
    cli_analyze.add_commands(sub)
    from ptpcert.cli import rules as cli_rules
    cli_rules.add_commands(sub)
    from ptpcert.cli import profile as cli_profile
    cli_profile.add_commands(sub)
    from ptpcert.cli import evidence as cli_evidence
    cli_evidence.add_commands(sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    words = sys.argv[1:] if argv is None else argv
    ap = build_parser("iut" if words[:1] == ["iut"] else None)
    args = ap.parse_args(argv)
    if not getattr(args, "func", None):
        ap.print_help()
        return 2
    # the ptpcert program itself (argv from the command line) ends with the command; a
    # caller that hands in argv goes on in the same process (see cli.run.Interrupts)
    args.process_exits_after = argv is None
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("ptpcert: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as exc:  # the last line of defence: one line, never a traceback
        if os.environ.get("PTPCERT_DEBUG"):
            raise
        text = " ".join(str(exc).split())[:300]
        print(f"ptpcert {args.command}: internal error: {type(exc).__name__}: {text} "
              "(a fault of ptpcert; PTPCERT_DEBUG=1 shows where)", file=sys.stderr)
        return 2

