"""``ptpcert iut``: the bundled reference implementation, the model as a real-time station.
Its start-up is part of every case of an exec: IUT, so this module loads nothing it does not
need."""

from __future__ import annotations

import signal
import sys


def add_commands(sub) -> None:
    """The ``iut`` command."""
    from ptpcert.registry import all_names, procedures
    i = sub.add_parser("iut", help="run the bundled reference implementation (the model, in real time)",
                       description="The reference model as a real-time station on stdin/stdout (or --port), "
                                   "with its application. STATUS events go to stderr as 'STATUS 16#XXXX' lines.")
    i.add_argument("--procedure", choices=all_names(), default=None,
                   help=f"the procedure (default {procedures()[0].names[0]}, or the profile's)")
    i.add_argument("--profile", metavar="FILE", default=None,
                   help="run the reference configured from this IUT profile, every key (its procedure, "
                        "parameters, application and line conditions); the options below then only add "
                        "what the profile does not say (a setup, a mutant)")
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


def cmd_iut(args) -> int:
    from ptpcert.iut import run_iut
    from ptpcert.registry import by_name, procedures

    profile = None
    if args.profile:
        from ptpcert.cli.common import load_profile
        profile = load_profile("iut", args.profile)
        if profile is None:
            return 2
        if args.procedure and by_name(args.procedure) is not profile.procedure:
            print(f"ptpcert iut: --procedure {args.procedure} but the profile is {profile.procedure.title}'s",
                  file=sys.stderr)
            return 2
        args.procedure = args.procedure or profile.procedure.names[0]
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
        args.app = proc.profile_app(profile) if profile is not None else proc.apps()[0]
    if args.app not in proc.apps():
        print(f"ptpcert iut: --app {args.app!r}: allowed values are {', '.join(proc.apps())}", file=sys.stderr)
        return 2
    from ptpcert.procedure import ProcedureError
    try:
        params = profile.params if profile is not None else proc.params_from_iut(args)
        host = proc.iut_host(params, args)
    except ProcedureError as exc:
        print(f"ptpcert iut: {exc}", file=sys.stderr)
        return 2
    if profile is None:   # the options are held to what a profile of the same settings must be
        problem = _options_problem(proc, params, args)
        if problem:
            print(f"ptpcert iut: {problem}", file=sys.stderr)
            return 2
    parmrk = args.parmrk or (profile is not None and profile.line_conditions == "parmrk")
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    return run_iut(host, proc.line(params), parmrk=parmrk, port=args.port, verbose=args.verbose)


def _options_problem(proc, params, args) -> str | None:
    """Why the options' settings would be refused as a profile (one validation for both: the
    profile schema and the procedure's checks), or None. Settings a profile cannot state (an
    unpaced output, --baud 0) are left out of the check."""
    from ptpcert.profile import ProfileError, profile_from_dict

    from ptpcert.schema import COMMON

    schema = proc.profile_schema()
    if not schema:   # a procedure that declares no profile keys: nothing to hold the options to
        return None
    known = {k.name for k in (*COMMON, *schema)} | {"procedure"}
    settings = proc.profile_dict(params)
    # settings only the reference takes (not profile keys) are the options' own business
    iut = {k: v for k, v in settings.items() if not isinstance(v, dict) and v is not None and k in known}
    iut.update(send_trigger=proc.send_triggers[0], line_conditions="parmrk" if args.parmrk else "none",
               status_from_stderr=True)
    raw = {"iut": iut, **{k: {kk: vv for kk, vv in v.items() if vv is not None}
                          for k, v in settings.items() if isinstance(v, dict)}}
    try:
        profile_from_dict(raw, "the options")
    except ProfileError as exc:
        return str(exc)
    return None
