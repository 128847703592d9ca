"""``ptpcert rules``: the traceability matrix (rule -> cases and vectors -> what is checked)."""

from __future__ import annotations

import fnmatch
import json
import sys


def add_commands(sub) -> None:
    from ptpcert.registry import all_names

    r = sub.add_parser(
        "rules", help="the traceability matrix: the manual's rules and the cases and vectors that check them",
        description="Print every rule of the manual (its id, reference and sentence) with the cases and golden "
                    "vectors that check it, for every IUT setting the rule applies to; rules that cannot be "
                    "checked on the line are listed with the reason. --check prints only what is missing and "
                    "exits 1 when a testable rule has no case.")
    r.add_argument("--check", action="store_true",
                   help="print only the problems; exit 1 when a testable rule has no case")
    r.add_argument("--procedure", choices=all_names(), help="only this procedure's catalogue")
    r.add_argument("--profile", metavar="FILE", help="the matrix for this IUT profile only (its cases)")
    r.add_argument("--select", action="append", metavar="GLOB", help="only rules whose id matches (repeatable)")
    r.add_argument("--json", metavar="PATH", help="also write the matrix as JSON ('-': standard output only)")
    r.add_argument("-q", "--brief", action="store_true", help="ids, status and cases, without the rule sentences")
    r.set_defaults(func=cmd_rules)


class _Virtual:
    """What a procedure's ``unsupported_reason`` asks of the transport: the matrix counts
    the cases as the simulator would run them (virtual time, every capability)."""

    virtual = True


_VIRTUAL = _Virtual()


def matrices(procedures, profile=None):
    """The matrix of each procedure: for each of its settings (or the profile's), the suite
    generated for it plus the golden vectors that run under it."""
    from ptpcert import conformance
    from ptpcert.rules import for_procedure
    from ptpcert.traceability import Setting, build, runs_under
    from ptpcert.scenario import load_vector_sets

    vectors = load_vector_sets()
    out = []
    for proc in procedures:
        catalogue = for_procedure(proc)
        if not len(catalogue):
            continue
        if profile is not None:
            params = profile.params
            settings = [(Setting("this profile", proc.setting_values(params)), profile)]
        else:
            settings = [(Setting(label, values), prof) for label, values, prof in proc.rule_settings()]
        suites = []
        for setting, prof in settings:
            cases = [v for v in vectors if v.procedure == proc.id and runs_under(v, prof.params)]
            cases += conformance.cases(prof)
            # a case counts where it runs: not one the IUT's profile makes unsupported (a
            # role it does not play, an area it does not have)
            cases = [v for v in cases if proc.unsupported_reason(v, prof, frozenset(), _VIRTUAL) is None]
            suites.append((setting, cases))
        out.append(build(catalogue, suites))
    return out


def cmd_rules(args) -> int:
    from ptpcert.registry import by_name, procedures
    from ptpcert.profile import ProfileError, load_profile
    from ptpcert.traceability import render_text, to_dict
    from ptpcert.scenario import VectorError

    profile = None
    if args.profile:
        try:
            profile = load_profile(args.profile)
        except ProfileError as exc:
            print(f"ptpcert rules: {exc}", file=sys.stderr)
            return 2
    if profile is not None:
        procs = [profile.procedure]
    elif args.procedure:
        procs = [by_name(args.procedure)]
    else:
        procs = list(procedures())
    try:
        ms = matrices(procs, profile)
    except VectorError as exc:
        print(f"ptpcert rules: broken vector: {exc}", file=sys.stderr)
        return 2
    if not ms:
        print("ptpcert rules: no rules catalogue for " + ", ".join(p.title for p in procs), file=sys.stderr)
        return 2
    if args.select:
        for m in ms:
            m.entries = [e for e in m.entries if any(fnmatch.fnmatchcase(e.rule.id, g) for g in args.select)]
    if args.json:
        data = [to_dict(m) for m in ms]
        text = json.dumps(data if len(data) > 1 else data[0], indent=1)
        if args.json == "-":
            print(text)
            return 0 if all(m.ok for m in ms) else 1
        with open(args.json, "w", encoding="utf-8") as f:
            f.write(text + "\n")
    for m in ms:
        sys.stdout.write(render_text(m, only_problems=args.check, verbose=not (args.brief or args.check)))
    return 0 if all(m.ok for m in ms) or not args.check else 1
