"""``ptpcert profile``: the example profiles that ship inside the package (so that a user in
an empty directory can start from one), every key a procedure's profile takes (from the
schema that validates profiles), and a check of a profile file without running anything."""

from __future__ import annotations

import difflib
import sys


def add_commands(sub) -> None:
    """The ``profile`` command."""
    from ptpcert.registry import all_names

    p = sub.add_parser("profile", help="example IUT profiles, the keys a profile takes, and a check of one",
                       description="Start a profile from a bundled example (ptpcert profile --example NAME > "
                                   "my-iut.toml), list the keys a procedure's profile takes with their allowed "
                                   "values, defaults and the manual's tables, or check a profile file. Exit "
                                   "status: 0 done, 2 bad usage or a bad profile.")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--list", action="store_true", help="list the bundled example profiles")
    what.add_argument("--example", metavar="NAME", help="print the bundled example profile NAME (see --list)")
    what.add_argument("--keys", metavar="PROCEDURE", choices=all_names(),
                      help="every key of PROCEDURE's profile: " + ", ".join(all_names()))
    what.add_argument("--check", metavar="FILE", help="check a profile file and say what it declares")
    p.set_defaults(func=cmd_profile)


def examples() -> dict[str, str]:
    """Name -> text of every bundled example profile."""
    from ptpcert.paths import bundled_profiles

    return {f.name[:-5]: f.read_text(encoding="utf-8") for f in sorted(bundled_profiles().iterdir(),
                                                                          key=lambda f: f.name)
            if f.name.endswith(".toml")}


def cmd_profile(args) -> int:
    if args.list or args.example:
        found = examples()
        if args.list:
            import tomllib
            for name, text in found.items():
                proc = tomllib.loads(text).get("iut", {}).get("procedure", "?")
                print(f"{name:<20} {proc}")
            print("ptpcert profile --example NAME > my-iut.toml writes one to start from")
            return 0
        name = args.example[:-5] if args.example.endswith(".toml") else args.example
        if name not in found:
            near = difflib.get_close_matches(name, list(found), n=1)
            hint = f"did you mean {near[0]}? " if near else ""
            print(f"ptpcert profile: --example {args.example}: no such example ({hint}known: {', '.join(found)})",
                  file=sys.stderr)
            return 2
        sys.stdout.write(found[name])
        return 0
    if args.keys:
        return _keys(args.keys)
    from ptpcert.cli.common import load_profile

    profile = load_profile("profile", args.check)
    if profile is None:
        return 2
    print(f"{args.check}: a valid {profile.procedure.title} profile")
    for key, value in profile.procedure.profile_dict(profile.params).items():
        print(f"  {key}: {value}")
    return 0


def _keys(name: str) -> int:
    from ptpcert.registry import by_name
    from ptpcert.schema import COMMON, IDENTITY

    proc = by_name(name)
    keys = list(COMMON) + list(IDENTITY) + list(proc.profile_schema())
    for k in keys:
        default = "required" if k.required else f"default {_shown(k.default)}"
        where = "; only where " + ", ".join(f"{o} is {' or '.join(map(_shown, v))}" for o, v in k.when.items()) \
            if k.when else ""
        ref = f" ({k.ref})" if k.ref else ""
        print(f"[{k.table}] {k.name}: {k.domain()}; {default}{where}{ref}\n    {k.doc}")
    return 0


def _shown(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    return str(v)
