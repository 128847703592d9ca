"""Evidence on the command line: ``run --evidence FILE.zip [--sign KEY]`` (the options, their
checks before anything runs, and the bundle written with the other reports) and
``ptpcert verify FILE.zip [--allowed-signers FILE]``."""

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


def options_problem(args) -> str | None:
    """Why ``--evidence``/``--sign`` cannot work, checked before anything runs."""
    from ptpcert.evidence import EvidenceError, sign
    from ptpcert.results import report_path_problem

    path, key = getattr(args, "evidence", None), getattr(args, "sign", None)
    if key and not path:
        return "--sign needs --evidence FILE.zip (the bundle whose manifest it signs)"
    if not path:
        return None
    written = {os.path.realpath(p) for p in (getattr(args, k, None) for k in ("junit", "json", "html", "pcap")) if p}
    if str(path).strip() and os.path.realpath(path) in written:
        return f"--evidence {path}: is also a report; give each file its own name"
    why = report_path_problem(path)
    if why:
        return f"--evidence {path}: {why}"
    if key:
        if not os.path.isfile(key):
            return f"--sign {key}: no such key file (an OpenSSH private key)"
        try:
            sign(b"ptpcert: can this key sign?\n", key)
        except EvidenceError as exc:
            return str(exc)
    return None


def pixit(args, profile, urls: list[str], result) -> dict[str, Any]:
    """The run's settings (ISO/IEC 9646's PIXIT): how the IUT was reached and driven."""
    line = profile.line
    return {
        "transport": urls, "iut_command": [u.split(":", 1)[1] for u in urls if u.startswith(("exec:", "pty:"))],
        "line": line.describe() if hasattr(line, "describe") else str(line),
        "setups": dict(profile.setups), "tolerance_ms": getattr(args, "tolerance_ms", 50.0),
        "timer_tolerance_ms": profile.timer_tolerance_ms,
        "startup_timeout_s": getattr(args, "startup_timeout", None),
        "edge_attempts": getattr(args, "edge_attempts", None), "max_failures": getattr(args, "max_failures", 0),
        "select": list(getattr(args, "select", None) or []), "vectors": [str(v) for v in getattr(args, "vectors", [])],
        "vectors_only": bool(getattr(args, "vectors_only", False)), "jobs": getattr(args, "jobs", 1),
        "device_pool": urls if len(urls) > 1 else [], "priority": getattr(args, "priority", "normal"),
        "harness_scheduling": result.harness_scheduling,
    }


def write_evidence(result, args, profile, cases, urls: list[str], view, cmd: str = "run") -> bool:
    """Write the bundle ``args.evidence`` asks for; False (said on stderr) where it cannot be."""
    from ptpcert.capture import CaptureError
    from ptpcert.evidence import EvidenceError, make_members, seal, tool_facts, write_bundle

    path = getattr(args, "evidence", None)
    if not path:
        return True
    try:
        tool = tool_facts(cases)
        members = make_members(result, view=view, profile=profile, pixit=pixit(args, profile, urls, result), tool=tool)
        write_bundle(path, seal(members, result, tool, getattr(args, "sign", None)))
        return True
    except (OSError, EvidenceError, CaptureError) as exc:
        print(f"ptpcert {cmd}: --evidence {path}: cannot be written ({getattr(exc, 'strerror', None) or exc})",
              file=sys.stderr)
        return False


def installed_facts(profile, pixit_: dict[str, Any]) -> dict[str, Any]:
    """The installed ptpcert's facts for a bundle's profile and selection (its bundled vectors)."""
    from ptpcert.evidence import tool_facts
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    vectors = load_vector_sets([], only=False)
    cases = load_suite(profile, vectors, include_suite=not pixit_.get("vectors_only"),
                       select=pixit_.get("select") or None)
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
