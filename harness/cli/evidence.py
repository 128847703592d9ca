"""Evidence on the command line: the options ``--evidence FILE.zip [--sign KEY]`` of ``run``
(checked and written by :mod:`ptpcert.evidence.output`) and ``ptpcert verify FILE.zip
[--allowed-signers FILE]``."""

from __future__ import annotations

import os
import sys
from typing import Any


def add_run_arguments(r) -> None:
    """``--evidence`` and ``--sign`` of ``run``."""
    r.add_argument("--evidence", metavar="FILE.zip",
                   help="write one evidence bundle: the reports, the run's capture, the profile as declared and as "
                        "read, the run's settings, the tool's identity and digests, a certificate and a manifest "
                        "of SHA-256 ('ptpcert verify' checks it)")
    r.add_argument("--sign", metavar="KEY",
                   help="sign the bundle's manifest with this OpenSSH private key (ssh-keygen -Y sign, namespace "
                        "ptpcert)")


def add_commands(sub) -> None:
    """The ``verify`` command."""
    v = sub.add_parser("verify", help="check an evidence bundle: hashes, signature, digests, and the capture re-judged",
                       description="Check an evidence bundle that 'run --evidence' wrote: every SHA-256 of its "
                                   "manifest, the signature where it has one, the suite, vector and rules digests "
                                   "against the installed ptpcert, and the capture re-judged offline against the "
                                   "bundled profile, agreeing with the recorded verdicts. One line per check, then "
                                   "the verdict. Exit status: 0 every check holds, 1 one does not, 2 bad usage or "
                                   "a file that is no bundle.")
    v.add_argument("bundle", metavar="FILE.zip")
    v.add_argument("--allowed-signers", metavar="FILE",
                   help="the keys trusted to sign (ssh-keygen's allowed_signers format); needed for a signed bundle")
    v.set_defaults(func=cmd_verify)


def installed_facts(profile, pixit_: dict[str, Any]) -> dict[str, Any]:
    """The installed ptpcert's facts for a bundle's profile and selection (its bundled vectors)."""
    from ptpcert.evidence import tool_facts
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    vectors = load_vector_sets([], only=False)
    cases = load_suite(profile, vectors, include_suite=not pixit_.get("vectors_only"),
                       select=pixit_.get("select") or None)
    if pixit_.get("shard"):   # the run was one shard of its selection
        from ptpcert.suite import shard_of
        cases = shard_of(profile, cases, *pixit_["shard"])[0]
    return tool_facts(cases)


def cmd_verify(args) -> int:
    from ptpcert.evidence import FAIL, EvidenceError, read_bundle, verify

    if args.allowed_signers and not os.path.isfile(args.allowed_signers):
        print(f"ptpcert verify: --allowed-signers {args.allowed_signers}: no such file", file=sys.stderr)
        return 2
    try:
        members = read_bundle(args.bundle)
    except EvidenceError as exc:
        print(f"ptpcert verify: {exc}", file=sys.stderr)
        return 2
    checks = verify(members, allowed_signers=args.allowed_signers, installed=installed_facts)
    for c in checks:
        print(c.line())
    failed = [c for c in checks if c.status == FAIL]
    print(f"{args.bundle}: " + (f"NOT VERIFIED ({len(failed)} check(s) failed)" if failed else "VERIFIED"))
    return 1 if failed else 0
