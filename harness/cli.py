"""The ``ptpcert`` command line."""

from __future__ import annotations

import argparse
import fnmatch
import sys

from . import __version__


def _vectors(args) -> int:
    from .check import check_vector
    from .cli_run import vector_set_label
    from .scenario import VectorError, load_vector_sets

    extra, only = list(args.vectors), args.vectors_only
    if args.dir:
        extra, only = extra + [args.dir], True
    try:
        vectors = load_vector_sets(extra, only=only)
    except VectorError as exc:
        print(f"ptpcert: broken vector: {exc}", file=sys.stderr)
        return 2
    root = vector_set_label(extra, only)
    if args.select:
        vectors = [v for v in vectors if any(fnmatch.fnmatchcase(v.id, g) for g in args.select)]
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
    from .status import UnknownStatus, catalogue, lookup

    if args.list:
        for code, e in sorted(catalogue().items()):
            print(f"{e.notation}  {e.event_class}  {e.side:<8} {', '.join(e.protocols):<24} {e.short}")
        print(f"{len(catalogue())} events (Tables 8-1, 8-2)")
        return 0
    if not args.code:
        print("ptpcert status: give a code (e.g. 16#0808) or --list", file=sys.stderr)
        return 2
    status = 0
    for code in args.code:
        try:
            print(lookup(code).describe())
        except UnknownStatus as exc:
            print(f"ptpcert status: {exc}", file=sys.stderr)
            status = 2
    return status


def _model(args) -> int:
    from . import statechart

    if args.svg:
        with open(args.svg, "w", encoding="utf-8") as f:
            f.write(statechart.svg())
        print(f"ptpcert: state machine drawn into {args.svg}")
    else:
        sys.stdout.write(statechart.table_text())
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="ptpcert",
        description="Conformance test suite and fuzzer for the CP 340/341/441 point-to-point "
                    "procedures 3964 / 3964R.")
    ap.add_argument("--version", action="version", version=f"ptpcert {__version__}")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")

    v = sub.add_parser("vectors", help="list the golden vectors, or check them against the model")
    v.add_argument("--check", action="store_true", help="replay every vector against the reference model")
    v.add_argument("--vectors", action="append", default=[], metavar="DIR",
                   help="a directory of vectors in addition to the bundled golden vectors (repeatable)")
    v.add_argument("--vectors-only", action="store_true",
                   help="only the vectors of --vectors, not the bundled ones")
    v.add_argument("--dir", help="only the vectors of this directory (--vectors DIR --vectors-only)")
    v.add_argument("--select", action="append", metavar="GLOB", help="only vectors whose id matches")
    v.add_argument("-v", "--verbose", action="store_true")
    v.set_defaults(func=_vectors)

    s = sub.add_parser("status", help="explain a STATUS event code (e.g. 16#0808)")
    s.add_argument("code", nargs="*", help="16#0808, 0x0808 or 0808")
    s.add_argument("--list", action="store_true", help="list all 80 events")
    s.set_defaults(func=_status)

    m = sub.add_parser("model", help="the 3964/3964R transition table, as text or drawn (--svg)")
    m.add_argument("--svg", metavar="FILE", help="draw the state machine into FILE (a self-contained SVG)")
    m.set_defaults(func=_model)

    from . import cli_run
    cli_run.add_commands(sub)
    from . import cli_capture
    cli_capture.add_commands(sub)
    from . import cli_analyze
    cli_analyze.add_commands(sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    ap = build_parser()
    args = ap.parse_args(argv)
    if not getattr(args, "func", None):
        ap.print_help()
        return 2
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("ptpcert: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
